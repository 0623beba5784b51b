"""motionmap.features: X (and D) as the library builds them; the numbers agree with what the
clips hold (quaternion features are the joints' rotations; D is the distance between point
clouds), and bad options are motionmap.Error."""
import numpy as np
import pytest

import motionmap


def test_quaternion_features_are_the_rotations(golf):
    clip = motionmap.load(golf)
    X = motionmap.features(clip, keep_first=True)
    q = clip.rotations[:, 1:, :]  # the non-root joints, w x y z each
    assert X.shape == (clip.num_frames, 4 * q.shape[1])
    Xq = X.reshape(clip.num_frames, -1, 4)
    # Sign-consistent over time: equal to the clip's rotations up to the sign of each quaternion.
    np.testing.assert_allclose(np.abs(np.sum(Xq * q, axis=2)), 1.0, atol=1e-12)


def test_distances_on_request(golf):
    X, D = motionmap.features(golf, return_distances=True)
    assert D.shape == (X.shape[0], X.shape[0])
    np.testing.assert_array_equal(D, D.T)
    assert np.all(np.diag(D) == 0) and np.all(D >= 0)
    # With distance="features", D is the Euclidean distance between rows of X.
    X2, D2 = motionmap.features(golf, distance="features", return_distances=True)
    np.testing.assert_array_equal(X2, X)
    ref = np.linalg.norm(X[:, None, :] - X[None, :, :], axis=2)
    np.testing.assert_allclose(D2, ref, atol=1e-12)


def test_frames_stride_and_several_clips(golf, golf2):
    X = motionmap.features([golf, golf2], frames=(10, 110), stride=2)
    assert X.shape[0] == 100  # 50 frames of each
    one = motionmap.features(golf, frames=(10, 110), stride=2)
    np.testing.assert_array_equal(X[:50], one)


def test_bad_options(golf):
    with pytest.raises(motionmap.Error, match="unknown name 'quaternion'"):
        motionmap.features(golf, features="quaternion")
    with pytest.raises(motionmap.Error, match="distance"):
        motionmap.features(golf, distance="cosine")
    with pytest.raises(motionmap.Error, match="expected motionmap.Clip objects or paths"):
        motionmap.features([1, 2])
    with pytest.raises(motionmap.Error, match="no clip"):
        motionmap.features([])


def test_knn_graph_as_scipy_sparse(golf):
    sparse = pytest.importorskip("scipy.sparse")
    k = 8
    X, D, G = motionmap.features(golf, return_distances=True, n_neighbors=k)
    assert sparse.issparse(G) and G.shape == D.shape
    assert (G != G.T).nnz == 0
    # Edge i-j exactly when j is among i's k nearest by D or i among j's, of length D[i, j].
    n = D.shape[0]
    order = np.argsort(D + np.diag(np.full(n, np.inf)), axis=1, kind="stable")[:, :k]
    expected = np.zeros((n, n), dtype=bool)
    expected[np.repeat(np.arange(n), k), order.ravel()] = True
    expected |= expected.T
    dense = G.toarray()
    np.testing.assert_array_equal(dense != 0, expected & (D > 0))
    np.testing.assert_allclose(dense[expected], D[expected], rtol=1e-12, atol=1e-12)
    X2, G2 = motionmap.features(golf, n_neighbors=k)
    np.testing.assert_array_equal(X2, X)
    assert (G2 != G).nnz == 0
    with pytest.raises(motionmap.Error, match="n_neighbors"):
        motionmap.features(golf, n_neighbors=0)
