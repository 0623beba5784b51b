#!/usr/bin/env python3
"""Scale measurements of issue 11: `motionmap map` over synthetic libraries of growing size.

For each size, makes (or reuses) a seeded synthetic library with motionmap-make-library (real CMU
clips time-warped, mirrored, noised and concatenated: bench/README.md), then for each method runs

    motionmap map LIBRARY/clip_*.bvh -m METHOD -o /dev/null -q [--verbose]

in a fresh child process, measuring its wall time and peak resident memory (the child's own
ru_maxrss, from wait4), and prints a Markdown table: frames, method, total seconds, peak MiB and
the slowest stage. The stages come from the lines `--verbose` prints on stderr,

    verbose: <stage name>: <seconds> s, peak <MiB> MiB

when the tool has that option (older builds: totals only, said in the header). A run that fails
gets `error: <last line of its stderr>`, one past --timeout `timeout (> N s)`; the table goes on.
Each run is limited to --mem-limit-gib of address space (RLIMIT_AS), so a map too big for the
machine ends in the tool's own bad_alloc error instead of the OOM killer on a shared machine.

    /usr/bin/python3 bench/scale_table.py                          # 20000 72000 100000 1000000
    /usr/bin/python3 bench/scale_table.py --sizes 20000 --methods pca mds --timeout 300

With --place N, each map is also saved (a second run, with --save) and a library of N other frames
(seed + 1000) is placed on it with `motionmap map … --onto`; a second table gives the placing
stage's seconds and frames per second (out-of-sample placement, issue 11).

Libraries are kept in --library-dir (one folder per size and seed, ~0.76 KB a frame: 760 MB at
1 000 000 frames) and reused when their manifest matches; --json saves every run's numbers.
"""
import argparse
import datetime
import hashlib
import json
import os
import re
import resource
import signal
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
METHODS = ["pca", "svd", "mds", "isomap", "le", "lle"]
STAGE_LINE = re.compile(r"^verbose: (.+): ([-+0-9.eE]+) s, peak ([-+0-9.eE]+) MiB\s*$")


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog="See bench/README.md.")
    p.add_argument("--sizes", type=int, nargs="+", default=[20000, 72000, 100000, 1000000],
                   help="library sizes in frames (default: 20000 72000 100000 1000000)")
    p.add_argument("--methods", nargs="+", default=METHODS, choices=METHODS,
                   help="methods (default: all six)")
    p.add_argument("--timeout", type=float, default=600,
                   help="seconds per run before it is killed (default 600)")
    p.add_argument("--mem-limit-gib", type=float, default=None,
                   help="address-space limit per run in GiB (default: half the machine's memory; "
                        "0: none)")
    p.add_argument("--seed", type=int, default=1, help="library seed (default 1)")
    p.add_argument("--clip-frames", type=int, default=6000,
                   help="frames per library file (default 6000)")
    p.add_argument("--source", help="source clips for the generator (default: its own, "
                                    "../shared/data/cmu)")
    p.add_argument("--library-dir", default=os.path.join(tempfile.gettempdir(),
                                                         "motionmap-scale-libraries"),
                   help="where libraries are made and kept (default: %(default)s)")
    p.add_argument("--cli", default=os.path.join(ROOT, "build", "apps", "cli", "motionmap"),
                   help="the motionmap tool (default: build/apps/cli/motionmap)")
    p.add_argument("--generator",
                   default=os.path.join(ROOT, "build", "bench", "library",
                                        "motionmap-make-library"),
                   help="the generator (default: build/bench/library/motionmap-make-library)")
    p.add_argument("--no-skip", action="store_true",
                   help="run a method at larger sizes even after it timed out at a smaller one")
    p.add_argument("--place", type=int, default=0, metavar="N",
                   help="also save each map and place a library of N other frames on it")
    p.add_argument("--json", help="also write every run's numbers (and stages) to this file")
    p.add_argument("extra", nargs="*", help="further `motionmap map` options, after --")
    return p.parse_args()


def load_average():
    """The load averages as `uptime` prints them (1, 5, 15 minutes)."""
    try:
        out = subprocess.run(["uptime"], capture_output=True, text=True, timeout=10).stdout
        m = re.search(r"load average:\s*(.+)$", out.strip())
        if m:
            return m.group(1)
    except (OSError, subprocess.SubprocessError):
        pass
    return ", ".join(f"{x:.2f}" for x in os.getloadavg())


def memory_total_bytes():
    with open("/proc/meminfo") as f:
        for line in f:
            if line.startswith("MemTotal:"):
                return int(line.split()[1]) * 1024
    return 0


def has_verbose(cli):
    p = subprocess.run([cli, "map", "--help"], capture_output=True, text=True, timeout=60)
    return "--verbose" in p.stdout + p.stderr


def library(args, frames, seed=None):
    """The folder of the library of `frames` frames, made unless a matching one is there."""
    seed = args.seed if seed is None else seed
    name = f"frames{frames}-clip{args.clip_frames}-seed{seed}"
    if args.source:  # another source, another library
        name += "-" + hashlib.sha1(os.path.abspath(args.source).encode()).hexdigest()[:8]
    folder = os.path.join(args.library_dir, name)
    manifest = os.path.join(folder, "manifest.txt")
    want = f"frames={frames} clip_frames={args.clip_frames} seed={seed} "
    if os.path.exists(manifest):
        with open(manifest) as f:
            if want in f.readline():
                return folder, None
    cmd = [args.generator, "--frames", str(frames), "--clip-frames", str(args.clip_frames),
           "--seed", str(seed), "--out", folder, "--force", "-q"]
    if args.source:
        cmd += ["--source", args.source]
    start = time.monotonic()
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"scale_table: the generator failed ({p.returncode}): {p.stderr.strip()}")
    return folder, time.monotonic() - start


def run_map(cmd, timeout, mem_limit):
    """Runs one map in a fresh child: (rc or None on timeout, wall s, peak MiB, stderr text)."""
    rc, wall, _, peak, text = run_measured(cmd, timeout, mem_limit)
    return rc, wall, peak, text


def run_measured(cmd, timeout, mem_limit=None, env=None):
    """Runs cmd in a fresh child: (rc or None on timeout, wall s, CPU s, peak MiB, stderr text);
    `mem_limit` bytes of address space at most (None: no limit); `env` its environment (None:
    this one's). bench/library_labels_table.py uses it too."""
    def limit():
        if mem_limit:
            resource.setrlimit(resource.RLIMIT_AS, (mem_limit, mem_limit))

    with tempfile.TemporaryFile(mode="w+") as err:
        start = time.monotonic()
        p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=err, preexec_fn=limit, env=env)
        timed_out = False
        while True:
            # wait4 reaps this child only and gives its own rusage (ru_maxrss in KiB on Linux).
            pid, status, usage = os.wait4(p.pid, os.WNOHANG)
            if pid:
                break
            if time.monotonic() - start > timeout:
                timed_out = True
                p.kill()
                pid, status, usage = os.wait4(p.pid, 0)
                break
            time.sleep(0.02)
        wall = time.monotonic() - start
        p.returncode = os.waitstatus_to_exitcode(status)  # reaped here: keep Popen from waiting
        err.seek(0)
        text = err.read()
    cpu = usage.ru_utime + usage.ru_stime
    return (None if timed_out else p.returncode), wall, cpu, usage.ru_maxrss / 1024.0, text


def stages_of(stderr):
    out = []
    for line in stderr.splitlines():
        m = STAGE_LINE.match(line.strip())
        if m:
            out.append({"stage": m.group(1), "seconds": float(m.group(2)),
                        "peak_mib": float(m.group(3))})
    return out


def failure_cell(rc, stderr):
    lines = [line.strip() for line in stderr.splitlines()
             if line.strip() and not STAGE_LINE.match(line.strip())]
    # The tool writes "motionmap: error: …"; the cell keeps "error: …".
    last = re.sub(r"^motionmap:\s*", "", lines[-1]) if lines else ""
    if rc < 0:
        name = signal.Signals(-rc).name if -rc in signal.valid_signals() else str(-rc)
        why = " (out of memory?)" if rc == -signal.SIGKILL else ""
        return f"killed by {name}{why}" + (f": {last}" if last else "")
    if not last:
        return f"error: exit {rc}, nothing on stderr"
    return last if last.startswith("error:") else f"error: {last}"


def bvh_files(folder):
    return sorted(os.path.join(folder, f) for f in os.listdir(folder)
                  if f.startswith("clip_") and f.endswith(".bvh"))


def place_row(args, frames, method, files, new_files, mem_limit):
    """Saves the map of `files` and places `new_files` on it: a row of the placement table."""
    with tempfile.TemporaryDirectory() as tmp:
        saved = os.path.join(tmp, "map.mmap.h5")
        rc, _, _, stderr = run_map([args.cli, "map", *files, "-m", method, "-o", "/dev/null", "-q",
                                    "--save", saved, *args.extra], args.timeout, mem_limit)
        if rc != 0:
            return [f"{frames}", method, "", cell(failure_cell(rc, stderr) if rc else "timeout"),
                    "", ""]
        rc, wall, peak, stderr = run_map([args.cli, "map", *new_files, "--onto", saved, "-o",
                                          "/dev/null", "-q", "--verbose"], args.timeout, mem_limit)
        size = os.path.getsize(saved) / 2**20
    if rc != 0:
        return [f"{frames}", method, f"{size:.0f}",
                cell(failure_cell(rc, stderr) if rc else "timeout"), "", ""]
    placing = [s["seconds"] for s in stages_of(stderr) if s["stage"] == "placing"]
    seconds = placing[0] if placing else wall
    return [f"{frames}", method, f"{size:.0f}", f"{seconds:.2f}",
            f"{args.place / seconds:,.0f}".replace(",", " ") if seconds > 0 else "", f"{peak:.0f}"]


def cell(text):
    return text.replace("|", "\\|")


def main():
    args = parse_args()
    for path, what in ((args.cli, "motionmap tool"), (args.generator, "generator")):
        if not os.access(path, os.X_OK):
            sys.exit(f"scale_table: the {what} {path} is missing; build first "
                     "(cmake --build build)")
    total_memory = memory_total_bytes()
    gib = args.mem_limit_gib if args.mem_limit_gib is not None else total_memory / 2 / 2**30
    mem_limit = int(gib * 2**30) if gib > 0 else 0
    verbose = has_verbose(args.cli)

    started = datetime.datetime.now().astimezone()
    header = (f"{started:%Y-%m-%d %H:%M %Z} · load average {load_average()} · nproc "
              f"{os.cpu_count()} · memory {total_memory / 2**30:.1f} GiB · limit per run "
              + (f"{gib:.1f} GiB" if mem_limit else "none") + f" · timeout {args.timeout:g} s")
    if not verbose:
        header += " · this motionmap has no --verbose: totals only"
    print(header, file=sys.stderr)

    new_files = []
    if args.place:
        folder, _ = library(args, args.place, seed=args.seed + 1000)
        new_files = bvh_files(folder)
    rows, records, timed_out_at, place_rows = [], [], {}, []
    for frames in sorted(args.sizes):
        folder, made = library(args, frames)
        files = bvh_files(folder)
        if made is not None:
            print(f"made {folder} ({len(files)} files) in {made:.1f} s", file=sys.stderr)
        for method in args.methods:
            if method in timed_out_at and not args.no_skip:
                rows.append([f"{frames}", method, f"skipped (timeout at {timed_out_at[method]})",
                             "", ""])
                continue
            cmd = [args.cli, "map", *files, "-m", method, "-o", "/dev/null", "-q"]
            if verbose:
                cmd.append("--verbose")
            cmd += args.extra
            rc, wall, peak, stderr = run_map(cmd, args.timeout, mem_limit)
            stages = stages_of(stderr)
            # The tool ends with a "total" line; the slowest stage is among the others.
            parts = [s for s in stages if s["stage"] != "total"]
            slowest = max(parts, key=lambda s: s["seconds"]) if parts else None
            slow = f"{slowest['stage']} ({slowest['seconds']:.2f} s)" if slowest else ""
            if rc is None:
                result = f"timeout (> {args.timeout:g} s)"
                timed_out_at[method] = frames
            elif rc != 0:
                result = failure_cell(rc, stderr)
            else:
                result = f"{wall:.2f}"
            rows.append([f"{frames}", method, cell(result), f"{peak:.0f}", cell(slow)])
            records.append({"frames": frames, "method": method, "rc": rc, "seconds": wall,
                            "peak_mib": peak, "result": result, "stages": stages})
            print(f"{frames:>8} {method:<6} {result} · {peak:.0f} MiB" +
                  (f" · slowest {slow}" if slow else ""), file=sys.stderr)
            if args.place and rc == 0:
                place_rows.append(place_row(args, frames, method, files, new_files, mem_limit))
                print(f"{frames:>8} {method:<6} placed: " + " · ".join(place_rows[-1][2:]),
                      file=sys.stderr)

    print(header)
    print()
    print("| frames | method | total s | peak MiB | slowest stage |")
    print("|---:|---|---:|---:|---|")
    for r in rows:
        print("| " + " | ".join(r) + " |")
    if place_rows:
        print()
        print(f"Placing {args.place} other frames (seed {args.seed + 1000}) on each saved map "
              "(`--onto`; the placing stage of `--verbose`):")
        print()
        print("| frames | method | map file MiB | placing s | frames/s | peak MiB |")
        print("|---:|---|---:|---:|---:|---:|")
        for r in place_rows:
            print("| " + " | ".join(r) + " |")
    print()
    print(f"load average at the end: {load_average()}")
    if any(r["stages"] for r in records):
        print()
        print("Stages (seconds, peak MiB):")
        for r in records:
            if r["stages"]:
                parts = "; ".join(f"{s['stage']} {s['seconds']:.2f} s {s['peak_mib']:.0f} MiB"
                                  for s in r["stages"])
                print(f"- {r['frames']} {r['method']}: {parts}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"header": header, "runs": records}, f, indent=1)


if __name__ == "__main__":
    main()
