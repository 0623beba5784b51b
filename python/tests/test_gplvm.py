"""motionmap.GPLVM: the CLI's `map --method gplvm` numbers (full and sparse), placement of new
frames (transform) on maps of clips and of arrays, pickling and map files that keep the GP's
predictive, the lengthscale held or fitted as the CLI's, and errors naming max_iter, n_inducing and
lengthscale. On CMU 64_08 every 4th frame (91 frames)
with 30 L-BFGS iterations: each fit well under a second."""
import pickle
import subprocess

import numpy as np
import pytest

import motionmap

ITER = 30


def read_csv_coordinates(path):
    rows = [line.split(",") for line in open(path) if line[0].isdigit()]
    return np.array([[float(v) for v in r[-2:]] for r in rows])


def cli_map(cli, clip, out, *args):
    subprocess.run([cli, "map", clip, "-q", "-o", str(out), "--method", "gplvm", "--stride", "4",
                    "--max-iter", str(ITER), *args], check=True, capture_output=True)
    return read_csv_coordinates(out)


def test_params_and_clone():
    est = motionmap.GPLVM(max_iter=50, n_inducing=20)
    assert est.get_params()["max_iter"] == 50 and est.get_params()["n_inducing"] == 20
    assert est.set_params(n_inducing=None) is est and est.n_inducing is None
    assert repr(est) == "GPLVM(max_iter=50)"
    assert motionmap._ESTIMATORS["gplvm"] is motionmap.GPLVM and "GPLVM" in motionmap.__all__
    with pytest.raises(ValueError, match="unknown parameter"):
        est.set_params(n_neighbors=5)
    with pytest.raises(motionmap.NotFittedError):
        est.transform(np.zeros((2, 4)))
    sklearn = pytest.importorskip("sklearn")
    copy = sklearn.base.clone(est)
    assert copy is not est and copy.get_params() == est.get_params()


def test_full_model_equals_cli(golf, cli, tmp_path):
    theirs = cli_map(cli, golf, tmp_path / "cli.csv")
    est = motionmap.GPLVM(max_iter=ITER, stride=4)
    Y = est.fit_transform(golf)
    assert Y.shape == (91, 2)
    np.testing.assert_array_equal(Y, theirs)
    est.write_csv(tmp_path / "py.csv")
    text = open(tmp_path / "py.csv").read()
    assert text == open(tmp_path / "cli.csv").read()
    assert "# note: gplvm (full): 30 iterations" in text


def test_sparse_model_equals_cli_and_differs_from_full(golf, cli, tmp_path):
    theirs = cli_map(cli, golf, tmp_path / "cli.csv", "--inducing", "20")
    sparse = motionmap.GPLVM(max_iter=ITER, n_inducing=20, stride=4)
    Y = sparse.fit_transform(golf)
    np.testing.assert_array_equal(Y, theirs)
    sparse.write_csv(tmp_path / "py.csv")
    text = open(tmp_path / "py.csv").read()
    assert text == open(tmp_path / "cli.csv").read()
    assert "# note: gplvm (sparse, 20 inducing points)" in text
    full = motionmap.GPLVM(max_iter=ITER, stride=4).fit_transform(golf)
    assert np.abs(Y - full).max() > 1e-3 * np.abs(full).max()


def test_transform_pickle_and_map_file(golf, golf2, cli, tmp_path):
    est = motionmap.GPLVM(max_iter=ITER, stride=4).fit(golf)
    Y = est.embedding_
    # The fitted frames placed back: each at the latent point that best explains it under the
    # predictive, searched from its own and its nearest frames' latent points. The full model puts
    # every frame within 1% of the map's extent of its fitted point (measured: 0.2% after 30
    # iterations, 0.1% after 300).
    back = est.transform(golf)
    assert back.shape == Y.shape
    assert np.linalg.norm(back - Y, axis=1).max() < 0.01 * np.ptp(Y, axis=0).max()
    # Another clip's frames: placed, finite, inside the map's neighbourhood.
    placed = est.transform(golf2)
    assert placed.shape == (len(motionmap.features(golf2, stride=4)), 2)
    assert np.all(np.isfinite(placed))
    assert np.abs(placed).max() < 3 * np.abs(Y).max()
    # A pickle round trip (the map file's bytes, /model/gplvm with them) places identically.
    thawed = pickle.loads(pickle.dumps(est))
    assert thawed.get_params() == est.get_params()
    np.testing.assert_array_equal(thawed.embedding_, Y)
    np.testing.assert_array_equal(thawed.transform(golf2), placed)
    # A map file written here, and one the CLI saves, read back: a GPLVM with its parameters.
    path = tmp_path / "m.mmap.h5"
    motionmap.write_map(est, path)
    again = motionmap.read_map(path)
    assert type(again) is motionmap.GPLVM and again.get_params() == est.get_params()
    np.testing.assert_array_equal(again.transform(golf2), placed)
    saved = tmp_path / "cli.mmap.h5"
    subprocess.run([cli, "map", golf, "-q", "-o", str(tmp_path / "m.csv"), "--method", "gplvm",
                    "--stride", "4", "--max-iter", str(ITER), "--inducing", "20", "--save",
                    str(saved)], check=True, capture_output=True)
    subprocess.run([cli, "map", golf2, "--onto", str(saved), "--stride", "4", "-q", "-o",
                    str(tmp_path / "onto.csv")], check=True, capture_output=True)
    read = motionmap.read_map(saved)
    assert type(read) is motionmap.GPLVM
    assert (read.max_iter, read.n_inducing, read.stride) == (ITER, 20, 4)
    np.testing.assert_array_equal(read.embedding_, read_csv_coordinates(tmp_path / "m.csv"))
    np.testing.assert_array_equal(read.transform(golf2),
                                  read_csv_coordinates(tmp_path / "onto.csv"))
    # Poses at map points, blended from the map's frames, as on the other maps.
    poses = est.inverse_transform(Y[[3, 40]])
    assert isinstance(poses, motionmap.Clip) and poses.num_frames == 2


def test_poses_default_to_the_gps_predictive_mean(golf, tmp_path):
    # blend=None on a GPLVM map is the gp mode (the GP's predictive mean), read back the same;
    # local blends other weights; a point far off the map is moved to the GP's edge (the pose
    # there, not a wild extrapolation), for every mode alike.
    est = motionmap.GPLVM(max_iter=ITER, stride=4).fit(golf)
    Y = est.embedding_
    at = np.vstack([Y[[3, 40]], 0.5 * (Y[10] + Y[11])])
    default = est.inverse_transform(at)
    gp = est.inverse_transform(at, blend="gp")
    local = est.inverse_transform(at, blend="local")
    np.testing.assert_array_equal(default.rotations, gp.rotations)
    assert np.abs(default.rotations - local.rotations).max() > 1e-3
    path = tmp_path / "g.mmap.h5"
    motionmap.write_map(est, path)
    np.testing.assert_allclose(motionmap.read_map(path).inverse_transform(at).rotations,
                               default.rotations, atol=1e-12)
    far = Y.max(axis=0) * 5
    edge = est.inverse_transform(far[None, :])
    assert np.all(np.isfinite(edge.rotations))


@pytest.mark.parametrize("n_inducing", [None, 15])
def test_matrix_fit_transform_and_pickle(golf, n_inducing):
    X = motionmap.features(golf, stride=4)
    est = motionmap.GPLVM(max_iter=ITER, n_inducing=n_inducing)
    Y = est.fit_transform(X)
    assert Y.shape == (X.shape[0], 2) and np.all(np.isfinite(Y))
    # The same frames as clips give the same map.
    np.testing.assert_array_equal(
        motionmap.GPLVM(max_iter=ITER, n_inducing=n_inducing, stride=4).fit_transform(golf), Y)
    # Fitted frames placed back (as in test_transform_pickle_and_map_file). The sparse model's
    # predictive only approximates the GP the latent points were fitted under, so its frames land
    # farther from them: measured on this clip, 15 inducing points, max 8.5% and median 2.7% of the
    # map's extent after 30 iterations (20 and 40 inducing points: max 10% and 11%; the full model
    # 0.2%). Tolerance: max 15%, median 5% sparse; max 1% full.
    d = np.linalg.norm(est.transform(X) - Y, axis=1) / np.ptp(Y, axis=0).max()
    if n_inducing is None:
        assert d.max() < 0.01
    else:
        assert d.max() < 0.15 and np.median(d) < 0.05
    new = (X[:-1] + X[1:]) / 2
    placed = est.transform(new)
    thawed = pickle.loads(pickle.dumps(est))
    assert thawed.get_params() == est.get_params()
    np.testing.assert_array_equal(thawed.embedding_, Y)
    np.testing.assert_array_equal(thawed.transform(new), placed)
    np.testing.assert_array_equal(est.transform(new[5:6]), placed[5:6])


def test_lengthscale_is_the_clis(golf, cli, tmp_path):
    # Fitted by default (0); a value holds it ("ℓ 1.000000 (held)" in the note), as
    # --lengthscale 1.
    free = motionmap.GPLVM(max_iter=ITER, stride=4)
    assert free.get_params()["lengthscale"] == 0.0
    free.fit(golf)
    free.write_csv(tmp_path / "free.csv")
    assert "(held)" not in open(tmp_path / "free.csv").read()
    theirs = cli_map(cli, golf, tmp_path / "cli.csv", "--lengthscale", "1")
    held = motionmap.GPLVM(max_iter=ITER, lengthscale=1, stride=4)
    np.testing.assert_array_equal(held.fit_transform(golf), theirs)
    held.write_csv(tmp_path / "py.csv")
    text = open(tmp_path / "py.csv").read()
    assert text == open(tmp_path / "cli.csv").read() and "ℓ 1.000000 (held)" in text
    assert not np.array_equal(free.embedding_, held.embedding_)


def test_bad_values_name_the_parameter(golf):
    X = motionmap.features(golf, stride=4)
    too_many = r"n_inducing: 92 is out of range; it must be in \[1, 91\]"  # 91 frames
    for bad, name in ((dict(max_iter=0), "max_iter"), (dict(max_iter=100001), "max_iter"),
                      (dict(n_inducing=-1), "n_inducing"), (dict(n_inducing=0), "n_inducing"),
                      (dict(n_inducing=92), too_many), (dict(lengthscale=-1), "lengthscale"),
                      (dict(lengthscale=float("inf")), "lengthscale")):
        with pytest.raises(ValueError, match=name):
            motionmap.GPLVM(stride=4, **bad).fit(golf)
        with pytest.raises(motionmap.Error, match=name):
            motionmap.GPLVM(**bad).fit(X)
