"""The estimators: scikit-learn's conventions (get_params/set_params, clone, a Pipeline,
NotFittedError), pickling of a fitted map that then places frames identically, float32 and
non-contiguous input, bad input, and placement (transform) agreeing with the map's own rows."""
import pickle

import numpy as np
import pytest

import motionmap

sklearn = pytest.importorskip("sklearn")
from sklearn.base import clone  # noqa: E402
from sklearn.pipeline import Pipeline  # noqa: E402
from sklearn.preprocessing import FunctionTransformer  # noqa: E402

ESTIMATORS = [motionmap.PCA, motionmap.SVD, motionmap.MDS, motionmap.Isomap,
              motionmap.LaplacianEigenmap, motionmap.LLE, motionmap.UMAP]


@pytest.fixture(scope="module")
def X():
    # Quaternion features of a real clip (every 3rd frame: 121 rows), as a plain matrix.
    import conftest
    return motionmap.features(conftest.data_path(conftest.GOLF), stride=3)


@pytest.mark.parametrize("cls", ESTIMATORS)
def test_params_and_clone(cls):
    est = cls(n_components=3)
    params = est.get_params()
    assert params["n_components"] == 3
    copy = clone(est)
    assert copy is not est and copy.get_params() == params
    assert est.set_params(n_components=2) is est and est.n_components == 2
    with pytest.raises(ValueError, match="unknown parameter"):
        est.set_params(n_neigbors=5)
    with pytest.raises(motionmap.NotFittedError):
        est.transform(np.zeros((2, 4)))
    assert isinstance(motionmap.NotFittedError("x"), AttributeError)


@pytest.mark.parametrize("cls", ESTIMATORS)
def test_matrix_fit_transform_and_pickle(cls, X):
    est = cls() if cls in (motionmap.PCA, motionmap.SVD, motionmap.MDS) else cls(n_neighbors=10)
    Y = est.fit_transform(X)
    assert Y.shape == (X.shape[0], 2) and np.all(np.isfinite(Y))
    # The map's own frames placed back land on their rows: pca/svd to rounding, le/lle/umap exactly,
    # dense mds/isomap to the eigen solver's tolerance (embed/placement.h).
    np.testing.assert_allclose(est.transform(X[:20]), Y[:20], atol=1e-6 * np.abs(Y).max())
    # New frames (midpoints of consecutive frames) after a pickle round trip: bit for bit.
    new = (X[:-1] + X[1:]) / 2
    placed = est.transform(new)
    back = pickle.loads(pickle.dumps(est))
    np.testing.assert_array_equal(back.embedding_, est.embedding_)
    np.testing.assert_array_equal(back.transform(new), placed)
    # Each frame is placed on its own.
    np.testing.assert_array_equal(est.transform(new[5:6]), placed[5:6])


def test_pca_matches_numpy(X):
    Y = motionmap.PCA().fit_transform(X)
    C = X - X.mean(axis=0)
    _, _, vt = np.linalg.svd(C, full_matrices=False)
    ref = C @ vt[:2].T
    # Same axes up to sign.
    for a in range(2):
        sign = np.sign(ref[:, a] @ Y[:, a])
        np.testing.assert_allclose(Y[:, a], sign * ref[:, a], atol=1e-9)


def test_float32_and_non_contiguous(X):
    est = motionmap.Isomap(n_neighbors=10).fit(X)
    f32 = X.astype(np.float32)
    np.testing.assert_array_equal(est.transform(f32), est.transform(f32.astype(np.float64)))
    wide = np.zeros((X.shape[0], 2 * X.shape[1]))
    wide[:, ::2] = X
    view = wide[:, ::2]
    assert not view.flags.c_contiguous
    np.testing.assert_array_equal(motionmap.Isomap(n_neighbors=10).fit_transform(view),
                                  est.embedding_)
    fortran = np.asfortranarray(X)
    np.testing.assert_array_equal(motionmap.Isomap(n_neighbors=10).fit_transform(fortran),
                                  est.embedding_)


def test_precomputed_distances(golf):
    X, D = motionmap.features(golf, stride=3, distance="features", return_distances=True)
    # D of the rows of X: the same map as from X itself.
    np.testing.assert_allclose(motionmap.MDS(metric="precomputed").fit_transform(D),
                               motionmap.MDS().fit_transform(X), atol=1e-9)
    with pytest.raises(motionmap.Error, match="cannot place new frames"):
        motionmap.MDS(metric="precomputed").fit(D).transform(D[:3])
    with pytest.raises(motionmap.Error, match="122 by 5; expected #frames by #frames"):
        motionmap.Isomap(metric="precomputed").fit(D[:, :5])
    with pytest.raises(ValueError, match="unknown parameter 'metric'"):
        motionmap.PCA().set_params(metric="precomputed")  # PCA reads X only


def test_pipeline(X):
    pipe = Pipeline([("scale", FunctionTransformer(lambda a: a * 2.0)),
                     ("map", motionmap.LaplacianEigenmap(n_neighbors=10))])
    Y = pipe.fit_transform(X)
    np.testing.assert_array_equal(
        Y, motionmap.LaplacianEigenmap(n_neighbors=10).fit_transform(X * 2.0))
    np.testing.assert_array_equal(pipe.transform(X[:7]), Y[:7])
    assert clone(pipe).get_params()["map__n_neighbors"] == 10


def test_bad_input(X):
    with pytest.raises(motionmap.Error, match="2-D"):
        motionmap.PCA().fit(X[0])
    with pytest.raises(motionmap.Error, match="empty"):
        motionmap.PCA().fit(np.zeros((0, 3)))
    nan = X.copy()
    nan[4, 2] = np.nan
    for cls in (motionmap.PCA, motionmap.Isomap):
        with pytest.raises(motionmap.Error, match="(?i)nan|finite"):
            cls().fit(nan)
    est = motionmap.PCA().fit(X)
    with pytest.raises(motionmap.Error, match="columns"):
        est.transform(X[:, :5])
    with pytest.raises(motionmap.Error, match="(?i)nan|finite"):
        est.transform(nan)
    with pytest.raises(motionmap.Error, match="n_components"):
        motionmap.PCA(n_components=5).fit(X)
    with pytest.raises(motionmap.Error, match="k|neighbo"):
        motionmap.Isomap(n_neighbors=0).fit(X)
    with pytest.raises(motionmap.Error, match="metric"):
        motionmap.MDS(metric="cosine").fit(X)
    with pytest.raises(motionmap.Error, match="path"):
        motionmap.MDS(path="fast").fit(X)


def test_docstrings_for_help():
    for name in motionmap.__all__:
        obj = getattr(motionmap, name)
        assert obj.__doc__ and obj.__doc__.strip(), name
    for cls in ESTIMATORS:
        assert "Feature parameters" in cls.__doc__
        for method in ("fit", "transform", "fit_transform", "get_params", "set_params"):
            assert getattr(cls, method).__doc__, (cls.__name__, method)
