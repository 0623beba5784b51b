#!/usr/bin/env python3
"""End-to-end tests of `motionmap keyposes`: the frames and errors it prints (--json and the
table), the key poses rebuilding a clip better than evenly spaced frames where the README says
they do, the first and last mapped frames always kept, the contact sheet in each format (a PNG
whose pose cells hold drawn bones), and usage errors. The clips are CMU 64_08/64_09 and Bandai
Namco's takes in ../shared/data; skips, with a message, when they are absent.

usage: keyposes_test.py MOTIONMAP_BINARY SHARED_DATA_DIR
"""
import json
import os
import struct
import sys
import zlib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from clirun import main, needs, run, test, tmp, data  # noqa: E402

GOLF = ["cmu/64_08.bvh", "cmu/64_09.bvh"]


def keyposes_json(*args):
    code, out, err = run("keyposes", *args, "--json", "-q")
    assert code == 0, err
    return json.loads(out)


@test
def frames_and_errors():
    if not needs(*GOLF):
        return
    result = keyposes_json(*[data(c) for c in GOLF], "-n", "6")
    assert result["method"] == "pca", result
    assert len(result["clips"]) == 2
    for clip in result["clips"]:
        frames = clip["frames"]
        assert len(frames) == 6 and frames == sorted(set(frames)), frames
        # The bind pose (frame 0) is left out as `map` leaves it out; the last frame is kept.
        assert frames[0] == clip["first"] == 1 and frames[-1] == clip["last"], clip
        assert len(clip["uniform_frames"]) == 6
        assert clip["rms_degrees"] >= 0 and clip["uniform_rms_degrees"] > 0
    # 64_09 on its own map: clearly better than even spacing (the README's table: 8.4° vs 12.0°).
    c = keyposes_json(data(GOLF[1]), "-n", "8")["clips"][0]
    assert c["rms_degrees"] < 0.8 * c["uniform_rms_degrees"], c
    # The table names each clip with both errors.
    code, out, err = run("keyposes", data(GOLF[1]), "-n", "6", "-q")
    assert code == 0, err
    assert "64_09.bvh" in out and "°" in out, out


@test
def other_methods_and_counts():
    if not needs("bandai/dataset-1_walk_angry_001.bvh"):
        return
    walk = data("bandai/dataset-1_walk_angry_001.bvh")
    iso = keyposes_json(walk, "-n", "4", "--method", "isomap")
    assert iso["method"] == "isomap" and len(iso["clips"][0]["frames"]) == 4
    # More keys than frames: every frame is a key and the rebuild is exact.
    short = keyposes_json(walk, "-n", "1000", "--frames", "0:10")
    assert short["clips"][0]["frames"] == list(range(10)), short
    assert short["clips"][0]["rms_degrees"] == 0


def png_size(path):
    with open(path, "rb") as f:
        head = f.read(24)
    assert head[:8] == b"\x89PNG\r\n\x1a\n", path
    return struct.unpack(">II", head[16:24])


@test
def contact_sheet():
    if not needs(*GOLF):
        return
    for ext in ("png", "svg", "pdf"):
        out = tmp("sheet." + ext)
        code, _, err = run("keyposes", *[data(c) for c in GOLF], "-n", "5", "-o", out, "-q",
                           "--pose-size", "100")
        assert code == 0, err
        assert os.path.getsize(out) > 2000, (ext, os.path.getsize(out))
    width, height = png_size(tmp("sheet.png"))
    # Two rows; a map cell (1.4 × 100) and five pose cells of 100 pixels across.
    assert width >= 5 * 100 + 140 and height >= 2 * 140, (width, height)
    with open(tmp("sheet.svg")) as f:
        svg = f.read()
    assert "<svg" in svg and "frame 1" in svg, svg[:200]


@test
def usage_errors():
    if not needs(*GOLF):
        return
    golf = data(GOLF[0])
    code, _, err = run("keyposes", golf, "-n", "1")
    assert code == 2 and "--count" in err, err
    code, _, err = run("keyposes", golf, "-o", tmp("sheet.gif"), "-q")
    assert code == 1 and "sheet.gif" in err and ".png, .svg or .pdf" in err, err
    code, _, err = run("keyposes", "-n", "4")
    assert code == 2 and "files is required" in err, err


if __name__ == "__main__":
    sys.exit(main())
