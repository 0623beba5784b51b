"""motionmap.dask.map_library on a real distributed.LocalCluster (2 worker processes, 1 thread
each): the coordinates equal the single-process fit-on-the-sample-then-place run bit for bit, and
a clip that fails to parse is reported with keep_going=True, raised without it."""
import os
import sys

import numpy as np
import pytest

import motionmap
import motionmap.dask

distributed = pytest.importorskip("distributed")

HELPERS = os.path.join(os.path.dirname(__file__), "helpers")


@pytest.fixture(scope="module")
def client():
    # Worker processes start with this process's sys.path (multiprocessing's spawn), so they
    # import motionmap from the same place, and the helpers.
    sys.path.insert(0, HELPERS)
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                       dashboard_address=None, silence_logs=40)
    with distributed.Client(cluster) as c:
        yield c
    cluster.close()
    sys.path.remove(HELPERS)


def test_equals_the_single_process_run(client, golf, golf2, tmp_path):
    bad = tmp_path / "bad.bvh"
    bad.write_text("HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0\n")
    paths = [golf, golf2, str(bad), golf]
    saved = tmp_path / "lib.mmap.h5"
    est = motionmap.Isomap(n_neighbors=12, stride=2)
    result = motionmap.dask.map_library(paths, client, est, sample=[golf2], save=saved,
                                        keep_going=True)
    single = motionmap.Isomap(n_neighbors=12, stride=2).fit(golf2)
    np.testing.assert_array_equal(result.estimator.embedding_, single.embedding_)
    for path, xy in zip(paths, result.coordinates):
        if path == str(bad):
            assert xy is None
        else:
            np.testing.assert_array_equal(xy, single.transform(path))
    assert list(result.failures) == [str(bad)]
    with pytest.raises(motionmap.Error) as local:
        motionmap.load(str(bad))
    assert result.failures[str(bad)] == str(local.value)  # bad.bvh:5:1: error: file ends early…
    # The map file holds every placed clip's frames, and places as the sample's map does.
    library = motionmap.read_map(saved)
    np.testing.assert_array_equal(library.embedding_,
                                  np.vstack([xy for xy in result.coordinates if xy is not None]))
    assert library.map_.paths == [golf, golf2, golf]
    np.testing.assert_array_equal(library.transform(golf2), single.transform(golf2))

    with pytest.raises(motionmap.Error, match="bad.bvh:5:1: error: file ends early"):
        motionmap.dask.map_library(paths, client, est, sample=[golf2])


def test_survives_a_worker_killed_mid_run(client, golf, golf2, tmp_path):
    from dying import DyingIsomap

    est = DyingIsomap(stride=3)
    est.marker = str(tmp_path / "died")
    paths = [golf, golf2, golf2, golf]
    result = motionmap.dask.map_library(paths, client, est, sample=[golf])
    assert os.path.exists(est.marker)  # a worker died placing a clip; Dask ran it again
    single = motionmap.Isomap(stride=3).fit(golf)
    assert not result.failures
    for path, xy in zip(paths, result.coordinates):
        np.testing.assert_array_equal(xy, single.transform(path))


def test_choose_sample():
    paths = [f"{i}.bvh" for i in range(10)]
    assert motionmap.dask.choose_sample(paths, 3) == ["0.bvh", "3.bvh", "6.bvh"]
    assert motionmap.dask.choose_sample(paths, None) == paths
    assert motionmap.dask.choose_sample(paths, 50) == paths
    with pytest.raises(motionmap.Error):
        motionmap.dask.choose_sample(paths, 0)
