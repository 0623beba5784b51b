"""Maps of clips: write_map/read_map (the map file h5py reads too), pickling (the map file's bytes)
that places new clips identically, transform of another clip, and errors for a clip of another
skeleton or a damaged file."""
import pickle
import warnings

import numpy as np
import pytest

import motionmap


@pytest.mark.parametrize("cls", [motionmap.PCA, motionmap.MDS, motionmap.LaplacianEigenmap,
                                 motionmap.UMAP])
def test_write_read_pickle_place(cls, golf, golf2, tmp_path):
    est = cls(stride=2).fit(golf)
    placed = est.transform(golf2)
    assert placed.shape == (len(motionmap.features(golf2, stride=2)), 2)
    # The map's own clip placed back: on its own rows (pca to rounding; le exactly; mds dense to
    # the eigen solver's tolerance).
    np.testing.assert_allclose(est.transform(golf), est.embedding_,
                               atol=1e-6 * np.abs(est.embedding_).max())
    path = tmp_path / "m.mmap.h5"
    motionmap.write_map(est, path)
    back = motionmap.read_map(path)
    assert type(back) is cls and back.get_params() == est.get_params()
    np.testing.assert_array_equal(back.embedding_, est.embedding_)
    np.testing.assert_array_equal(back.transform(golf2), placed)
    thawed = pickle.loads(pickle.dumps(est))
    np.testing.assert_array_equal(thawed.embedding_, est.embedding_)
    np.testing.assert_array_equal(thawed.transform(golf2), placed)
    np.testing.assert_array_equal(thawed.frame_of_, est.frame_of_)
    with pytest.raises(motionmap.Error, match="write_csv"):
        thawed.write_csv(tmp_path / "x.csv")


def test_h5py_reads_the_file(golf, tmp_path):
    h5py = pytest.importorskip("h5py")
    est = motionmap.Isomap().fit(golf)
    path = tmp_path / "m.mmap.h5"
    motionmap.write_map(est, path)
    with h5py.File(path, "r") as f:
        assert f.attrs["format"] in ("motionmap-map", b"motionmap-map")
        np.testing.assert_array_equal(f["coordinates"][()], est.embedding_)


def test_errors(golf, other, tmp_path):
    est = motionmap.PCA().fit(golf)
    with pytest.raises(motionmap.Error, match="cannot be placed"):
        est.transform(other)
    with pytest.raises(motionmap.Error, match="fitted on clips"):
        est.transform(np.zeros((3, 4)))
    bad = tmp_path / "bad.mmap.h5"
    bad.write_bytes(b"not a map file")
    with pytest.raises(motionmap.Error, match=str(bad)):
        motionmap.read_map(bad)
    with pytest.raises(motionmap.Error, match="unknown name 'positionz'"):
        motionmap.PCA(features="positionz").fit(golf)


def test_a_file_without_checksums_reads_with_a_warning(golf, tmp_path):
    # A layout-1 file, as an older MotionMap wrote it: no user block, no checksum attributes.
    h5py = pytest.importorskip("h5py")
    est = motionmap.MDS().fit(golf)
    new, old = tmp_path / "new.mmap.h5", tmp_path / "old.mmap.h5"
    motionmap.write_map(est, new)
    with h5py.File(new, "r") as src, h5py.File(old, "w") as dst:
        for name in src:
            src.copy(src[name], dst, name=name)
        for name, value in src.attrs.items():
            if "xxh3" not in name and name != "datasets":
                dst.attrs[name] = value

        def strip(_, obj):  # visititems stops at the first call that returns something
            for a in [a for a in obj.attrs if "xxh3" in a]:
                del obj.attrs[a]

        dst.visititems(strip)
        dst.attrs["format_version"] = 1
    with pytest.warns(UserWarning, match="without checksums: damage to its data cannot be detected"):
        back = motionmap.read_map(old)
    np.testing.assert_array_equal(back.embedding_, est.embedding_)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        motionmap.read_map(new)  # a file with checksums: no warning
