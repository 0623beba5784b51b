#!/usr/bin/env python3
"""End-to-end test of motionmap-make-library (bench/library): the same seed gives byte-identical
files, another seed other files, and `motionmap info` reads every clip with the requested frame
counts, one hierarchy and no leading bind pose (which `motionmap map` would leave out).

usage: make_library_test.py MAKE_LIBRARY_BINARY MOTIONMAP_BINARY SHARED_DATA_DIR

Sources: the CMU clips in SHARED_DATA_DIR/cmu when present, else the tool's own sample walk and
swing (the same 31-joint hierarchy), so the test runs without the shared data too.
"""
import filecmp
import json
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "reference"))
import mocap  # noqa: E402  (independent numpy BVH reader and forward kinematics)

GEN, CLI, DATA = sys.argv[1:4]
TMP = tempfile.mkdtemp(prefix="motionmap-make-library-")
FRAMES, CLIP_FRAMES = 700, 300  # files of 300, 300 and 100 frames


def run(*args):
    p = subprocess.run(list(args), capture_output=True, text=True, timeout=60)
    return p.returncode, p.stdout, p.stderr


def generate(out, seed, *extra):
    rc, stdout, stderr = run(GEN, "--source", SOURCE, "--frames", str(FRAMES), "--clip-frames",
                             str(CLIP_FRAMES), "--seed", str(seed), "--out", out, "-q", *extra)
    assert rc == 0, f"generator failed ({rc}): {stderr}"
    assert f"{FRAMES} frames" in stdout, stdout
    return sorted(os.listdir(out))


def main():
    global SOURCE
    SOURCE = os.path.join(DATA, "cmu")
    if not os.path.isdir(SOURCE):
        print(f"note: {SOURCE} absent; using the sample walk and swing as sources")
        SOURCE = os.path.join(TMP, "sources")
        os.makedirs(SOURCE)
        for kind in ("walk", "swing"):
            rc, _, err = run(CLI, "sample", "--kind", kind, "-o",
                             os.path.join(SOURCE, kind + ".bvh"))
            assert rc == 0, err

    a, b, c = (os.path.join(TMP, n) for n in ("a", "b", "c"))
    files = generate(a, 5)
    assert files == ["clip_00000.bvh", "clip_00001.bvh", "clip_00002.bvh", "manifest.txt"], files
    assert generate(b, 5) == files
    _, mismatch, errors = filecmp.cmpfiles(a, b, files, shallow=False)
    assert not mismatch and not errors, f"same seed, different files: {mismatch} {errors}"
    generate(c, 6)
    _, mismatch, _ = filecmp.cmpfiles(a, c, files, shallow=False)
    repeated = set(files) - set(mismatch)
    assert not repeated, f"seed 6 repeated files of seed 5: {repeated}"

    clips = [os.path.join(a, f) for f in files if f.endswith(".bvh")]
    rc, out, err = run(CLI, "info", "--json", *clips)
    assert rc == 0, err
    infos = [json.loads(line) for line in out.splitlines() if line.strip()]
    assert [i["frames"] for i in infos] == [300, 300, 100], [i["frames"] for i in infos]
    assert len({i["joints"] for i in infos}) == 1, infos
    for i in infos:
        assert abs(i["fps"] - 120) < 1e-3, i
        bind = [w for w in i["warnings"] if "bind pose" in w]
        assert not bind, f"{i['file']}: {bind}"

    manifest = open(os.path.join(a, "manifest.txt")).read().splitlines()
    segments = [line.split() for line in manifest if not line.startswith("#")]
    for name, frames in (("clip_00000.bvh", 300), ("clip_00002.bvh", 100)):
        assert sum(int(s[2]) for s in segments if s[0] == name) == frames, (name, segments)

    # Usage errors exit 2, an occupied output directory 1 unless --force.
    assert run(GEN, "--out", a)[0] == 2
    assert run(GEN, "--frames", "10", "--out", a, "--seed", "x")[0] == 2
    rc, _, err = run(GEN, "--source", SOURCE, "--frames", "10", "--out", a, "-q")
    assert rc == 1 and "--force" in err, (rc, err)
    rc, _, err = run(GEN, "--source", SOURCE, "--frames", "10", "--out", a, "-q", "--force")
    assert rc == 0 and sorted(os.listdir(a)) == ["clip_00000.bvh", "manifest.txt"], (rc, err)
    check_mirrored_walk()
    print("make_library: ok")


def check_mirrored_walk():
    """One clip of one mirrored, unwarped, noiseless segment of the sample walk (a symmetric
    skeleton, Y up, left on +X), written at full precision: in heading-local coordinates (which
    take out the turn and move the generator gives each clip), its LeftFoot at frame i is the
    source's RightFoot at the segment's source frame begin + i with x negated. The source is
    interpolated linearly between frames, hence the 0.05 cm tolerance (feet move ≤ 5 cm a frame).
    """
    src = os.path.join(TMP, "walk")
    out = os.path.join(TMP, "mirrored")
    os.makedirs(src)
    rc, _, err = run(CLI, "sample", "--kind", "walk", "-o", os.path.join(src, "walk.bvh"))
    assert rc == 0, err
    rc, _, err = run(GEN, "--source", src, "--frames", "100", "--clip-frames", "100", "--seed", "3",
                     "--out", out, "-q", "--mirror-probability", "1", "--max-rate", "1",
                     "--noise-degrees", "0", "--noise-translation", "0", "--decimals", "-1")
    assert rc == 0, err
    segments = [line.split() for line in open(os.path.join(out, "manifest.txt"))
                if not line.startswith("#")]
    assert len(segments) == 1 and segments[0][6] == "mirrored", segments
    begin = float(segments[0][4])

    def feet(path):
        joints, values, _ = mocap.parse_bvh(path)
        cloud = mocap.heading_local_points(joints, values).reshape(len(values), -1, 3)
        names = [j["name"] for j in joints]
        return cloud[:, names.index("LeftFoot")], cloud[:, names.index("RightFoot")]

    left, _ = feet(os.path.join(out, "clip_00000.bvh"))
    src_left, src_right = feet(os.path.join(src, "walk.bvh"))
    at = begin + np.arange(len(left))
    k = np.minimum(np.floor(at).astype(int), len(src_right) - 2)
    a = (at - k)[:, None]
    mirror = np.array([-1.0, 1.0, 1.0])
    expected = ((1 - a) * src_right[k] + a * src_right[k + 1]) * mirror
    error = np.abs(left - expected).max()
    assert error < 0.05, f"mirrored LeftFoot off the reflected RightFoot by {error:.4g} cm"
    # The check discriminates: the unswapped foot, or the swap without the reflection, is far off.
    wrong_foot = (((1 - a) * src_left[k] + a * src_left[k + 1]) * mirror - left)
    unreflected = (1 - a) * src_right[k] + a * src_right[k + 1] - left
    assert np.abs(wrong_foot).max() > 5 and np.abs(unreflected).max() > 5, (
        np.abs(wrong_foot).max(), np.abs(unreflected).max())
    print(f"mirrored walk: LeftFoot within {error:.2g} cm of the reflected RightFoot "
          f"(other foot {np.abs(wrong_foot).max():.3g} cm, no reflection "
          f"{np.abs(unreflected).max():.3g} cm)")


if __name__ == "__main__":
    try:
        main()
    finally:
        shutil.rmtree(TMP, ignore_errors=True)
