#!/usr/bin/env python3
"""End-to-end tests of `motionmap inbetween`: frame counts for --frames-between, --times and @
times, the key frames of the written BVH equal the clips' own frames (pose and root: the same
rows `convert` writes for them), the route CSV (one t,x,y row per frame, the keys' points at their
frames), a frame of a clip not in the map placed on it, the same on a saved map, keys naming a
map's clips by the end of their paths, a note for keys
further apart than the clips walk in the time given or where the root glides (none with
--free-roots), a note for keys timed out of step with their gait, and clear errors for bad keys. The clips are
the Bandai walks and runs in ../shared/data; skips without them.

usage: inbetween_test.py MOTIONMAP_BINARY SHARED_DATA_DIR
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from clirun import data, main, needs, run, test, tmp  # noqa: E402

ANGRY = "bandai/dataset-1_walk_angry_001.bvh"
OLD = "bandai/dataset-1_walk_old_001.bvh"
RUN = "bandai/dataset-1_run_old_001.bvh"
HELD_OUT = "bandai/dataset-1_walk_feminine_001.bvh"
GOLF = "cmu/64_08.bvh"
CLIPS = (ANGRY, OLD, RUN)


def have():
    return needs(*CLIPS, HELD_OUT, GOLF)


def motion_rows(path):
    """The MOTION rows of a BVH file as lists of floats."""
    with open(path) as f:
        lines = f.read().splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("Frame Time")) + 1
    return [[float(v) for v in line.split()] for line in lines[start:] if line.strip()]


def converted(rel):
    """The rows `convert` writes for a clip: the same conversion from rotations as inbetween's."""
    out = tmp(os.path.basename(rel) + ".converted.bvh")
    if not os.path.exists(out):
        code, _, err = run("convert", data(rel), "-o", out)
        assert code == 0, err
    return motion_rows(out)


def close(a, b, tol=1e-4):
    """Rows equal to `tol`, angles modulo 360° (the writer keeps Euler angles continuous from
    frame to frame, so the same rotation may be written 360° apart)."""
    def diff(x, y):
        d = abs(x - y)
        return min(d, abs(d - 360.0 * round(d / 360.0)))
    return len(a) == len(b) and all(diff(x, y) <= tol * max(1.0, abs(y)) for x, y in zip(a, b))


def inbetween(*args):
    return run("inbetween", *[data(c) for c in CLIPS], "--stride", "2", "-q", *args)


def saved_map():
    """The map of CLIPS saved as a map file (made once)."""
    h5 = tmp("lib.mmap.h5")
    if not os.path.exists(h5):
        code, _, err = run("map", *[data(c) for c in CLIPS], "--stride", "2", "--save", h5,
                           "-o", tmp("lib.csv"), "-q")
        assert code == 0, err
    return h5


def route_rows(path):
    with open(path) as f:
        lines = [line for line in f.read().splitlines() if not line.startswith("#")]
    assert lines[0] == "t,x,y", lines[0]
    return [[float(v) for v in line.split(",")] for line in lines[1:]]


@test
def help_describes_keys():
    code, out, _ = run("inbetween", "--help")
    assert code == 0, out
    for word in ("FILE:FRAME", "X:Y", "@SECONDS", "--frames-between", "--times", "--grid",
                 "--route-csv", "lib.mmap.h5"):
        assert word in out, word


@test
def frames_between_hits_the_key_frames():
    if not have():
        return
    out, route = tmp("fb.bvh"), tmp("fb.csv")
    keys = f"{data(ANGRY)}:20,{data(OLD)}:101,{data(RUN)}:40"
    code, _, err = inbetween("--keys", keys, "--frames-between", "15", "-o", out,
                             "--route-csv", route)
    assert code == 0, err
    assert "keys at frames 0, 16, 32" in err, err
    rows = motion_rows(out)
    assert len(rows) == 33, len(rows)
    for frame, (clip, f) in zip((0, 16, 32), ((ANGRY, 20), (OLD, 101), (RUN, 40))):
        assert close(rows[frame], converted(clip)[f]), (frame, clip, f)
    r = route_rows(route)
    assert len(r) == 33
    assert abs(r[16][0] - 16 / 30) < 1e-6, r[16]


@test
def times_and_own_speed():
    if not have():
        return
    out = tmp("times.bvh")
    keys = f"{data(ANGRY)}:20,{data(OLD)}:100"
    code, _, err = inbetween("--keys", keys, "--times", "0,1.5", "-o", out)
    assert code == 0, err
    assert len(motion_rows(out)) == 46, err
    code, _, err = inbetween("--keys", f"{data(ANGRY)}:20@2,{data(OLD)}:100@3", "-o", out)
    assert code == 0, err
    assert len(motion_rows(out)) == 31, err
    code, _, err = inbetween("--keys", keys, "-o", out)
    assert code == 0, err
    rows = motion_rows(out)
    assert len(rows) >= 2 and close(rows[-1], converted(OLD)[100]), err


@test
def keys_too_far_apart_for_their_time_are_noted():
    if not have():
        return
    out = tmp("far.bvh")
    keys = f"{data(ANGRY)}:20,{data(OLD)}:100"
    code, _, err = inbetween("--keys", keys, "--frames-between", "5", "-o", out)
    assert code == 0, err
    note = next((line for line in err.splitlines() if "apart (each where it stood" in line), "")
    assert note.startswith(f"note: key 1 ({data(ANGRY)}:20) to key 2 ({data(OLD)}:100): their "
                           "roots stand"), err
    assert "the feet slide; at the clips' pace it takes" in note, note
    # Untimed, the segment takes at least the clips' time (the frames the note names; keys of two
    # walks, up to a step cycle more, till the later key's gait phase comes round): no note.
    code, _, err = inbetween("--keys", keys, "-o", out)
    assert code == 0, err
    assert "apart (each where it stood" not in err, err
    frames = len(motion_rows(out)) - 2
    noted = int(note.split(" frames between the keys)")[0].rsplit("(", 1)[1])
    assert noted <= frames <= noted + 45, (frames, note)


@test
def a_key_behind_the_other_glides_unless_the_roots_are_free():
    if not have():
        return
    out = tmp("behind.bvh")
    # The old walk's frame 130 to its frame 100, 30 frames later: in time for their distance, but
    # behind: the walk carries the root forward, and it glides back.
    keys = f"{data(OLD)}:130,{data(OLD)}:100"
    code, _, err = inbetween("--keys", keys, "--frames-between", "29", "-o", out)
    assert code == 0, err
    note = next((line for line in err.splitlines() if "glides that in" in line), "")
    assert note.startswith(f"note: key 1 ({data(OLD)}:130) to key 2 ({data(OLD)}:100): the "
                           "clips played carry the root"), err
    assert "(with free roots it stands where the clips carry it)" in note, note
    assert close(motion_rows(out)[-1], converted(OLD)[100]), err
    # --free-roots: key 2's pose still below the hips (the values after the first 12: the static
    # joint_Root's 6 channels and the hips' position and rotation), the hips elsewhere, no glide.
    code, _, err = inbetween("--keys", keys, "--frames-between", "29", "--free-roots", "-o", out)
    assert code == 0, err
    assert "glides" not in err, err
    last, want = motion_rows(out)[-1], converted(OLD)[100]
    assert close(last[12:], want[12:]) and not close(last[6:9], want[6:9]), (last[:12], want[:12])


@test
def keys_timed_out_of_step_with_their_gait_are_noted():
    """The angry walk's frame 20 to the old walk's frame 101, free roots: the old walk's phase
    comes round 0.57 s after the angry walk's, so 5 frames between ask the legs to step about 3
    times as fast: a note says so, with the time in step; timed so, no note."""
    if not have():
        return
    out = tmp("out_of_step.bvh")
    keys = f"{data(ANGRY)}:20,{data(OLD)}:101"
    code, _, err = inbetween("--keys", keys, "--frames-between", "5", "--free-roots", "-o", out)
    assert code == 0, err
    note = next((line for line in err.splitlines() if "out of step" in line), "")
    assert note.startswith(f"note: key 1 ({data(ANGRY)}:20) to key 2 ({data(OLD)}:101): out of "
                           "step, the later key's gait phase comes round "), err
    assert " times as fast as the clips, and the feet slide; in step it takes " in note, note
    in_step = note.split(" frames between the keys)")[0].rsplit("(", 1)[1]
    code, _, err = inbetween("--keys", keys, "--frames-between", in_step, "--free-roots", "-o",
                             out)
    assert code == 0, err
    assert "out of step" not in err, err


@test
def map_point_keys_with_times():
    if not have():
        return
    out, route = tmp("points.bvh"), tmp("points.csv")
    # Two frames' points, read from a first route CSV, then given as X:Y keys.
    code, _, err = inbetween("--keys", f"{data(ANGRY)}:20,{data(OLD)}:100", "--frames-between",
                             "3", "-o", out, "--route-csv", route)
    assert code == 0, err
    r = route_rows(route)
    (_, x0, y0), (_, x1, y1) = r[0], r[-1]
    code, _, err = inbetween(f"--keys={x0!r}:{y0!r}@0,{x1!r}:{y1!r}@0.5", "-o", out,
                             "--route-csv", route)
    assert code == 0, err
    assert len(motion_rows(out)) == 16
    r2 = route_rows(route)
    assert (r2[0][1], r2[0][2]) == (x0, y0) and (r2[-1][1], r2[-1][2]) == (x1, y1)


@test
def a_frame_of_a_clip_not_in_the_map_is_placed_and_hit():
    if not have():
        return
    out = tmp("held.bvh")
    keys = f"{data(ANGRY)}:20,{data(HELD_OUT)}:120,{data(OLD)}:100"
    code, _, err = inbetween("--keys", keys, "--frames-between", "10", "-o", out)
    assert code == 0, err
    assert "is not a sample of the map: placed at" not in err  # -q
    rows = motion_rows(out)
    assert close(rows[11], converted(HELD_OUT)[120])
    code, _, err = run("inbetween", *[data(c) for c in CLIPS], "--stride", "2", "--keys", keys,
                       "--frames-between", "10", "-o", out)
    assert code == 0 and "is not a sample of the map: placed at" in err, err


@test
def on_a_saved_map():
    if not have():
        return
    h5 = saved_map()
    out = tmp("saved.bvh")
    keys = f"{data(ANGRY)}:20,{data(HELD_OUT)}:120,{data(OLD)}:101"
    code, _, err = run("inbetween", "--map", h5, "--keys", keys, "--frames-between", "10",
                       "-o", out)
    assert code == 0, err
    rows = motion_rows(out)
    assert len(rows) == 23
    assert close(rows[0], converted(ANGRY)[20]) and close(rows[11], converted(HELD_OUT)[120])
    assert close(rows[22], converted(OLD)[101])
    # The saved map fixes its clips and features.
    code, _, err = run("inbetween", "--map", h5, data(ANGRY), "--keys", keys, "-o", out)
    assert code == 2 and "give no FILE with --map" in err, err
    code, _, err = run("inbetween", "--map", tmp("lib.csv"), "--keys", keys, "-o", out)
    assert code == 2 and "is not a saved map" in err, err


@test
def keys_name_clips_of_the_map():
    """A key's FILE may be the end of a map clip's path, as a user names the clips given or a
    saved map's: the same motion as their paths give."""
    if not have():
        return
    by_path = tmp("by_path.bvh")
    keys = f"{data(ANGRY)}:20,{data(OLD)}:101"
    code, _, err = inbetween("--keys", keys, "--frames-between", "10", "-o", by_path)
    assert code == 0, err
    by_name = tmp("by_name.bvh")
    code, _, err = inbetween("--keys", "dataset-1_walk_angry_001.bvh:20,"
                             "bandai/dataset-1_walk_old_001.bvh:101", "--frames-between", "10",
                             "-o", by_name)
    assert code == 0, err
    assert motion_rows(by_name) == motion_rows(by_path)
    code, _, err = run("inbetween", "--map", saved_map(), "--keys", "dataset-1_run_old_001.bvh:40,"
                       "dataset-1_walk_old_001.bvh:101", "--frames-between", "10", "-q", "-o",
                       by_name)
    assert code == 0, err
    rows = motion_rows(by_name)
    assert close(rows[0], converted(RUN)[40]) and close(rows[11], converted(OLD)[101])
    # A name of no clip of the map, or of several: usage errors that say which clips there are,
    # or which ones the name is part of.
    code, _, err = inbetween("--keys", "jog_001.bvh:20,dataset-1_walk_old_001.bvh:3",
                             "-o", by_name)
    assert code == 2, err
    assert "no such clip file 'jog_001.bvh', and no clip of the map is named so" in err
    assert "(its 3 clips: dataset-1_walk_angry_001.bvh, dataset-1_walk_old_001.bvh, " in err, err
    code, _, err = inbetween("--keys", "walk_angry_001.bvh:20,dataset-1_walk_old_001.bvh:3",
                             "-o", by_name)
    assert code == 2, err
    assert ("no such clip file 'walk_angry_001.bvh', and no clip of the map is named so; did you "
            "mean dataset-1_walk_angry_001.bvh?") in err, err
    for folder, rel in (("a", ANGRY), ("b", OLD)):
        os.makedirs(tmp(folder), exist_ok=True)
        link = tmp(folder, "walk.bvh")
        if not os.path.exists(link):
            os.symlink(data(rel), link)
    code, _, err = run("inbetween", tmp("a", "walk.bvh"), tmp("b", "walk.bvh"), "--stride", "2",
                       "--keys", "walk.bvh:20,b/walk.bvh:3", "-o", by_name)
    assert code == 2 and "'walk.bvh' names 2 clips of the map" in err, err
    assert "give more of its path" in err, err


@test
def route_grid_and_smoothing_options():
    if not have():
        return
    keys = f"{data(ANGRY)}:20,{data(RUN)}:40"
    for extra in (["--grid", "20"], ["--grid", "40", "--no-smooth"], ["--no-smooth"], []):
        out = tmp("grid.bvh")
        route = ["--route", "grid"] if extra else []
        code, _, err = inbetween("--keys", keys, "--frames-between", "12", "-o", out, *route,
                                 *extra)
        assert code == 0, (extra, err)
        if extra[:1] == ["--grid"]:
            assert f"route grid {extra[1]}×" in err, err
        if not extra:  # the default: through the clips' own frames
            assert "routes through the clips' frames" in err, err
        rows = motion_rows(out)
        assert len(rows) == 14 and close(rows[0], converted(ANGRY)[20])
        assert close(rows[13], converted(RUN)[40])
    code, _, err = inbetween("--keys", keys, "--grid", "1", "-o", tmp("grid.bvh"))
    assert code == 2 and "--grid" in err, err
    code, _, err = inbetween("--keys", keys, "--route", "fast", "-o", tmp("grid.bvh"))
    assert code == 2 and "--route" in err, err


@test
def bad_keys_are_clear_errors():
    if not have():
        return
    out = tmp("bad.bvh")
    code, _, err = inbetween("--keys", f"{data(ANGRY)}:20,{data(ANGRY)}:143", "-o", out)
    assert code == 1, err
    assert f"frame 143 is out of range: {data(ANGRY)} has 143 frames, 0 to 142" in err, err
    code, _, err = inbetween("--keys", f"{data(ANGRY)}:20,{data(GOLF)}:100", "-o", out)
    assert code == 1 and "is a clip of another skeleton than the map's" in err, err
    broken = tmp("broken.bvh")
    with open(broken, "w") as f:
        f.write("HIERARCHY\nROOT Hips\n{\n")
    code, _, err = inbetween("--keys", f"{data(ANGRY)}:20,{broken}:3", "-o", out)
    assert code == 1 and "the clip cannot be loaded" in err and "broken.bvh" in err, err
    code, _, err = inbetween("--keys", f"{data(ANGRY)}:20,nothere.bvh:3", "-o", out)
    assert code == 2 and "no such clip file 'nothere.bvh'" in err, err
    code, _, err = inbetween("--keys", f"{data(ANGRY)}:x", "-o", out)
    assert code == 2 and "not a frame number" in err, err
    # A negative frame of a clip named by the end of its path: the frame is what is wrong.
    code, _, err = inbetween("--keys", f"{data(ANGRY)}:20,{os.path.basename(ANGRY)}:-3", "-o", out)
    assert code == 2 and "'-3' is not a frame number" in err, err
    code, _, err = inbetween("--keys", f"{data(ANGRY)}:20", "-o", out)
    assert code == 2 and "at least 2 keys" in err, err
    code, _, err = inbetween("--keys", f"{data(ANGRY)}:20@x,{data(OLD)}:3", "-o", out)
    assert code == 2 and "not a finite number of seconds" in err, err
    code, _, err = inbetween("--keys", f"{data(ANGRY)}:20,{data(OLD)}:3", "--times", "0", "-o",
                             out)
    assert code == 2 and "1 times for 2 keys" in err, err
    code, _, err = inbetween("--keys", f"{data(ANGRY)}:20,{data(OLD)}:3", "--times", "0,1",
                             "--frames-between", "3", "-o", out)
    assert code == 2, err
    code, _, err = inbetween("--keys", f"{data(ANGRY)}:20@0,{data(OLD)}:3", "-o", out)
    assert code == 1 and "give a time to every key or to none" in err, err


if __name__ == "__main__":
    sys.exit(main())
