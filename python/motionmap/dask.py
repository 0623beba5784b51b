"""Maps of clip libraries on a Dask cluster: fit on a sample of the clips, place every clip in
parallel on the workers.

    from distributed import Client
    import motionmap.dask
    client = Client("scheduler:8786")          # or Client(LocalCluster(...))
    result = motionmap.dask.map_library(paths, client, motionmap.Isomap(), sample=50)
    result.coordinates[i]                      # the map positions of paths[i]'s frames

How it runs (every task is pure: the same input gives the same output, so Dask may retry a task
on another worker):
 1. one task loads the sample clips and fits the estimator on them (a map of their frames: the
    dense map up to 10 000 frames, the landmark/sparse path above, as the estimator's `path` says);
 2. the fitted estimator is scattered to every worker once (it pickles as its map file's bytes);
 3. one task per clip loads it on a worker and places its frames on the fitted map
    (`transform`, which places each frame on its own), so the result equals, bit for bit, the
    single-process `estimator.fit(sample).transform(path)` for every path;
 4. the coordinates are gathered in the order of `paths` and, with `save`, written as one map
    file of the whole library: every placed frame a row (what MotionMap Studio draws and
    `motionmap pose/synth --map` blend), the model the sample's, so that placing a new clip on
    the file gives what `transform` gives (docs/map-file.md, layout version 2).
Workers need the module (`import motionmap`) and the clip files at the same paths (shared
storage).
"""

from collections import namedtuple

import numpy as np

from . import Error, _is_clips

LibraryMap = namedtuple("LibraryMap", "estimator paths sample coordinates failures")
LibraryMap.__doc__ = """What map_library returns.

estimator: the estimator fitted on the sample; paths: the clips, in order; sample: the clips the
map was fitted on; coordinates: per path, its frames' map positions (#frames by n_components), or
None for a clip that failed (keep_going); failures: {path: the error message} of those clips."""


def choose_sample(paths, sample):
    """The clips a library map is fitted on: `sample` itself when it is a list of paths; with an
    int n, n clips spread evenly over `paths` (the i·len/n-th, in path order); None: all."""
    paths = list(paths)
    if sample is None:
        return paths
    if isinstance(sample, int):
        if sample < 1:
            raise Error(f"sample: {sample} clips; expected at least 1")
        n = min(sample, len(paths))
        return [paths[i * len(paths) // n] for i in range(n)]
    if _is_clips(sample):
        return [sample] if isinstance(sample, str) else list(sample)
    raise Error("sample: expected a number of clips, a list of paths or None")


def _fit(estimator, sample):
    return estimator.fit(sample)


def _place(path, fitted, keep_going):
    try:
        return fitted._placed_clips(path)[0]
    except Error as e:
        if not keep_going:
            raise
        return e


def map_library(paths, client, estimator, sample=None, *, save=None, keep_going=False):
    """Maps a library of clips on a Dask cluster: fits `estimator` (a motionmap estimator, not
    fitted: it is cloned by pickling) on `sample` (see choose_sample), then places every clip of
    `paths` on that map, one task per clip. `save`: also write the library's map file (every
    clip placed, on the sample's model). keep_going=True: a clip that fails to load or to place
    is reported in `failures` instead of raising (and left out of the map file). Returns a
    LibraryMap. Raises motionmap.Error for a failing clip (without keep_going), a sample that
    cannot be fitted, or nothing placed to save."""
    paths = [str(p) for p in paths]
    if not paths:
        raise Error("map_library: no clip given")
    chosen = choose_sample(paths, sample)
    fit = client.submit(_fit, estimator, chosen, pure=False)
    fitted = fit.result()
    # The tasks take the fit's own future rather than a scattered copy: a task's result that a
    # dying worker takes with it is computed again, where scattered data is lost and every task
    # needing it cancelled (a fresh `make test` once failed so, a worker killed mid-run).
    futures = client.map(_place, paths, fitted=fit, keep_going=keep_going)
    results = client.gather(futures)
    coordinates, placed, failures = [], [], {}
    for path, result in zip(paths, results):
        if isinstance(result, Exception):
            failures[path] = str(result)
            coordinates.append(None)
        else:
            coordinates.append(np.asarray(result.coordinates))
            placed.append(result)
    if save is not None:
        if not placed:
            raise Error("map_library: no clip could be placed; no map file written")
        fitted.map_.write_placed_map(placed, save, "of the sample")
    return LibraryMap(fitted, paths, chosen, coordinates, failures)
