#!/usr/bin/env python3
"""End-to-end tests of map files in the `motionmap` tool: `map --save lib.mmap.h5` (read back with
h5py: shapes, and the coordinates equal to the CSV's) and `map NEW.bvh --onto lib.mmap.h5` (new
frames placed on a saved map; the map's own clip placed back on its own rows), and the errors for
bad map files and clips. The clips are the real ones in ../shared/data (never copied); the tests
skip, with a message, when a file is absent, and the h5py checks skip when h5py is missing.

usage: mapfile_test.py MOTIONMAP_BINARY SHARED_DATA_DIR
"""
import hashlib
import os
import shutil
import sys

try:
    import h5py
    import numpy as np
except ImportError:  # scripts/install-deps.sh installs python3-h5py
    h5py = None

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from clirun import BIN, DATA, data, main, needs, read_map, run, test, tmp  # noqa: E402

GOLF = "cmu/64_08.bvh"
GOLF2 = "cmu/64_09.bvh"
OTHER = "other/omimo_AV_8Walk_Meredith_HVHA_Rep1.bvh"  # another skeleton (23 joints)


def text(value):
    """An attribute's text: layout 3 writes fixed-length UTF-8 strings, which h5py reads as bytes."""
    return value.decode("utf-8") if isinstance(value, bytes) else value


def needs_h5py():
    if h5py is None:
        print("  skipped: h5py is not installed (apt-get install python3-h5py)")
        return False
    return True


def parameters_of(comments):
    """The parameter line's parameters (between '# motionmap map ' and ' files=')."""
    first = comments[0]
    assert first.startswith("# motionmap map "), first
    return first[len("# motionmap map "):first.index(" files=")]


def save(name, *options, clip=GOLF):
    """map CLIP --save NAME.mmap.h5 -o NAME.csv; returns (map file, csv)."""
    h5, csv = tmp(name + ".mmap.h5"), tmp(name + ".csv")
    code, _, err = run("map", data(clip), "-q", "-o", csv, "--save", h5, *options)
    assert code == 0, err
    return h5, csv


@test
def help_describes_save_and_onto():
    code, out, _ = run("map", "--help")
    assert code == 0
    for word in ("--save", "--onto", "HDF5", "without refitting", "--frames, --stride"):
        assert word in out, word


@test
def saved_file_holds_the_clips_parameters_and_the_csv_coordinates():
    if not needs(GOLF) or not needs_h5py():
        return
    # One map per method, the dense and the landmark path; the shapes of what each keeps.
    cases = [("pca", []), ("svd", []), ("mds", []), ("mds", ["--landmarks", "0"]),
             ("isomap", []), ("isomap", ["--landmarks", "0"]), ("le", []), ("lle", []),
             ("pca", ["--dims", "3", "--standardize"])]
    with open(data(GOLF), "rb") as f:
        digest = hashlib.sha256(f.read()).hexdigest()
    for method, extra in cases:
        name = "-".join([method, *extra]).replace("--", "")
        h5, csv = save(name, "--method", method, *extra)
        comments, header, rows = read_map(csv)
        dims = len(header) - 1
        xy = np.array([[float(v) for v in r[1:]] for r in rows])
        with h5py.File(h5, "r") as f:
            assert text(f.attrs["format"]) == "motionmap-map"
            assert f.attrs["format_version"] == 3
            coords = f["coordinates"][()]
            assert coords.dtype == np.float64 and coords.shape == (len(rows), dims), coords.shape
            # %.17g in the CSV: the same doubles, bit for bit.
            assert np.array_equal(coords, xy), (name, np.abs(coords - xy).max())
            assert list(f["samples/frame"][()]) == [int(r[0]) for r in rows]
            assert set(f["samples/clip"][()]) == {0}
            assert list(f["clips/path"].asstr()[()]) == [data(GOLF)]
            assert f["clips/sha256"].asstr()[0] == digest
            assert f["clips/frames"][0] == 365 and f["clips/samples"][0] == len(rows)
            p = {k: text(v) for k, v in f["parameters"].attrs.items()}
            assert p["description"] == parameters_of(comments), (p["description"], comments[0])
            assert p["method"] == method and p["dims"] == dims
            assert p["features"] == "quat" and p["distance"] == "pointcloud" and p["up"] == "y"
            assert p["path_taken"] == ("points" if "--landmarks" in extra else "dense")
            names = f["skeleton/names"].asstr()[()]
            assert len(names) == 31 and names[0] == "Hips" and f["skeleton/parents"][0] == -1
            F, V = f["joints"].attrs["x_columns"], f["joints"].attrs["point_columns"]
            assert F == 4 * len(f["joints/used"]), F
            m = f["model"]
            assert text(m.attrs["method"]) == method and m.attrs["dimensions"] == dims
            assert np.array_equal(m["coordinates"][()], coords)
            N = len(rows)
            kept = sorted(m.keys())
            if method in ("pca", "svd"):
                assert m["axes"].shape == (F, dims)
                assert ("mean" in m) == (method == "pca"), kept
                assert ("scale" in m) == ("--standardize" in extra), kept
                assert "points" not in m, kept
            else:
                L = len(m["landmarks/frames"]) if "landmarks" in m else 0
                rows_kept = L if method == "mds" and "--landmarks" in extra else N
                assert m["points"].shape == (rows_kept, V), (name, m["points"].shape)
            if method in ("mds", "isomap"):
                assert m["landmarks/projection"].shape == (dims, L)
                assert m["landmarks/offset"].shape == (dims,)
                if "--landmarks" not in extra:
                    assert L == N
                if method == "isomap":
                    landmark = "--landmarks" in extra
                    assert ("geodesic" in m["landmarks"]) == landmark, kept
                    assert ("graph" in m) == (not landmark), kept
                    if landmark:
                        assert m["landmarks/geodesic"].shape == (L, N)
                    else:
                        assert m["graph/offsets"].shape == (N + 1,)
            if method == "le":
                assert m["eigenvalues"].shape == (dims,) and m.attrs["k"] == 20
            if method == "lle":
                assert m["features"].shape == (N, F) and m.attrs["k"] == 20


@test
def new_clip_placed_onto_a_saved_map():
    if not needs(GOLF, GOLF2):
        return
    h5, _ = save("golf-isomap", "--method", "isomap")
    out, plot = tmp("onto-64_09.csv"), tmp("onto-64_09.png")
    code, stdout, err = run("map", data(GOLF2), "--onto", h5, "-q", "-o", out, "--plot", plot)
    assert code == 0, err
    assert stdout == ""
    comments, header, rows = read_map(out)
    assert header == ["frame", "x", "y"], header
    # As many rows as 64_09 maps to on its own (its T-pose left out the same way).
    own = tmp("64_09-pca.csv")
    assert run("map", data(GOLF2), "--method", "pca", "-q", "-o", own)[0] == 0
    assert [r[0] for r in rows] == [r[0] for r in read_map(own)[2]]
    assert len(rows) == 452, len(rows)  # 453 frames, the T-pose left out
    assert comments[0].startswith("# motionmap map method=isomap dims=2 k=20"), comments[0]
    assert comments[0].endswith(" files=64_09.bvh"), comments[0]
    assert any(c.startswith("# note: placed onto " + h5 + " without refitting it (the isomap map "
                            "of 364 frames of 64_08.bvh)") for c in comments), comments
    assert "note: placed onto" in err
    with open(plot, "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"
    # Two clips: a clip column, each clip's rows as when placed alone.
    both = tmp("onto-both.csv")
    code, _, err = run("map", data(GOLF2), data(GOLF), "--onto", h5, "-q", "-o", both)
    assert code == 0, err
    _, header2, rows2 = read_map(both)
    assert header2 == ["clip", "frame", "x", "y"]
    assert [r[1:] for r in rows2 if r[0] == "0"] == rows
    # --frames and --stride choose the frames placed; a frame lands where it did among all.
    part = tmp("onto-part.csv")
    code, _, err = run("map", data(GOLF2), "--onto", h5, "-q", "-o", part, "--frames", "100:200",
                       "--stride", "7")
    assert code == 0, err
    _, _, rows3 = read_map(part)
    by_frame = {r[0]: r for r in rows}
    assert [r[0] for r in rows3] == [str(f) for f in range(100, 200, 7)]
    assert all(by_frame[r[0]] == r for r in rows3)


@test
def placed_clips_saved_as_a_map_of_their_own():
    # `--onto fitted --save lib`: the placed frames are lib's rows (what Studio shows and
    # pose/synth --map blend); placing on lib is placing on the fitted map.
    if not needs(GOLF, GOLF2):
        return
    fitted, _ = save("golf-le", "--method", "le")
    lib, lib_csv = tmp("lib.mmap.h5"), tmp("lib.csv")
    code, _, err = run("map", data(GOLF), data(GOLF2), "--onto", fitted, "-q", "-o", lib_csv,
                       "--save", lib)
    assert code == 0, err
    _, _, rows = read_map(lib_csv)
    again, direct = tmp("again.csv"), tmp("direct.csv")
    assert run("map", data(GOLF2), "--onto", lib, "-q", "-o", again)[0] == 0
    assert run("map", data(GOLF2), "--onto", fitted, "-q", "-o", direct)[0] == 0
    assert read_map(again)[2] == read_map(direct)[2]
    if needs_h5py():
        with h5py.File(lib, "r") as f:
            assert f.attrs["format_version"] == 3
            coords = f["coordinates"][()]
            assert coords.shape == (len(rows), 2)
            assert [float(v) for v in rows[0][2:]] == list(coords[0])
            assert list(f["clips/samples"][()]) == [364, 452]
            assert f["model/coordinates"].shape == (364, 2)
            assert "without refitting it (fitted on 364 frames of 64_08.bvh)" in f["notes"][-1].decode()
    # A saved map fixes the clips pose/synth blend from: the placed library's.
    code, out, err = run("pose", "--map", lib, "--at=%s,%s" % tuple(rows[500][2:]), "-o",
                         tmp("pose.bvh"))
    assert code == 0, err


@test
def a_clip_placed_onto_its_own_map_lands_on_its_rows():
    if not needs(GOLF):
        return
    # Exactly (the same CSV text) where a frame equal to a sample lands on it: mds, isomap, le,
    # lle, dense or landmark (--landmarks 0). pca and svd recompute the projection from the saved
    # axes: equal to rounding, within 1e-10 of the largest coordinate.
    cases = [("pca", [], 1e-10), ("svd", [], 1e-10), ("pca", ["--standardize"], 1e-10),
             ("mds", ["--landmarks", "0"], 0), ("isomap", ["--landmarks", "0"], 0),
             ("mds", [], 0), ("isomap", [], 0), ("le", [], 0), ("lle", [], 0),
             ("le", ["--landmarks", "0"], 0), ("lle", ["--landmarks", "0"], 0),
             ("isomap", ["--dims", "3", "-k", "12"], 0)]
    for method, extra, tolerance in cases:
        name = "self-" + "-".join([method, *extra]).replace("--", "")
        h5, csv = save(name, "--method", method, *extra)
        out = tmp(name + "-onto.csv")
        code, _, err = run("map", data(GOLF), "--onto", h5, "-q", "-o", out)
        assert code == 0, (name, err)
        c1, h1, r1 = read_map(csv)
        c2, h2, r2 = read_map(out)
        assert h1 == h2 and c1[0] == c2[0], (name, c1[0], c2[0])
        assert [r[0] for r in r1] == [r[0] for r in r2], name
        if tolerance == 0:
            assert r1 == r2, (name, [(a, b) for a, b in zip(r1, r2) if a != b][:3])
        else:
            a = [[float(v) for v in r[1:]] for r in r1]
            b = [[float(v) for v in r[1:]] for r in r2]
            diff = max(abs(x - y) for ra, rb in zip(a, b) for x, y in zip(ra, rb))
            size = max(abs(x) for ra in a for x in ra)
            assert diff <= tolerance * size, (name, diff / size)


@test
def bad_map_files_and_clips_are_errors_naming_them():
    if not needs(GOLF, OTHER):
        return
    h5, _ = save("golf-pca", "--method", "pca")
    out = tmp("bad.csv")

    def onto(map_file, clip=GOLF, *extra):
        return run("map", data(clip), "--onto", map_file, "-q", "-o", out, *extra)

    # Missing: a usage error, like any missing input.
    missing = tmp("missing.mmap.h5")
    code, stdout, err = onto(missing)
    assert code == 2 and "--onto" in err and missing in err, (code, err)
    # Not HDF5.
    text = tmp("text.mmap.h5")
    with open(text, "w") as f:
        f.write("frame,x,y\n1,2,3\n")
    code, stdout, err = onto(text)
    assert code == 1, (code, err)
    assert err == ("motionmap: " + text + ": error: not an HDF5 file (expected a MotionMap map "
                   "file, as `motionmap map --save` writes)\n"), err
    if needs_h5py():
        # Edited with h5py (a newer layout version, another format, a dataset removed, one of
        # the wrong shape): HDF5's structure changed under its checksum, refused before anything
        # else is read (tests/mapfile/map_file_test.cpp makes each edit with the checksums
        # recomputed and checks the specific messages).
        def edited(name, change):
            path = tmp(name + ".mmap.h5")
            shutil.copy(h5, path)
            with h5py.File(path, "r+") as f:
                change(f)
            return path

        def coordinates_cut(f):
            xy = f["coordinates"][()]
            del f["model/coordinates"]
            del f["coordinates"]
            f["coordinates"] = xy[:-1]

        edits = [("newer", lambda f: f.attrs.__setitem__("format_version", 4)),
                 ("other", lambda f: f.attrs.__setitem__("format", np.bytes_("someone-else"))),
                 ("gone", lambda f: f.__delitem__("model/axes")),
                 ("shape", coordinates_cut)]
        for name, change in edits:
            path = edited(name, change)
            code, _, err = onto(path)
            assert code == 1, (name, err)
            assert err.startswith("motionmap: " + path + ": error: its HDF5 structure (everything "
                                  "but the datasets' values) is damaged: "), (name, err)
    # A clip of another skeleton.
    code, stdout, err = onto(h5, OTHER)
    assert code == 1, err
    assert ("motionmap: " + data(OTHER) + ": cannot be placed on " + h5 + ": its joint hierarchy "
            "differs from the map's (it has 23 joints, 64_08.bvh 31;") in err, err
    assert stdout == ""
    # Options the map fixes are usage errors.
    for extra in (["--method", "pca"], ["-k", "5"], ["--features", "positions"], ["--metrics"],
                  ["--landmarks", "0"]):
        code, _, err = onto(h5, GOLF, *extra)
        assert code == 2 and "--onto" in err and "excludes" in err, (extra, code, err)



@test
def checksums_are_the_documented_xxh3_of_1_mib_blocks():
    # docs/map-file.md's definition, computed independently (python3-xxhash; skipped without).
    try:
        import xxhash
    except ImportError:
        print("  skipped: python3-xxhash is not installed")
        return
    if not needs(GOLF) or not needs_h5py():
        return

    def checksum(data):
        blocks = (xxhash.xxh3_64_digest(data[i:i + 2**20])[::-1] for i in range(0, len(data), 2**20))
        return xxhash.xxh3_64_intdigest(b"".join(blocks))

    h5, _ = save("checksums", "--method", "isomap", "--landmarks", "0")
    with h5py.File(h5, "r") as f:
        for name in ("coordinates", "model/points", "model/landmarks/geodesic", "samples/frame"):
            values = f[name][()]
            data = (values.astype("<f8") if values.dtype.kind == "f" else values.astype("<i4")).tobytes()
            assert checksum(data) == int(f[name].attrs["xxh3"]), name
        names = b"".join(bytes(n) + b"\0" for n in f["skeleton/names"][()])
        assert checksum(names) == int(f["skeleton/names"].attrs["xxh3"])
    with open(h5, "rb") as f:
        head = f.read(4096).rstrip(b"\0").decode()
    assert head.startswith("MotionMap map file (docs/map-file.md)\nstructure-xxh3 "), head[:80]
    assert "\nsize %d\n" % os.path.getsize(h5) in head, head


@test
def damaged_copies_are_errors_never_crashes_or_other_results():
    # Issue 22's experiment, short: 20 copies of a dense and a landmark isomap map with 1 to 32
    # random bytes changed, through --onto and pose --map (the full run, 400 copies, is
    # tests/mapfile/damage_experiment.py; its table is in docs/map-file.md).
    if not needs(GOLF, GOLF2):
        return
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "mapfile"))
    import damage_experiment
    work = tmp("damage")
    os.makedirs(work)
    table, not_utf8, bad = damage_experiment.experiment(BIN, DATA, 20, 22, 2, work)
    assert not bad, [(name, i, command, outcome, message[:300])
                     for name, i, command, outcome, message in bad]
    assert not not_utf8, not_utf8
    assert all(sum(counts.values()) == 20 for counts in table.values()), table

if __name__ == "__main__":
    sys.exit(main())
