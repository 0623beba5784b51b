#!/usr/bin/env python3
"""End-to-end tests of libraries of clips in the `motionmap` tool: folders (--recursive), @list
files, clips of different skeletons (--joints common), clips that fail to load (--keep-going),
the loading progress line, and pca/svd maps read a clip at a time (--stream). The clips are the real ones in ../shared/data, linked (never
copied) into temporary folders; the tests skip, with a message, when a file is absent.

usage: library_test.py MOTIONMAP_BINARY SHARED_DATA_DIR
"""
import os
import pty
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from clirun import BIN, TMP, data, main, needs, read_map, run, test, tmp  # noqa: E402

GOLF = "cmu/64_08.bvh"
GOLF2 = "cmu/64_09.bvh"
RUN = "cmu/02_03.bvh"
OTHER = "other/omimo_AV_8Walk_Meredith_HVHA_Rep1.bvh"  # 23 joints, 19 of them named as CMU's

# A valid two-joint clip and the same with a letter where line 20, column 1 needs a number.
TINY_BVH = """HIERARCHY
ROOT Hips
{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT Spine
  {
    OFFSET 0 10 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    End Site
    {
      OFFSET 0 5 0
    }
  }
}
MOTION
Frames: 3
Frame Time: 0.0333333
0 90 0 0 0 0 0 0 0
1 90 0 0 5 0 0 10 0
2 90 0 0 10 0 0 20 0
"""
BROKEN_BVH = TINY_BVH.replace("1 90 0 0 5", "x 90 0 0 5")


def folder(name, links=(), files=()):
    """A fresh folder under TMP with `links` (relative path, shared data file) as symbolic links
    and `files` (relative path, text) written; returns its path."""
    root = tmp(name)
    for rel, target in links:
        os.makedirs(os.path.dirname(os.path.join(root, rel)), exist_ok=True)
        os.symlink(data(target), os.path.join(root, rel))
    for rel, text in files:
        os.makedirs(os.path.dirname(os.path.join(root, rel)), exist_ok=True)
        with open(os.path.join(root, rel), "w") as f:
            f.write(text)
    os.makedirs(root, exist_ok=True)
    return root


def files_of(comments):
    """The files= list of the CSV's parameter line."""
    first = comments[0]
    return first[first.index(" files=") + len(" files="):].split(",")


def clip_counts(rows):
    counts = {}
    for r in rows:
        counts[int(r[0])] = counts.get(int(r[0]), 0) + 1
    return counts


@test
def help_describes_folders_lists_and_the_new_options():
    for cmd in ("map", "figure", "pose", "synth"):
        code, out, _ = run(cmd, "--help")
        assert code == 0, cmd
        flat = " ".join(out.split())
        for word in ("@LIST", "--recursive", "--keep-going", "--joints", "subfolders only with"):
            assert word in flat, (cmd, word)


@test
def a_folder_maps_its_clips_in_sorted_order():
    if not needs(GOLF, GOLF2, RUN):
        return
    out = tmp("cmu.csv")
    code, _, err = run("map", data("cmu"), "--method", "pca", "-q", "-o", out)
    assert code == 0, err
    comments, header, rows = read_map(out)
    assert header == ["clip", "frame", "x", "y"], header
    # SUBJECT64.txt is not a clip; the T-pose frame of each is left out
    assert files_of(comments) == ["02_03.bvh", "64_08.bvh", "64_09.bvh"], comments[0]
    assert clip_counts(rows) == {0: 173, 1: 364, 2: 452}, clip_counts(rows)
    # the same folder given with a trailing slash, twice: the same map, byte for byte
    again = tmp("cmu-again.csv")
    code, _, err = run("map", data("cmu") + "/", "--method", "pca", "-q", "-o", again)
    assert code == 0, err
    with open(out, "rb") as a, open(again, "rb") as b:
        assert a.read() == b.read()


@test
def asf_files_in_a_folder_are_skeletons_not_clips():
    if not needs("asfamc/02.asf", "asfamc/02_02.amc", "asfamc/02_03.amc"):
        return
    out = tmp("asfamc.csv")
    code, _, err = run("map", data("asfamc"), "--method", "pca", "-q", "-o", out)
    assert code == 0, err
    comments, _, rows = read_map(out)
    assert files_of(comments) == ["02_02.amc", "02_03.amc"], comments[0]
    assert set(clip_counts(rows)) == {0, 1}


@test
def subfolders_only_with_recursive():
    if not needs(GOLF, GOLF2):
        return
    root = folder("tree", links=[("b/c/64_09.bvh", GOLF2), ("a/64_08.bvh", GOLF)],
                  files=[("readme.txt", "not a clip\n"), (".hidden/skip.bvh", BROKEN_BVH)])
    out = tmp("tree.csv")
    code, _, err = run("map", root, "--method", "pca", "-q", "-o", out)
    assert code == 1, (code, err)
    assert root + ": error: no clip (.bvh or .amc file) in this folder" in err, err
    assert "--recursive" in err, err
    code, _, err = run("map", root, "--recursive", "--method", "pca", "-q", "-o", out)
    assert code == 0, err
    comments, _, rows = read_map(out)
    assert files_of(comments) == ["64_08.bvh", "64_09.bvh"], comments[0]  # a/ before b/c/
    assert clip_counts(rows) == {0: 364, 1: 452}


@test
def list_files_with_comments_blank_lines_and_relative_paths():
    if not needs(GOLF, GOLF2):
        return
    lists = folder("lists")
    list_path = os.path.join(lists, "takes.txt")
    relative = os.path.relpath(data(GOLF2), lists)
    with open(list_path, "w") as f:
        f.write("# golf swings\n\n" + relative + "\n   \n  " + data(GOLF) + "  \n")
    out = tmp("list.csv")
    code, _, err = run("map", "@" + list_path, "--method", "pca", "-q", "-o", out)
    assert code == 0, err
    comments, _, rows = read_map(out)
    assert files_of(comments) == ["64_09.bvh", "64_08.bvh"], comments[0]  # the list's order
    assert clip_counts(rows) == {0: 452, 1: 364}

    # A list named by a relative path: its entries are relative to the list, not to the caller.
    p = subprocess.run([BIN, "map", "@lists/takes.txt", "--method", "pca", "-q", "-o", out],
                       capture_output=True, text=True, cwd=TMP, timeout=300)
    assert p.returncode == 0, p.stderr
    assert files_of(read_map(out)[0]) == ["64_09.bvh", "64_08.bvh"]

    missing = os.path.join(lists, "missing.txt")
    with open(missing, "w") as f:
        f.write("# first line\n" + relative + "\n\n  nope/missing.bvh\n")
    code, stdout, err = run("map", "@" + missing, "-q", "-o", out)
    assert code == 1, (code, err)
    assert missing + ":4:3: error: no such file or folder: 'nope/missing.bvh'" in err, err
    assert stdout == ""

    empty = os.path.join(lists, "empty.txt")
    with open(empty, "w") as f:
        f.write("# nothing yet\n\n")
    code, _, err = run("map", "@" + empty, "-q", "-o", out)
    assert code == 1 and empty + ": error: the list names no clip" in err, (code, err)

    code, _, err = run("map", "@" + os.path.join(lists, "absent.txt"), "-q", "-o", out)
    assert code == 2 and "absent.txt" in err, (code, err)  # a usage error, like a missing file


@test
def different_skeletons_are_an_error_naming_the_clip_and_offering_common_joints():
    if not needs(GOLF, OTHER):
        return
    code, stdout, err = run("map", data(GOLF), data(OTHER), "-q", "-o", tmp("mixed.csv"))
    assert code == 1, (code, err)
    assert data(OTHER) + ": its joint hierarchy differs from " + data(GOLF) + "'s" in err, err
    assert "it has 23 joints, 64_08.bvh 31" in err, err
    assert "'Spine' (parent 'Hips') where 64_08.bvh has 'LHipJoint' (parent 'Hips')" in err, err
    assert "--joints common" in err, err
    assert stdout == ""


@test
def common_joints_map_clips_of_different_skeletons():
    if not needs(GOLF, OTHER):
        return
    out = tmp("common.csv")
    code, _, err = run("map", data(GOLF), data(OTHER), "--joints", "common", "-q", "-o", out)
    assert code == 0, err
    kept = "note: joints common: 19 joints shared by the 2 clips are kept (18 in X, the root " \
           "Hips only in the point cloud, 3 End Sites)"
    assert kept in err, err
    assert "dropped: LHipJoint, RHipJoint, LowerBack" in err, err
    assert "6 kept joints have another parent in some clip" in err, err
    comments, _, rows = read_map(out)
    assert " joints=common" in comments[0], comments[0]
    assert any("joints common: 19 joints shared by the 2 clips are kept" in c
               for c in comments), comments
    assert clip_counts(rows) == {0: 364, 1: 1064}, clip_counts(rows)
    code, _, err = run("map", data(GOLF), "--joints", "some", "-q", "-o", out)
    assert code == 2 and "some" in err, (code, err)
    # A blended pose has one skeleton: pose and synth say so before computing the map.
    code, _, err = run("pose", data(GOLF), data(OTHER), "--joints", "common", "--at=0,0", "-q",
                       "-o", tmp("mixed-pose.bvh"))
    assert code == 1, (code, err)
    assert data(OTHER) + ": its joint hierarchy differs" in err and "cannot blend" in err, err


def map_skipping_the_broken_clip(root, broken, out, *options):
    """`map root --keep-going` with 64_08.bvh and the broken clip `broken` in `root`: the error
    and a note on stderr, and the map of 64_08 alone in `out`."""
    code, _, err = run("map", root, *options, "--keep-going", "-q", "-o", out)
    assert code == 0, err
    assert broken + ":20:1: error: expected a number" in err, err
    assert "note: skipped 1 of 2 clips that failed to load (--keep-going)" in err, err
    comments, header, rows = read_map(out)
    assert files_of(comments) == ["64_08.bvh"] and header == ["frame", "x", "y"], comments
    assert len(rows) == 364


@test
def keep_going_skips_a_broken_clip_and_without_it_the_error_stops_the_map():
    if not needs(GOLF):
        return
    root = folder("broken", links=[("64_08.bvh", GOLF)], files=[("a-broken.bvh", BROKEN_BVH)])
    broken = os.path.join(root, "a-broken.bvh")
    out = tmp("broken.csv")
    code, stdout, err = run("map", root, "-q", "-o", out)
    assert code == 1, (code, err)
    assert broken + ":20:1: error: expected a number" in err, err
    assert stdout == ""

    map_skipping_the_broken_clip(root, broken, out, "--method", "pca")

    # Every clip failing is an error with --keep-going too.
    only_broken = folder("only-broken", files=[("x.bvh", BROKEN_BVH), ("y.bvh", "HIERARCHY\n")])
    for streamed in ([], ["--stream", "--method", "pca"]):
        code, _, err = run("map", only_broken, "--keep-going", "-q", "-o", out, *streamed)
        assert code == 1, (streamed, code, err)
        assert "no clip could be loaded (2 of 2 failed)" in err, (streamed, err)
        assert os.path.join(only_broken, "x.bvh") + ":20:1: error:" in err, (streamed, err)


@test
def figure_pose_and_synth_take_folders_and_lists_too():
    if not needs(GOLF, GOLF2):
        return
    root = folder("swings", links=[("1.bvh", GOLF), ("2.bvh", GOLF2)])
    list_path = os.path.join(root, "one.txt")
    with open(list_path, "w") as f:
        f.write("1.bvh\n")
    png = tmp("swings.png")
    code, out, err = run("figure", root, "--stride", "4", "-q", "-o", png)
    assert code == 0, err
    with open(png, "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"
    pose = tmp("pose.bvh")
    code, _, err = run("pose", "@" + list_path, "--at=0,0", "-q", "-o", pose)
    assert code == 0, err
    assert "1.bvh frame" in err or os.path.exists(pose), err
    path_csv = tmp("path.csv")
    with open(path_csv, "w") as f:
        f.write("0,0\n1,0.5\n")
    code, _, err = run("synth", root, "--path", path_csv, "--stride", "4", "-q", "-o",
                       tmp("synth.bvh"))
    assert code == 0, err
    # a map written from the folder belongs to the same folder given to pose --map
    csv = tmp("swings.csv")
    code, _, err = run("map", root, "--method", "pca", "-q", "-o", csv)
    assert code == 0, err
    code, _, err = run("pose", root, "--map", csv, "--at=0,0", "-q", "-o", pose)
    assert code == 0, err


@test
def loading_progress_counts_clips_and_frames_on_a_terminal():
    if not needs(GOLF, GOLF2, RUN):
        return
    master, slave = pty.openpty()
    p = subprocess.Popen([BIN, "map", data("cmu"), "--method", "pca", "-o", tmp("tty.csv")],
                         stdout=subprocess.DEVNULL, stderr=slave)
    os.close(slave)
    chunks = []
    while True:
        try:
            chunk = os.read(master, 4096)
        except OSError:  # EIO: the other end closed
            break
        if not chunk:
            break
        chunks.append(chunk)
    os.close(master)
    assert p.wait(timeout=300) == 0
    text = b"".join(chunks).decode("utf-8", "replace")
    # 02_03.bvh has 174 frames, 64_08.bvh 365, 64_09.bvh 453 (T-poses included: all are loaded)
    assert "loading 1/3 clips (0 frames)" in text, text
    # Clips load a clip per thread: which lines come between depends on the timing, but the
    # clips started and the frames loaded only grow.
    line = r"loading (\d)/3 clips \((\d+) frames\)"
    steps = [(int(k), int(f)) for k, f in re.findall(line, text)]
    assert steps == sorted(steps) and all(1 <= k <= 3 for k, _ in steps), text
    assert "loaded 3 clips (992 frames)" in text, text


def same_map_within(a_csv, b_csv, tolerance=1e-10):
    """Asserts two map CSVs have the same comment lines, header and clip/frame columns, and
    coordinates within `tolerance` of the map's extent (Procrustes disparity too), each axis
    with the same sign."""
    import numpy as np

    ca, ha, ra = read_map(a_csv)
    cb, hb, rb = read_map(b_csv)
    assert ca == cb, (ca, cb)
    assert ha == hb, (ha, hb)
    dims = sum(1 for h in ha if h in ("x", "y", "z"))
    assert [r[:-dims] for r in ra] == [r[:-dims] for r in rb]
    a = np.array([[float(v) for v in r[-dims:]] for r in ra])
    b = np.array([[float(v) for v in r[-dims:]] for r in rb])
    extent = np.abs(a).max()
    assert np.abs(a - b).max() <= tolerance * extent, np.abs(a - b).max() / extent
    a0, b0 = a - a.mean(0), b - b.mean(0)
    a0, b0 = a0 / np.linalg.norm(a0), b0 / np.linalg.norm(b0)
    u, s, vt = np.linalg.svd(b0.T @ a0)
    disparity = ((a0 - s.sum() * b0 @ (u @ vt)) ** 2).sum()
    assert disparity <= tolerance, disparity
    assert ((a * b).sum(0) > 0).all(), "an axis flipped"


@test
def stream_gives_the_in_memory_pca_and_svd_maps():
    if not needs(GOLF, GOLF2, RUN):
        return
    code, out, _ = run("map", "--help")
    assert code == 0 and "--stream" in out, out
    for i, (method, extra) in enumerate((("pca", []), ("svd", []),
                                         ("pca", ["--standardize", "--dims", "3"]))):
        whole, streamed = tmp("whole-%d.csv" % i), tmp("streamed-%d.csv" % i)
        code, _, err_whole = run("map", data("cmu"), "-m", method, *extra, "-q", "-o", whole)
        assert code == 0, err_whole
        code, _, err = run("map", data("cmu"), "-m", method, *extra, "--stream", "-q",
                           "-o", streamed)
        assert code == 0, err
        assert err == err_whole, (err, err_whole)  # the same notes and warnings on stderr
        same_map_within(whole, streamed)

    # A clip per thread, merged in clip order: the same bytes on one thread.
    one_thread = tmp("streamed-one-thread.csv")
    code, _, err = run("map", data("cmu"), "-m", "pca", "--stream", "-q", "-o", one_thread,
                       env=dict(os.environ, MOTIONMAP_THREADS="1"))
    assert code == 0, err
    with open(tmp("streamed-0.csv"), "rb") as a, open(one_thread, "rb") as b:
        assert a.read() == b.read()

    # A streamed map saved as a map file places new frames as the in-memory one's does.
    for mode in ("whole", "streamed"):
        flags = ["--stream"] if mode == "streamed" else []
        code, _, err = run("map", data(GOLF), data(GOLF2), "-m", "pca", *flags, "-q",
                           "--save", tmp(mode + ".mmap.h5"), "-o", tmp(mode + "-saved.csv"))
        assert code == 0, err
        code, _, err = run("map", data(RUN), "--onto", tmp(mode + ".mmap.h5"), "-q",
                           "-o", tmp(mode + "-placed.csv"))
        assert code == 0, err
    same_map_within(tmp("whole-saved.csv"), tmp("streamed-saved.csv"))
    # The placed frames (the CSVs' notes name the two map files).
    _, _, ra = read_map(tmp("whole-placed.csv"))
    _, _, rb = read_map(tmp("streamed-placed.csv"))
    assert len(ra) == len(rb) == 173
    assert max(abs(float(x) - float(y)) for p, q in zip(ra, rb) for x, y in zip(p, q)) < 1e-9


@test
def stream_skips_broken_clips_with_keep_going_and_refuses_what_it_cannot_stream():
    if not needs(GOLF):
        return
    root = folder("broken-stream", links=[("64_08.bvh", GOLF)],
                  files=[("a-broken.bvh", BROKEN_BVH)])
    broken = os.path.join(root, "a-broken.bvh")
    out = tmp("broken-stream.csv")
    code, _, err = run("map", root, "-m", "pca", "--stream", "-q", "-o", out)
    assert code == 1, (code, err)
    assert broken + ":20:1: error: expected a number" in err, err
    map_skipping_the_broken_clip(root, broken, out, "-m", "pca", "--stream")

    # Usage errors (exit 2) saying why.
    for args, why in ((["-m", "isomap"], "only pca and svd"),
                      (["-m", "pca", "--metrics"], "no metrics"),
                      (["-m", "pca", "--joints", "common"], "--joints common")):
        code, _, err = run("map", data(GOLF), *args, "--stream", "-q", "-o", out)
        assert code == 2 and "--stream" in err and why in err, (args, code, err)
    code, _, err = run("map", data(GOLF), "--onto", tmp("whole.mmap.h5"), "--stream", "-q")
    assert code == 2, (code, err)


if __name__ == "__main__":
    sys.exit(main())
