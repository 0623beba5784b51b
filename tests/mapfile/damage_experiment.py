#!/usr/bin/env python3
"""Issue 22's experiment: damaged copies of saved maps, used by `map --onto`, `pose --map` and
(with --studio) MotionMap Studio opening them.

Saves two maps of CMU 64_08 (a dense isomap map, and a landmark isomap map: the points path with
landmark geodesics), makes COPIES copies of each with 1 to 32 random bytes changed (seeded: the
same copies every run), and runs on each copy

    motionmap map 64_09.bvh --onto COPY -q -o out.csv
    motionmap pose --map COPY --at=X,Y -o pose.bvh      (X,Y: a point of the map)
    motionmap-studio COPY --screenshot shot.png          (with --studio, offscreen)

Each run is one of: a crash (killed by a signal or an abort), a hang (over the time limit), a
clear error (exit status 1 or 2 with a message "error"), the same result as the undamaged file
(the output's bytes), or a different result without an error. Every message must be valid
UTF-8. Prints a Markdown table; exits 1 when a run crashed, hung, gave a different result
without an error or wrote a message that is not UTF-8.

usage: damage_experiment.py MOTIONMAP SHARED_DATA_DIR [--copies 400] [--seed 22] [--jobs 2]
                            [--studio MOTIONMAP_STUDIO]
"""
import argparse
import concurrent.futures
import os
import random
import shutil
import subprocess
import sys
import tempfile

OUTCOMES = ["crash", "hang", "clear error", "same result", "different result, no error"]


def run(binary, args, timeout=120, env=None):
    """(return code or None on a timeout, stdout bytes, stderr bytes)."""
    try:
        p = subprocess.run([binary, *args], capture_output=True, timeout=timeout, env=env)
        return p.returncode, p.stdout, p.stderr
    except subprocess.TimeoutExpired as e:
        return None, e.stdout or b"", e.stderr or b""


def utf8(data):
    try:
        data.decode("utf-8")
        return True
    except UnicodeDecodeError:
        return False


def read_bytes(path):
    with open(path, "rb") as f:
        return f.read()


def damage(original, seed):
    """`original` with 1 to 32 random bytes changed (each to another value), by `seed`."""
    rng = random.Random(seed)
    data = bytearray(original)
    for _ in range(rng.randint(1, 32)):
        at = rng.randrange(len(data))
        data[at] ^= rng.randint(1, 255)
    return bytes(data)


class Map:
    """One saved map, and the outputs of its two commands on the undamaged file."""

    def __init__(self, binary, work, name, clip, other, options, studio=None):
        self.binary, self.work, self.name, self.other = binary, work, name, other
        self.studio = studio
        self.commands = ("onto", "pose", "studio") if studio else ("onto", "pose")
        self.path = os.path.join(work, name + ".mmap.h5")
        csv = os.path.join(work, name + ".csv")
        code, _, err = run(binary, ["map", clip, "-q", "-o", csv, "--save", self.path, *options])
        if code != 0:
            sys.exit("damage_experiment: cannot save %s: %s" % (name, err.decode(errors="replace")))
        with open(csv) as f:
            rows = [line.split(",") for line in f.read().splitlines() if not line.startswith("#")]
        row = rows[1 + (len(rows) - 1) // 3]
        self.at = "--at=%s,%s" % (row[-2], row[-1])
        self.original = read_bytes(self.path)
        self.expected = {}
        for command in self.commands:
            code, out, err = self.run(command, self.path, os.path.join(work, name + "-base"))
            if code != 0:
                sys.exit("damage_experiment: %s on the undamaged %s failed: %s"
                         % (command, name, err.decode(errors="replace")))
            self.expected[command] = out

    def run(self, command, map_file, prefix):
        """(code, the output file's bytes or b"", stderr) of `command` on `map_file`."""
        binary, env = self.binary, None
        if command == "onto":
            output = prefix + ".csv"
            args = ["map", self.other, "--onto", map_file, "-q", "-o", output]
        elif command == "pose":
            output = prefix + ".bvh"
            args = ["pose", "--map", map_file, self.at, "-q", "-o", output]
        else:
            output = prefix + ".png"
            args = [map_file, "--screenshot", output]
            binary, env = self.studio, dict(os.environ, QT_QPA_PLATFORM="offscreen")
        if os.path.exists(output):
            os.remove(output)
        code, out, err = run(binary, args, env=env)
        result = read_bytes(output) if code == 0 and os.path.exists(output) else b""
        return code, result, out + err

    def outcome(self, index, seed):
        """[(command, outcome, message is UTF-8, message)] for copy `index`."""
        copy = os.path.join(self.work, "%s-%03d.mmap.h5" % (self.name, index))
        with open(copy, "wb") as f:
            f.write(damage(self.original, "%d-%s-%d" % (seed, self.name, index)))
        results = []
        for command in self.commands:
            code, out, message = self.run(command, copy, copy[:-len(".mmap.h5")] + "-" + command)
            if code is None:
                outcome = "hang"
            elif code < 0 or code > 2:
                outcome = "crash"
            elif code != 0:
                outcome = "clear error" if b"error" in message else "crash"
            elif out == self.expected[command]:
                outcome = "same result"
            else:
                outcome = "different result, no error"
            results.append((command, outcome, utf8(message), message))
        os.remove(copy)
        return results


def experiment(binary, data, copies, seed, jobs, work, verbose=False, studio=None):
    """{(map name, command): {outcome: count}}, the messages that are not UTF-8, the bad runs."""
    clip = os.path.join(data, "cmu", "64_08.bvh")
    other = os.path.join(data, "cmu", "64_09.bvh")
    maps = [Map(binary, work, "dense-isomap", clip, other, ["--method", "isomap"], studio),
            Map(binary, work, "landmark-isomap", clip, other,
                ["--method", "isomap", "--landmarks", "0"], studio)]
    table, not_utf8, bad = {}, [], []
    for m in maps:
        for command in m.commands:
            table[(m.name, command)] = {o: 0 for o in OUTCOMES}
        with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
            for index, results in enumerate(pool.map(lambda i: m.outcome(i, seed), range(copies))):
                for command, outcome, is_utf8, message in results:
                    table[(m.name, command)][outcome] += 1
                    if not is_utf8:
                        not_utf8.append((m.name, index, command, message))
                    if outcome not in ("clear error", "same result"):
                        bad.append((m.name, index, command, outcome, message))
                    if verbose and outcome not in ("clear error", "same result"):
                        print("%s copy %d, %s: %s: %s" % (m.name, index, command, outcome,
                                                          message.decode(errors="replace").strip()))
    return table, not_utf8, bad


def markdown(table, copies):
    lines = ["| map, command | " + " | ".join(OUTCOMES) + " |",
             "|---|" + "---:|" * len(OUTCOMES)]
    for (name, command), counts in table.items():
        what = {"onto": "`map 64_09.bvh --onto`", "pose": "`pose --map`",
                "studio": "Studio opening it"}[command]
        lines.append("| %s, %s | " % (name, what) + " | ".join(str(counts[o]) for o in OUTCOMES)
                     + " |")
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("motionmap")
    parser.add_argument("data")
    parser.add_argument("--copies", type=int, default=400)
    parser.add_argument("--seed", type=int, default=22)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--verbose", action="store_true")
    parser.add_argument("--studio", help="motionmap-studio: also open every copy in Studio")
    args = parser.parse_args()
    if not os.path.exists(os.path.join(args.data, "cmu", "64_08.bvh")):
        print("damage_experiment: skipped: cmu/64_08.bvh absent from " + args.data)
        return 77
    work = tempfile.mkdtemp(prefix="motionmap-damage-")
    try:
        table, not_utf8, bad = experiment(os.path.abspath(args.motionmap),
                                          os.path.abspath(args.data), args.copies, args.seed,
                                          args.jobs, work, args.verbose,
                                          os.path.abspath(args.studio) if args.studio else None)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print(markdown(table, args.copies))
    print("\n%d copies of each map, 1 to 32 bytes changed, seed %d; messages not valid UTF-8: %d"
          % (args.copies, args.seed, len(not_utf8)))
    for name, index, command, outcome, message in bad[:20]:
        print("  %s copy %d, %s: %s: %s" % (name, index, command, outcome,
                                            message.decode(errors="replace").strip()[:300]))
    return 1 if bad or not_utf8 else 0


if __name__ == "__main__":
    sys.exit(main())
