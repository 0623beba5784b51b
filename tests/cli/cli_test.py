#!/usr/bin/env python3
"""End-to-end tests of the `motionmap` command-line tool: exit codes (0 ok, 1 runtime error,
2 usage error), errors on stderr, --help everywhere, --json, and the commands on real files.

usage: cli_test.py MOTIONMAP_BINARY SHARED_DATA_DIR
"""
import json
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "reference"))
import mocap  # noqa: E402  (independent numpy BVH reader)

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from clirun import DATA, TMP, data, main, needs, run, test  # noqa: E402


def have(rel):
    return os.path.exists(data(rel))


def write(name, text):
    path = os.path.join(TMP, name)
    with open(path, "w", newline="") as f:
        f.write(text)
    return path


@test
def help_everywhere_exits_zero():
    for cmd in ([], ["info"], ["convert"], ["sample"], ["map"], ["figure"], ["pose"], ["synth"]):
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


SEEDS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "fuzz", "seeds", "bvh")


@test
def info_shows_tolerated_bvh_quirks_as_warnings_and_truncation_as_an_error():
    # The tiny files of tests/io/bvh_test.cpp: a root declared with JOINT, a leaf JOINT with
    # CHANNELS 0 (read as an End Site), a file cut inside a joint.
    joint_root = os.path.join(SEEDS, "joint_root.bvh")
    code, out, err = run("info", joint_root)
    assert code == 0, err
    assert joint_root + ":2:1: warning: root declared with JOINT instead of ROOT; read as ROOT" in out, out
    leaf = os.path.join(SEEDS, "channels_zero_leaf.bvh")
    code, out, err = run("info", "--json", leaf)
    assert code == 0, err
    info = json.loads(out)
    assert info["joints"] == 4 and info["end_sites"] == 2 and info["channels"] == 5, info
    assert info["warnings"] == [leaf + ":10:5: warning: joint 'HeadTop' has CHANNELS 0 and no "
                                "children; read as an end site"], info
    cut = os.path.join(SEEDS, "ends_in_hierarchy.bvh")
    code, out, err = run("info", cut)
    assert code == 1 and out == "", (code, out)
    assert cut + ":10:1: error: file ends early: expected '}' closing joint 'LeftArm'" in err, err


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


GOLF = "cmu/64_08.bvh"


def read_map(path):
    """(comment lines, header, values as a numpy array) of a map CSV."""
    with open(path) as f:
        lines = f.read().splitlines()
    comments = [l for l in lines if l.startswith("#")]
    rows = [l for l in lines if not l.startswith("#")]
    header = rows[0].split(",")
    values = np.array([[float(v) for v in r.split(",")] for r in rows[1:]])
    return comments, header, values


@test
def map_writes_csv_with_parameters_and_is_deterministic():
    if not needs(GOLF):
        return
    a, b = os.path.join(TMP, "a.csv"), os.path.join(TMP, "b.csv")
    for out in (a, b):
        code, _, err = run("map", data(GOLF), "--method", "le", "-o", out, "-q")
        assert code == 0, err
    assert "bind pose" in err and "heat" in err, err
    with open(a, "rb") as fa, open(b, "rb") as fb:
        assert fa.read() == fb.read(), "same input, different CSV"
    comments, header, values = read_map(a)
    assert comments[0].startswith("# motionmap map method=le") and "k=20" in comments[0], comments
    assert "heat=" in comments[0] and "files=64_08.bvh" in comments[0], comments
    assert any("bind pose" in c for c in comments), comments
    assert header == ["frame", "x", "y"], header
    assert values.shape == (364, 3) and values[0, 0] == 1 and values[-1, 0] == 364, values.shape
    # LE's coordinates satisfy y'·Deg·y = 1, so they are not all tiny or huge
    assert np.all(np.isfinite(values)) and 0 < np.abs(values[:, 1:]).max() < 1e3


@test
def maps_do_not_depend_on_the_number_of_threads():
    # MOTIONMAP_THREADS sizes the thread pool: 1 (the caller alone), 2, and more threads than
    # cores must give byte-identical maps for every method, metrics included.
    if not needs(GOLF):
        return
    for method in ("pca", "svd", "mds", "isomap", "le", "lle", "umap"):
        outputs = []
        for threads in ("1", "2", "7"):
            out = os.path.join(TMP, "threads-%s-%s.csv" % (method, threads))
            env = dict(os.environ, MOTIONMAP_THREADS=threads)
            code, _, err = run("map", data(GOLF), "--method", method, "--metrics", "-o", out,
                               "-q", env=env)
            assert code == 0, err
            with open(out, "rb") as f:
                outputs.append(f.read())
        assert outputs[0] == outputs[1] == outputs[2], method + ": maps differ between thread counts"


@test
def landmarks_exact_and_verbose_choose_and_report_the_path():
    # --landmarks forces the points path (landmark MDS/Isomap, sparse graphs), --exact the dense
    # one; both are the same map to rounding when every frame is a landmark. The points path is
    # byte-identical between thread counts too (HNSW is built on one thread), and --verbose
    # prints a line per stage with its time and the peak memory.
    if not needs(GOLF):
        return
    for method in ("mds", "isomap", "le", "lle"):
        dense, full = os.path.join(TMP, "dense.csv"), os.path.join(TMP, "full.csv")
        code, _, err = run("map", data(GOLF), "-m", method, "--exact", "-o", dense, "-q")
        assert code == 0, err
        code, _, err = run("map", data(GOLF), "-m", method, "--landmarks", "5000", "-o", full,
                           "-q", "--verbose")
        assert code == 0, err
        stages = re.findall(r"^verbose: ([^:]+): [0-9.]+ s, peak [0-9]+ MiB$", err, re.M)
        assert "features" in stages and "total" in stages, err
        if method in ("mds", "isomap"):
            assert "landmarks" in stages and "triangulation" in stages, stages
        else:
            assert "neighbours" in stages and "eigen" in stages, stages
        c_dense, _, v_dense = read_map(dense)
        c_full, _, v_full = read_map(full)
        if method in ("mds", "isomap"):
            assert "landmarks=364" in c_full[0] and "landmarks" not in c_dense[0], c_full[0]
        a = v_dense[:, 1:] - v_dense[:, 1:].mean(0)
        b = v_full[:, 1:] - v_full[:, 1:].mean(0)
        u, _, vt = np.linalg.svd(b.T @ a)
        assert np.abs(b @ (u @ vt) - a).max() <= 1e-6 * np.abs(a).max(), method
    for method in ("mds", "le", "umap"):
        outputs = []
        for threads in ("1", "2"):
            out = os.path.join(TMP, "lm-%s-%s.csv" % (method, threads))
            env = dict(os.environ, MOTIONMAP_THREADS=threads)
            code, _, err = run("map", data(GOLF), "-m", method, "--landmarks", "40", "-o", out,
                               "-q", "--metrics", env=env)
            assert code == 0, err
            with open(out, "rb") as f:
                outputs.append(f.read())
        assert outputs[0] == outputs[1], method + ": points-path maps differ between thread counts"
    code, _, err = run("map", data(GOLF), "--exact", "--landmarks", "3")
    assert code == 2 and "excludes" in err, err
    code, _, err = run("map", data(GOLF), "-m", "mds", "--landmarks", "2", "-q")
    assert code == 1 and "landmarks = 2 is out of range" in err, err


@test
def map_options_frames_stride_dims_several_files_metrics_plot():
    if not (needs(GOLF) and needs("cmu/64_09.bvh")):
        return
    out, png = os.path.join(TMP, "two.csv"), os.path.join(TMP, "two.png")
    code, stdout, err = run("map", data(GOLF), data("cmu/64_09.bvh"), "--method", "isomap",
                            "--frames", "10:210", "--stride", "2", "--dims", "3", "--metrics", "--axes", "fill",
                            "-o", out, "--plot", png)
    assert code == 0, err
    comments, header, values = read_map(out)
    assert header == ["clip", "frame", "x", "y", "z"], header
    assert values.shape == (200, 5), values.shape
    assert set(values[:, 0]) == {0, 1} and values[0, 1] == 10 and values[1, 1] == 12, values[:3]
    assert any(c.startswith("# metrics trustworthiness=") for c in comments), comments
    assert "trustworthiness" in stdout and "continuity" in stdout, stdout
    with open(png, "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"


@test
def map_errors_name_the_problem():
    if not needs(GOLF):
        return
    cases = [
        (["--frames", "10-20"], "--frames", 1),
        (["--frames", "a:20"], "--frames", 1),
        (["--frames", "300:100"], "empty", 1),
        (["--heat", "warm"], "--heat", 1),
        (["-k", "0"], "k", 1),
        (["-k", "5000"], "k", 1),
        (["--exclude", "("], "exclude", 1),
        (["--method", "tsne"], "tsne", 2),
        (["--dims", "4"], "dims", 2),
        (["--axes", "stretched", "--plot", os.path.join(TMP, "x.png")], "axes", 2),
    ]
    for extra, word, want in cases:
        code, out, err = run("map", data(GOLF), "-q", "-o", os.path.join(TMP, "x.csv"), *extra)
        assert code == want, (extra, code, err)
        assert word in err, (extra, err)
        assert out == "", (extra, out)


@test
def figure_draws_six_methods():
    path = os.path.join(TMP, "swing-fig.bvh")
    code, _, err = run("sample", "--kind", "swing", "-o", path)
    assert code == 0, err
    png = os.path.join(TMP, "fig.png")
    # Without XDG_RUNTIME_DIR (root in a container) Qt's warning about it is not passed on.
    env = {k: v for k, v in os.environ.items() if k != "XDG_RUNTIME_DIR"}
    code, out, err = run("figure", path, "-o", png, "-q", "--axes", "equal", env=env)
    assert code == 0, err
    assert "XDG_RUNTIME_DIR" not in err and "QStandardPaths" not in err, err
    for method in ("pca", "svd", "mds", "isomap", "le", "lle"):
        assert method in out, out
    with open(png, "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"


@test
def figure_methods_chooses_the_panels_umap_and_gplvm_among_them():
    path = os.path.join(TMP, "swing-fig.bvh")
    code, _, err = run("sample", "--kind", "swing", "--seconds", "2", "--fps", "30", "-o", path)
    assert code == 0, err
    png = os.path.join(TMP, "fig-methods.png")
    code, out, err = run("figure", path, "-o", png, "-q", "--methods", "gplvm,pca,umap",
                         "--max-iter", "20", "--seed", "1")
    assert code == 0, err
    rows = [line.split()[0] for line in out.splitlines()[1:] if line.strip()]
    assert rows == ["gplvm", "pca", "umap"], out
    with open(png, "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"
    for methods, word in (("pca,tsne", "unknown method 'tsne'"), ("pca,pca", "given twice"),
                          ("pca,,mds", "an empty name")):
        code, out, err = run("figure", path, "-o", png, "-q", "--methods", methods)
        assert code != 0 and word in err, (methods, code, err)
        assert out == "", (methods, out)


@test
def a_static_clip_maps_to_one_point_with_a_note():
    # A hierarchy file whose 60 frames are one pose: the centred data are zero (Spectra's
    # Lanczos used to throw on PCA and return garbage for SVD's second axis).
    static = "other/facebookresearch_pfnn_hierarchy.bvh"
    if not needs(static):
        return
    code, out, err = run("figure", data(static), "-q", "-o", os.path.join(TMP, "static.png"))
    assert code == 0, err
    assert "every frame has the same pose" in err, err
    for method in ("pca", "svd", "mds", "isomap", "le", "lle"):
        assert method in out, out
    for method in ("pca", "svd", "mds", "isomap"):
        csv = os.path.join(TMP, "static-" + method + ".csv")
        code, _, err = run("map", data(static), "--method", method, "-q", "-o", csv)
        assert code == 0, (method, err)
        _, _, values = read_map(csv)
        xy = values[:, 1:]
        assert np.all(np.isfinite(xy)), method
        # one point: every frame at the first frame's place (SVD: the mean pose's projection)
        assert np.abs(xy - xy[0]).max() <= 1e-9 * (1 + np.abs(xy).max()), (method, xy[:3])
        assert np.all(xy[:, 1] == 0), (method, "the second axis is flat")


def rotation_errors_deg(path_a, frames_a, path_b):
    """Per frame: the largest angle (degrees) between the non-root joints' local rotations of
    `path_a` frames `frames_a` and `path_b` (same skeleton), via an independent reader."""
    ja, va, _ = mocap.parse_bvh(path_a)
    jb, vb, _ = mocap.parse_bvh(path_b)
    assert [j["name"] for j in ja] == [j["name"] for j in jb]
    assert [j["channels"] for j in ja] == [j["channels"] for j in jb], "channel order changed"
    la, lb = mocap.local_transforms(ja, va[frames_a]), mocap.local_transforms(jb, vb)
    worst = np.zeros(vb.shape[0])
    for k, j in enumerate(ja):
        if j["parent"] < 0:
            continue
        worst = np.maximum(worst, np.degrees((la[k][1].inv() * lb[k][1]).magnitude()))
    return worst, (ja, va, jb, vb)


@test
def synth_retracing_the_map_reproduces_the_clip():
    if not needs(GOLF):
        return
    csv, path, bvh = (os.path.join(TMP, n) for n in ("golf.csv", "golf-path.csv", "golf-synth.bvh"))
    code, _, err = run("map", data(GOLF), "--method", "mds", "-o", csv, "-q")
    assert code == 0, err
    _, _, values = read_map(csv)
    frame_time = mocap.parse_bvh(data(GOLF))[2]  # 0.0083333 s, as the file says (not 1/120)
    with open(path, "w") as f:
        f.write("t,x,y\n")
        for frame, x, y in values:
            f.write(f"{(frame - values[0, 0]) * frame_time!r},{x!r},{y!r}\n")
    code, _, err = run("synth", data(GOLF), "--map", csv, "--path", path, "-o", bvh, "-q",
                       "--no-clean-feet")  # the blend itself: clean feet would hold them still
    assert code == 0, err
    assert "364 frames at 120 fps" in err and "feet held" not in err, err
    frames = values[:, 0].astype(int)
    worst, (ja, va, jb, vb) = rotation_errors_deg(data(GOLF), frames, bvh)
    assert len(worst) == 364 and worst.max() < 1e-6, worst.max()
    # the root height follows the clip
    assert np.abs(va[frames, 1] - vb[:, 1]).max() < 1e-3


@test
def synth_untimed_path_speed_fps_and_clamping():
    if not needs(GOLF):
        return
    path, bvh = os.path.join(TMP, "line.csv"), os.path.join(TMP, "line.bvh")
    with open(path, "w") as f:
        f.write("x,y\n0,0\n1,0\n")
    code, _, err = run("synth", data(GOLF), "--method", "isomap", "--path", path, "--speed", "2",
                       "--fps", "30", "-o", bvh, "-q")
    assert code == 0, err
    assert "16 frames at 30 fps" in err, err  # 1 map unit at 2 units/s = 0.5 s → 15 steps + 1
    _, values, frame_time = mocap.parse_bvh(bvh)
    assert values.shape[0] == 16 and abs(frame_time - 1 / 30) < 1e-6
    far = write("far.csv", "x,y\n1000,1000\n1001,1000\n")
    code, _, err = run("synth", data(GOLF), "--path", far, "-o", bvh, "-q")
    assert code == 0, err
    assert "2 of 2 frames lie outside the data" in err, err
    assert "2 play the clips' own frames along the path there" in err, err
    assert np.all(np.isfinite(mocap.parse_bvh(bvh)[1]))


@test
def info_contacts_and_skating_and_units():
    walk = "bandai/dataset-1_walk_angry_001.bvh"
    if not needs(walk):
        return
    code, out, err = run("info", data(walk), "--contacts", "--skating")
    assert code == 0, err
    assert "(cm, detected from the body's size" in out, out
    assert "contacts    left (Foot_L): 7" in out and "contacts    right (Foot_R): 6" in out, out
    assert "    - frames 0-3 (0.000-0.133 s)" in out, out
    assert re.search(r"skating     ratio 0\.\d+ \(\d+ of 142 frame transitions\), in contact [\d.]+ "
                     r"cm/s, a foot up \d\.\d{3} s at most \(ankles Foot_L, Foot_R; units cm\)", out), out
    code, out, err = run("info", "--json", "--contacts", "--skating", data(walk))
    assert code == 0, err
    info = json.loads(out)
    assert info["units"] == "cm" and info["metres_per_unit"] == 0.01, info
    assert info["contacts"]["left"][0] == [0, 3] and len(info["contacts"]["right"]) == 6, info
    assert 0 < info["skating"]["ratio"] < 1 and info["skating"]["transitions"] == 142, info
    assert 0 < info["skating"]["longest_raised_s"] < 1, info
    # Without the flags the JSON keys stay as they were.
    code, out, err = run("info", "--json", data(walk))
    assert "units" not in json.loads(out), out
    # The CMU conversions are in CMU units (1/0.45 inch), the fairmotion skeleton in metres.
    if have(GOLF):
        code, out, err = run("info", data(GOLF))
        assert "(CMU units (1/0.45 in), detected" in out, out
    # A clip without feet says so and is not an error.
    sine = "other/facebookresearch_sinusoidal.bvh"
    if have(sine):
        code, out, err = run("info", data(sine), "--contacts")
        assert code == 0, err
        assert "feet        no feet found" in out, out


@test
def info_looks_at_the_feet_from_after_a_bind_pose():
    """CMU's BVH conversion of the 02_03 jog starts with a T-pose, whose ankles stand 5 cm under
    the jog's lowest: --skating and --contacts leave it out, as `map` does, and then read the BVH as
    they read the same take's ASF/AMC original (its frames one earlier); --keep-first keeps it."""
    bvh, amc, asf = "cmu/02_03.bvh", "asfamc/02_03.amc", "asfamc/02.asf"
    if not needs(bvh, amc, asf):
        return
    code, out, err = run("info", "--json", "--contacts", "--skating", data(bvh))
    assert code == 0, err
    b = json.loads(out)
    code, out, err = run("info", "--json", "--contacts", "--skating", data(amc), "--asf", data(asf))
    assert code == 0, err
    a = json.loads(out)
    assert b["feet_from_frame"] == 1 and a["feet_from_frame"] == 0, (a, b)
    assert b["skating"]["transitions"] == a["skating"]["transitions"] == 172, (a, b)
    assert b["skating"]["skating_transitions"] == a["skating"]["skating_transitions"], (a, b)
    assert abs(b["skating"]["contact_speed_cm_s"] - a["skating"]["contact_speed_cm_s"]) < 0.01
    assert b["skating"]["ratio"] > 0.2, b  # 37 of 172; 3 of 173 with the T-pose
    for side in ("left", "right"):
        assert b["contacts"][side] == [[f + 1, l + 1] for f, l in a["contacts"][side]], (a, b)
    code, out, err = run("info", "--contacts", "--skating", data(bvh))
    assert "feet        from frame 1: frame 0 looks like a bind pose" in out, out
    code, out, err = run("info", "--json", "--skating", "--keep-first", data(bvh))
    k = json.loads(out)
    assert k["feet_from_frame"] == 0 and k["skating"]["transitions"] == 173, k
    assert k["skating"]["skating_transitions"] < 10, k


@test
def synth_cleans_the_feet_unless_asked_not_to():
    walk = "bandai/dataset-1_walk_angry_001.bvh"
    if not needs(walk):
        return
    path, bvh = write("walk-path.csv", "x,y\n0,0\n1,0\n"), os.path.join(TMP, "walk-synth.bvh")
    code, _, err = run("synth", data(walk), "--method", "pca", "--path", path, "-o", bvh, "-q")
    assert code == 0, err
    assert re.search(r"; feet held through \d+ contacts", err), err
    code, _, err = run("synth", data(walk), "--method", "pca", "--path", path, "-o", bvh, "-q",
                       "--no-clean-feet")
    assert code == 0, err
    assert "feet held" not in err, err
    code, out, _ = run("synth", "--help")
    assert "--no-clean-feet" in out, out


def motion_lines(bvh):
    with open(bvh) as f:
        lines = f.read().splitlines()
    return lines[lines.index("MOTION") + 3:]


@test
def synth_edit_of_remakes_only_what_the_edit_changes():
    walk = "bandai/dataset-1_walk_angry_001.bvh"
    if not needs(walk):
        return
    csv = os.path.join(TMP, "edit-map.csv")
    code, _, err = run("map", data(walk), "--method", "pca", "-o", csv, "-q")
    assert code == 0, err
    _, _, values = read_map(csv)
    frame_time = mocap.parse_bvh(data(walk))[2]
    rows = list(range(0, len(values), 10)) + [len(values) - 1]
    points = [((values[r, 0] - values[0, 0]) * frame_time, values[r, 1], values[r, 2]) for r in rows]
    old = write("edit-old.csv", "t,x,y\n" + "".join(f"{t!r},{x!r},{y!r}\n" for t, x, y in points))
    t, x, y = points[6]
    _, x7, y7 = points[7]
    points[6] = (t, x + 0.4 * (x7 - x), y + 0.4 * (y7 - y))
    new = write("edit-new.csv", "t,x,y\n" + "".join(f"{t!r},{x!r},{y!r}\n" for t, x, y in points))
    take, edited, full = (os.path.join(TMP, n) for n in ("take.bvh", "edited.bvh", "full.bvh"))
    base = ["synth", data(walk), "--map", csv, "--smooth", "0.05", "-q"]
    code, _, err = run(*base, "--path", old, "-o", take)
    assert code == 0, err
    code, _, err = run(*base, "--path", new, "--edit-of", old, "-o", edited)
    assert code == 0, err
    m = re.search(r"; re-made frames (\d+)-(\d+), the rest as the take of " + re.escape(old), err)
    assert m, err
    first, last = int(m.group(1)), int(m.group(2))
    a, b = motion_lines(take), motion_lines(edited)
    assert len(a) == len(b) and 0 < first <= last < len(a) - 1, (first, last, len(a))
    # Outside the window the take's frames, as written; inside, the edit.
    assert a[:first] == b[:first] and a[last + 1:] == b[last + 1:]
    assert a[first:last + 1] != b[first:last + 1]
    # A whole synthesis of the edited path differs beyond the window (its root carries the edit on).
    code, _, err = run(*base, "--path", new, "-o", full)
    assert code == 0, err
    assert motion_lines(full)[last + 1:] != a[last + 1:]
    # The same path: nothing re-made, the take itself.
    code, _, err = run(*base, "--path", old, "--edit-of", old, "-o", edited)
    assert code == 0 and "; the same path as " + old + ": nothing re-made" in err, err
    assert motion_lines(edited) == a
    # An untimed path whose first point moved changes every frame: re-made whole.
    xy = "x,y\n" + "".join(f"{x!r},{y!r}\n" for _, x, y in points)
    untimed_old = write("edit-untimed-old.csv", xy)
    untimed_new = write("edit-untimed-new.csv", "x,y\n0.5,0.5\n" + xy[4:])
    code, _, err = run(*base, "--path", untimed_new, "--edit-of", untimed_old, "-o", edited)
    assert code == 0, err
    assert "; the edit of " + untimed_old + " reaches every frame: re-made whole" in err, err
    code, _, err = run(*base, "--path", untimed_new, "-o", full)
    assert code == 0, err
    assert motion_lines(edited) == motion_lines(full)
    # A malformed previous path is named with its line.
    bad = write("edit-bad.csv", "t,x,y\n0,1,nan\n")
    code, _, err = run(*base, "--path", new, "--edit-of", bad, "-o", edited)
    assert code == 1 and bad + ":2:" in err, err
    code, _, err = run(*base, "--path", new, "--edit-of", "/no/such.csv", "-o", edited)
    assert code == 2 and "--edit-of" in err, err
    code, out, _ = run("synth", "--help")
    assert "--edit-of" in out, out


@test
def pose_at_a_sample_is_that_frame():
    if not needs(GOLF):
        return
    csv, bvh = os.path.join(TMP, "pose-map.csv"), os.path.join(TMP, "pose.bvh")
    code, _, err = run("map", data(GOLF), "--method", "isomap", "-o", csv, "-q")
    assert code == 0, err
    _, _, values = read_map(csv)
    row = 150
    frame, x, y = values[row]
    for blend in ("local", "kriging"):
        code, _, err = run("pose", data(GOLF), "--map", csv, "--blend", blend, f"--at={x!r},{y!r}",
                           "-o", bvh, "-q")
        assert code == 0, err
        assert f"frame {int(frame)} at 0" in err, err
        worst, (_, _, _, vb) = rotation_errors_deg(data(GOLF), [int(frame)], bvh)
        assert vb.shape[0] == 1 and worst.max() < 1e-6, (blend, worst.max())
        assert vb[0, 0] == 0 and vb[0, 2] == 0, vb[0, :3]  # at the origin


@test
def pose_and_synth_errors():
    if not needs(GOLF):
        return
    out = os.path.join(TMP, "x.bvh")
    csv = os.path.join(TMP, "err-map.csv")
    code, _, err = run("map", data(GOLF), "-o", csv, "-q")
    assert code == 0, err
    with open(csv) as f:
        lines = f.read().splitlines()
    short = write("short-map.csv", "\n".join(lines[:-5]) + "\n")
    broken = write("broken-map.csv", "\n".join(lines[:6] + ["7,abc,1"] + lines[7:]) + "\n")
    headless = write("headless-map.csv", "1,2,3\n")
    cases = [
        (["pose", "--at", "1"], "--at", 1),
        (["pose", "--at", "1,nan"], "--at", 1),
        (["pose", "--at=0,0", "--map", short], "359 map rows, but the clips give 364", 1),
        (["pose", "--at=0,0", "--map", csv, "--stride", "2"], "364 map rows, but the clips give 182", 1),
        (["pose", "--at=0,0", "--map", broken], broken + ":7:3: error: expected a finite coordinate", 1),
        (["pose", "--at=0,0", "--map", headless], headless + ":1:1: error: expected the header", 1),
        (["pose", "--at=0,0", "--neighbors", "0"], "neighbors", 1),
        (["pose", "--at=0,0", "--reach", "-1"], "reach", 1),
        (["pose", "--at=0,0", "--blend", "magic"], "magic", 2),
        (["synth", "--path", write("one.csv", "t,x,y\n0,1,1\n")], "one.csv:2:1: error: expected at least 2", 1),
        (["synth", "--path", write("empty.csv", "")], "empty.csv:1:1: error: expected at least 2", 1),
        (["synth", "--path", write("nan.csv", "0,1\n1,nan\n")], "nan.csv:2:3: error: expected a finite number", 1),
        (["synth", "--path", write("text.csv", "0,1\n1,one\n")], "text.csv:2:3: error: expected a number", 1),
        (["synth", "--path", write("back.csv", "0,0,0\n1,1,1\n0.5,2,2\n")], "back.csv:3:1: error: time 0.5", 1),
        (["synth", "--path", write("ok.csv", "0,0\n1,1\n"), "--smooth", "-1"], "smooth", 1),
        (["synth", "--path", write("ok2.csv", "0,0\n1,1\n"), "--fps", "-5"], "fps", 1),
        (["synth", "--path", write("ok3.csv", "0,0\n1,1\n"), "--speed", "-1"], "speed", 1),
        (["synth", "--path", write("ok4.csv", "0,0\n1,1\n"), "--amc-fps", "0"], "amc-fps", 2),
    ]
    for args, word, want in cases:
        code, stdout, err = run(args[0], data(GOLF), "-q", "-o", out, *args[1:])
        assert code == want, (args, code, err)
        assert word in err, (args, err)
        assert stdout == "", (args, stdout)


if __name__ == "__main__":
    sys.exit(main())
