#!/usr/bin/env python3
"""End-to-end tests of the `motionmap` command-line tool: exit codes (0 ok, 1 runtime error,
2 usage error), errors on stderr, --help everywhere, --json, and the commands on real files.

usage: cli_test.py MOTIONMAP_BINARY SHARED_DATA_DIR
"""
import json
import os
import subprocess
import sys
import tempfile
import traceback

BIN = sys.argv[1]
DATA = sys.argv[2]
TMP = tempfile.mkdtemp(prefix="motionmap-cli-")


def run(*args):
    p = subprocess.run([BIN, *args], capture_output=True, text=True, timeout=300)
    return p.returncode, p.stdout, p.stderr


def data(rel):
    return os.path.join(DATA, rel)


def have(rel):
    return os.path.exists(data(rel))


def write(name, text):
    path = os.path.join(TMP, name)
    with open(path, "w", newline="") as f:
        f.write(text)
    return path


TESTS = []


def test(fn):
    TESTS.append(fn)
    return fn


@test
def help_everywhere_exits_zero():
    for cmd in ([], ["info"], ["convert"], ["sample"]):
        code, out, _ = run(*cmd, "--help")
        assert code == 0, (cmd, code)
        assert "Usage" in out or "usage" in out.lower(), out


@test
def usage_errors_exit_two_on_stderr():
    for args in ([], ["frobnicate"], ["info"], ["sample", "--kind", "dance", "-o", "x.bvh"],
                 ["convert", data("cmu/64_08.bvh")], ["info", "/no/such/file.bvh"]):
        code, out, err = run(*args)
        assert code == 2, (args, code, err)
        assert err.strip(), args
        assert out == "", (args, out)


@test
def sample_then_info_json():
    for kind in ("swing", "walk"):
        path = os.path.join(TMP, kind + ".bvh")
        code, _, err = run("sample", "--kind", kind, "-o", path)
        assert code == 0, err
        code, out, err = run("info", "--json", path)
        assert code == 0, err
        info = json.loads(out)
        assert info["joints"] == 31 and info["roots"] == 1, info
        assert info["channels"] == 96, info
        assert abs(info["frame_time"] - 1 / 120) < 1e-12, info
        assert info["frames"] >= 240, info
        assert isinstance(info["warnings"], list) and isinstance(info["end_sites"], int)


@test
def info_on_cmu_golf_swing_warns_about_tpose_and_flips():
    if not have("cmu/64_08.bvh"):
        print("  skipped: shared data absent")
        return
    code, out, err = run("info", data("cmu/64_08.bvh"))
    assert code == 0, err
    assert "31" in out and "365" in out, out
    assert "bind pose" in out, out
    assert "Thumb" in out, out  # CMU's thumbs flip by ~180°
    code, out, err = run("info", "--json", data("cmu/64_08.bvh"), data("cmu/02_03.bvh"))
    lines = [json.loads(line) for line in out.splitlines()]
    assert [l["frames"] for l in lines] == [365, 174], lines
    assert lines[0]["end_sites"] == 7, lines[0]  # toes, head, hands, thumbs
    assert any("bind pose" in w for w in lines[0]["warnings"]), lines[0]


@test
def info_reads_every_real_file():
    files = []
    for root, _, names in os.walk(DATA):
        files += [os.path.join(root, n) for n in names if n.endswith((".bvh", ".amc"))]
    if not files:
        print("  skipped: shared data absent")
        return
    code, out, err = run("info", "--json", *sorted(files))
    assert code == 0, err
    assert len(out.splitlines()) == len(files)


@test
def bad_file_exits_one_with_location():
    bad = write("bad.bvh", "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0\n}\n")
    code, out, err = run("info", bad)
    assert code == 1, (code, err)
    assert bad + ":4:" in err and "error: expected" in err, err


@test
def convert_bvh_round_trips_values():
    if not have("cmu/64_08.bvh"):
        print("  skipped: shared data absent")
        return
    out_path = os.path.join(TMP, "copy.bvh")
    code, _, err = run("convert", data("cmu/64_08.bvh"), "-o", out_path)
    assert code == 0, err

    def motion_values(path):
        with open(path) as f:
            text = f.read()
        rows = text.split("Frame Time:")[1].splitlines()[1:]
        return [[float(v) for v in r.split()] for r in rows if r.strip()]

    a, b = motion_values(data("cmu/64_08.bvh")), motion_values(out_path)
    assert len(a) == len(b) == 365
    assert max(abs(x - y) for ra, rb in zip(a, b) for x, y in zip(ra, rb)) == 0.0


@test
def convert_amc_to_bvh():
    if not have("asfamc/02_03.amc"):
        print("  skipped: shared data absent")
        return
    out_path = os.path.join(TMP, "02_03.bvh")
    code, _, err = run("convert", data("asfamc/02_03.amc"), "-o", out_path)
    assert code == 0, err
    code, out, err = run("info", "--json", out_path)
    assert code == 0, err
    info = json.loads(out)
    assert info["frames"] == 173 and abs(info["frame_time"] - 1 / 120) < 1e-12, info
    code, out, err = run("info", "--json", "--fps", "60", data("asfamc/02_03.amc"),
                         "--asf", data("asfamc/02.asf"))
    assert code == 0, err
    assert abs(json.loads(out)["frame_time"] - 1 / 60) < 1e-12


def main():
    passed = failed = 0
    for fn in TESTS:
        try:
            fn()
            passed += 1
            print(f"PASS {fn.__name__}")
        except Exception:
            failed += 1
            print(f"FAIL {fn.__name__}")
            traceback.print_exc()
    print(f"{passed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
