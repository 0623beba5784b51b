#!/usr/bin/env python3
"""End-to-end tests of `motionmap pose/synth --map lib.mmap.h5`: blending on a saved map equals
blending on the same clips mapped directly (the BVH written is the same, byte for byte, for every
blend mode, with and without smoothing, though the saved map's clips are read on demand), a saved map fixes its clips and options (giving them is a usage error), and a clip
file changed or removed since the map was made is an error naming the file and what was expected.
The clips are the real ones in ../shared/data; map files are made in a temporary folder (a clip is
copied there only to be changed). Skips, with a message, when a clip is absent.

usage: saved_map_synthesis_test.py MOTIONMAP_BINARY SHARED_DATA_DIR
"""
import csv
import os
import shutil
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from clirun import DATA, main, run, test, tmp  # noqa: E402

GOLF = os.path.join(DATA, "cmu/64_08.bvh")
GOLF2 = os.path.join(DATA, "cmu/64_09.bvh")


def read(path):
    with open(path, "rb") as f:
        return f.read()


def map_rows(csv_path):
    with open(csv_path) as f:
        rows = [r for r in csv.reader(line for line in f if not line.startswith("#"))]
    header, body = rows[0], rows[1:]
    ix, iy = header.index("x"), header.index("y")
    return [(float(r[ix]), float(r[iy])) for r in body]


def have_clips():
    for p in (GOLF, GOLF2):
        if not os.path.exists(p):
            print(f"  skipped: {p} absent")
            return False
    return True


def save_map(name, *clips, method="isomap"):
    h5, csv_path = tmp(name + ".mmap.h5"), tmp(name + ".csv")
    code, _, err = run("map", *clips, "--method", method, "--save", h5, "-o", csv_path, "-q")
    assert code == 0, err
    return h5, csv_path


@test
def help_names_saved_maps():
    for command in ("pose", "synth"):
        code, out, _ = run(command, "--help")
        assert code == 0 and "lib.mmap.h5" in out and "SHA-256" in out, out


@test
def pose_on_a_saved_map_equals_pose_on_the_clips():
    if not have_clips():
        return
    h5, csv_path = save_map("two", GOLF, GOLF2)
    xy = map_rows(csv_path)
    points = [xy[10], xy[400], ((xy[100][0] + xy[101][0]) / 2, (xy[100][1] + xy[101][1]) / 2),
              (xy[50][0] + 1e3, xy[50][1])]  # the last far outside: clamped in both
    for blend in ("local", "idw"):
        for i, (x, y) in enumerate(points):
            at = f"--at={x!r},{y!r}"
            direct, saved = tmp(f"direct-{blend}-{i}.bvh"), tmp(f"saved-{blend}-{i}.bvh")
            c1, _, e1 = run("pose", GOLF, GOLF2, "--method", "isomap", "--map", csv_path, at,
                            "--blend", blend, "-o", direct)
            c2, _, e2 = run("pose", "--map", h5, at, "--blend", blend, "-o", saved)
            assert c1 == 0 and c2 == 0, (e1, e2)
            assert read(direct) == read(saved), (blend, i)
            # The same report (samples blended, nearest sample, clamping) on both paths.
            def report(err, out):
                return [line.replace(out, "OUT") for line in err.splitlines()
                        if "bind pose" not in line]
            assert report(e1, direct) == report(e2, saved), (e1, e2)


@test
def synth_on_a_saved_map_equals_synth_on_the_clips():
    if not have_clips():
        return
    h5, csv_path = save_map("two-mds", GOLF, GOLF2, method="mds")
    xy = map_rows(csv_path)
    path = tmp("path.csv")
    with open(path, "w") as f:
        f.write("t,x,y\n")
        for k, row in enumerate(range(30, 200, 10)):
            f.write(f"{k * 0.1!r},{xy[row][0]!r},{xy[row][1]!r}\n")
    direct, saved = tmp("direct.bvh"), tmp("saved.bvh")
    c1, _, e1 = run("synth", GOLF, GOLF2, "--method", "mds", "--map", csv_path, "--path", path,
                    "-o", direct)
    c2, _, e2 = run("synth", "--map", h5, "--path", path, "-o", saved)
    assert c1 == 0 and c2 == 0, (e1, e2)
    assert read(direct) == read(saved)
    assert read(saved).startswith(b"HIERARCHY")


@test
def synth_on_demand_equals_synth_on_the_clips_for_every_blend():
    if not have_clips():
        return
    h5, csv_path = save_map("two-pca", GOLF, GOLF2, method="pca")
    xy = map_rows(csv_path)
    timed, untimed = tmp("timed.csv"), tmp("untimed.csv")
    with open(timed, "w") as f, open(untimed, "w") as g:
        f.write("t,x,y\n")
        for k, row in enumerate(range(400, 700, 15)):
            f.write(f"{k * 0.08!r},{xy[row][0]!r},{xy[row][1]!r}\n")
            g.write(f"{xy[row][0]!r},{xy[row][1]!r}\n")
    for blend in ("local", "idw", "kriging"):
        for path, extra in ((timed, []), (timed, ["--smooth", "0.05"]), (untimed, [])):
            direct, saved = tmp(f"d-{blend}.bvh"), tmp(f"s-{blend}.bvh")
            c1, _, e1 = run("synth", GOLF, GOLF2, "--method", "pca", "--map", csv_path, "--path",
                            path, "--blend", blend, *extra, "-o", direct)
            c2, _, e2 = run("synth", "--map", h5, "--path", path, "--blend", blend, *extra,
                            "-o", saved)
            assert c1 == 0 and c2 == 0, (e1, e2)
            if blend == "local" and path == untimed:
                # Played at the map's median speed, this path cuts across the swing's arcs, far
                # from the samples: those frames play a route through the clips' frames, whose
                # jumps are priced by their poses on the clips and by the map distance alone on a
                # saved map (docs/synthesis.md). The same frames, another route.
                assert read(direct).count(b"\n") == read(saved).count(b"\n"), (blend, path)
                continue
            assert read(direct) == read(saved), (blend, path, extra)
        x, y = xy[555]
        c1, _, e1 = run("pose", GOLF, GOLF2, "--method", "pca", "--map", csv_path,
                        f"--at={x + 1e-4!r},{y!r}", "--blend", blend, "-o", tmp("dp.bvh"))
        c2, _, e2 = run("pose", "--map", h5, f"--at={x + 1e-4!r},{y!r}", "--blend", blend,
                        "-o", tmp("sp.bvh"))
        assert c1 == 0 and c2 == 0, (e1, e2)
        assert read(tmp("dp.bvh")) == read(tmp("sp.bvh")), blend


@test
def a_saved_map_fixes_its_clips_and_options():
    if not have_clips():
        return
    h5, _ = save_map("one", GOLF)
    for extra in ([GOLF], ["--method", "pca"], ["-k", "5"], ["--features", "positions"],
                  ["--frames", "0:10"]):
        code, _, err = run("pose", "--map", h5, "--at=0,0", "-o", tmp("x.bvh"), *extra)
        assert code == 2 and "fixes its clips" in err, (extra, code, err)
    # Neither clips nor a map file: a usage error saying what to give.
    code, _, err = run("pose", "--at=0,0", "-o", tmp("x.bvh"))
    assert code == 2 and "give the clips" in err, err


@test
def a_changed_or_missing_clip_is_a_clear_error():
    if not have_clips():
        return
    copy = tmp("golf-copy.bvh")
    shutil.copyfile(GOLF, copy)
    h5, _ = save_map("copy", copy)
    with open(copy, "ab") as f:
        f.write(b"\n")
    code, out, err = run("pose", "--map", h5, "--at=0,0", "-o", tmp("x.bvh"))
    assert code == 1 and out == "", (code, err)
    assert h5 in err and copy in err and "has changed since the map was made" in err, err
    assert not os.path.exists(tmp("x.bvh"))
    os.remove(copy)
    code, _, err = run("synth", "--map", h5, "--path", tmp("path.csv"), "-o", tmp("y.bvh"))
    assert code in (1, 2) and (("is missing" in err and copy in err) or "path.csv" in err), err
    with open(tmp("p2.csv"), "w") as f:
        f.write("x,y\n0,0\n1,1\n")
    code, _, err = run("synth", "--map", h5, "--path", tmp("p2.csv"), "-o", tmp("y.bvh"))
    assert code == 1 and "is missing" in err and copy in err, err


if __name__ == "__main__":
    sys.exit(main())
