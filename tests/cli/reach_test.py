#!/usr/bin/env python3
"""End-to-end tests of `motionmap reach`: the map point and error it prints (text and --json), the
BVH it writes (the pose `motionmap pose` blends at that point, byte for byte), a position it
reached is reached again within 1 % of the body's height, pins, a target out of reach (the best
valid point), a saved map (the same answer as its clips mapped directly), and usage errors (an
unknown joint names the near matches, malformed positions, a pin without a position). The clips
are Bandai Namco's walks in ../shared/data; skips, with a message, when they are absent.

usage: reach_test.py MOTIONMAP_BINARY SHARED_DATA_DIR
"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from clirun import main, needs, run, test, tmp, data  # noqa: E402

CLIPS = ["bandai/dataset-1_walk_old_001.bvh", "bandai/dataset-1_walk_proud_001.bvh"]
_MAP = {}


def clips():
    return [data(c) for c in CLIPS]


def the_map():
    """(map CSV, saved map) of the two walks, made once."""
    if not _MAP:
        csv_path, h5 = tmp("walks.csv"), tmp("walks.mmap.h5")
        code, _, err = run("map", *clips(), "--method", "isomap", "--save", h5, "-o", csv_path,
                           "-q")
        assert code == 0, err
        _MAP["csv"], _MAP["h5"] = csv_path, h5
    return _MAP["csv"], _MAP["h5"]


def reach_json(*args):
    csv_path, _ = the_map()
    code, out, err = run("reach", *clips(), "--map", csv_path, "--json", "-q", *args)
    assert code == 0, err
    return json.loads(out)


def vec(v):
    return ",".join(repr(float(x)) for x in v)


@test
def help_names_the_options():
    code, out, _ = run("reach", "--help")
    assert code == 0, out
    for option in ("--joint", "--to", "--pin", "--from", "--json", "lib.mmap.h5"):
        assert option in out, (option, out)


@test
def prints_the_error_and_the_map_point_and_writes_that_points_pose():
    if not needs(*CLIPS):
        return
    csv_path, _ = the_map()
    out_bvh, pose_bvh = tmp("reach.bvh"), tmp("pose.bvh")
    code, out, err = run("reach", *clips(), "--map", csv_path, "--joint", "Hand_L",
                         "--to=20,100,30", "-o", out_bvh)
    assert code == 0, err
    lines = out.splitlines()
    assert lines[0].startswith("map point: "), out
    assert lines[1].startswith("error: ") and "% of the body's height" in lines[1], out
    assert "wrote " + out_bvh in err, err
    point = lines[0][len("map point: "):]
    code, _, err = run("pose", *clips(), "--map", csv_path, "--at=" + point, "-o", pose_bvh)
    assert code == 0, err
    with open(out_bvh, "rb") as a, open(pose_bvh, "rb") as b:
        assert a.read() == b.read()


@test
def a_position_it_reached_is_reached_again():
    if not needs(*CLIPS):
        return
    first = reach_json("--joint", "Foot_R", "--to=15,20,25", "-o", tmp("a.bvh"))
    for key in ("joint", "target", "reached", "error", "error_percent", "height", "point",
                "distance", "reach_distance", "nearest_sample", "pins", "evaluations"):
        assert key in first, (key, first)
    assert first["joint"] == "Foot_R" and len(first["point"]) == 2 and first["height"] > 0
    assert first["distance"] <= first["reach_distance"] * (1 + 1e-9), first
    again = reach_json("--joint", "Foot_R", "--to=" + vec(first["reached"]), "-o", tmp("b.bvh"))
    assert again["error_percent"] <= 1.0, again


@test
def pins_weigh_in():
    if not needs(*CLIPS):
        return
    csv_path, _ = the_map()
    start = reach_json("--joint", "Hand_L", "--to=20,100,30", "-o", tmp("s.bvh"))
    at = "--from=" + vec(start["point"])
    target = [start["reached"][0] + 25, start["reached"][1] + 20, start["reached"][2] + 10]
    free = reach_json("--joint", "Hand_L", "--to=" + vec(target), at, "-o", tmp("free.bvh"))
    pinned = reach_json("--joint", "Hand_L", "--to=" + vec(target), at, "--pin", "Foot_R",
                        "--pin", "Foot_L", "--pin-weight", "10", "-o", tmp("pinned.bvh"))
    assert [p["joint"] for p in pinned["pins"]] == ["Foot_R", "Foot_L"], pinned
    assert all(p["weight"] == 10 for p in pinned["pins"]), pinned
    # The pins' errors are distances from where the feet were in the --from pose.
    feet = reach_json("--joint", "Hand_L", "--to=" + vec(target), at, "--pin", "Foot_R",
                      "--pin", "Foot_L", "--pin-weight", "0", "-o", tmp("zero.bvh"))
    assert feet["point"] == free["point"], (feet, free)
    assert sum(p["error"] for p in pinned["pins"]) <= sum(p["error"] for p in feet["pins"]), (
        pinned, feet)
    explicit = reach_json("--joint", "Hand_L", "--to=" + vec(target), "--pin",
                          "Head=" + vec(start["reached"]), "-o", tmp("explicit.bvh"))
    assert explicit["pins"][0]["joint"] == "Head", explicit


@test
def a_target_out_of_reach_gives_the_best_valid_point():
    if not needs(*CLIPS):
        return
    r = reach_json("--joint", "Head", "--to=0,100000,0", "-o", tmp("far.bvh"))
    assert r["error_percent"] > 1000, r
    assert r["distance"] <= r["reach_distance"] * (1 + 1e-9), r


@test
def a_saved_map_gives_the_same_answer():
    if not needs(*CLIPS):
        return
    _, h5 = the_map()
    direct = reach_json("--joint", "Hand_R", "--to=-20,110,20", "-o", tmp("d.bvh"))
    code, out, err = run("reach", "--map", h5, "--joint", "Hand_R", "--to=-20,110,20", "--json",
                         "-q", "-o", tmp("s.bvh"))
    assert code == 0, err
    saved = json.loads(out)
    for key in ("point", "error", "reached"):
        assert saved[key] == direct[key], (key, saved, direct)
    with open(tmp("d.bvh"), "rb") as a, open(tmp("s.bvh"), "rb") as b:
        assert a.read() == b.read()


@test
def usage_errors():
    if not needs(*CLIPS):
        return
    csv_path, _ = the_map()
    base = ["reach", *clips(), "--map", csv_path, "-o", tmp("e.bvh")]
    code, _, err = run(*base, "--joint", "LeftHand", "--to=1,2,3")
    assert code == 2 and "no joint named 'LeftHand'" in err and "did you mean Hand_L?" in err, err
    assert "joint_Root, Hips" in err, err
    for to in ("1,2", "1,nan,3", "a,b,c", "1,2,3,4"):
        code, _, err = run(*base, "--joint", "Head", "--to=" + to)
        assert code == 2 and "--to" in err and "x,y,z" in err, (to, err)
    code, _, err = run(*base, "--joint", "Head", "--to=1,2,3", "--pin", "Foot_R")
    assert code == 2 and "--from" in err, err
    code, _, err = run(*base, "--joint", "Head", "--to=1,2,3", "--from=1")
    assert code == 2 and "--from" in err, err
    code, _, err = run("reach", "--joint", "Head", "--to=1,2,3", "-o", tmp("e.bvh"))
    assert code == 2 and "FILE" in err, err


if __name__ == "__main__":
    sys.exit(main())
