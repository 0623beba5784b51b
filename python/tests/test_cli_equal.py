"""The same clips mapped with the `motionmap` tool and with the module give the same file, byte
for byte (the CSV's 17 significant digits, its parameter and note lines): the module is a shell
over the same library calls. And the map file of `map --save`, read with read_map, places new
clips as `map --onto` does."""
import filecmp
import subprocess

import numpy as np
import pytest

import motionmap

CASES = [
    (motionmap.PCA(), ["--method", "pca"]),
    (motionmap.Isomap(n_neighbors=12), ["--method", "isomap", "-k", "12"]),
    (motionmap.LaplacianEigenmap(frames=(0, 300), stride=2),
     ["--method", "le", "--frames", "0:300", "--stride", "2"]),
    (motionmap.LLE(n_neighbors=15, distance="geodesic"),
     ["--method", "lle", "-k", "15", "--distance", "geodesic"]),
    (motionmap.UMAP(n_epochs=60, random_state=3, min_dist=0.2),
     ["--method", "umap", "--epochs", "60", "--seed", "3", "--min-dist", "0.2"]),
]


def read_csv_coordinates(path):
    rows = [line.split(",") for line in open(path) if line[0].isdigit()]
    return np.array([[float(v) for v in r[-2:]] for r in rows])


@pytest.mark.parametrize("estimator,args", CASES, ids=[a[1] for _, a in CASES])
def test_csv_byte_for_byte(estimator, args, golf, cli, tmp_path):
    theirs = tmp_path / "cli.csv"
    subprocess.run([cli, "map", golf, "-q", "-o", str(theirs), *args], check=True,
                   capture_output=True)
    ours = tmp_path / "py.csv"
    Y = estimator.fit_transform(golf)
    estimator.write_csv(ours)
    assert filecmp.cmp(theirs, ours, shallow=False), (open(theirs).read()[:400],
                                                        open(ours).read()[:400])
    # The numbers in the file are the coordinates returned (17 digits read back exactly).
    np.testing.assert_array_equal(read_csv_coordinates(theirs), Y)


def test_two_clips_byte_for_byte(golf, golf2, cli, tmp_path):
    theirs = tmp_path / "cli.csv"
    subprocess.run([cli, "map", golf, golf2, "-q", "-o", str(theirs), "--method", "mds"],
                   check=True, capture_output=True)
    ours = tmp_path / "py.csv"
    est = motionmap.MDS().fit([golf, motionmap.load(golf2)])
    est.write_csv(ours)
    assert filecmp.cmp(theirs, ours, shallow=False)
    assert set(est.clip_of_) == {0, 1}


def test_onto_matches_read_map_transform(golf, golf2, cli, tmp_path):
    saved = tmp_path / "golf.mmap.h5"
    subprocess.run([cli, "map", golf, "-q", "-o", str(tmp_path / "m.csv"), "--method", "isomap",
                    "--save", str(saved)], check=True, capture_output=True)
    placed_csv = tmp_path / "onto.csv"
    subprocess.run([cli, "map", golf2, "--onto", str(saved), "-q", "-o", str(placed_csv)],
                   check=True, capture_output=True)
    est = motionmap.read_map(saved)
    assert isinstance(est, motionmap.Isomap) and est.n_neighbors == 20
    np.testing.assert_array_equal(est.embedding_, read_csv_coordinates(tmp_path / "m.csv"))
    np.testing.assert_array_equal(est.transform(golf2), read_csv_coordinates(placed_csv))
