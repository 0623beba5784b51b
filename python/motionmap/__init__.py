"""MotionMap from Python: motion-capture clips (BVH, ASF/AMC) mapped to 2-D maps.

    import motionmap
    clip = motionmap.load("64_08.bvh")
    xy = motionmap.Isomap(n_neighbors=15).fit_transform(clip)    # #frames by 2

A thin shell over MotionMap's C++ library (the compiled module motionmap._motionmap), like the
``motionmap`` command-line tool: the same inputs give the same numbers, bit for bit. The
estimators follow scikit-learn's conventions (fit/transform/fit_transform, get_params/set_params,
pickling); see docs/python.md.
"""

import inspect
import os
import warnings

import numpy as np

from . import _motionmap
from ._motionmap import Clip, Error, Skeleton, load

__all__ = [
    "Clip", "Error", "Skeleton", "load", "features", "read_map", "write_map", "synthesize",
    "edit_path", "inbetween",
    "PCA", "SVD", "MDS", "Isomap", "LaplacianEigenmap", "LLE", "UMAP", "GPLVM",
    "NotFittedError",
]
__version__ = "0.1.0"

Error.__doc__ = """Every error MotionMap's library reports, a ValueError: a malformed file
('path:line:col: error: …', the CLI's message), a bad parameter or input (naming it, its value and
the valid range), a failed computation."""


class NotFittedError(Error, AttributeError):
    """transform (or another method that needs a fitted map) called before fit.

    Also an AttributeError, like scikit-learn's NotFittedError."""


def _is_clips(X):
    """Whether X names clips (a Clip, a path, or a list of them) rather than holding a matrix."""
    if isinstance(X, (Clip, str, os.PathLike)):
        return True
    if isinstance(X, (list, tuple)) and len(X) > 0:
        return all(isinstance(x, (Clip, str, os.PathLike)) for x in X)
    return False


def _feature_options(features, distance, exclude, up, joints, frames, stride, keep_first):
    return {
        "features": features, "distance": distance, "exclude": exclude, "up": up,
        "joints": joints, "frames": None if frames is None else tuple(frames),
        "stride": int(stride), "keep_first": bool(keep_first),
    }


def features(clips, features="quat", distance="pointcloud", exclude=None, *, up="y",
             joints="all", frames=None, stride=1, keep_first=False, return_distances=False,
             n_neighbors=None, asf=None, fps=None, progress=None):
    """The feature matrix X of clips; with return_distances=True also the pose distances D, and
    with n_neighbors=k the k-NN graph of the frames as a scipy.sparse matrix.

    clips: a Clip, a path, or a list of them (one map's worth: one skeleton, or several with
    joints="common"). features: "quat" (joint rotation quaternions, w x y z per joint) or
    "positions" (heading-local joint positions). distance: "pointcloud", "geodesic" or
    "features" (Euclidean on X). exclude: a regular expression of joint names to leave out.
    frames: (first, end) file frames per clip (end exclusive, None = to the end); stride: every
    stride-th frame; keep_first: keep a leading bind pose (left out by default). progress: a
    callable(fraction, stage) or a tqdm bar.

    Returns X (#frames by #features); with return_distances, (X, D), D #frames by #frames; with
    n_neighbors, (X, G) or (X, D, G): G is the symmetric k-NN graph (scipy.sparse.csr_matrix,
    #frames by #frames; entry i, j is the pose distance when j is among i's k nearest or i among
    j's), found from the points D is computed from without forming D (exact up to 100 000
    frames; above, possibly approximate: docs/scale.md). An edge of length 0 (two identical
    poses) is not stored, as scipy.sparse drops explicit zeros. Raises motionmap.Error.
    """
    options = _feature_options(features, distance, exclude, up, joints, frames, stride,
                               keep_first)
    k = 0 if n_neighbors is None else int(n_neighbors)
    if n_neighbors is not None and k < 1:
        raise Error(f"n_neighbors: {n_neighbors} is not a number of neighbours >= 1")
    X, D, index, distance, _ = _motionmap._features(
        clips, options, bool(return_distances), k, "" if asf is None else os.fspath(asf),
        0.0 if fps is None else float(fps), progress)
    out = [X]
    if return_distances:
        out.append(D)
    if n_neighbors is not None:
        from scipy import sparse

        n = index.shape[0]
        rows = np.repeat(np.arange(n), index.shape[1])
        G = sparse.csr_matrix((distance.ravel(), (rows, index.ravel())), shape=(n, n))
        out.append(G.maximum(G.T).tocsr())
    return out[0] if len(out) == 1 else tuple(out)


def _keep_arguments(estimator, arguments):
    """Stores an __init__'s arguments as attributes of the same names (scikit-learn's
    convention: get_params reads them back by the signature's names)."""
    for name, value in arguments.items():
        if name != "self":
            setattr(estimator, name, value)


class _MapEstimator:
    """What the estimators share. Parameters are stored by __init__ as given (scikit-learn's
    rule: no validation there); fit validates them, through the library."""

    _method = None

    @classmethod
    def _get_param_names(cls):
        signature = inspect.signature(cls.__init__)
        return sorted(p.name for p in signature.parameters.values()
                      if p.name != "self" and p.kind != p.VAR_KEYWORD)

    def get_params(self, deep=True):
        """The constructor's parameters and their values (scikit-learn's get_params)."""
        return {name: getattr(self, name) for name in self._get_param_names()}

    def set_params(self, **params):
        """Sets constructor parameters by name; returns self. Unknown names raise ValueError."""
        valid = self._get_param_names()
        for name, value in params.items():
            if name not in valid:
                raise ValueError(f"{type(self).__name__}: unknown parameter {name!r} "
                                 f"(parameters: {', '.join(valid)})")
            setattr(self, name, value)
        return self

    def __repr__(self):
        defaults = {p.name: p.default
                    for p in inspect.signature(type(self).__init__).parameters.values()}
        changed = [f"{k}={v!r}" for k, v in self.get_params().items()
                   if not (isinstance(v, type(defaults.get(k))) and v == defaults.get(k))]
        return f"{type(self).__name__}({', '.join(changed)})"

    def _options(self):
        params = self.get_params()
        options = {"method": self._method}
        for key in ("n_components", "n_neighbors", "heat", "reg", "min_dist", "n_epochs",
                    "random_state", "max_iter", "n_inducing", "lengthscale", "standardize",
                    "strict", "n_landmarks", "path", "features", "distance", "exclude", "up",
                    "joints", "frames", "stride", "keep_first"):
            if key in params:
                options[key] = params[key]
        if options.get("frames") is not None:
            options["frames"] = tuple(options["frames"])
        return options

    def _precomputed(self):
        return getattr(self, "metric", "euclidean") == "precomputed"

    def fit(self, X, y=None, *, asf=None, fps=None, progress=None, labels_from_name=None,
            labels=None):
        """Makes the map.

        X: clips (a Clip, a path, or a list of them: the map of all their frames, with this
        estimator's feature parameters), or an array of #frames by #features (rows are frames;
        mds, isomap, le and lle measure Euclidean distances between rows), or with
        metric="precomputed" a #frames by #frames distance matrix. y is ignored. asf, fps: for
        .amc paths. progress: a callable(fraction, stage) or a tqdm bar. Returns self.
        labels_from_name (a file-name pattern such as "{action}_{style}_{take}") and labels (a
        CSV or JSON label file) label the clips' frames as the CLI's --labels-from-name and
        --labels do (docs/labels.md): labels_ then holds them, and write_map keeps them.
        """
        metric = getattr(self, "metric", "euclidean")
        if metric not in ("euclidean", "precomputed"):
            raise Error(f"metric: unknown name {metric!r} (expected 'euclidean' or "
                        f"'precomputed')")
        if _is_clips(X):
            if self._precomputed():
                raise Error("metric='precomputed' expects a distance matrix, not clips")
            self.map_ = _motionmap._fit_clips(
                X, self._options(), "" if asf is None else os.fspath(asf),
                0.0 if fps is None else float(fps), progress,
                labels_from_name="" if labels_from_name is None else str(labels_from_name),
                labels="" if labels is None else os.fspath(labels))
        else:
            if labels_from_name is not None or labels is not None:
                raise Error("labels_from_name and labels label clips; this is an array")
            self.map_ = _motionmap._fit_matrix(X, self._precomputed(), self._options(), progress)
        self._set_fitted_attributes()
        return self

    def _set_fitted_attributes(self):
        self.embedding_ = np.asarray(self.map_.coordinates)
        self.eigenvalues_ = np.asarray(self.map_.eigenvalues)
        self.n_features_in_ = self.map_.x_columns
        self.warnings_ = list(self.map_.warnings)

    def _check_fitted(self):
        if not hasattr(self, "map_"):
            raise NotFittedError(f"This {type(self).__name__} is not fitted yet: call fit first")

    def transform(self, X, *, asf=None, fps=None, progress=None):
        """Places new frames on the fitted map without refitting it (docs/map-file.md,
        "placement"): X is clips (for a map of clips) or an array of #frames by #features (for a
        map of an array). Each frame is placed on its own. Returns #frames by n_components."""
        self._check_fitted()
        if _is_clips(X):
            if not isinstance(self.map_, _motionmap._ClipMap):
                raise Error("transform: this map was fitted on an array; give an array")
            return self.map_.transform(X, self._options(),
                                       "" if asf is None else os.fspath(asf),
                                       0.0 if fps is None else float(fps), progress)
        if isinstance(self.map_, _motionmap._ClipMap):
            raise Error("transform: this map was fitted on clips; give clips (a Clip, a path, "
                        "or a list of them)")
        return self.map_.transform(X, progress)

    def _placed_clips(self, clips, *, asf=None, fps=None, progress=None):
        """transform(clips) with each clip's record (path, SHA-256, frames placed): the
        _PlacedClip objects motionmap.dask.map_library gathers into one map file."""
        self._check_fitted()
        if not isinstance(self.map_, _motionmap._ClipMap):
            raise Error("this map was fitted on an array; only maps of clips place clips")
        return self.map_.place_clips(clips, self._options(), "" if asf is None else os.fspath(asf),
                                     0.0 if fps is None else float(fps), progress)

    def fit_transform(self, X, y=None, **fit_params):
        """fit(X), then the map of X's frames (embedding_)."""
        return self.fit(X, y, **fit_params).embedding_

    def inverse_transform(self, Y, *, blend=None, neighbors=12, reach=3.0, progress=None):
        """The poses at map points: MotionMap's pose synthesis (docs/synthesis.md), blended from
        the map's frames around each point. Y: #points by 2 (a 2-D map of clips). blend: "local"
        (kriging on small neighbourhoods), "kriging", "idw" or "gp" (a GPLVM's predictive mean);
        None: the map's default, "gp" on a GPLVM map (whose GP also decides where the map is
        valid, in place of reach) and "local" on the others; neighbors: K; reach: how far (in
        median steps) a point may be from the data before it is moved to its edge. Returns a
        Clip of one frame per point (the root at the origin, facing heading 0)."""
        self._check_fitted()
        if not isinstance(self.map_, _motionmap._ClipMap):
            raise Error("inverse_transform: poses are blended from clips; this map was fitted "
                        "on an array")
        return self.map_.poses_at(Y, blend or "", int(neighbors), float(reach), progress)

    def write_csv(self, path):
        """Writes the fitted map of clips as the CLI's `motionmap map -o` writes it (byte for
        byte the same for the same clips and parameters)."""
        self._check_fitted()
        if not isinstance(self.map_, _motionmap._ClipMap):
            raise Error("write_csv: only maps of clips are written as CSV")
        self.map_.write_csv(path)

    @property
    def clip_of_(self):
        """Per map row: the index of its clip (maps of clips)."""
        self._check_fitted()
        return np.asarray(self.map_.clip_of)

    @property
    def frame_of_(self):
        """Per map row: its frame in its clip's file (maps of clips)."""
        self._check_fitted()
        return np.asarray(self.map_.frame_of)

    @property
    def labels_(self):
        """The map rows' labels (maps of clips fitted with labels_from_name or labels, or read
        from a map file that has them): a dict of label name → numpy array of str (dtype
        object), one per map row, so pandas.DataFrame(estimator.labels_) is a table of them.
        Empty without labels."""
        self._check_fitted()
        if not isinstance(self.map_, _motionmap._ClipMap):
            return {}
        return self.map_.labels

    def label_accuracy(self, k=10, sample=5000):
        """The label accuracy of the fitted map (docs/labels.md): for each label with two or
        more values, the fraction of frames whose label wins the vote of their k nearest frames
        of other clips, on the map ("map") and by the pose distance ("features"); over every
        labelled frame, or a seeded sample of `sample` of them ("queries"). In the process that
        fitted the map."""
        self._check_fitted()
        if not isinstance(self.map_, _motionmap._ClipMap):
            raise Error("label_accuracy: only maps of clips have labels")
        return self.map_.label_accuracy(int(k), int(sample))


_FEATURE_DOC = """
    Feature parameters (maps of clips): features ("quat" or "positions"), distance
    ("pointcloud", "geodesic" or "features"), exclude (regular expression of joint names), up
    ("y" or "z"), joints ("all" or "common"), frames ((first, end) per clip), stride, keep_first.
    path: "auto" (dense up to 10 000 frames), "dense" or "landmarks" (the scalable path,
    docs/scale.md).
"""


class PCA(_MapEstimator):
    __doc__ = """Principal component analysis of X (clips: joint rotation quaternions by default).

    standardize=True divides every column by its standard deviation first.
    """ + _FEATURE_DOC
    _method = "pca"

    def __init__(self, n_components=2, *, standardize=False, features="quat",
                 distance="pointcloud", exclude=None, up="y", joints="all", frames=None,
                 stride=1, keep_first=False, path="auto"):
        _keep_arguments(self, locals())


class SVD(_MapEstimator):
    __doc__ = """Truncated SVD of X (no centring).""" + _FEATURE_DOC
    _method = "svd"

    def __init__(self, n_components=2, *, features="quat", distance="pointcloud", exclude=None,
                 up="y", joints="all", frames=None, stride=1, keep_first=False, path="auto"):
        _keep_arguments(self, locals())


class MDS(_MapEstimator):
    __doc__ = """Classical (Torgerson) MDS of the pose distances; landmark MDS on the scalable path.

    metric="precomputed": fit takes a distance matrix D instead of X.
    """ + _FEATURE_DOC
    _method = "mds"

    def __init__(self, n_components=2, *, metric="euclidean", n_landmarks=None,
                 features="quat", distance="pointcloud", exclude=None, up="y", joints="all",
                 frames=None, stride=1, keep_first=False, path="auto"):
        _keep_arguments(self, locals())


class Isomap(_MapEstimator):
    __doc__ = """Isomap: classical MDS of the geodesic distances on the k-NN graph.

    n_neighbors: k; strict=True fails on a disconnected graph instead of joining it.
    metric="precomputed": fit takes a distance matrix D instead of X.
    """ + _FEATURE_DOC
    _method = "isomap"

    def __init__(self, n_neighbors=20, n_components=2, *, metric="euclidean", strict=False,
                 n_landmarks=None, features="quat", distance="pointcloud", exclude=None, up="y",
                 joints="all", frames=None, stride=1, keep_first=False, path="auto"):
        _keep_arguments(self, locals())


class LaplacianEigenmap(_MapEstimator):
    __doc__ = """Laplacian eigenmap (scikit-learn's SpectralEmbedding) of the k-NN graph.

    heat: the heat-kernel width t of exp(-d²/t); None = the median squared k-NN distance;
    <= 0 = every weight 1. metric="precomputed": fit takes a distance matrix D.
    """ + _FEATURE_DOC
    _method = "le"

    def __init__(self, n_neighbors=20, n_components=2, *, heat=None, metric="euclidean",
                 strict=False, features="quat", distance="pointcloud", exclude=None, up="y",
                 joints="all", frames=None, stride=1, keep_first=False, path="auto"):
        _keep_arguments(self, locals())


class LLE(_MapEstimator):
    __doc__ = """Locally linear embedding: neighbours by the pose distance, weights solved in X.

    reg: regularisation, C += reg·trace(C)·I.
    """ + _FEATURE_DOC
    _method = "lle"

    def __init__(self, n_neighbors=20, n_components=2, *, reg=1e-3, strict=False,
                 features="quat", distance="pointcloud", exclude=None, up="y", joints="all",
                 frames=None, stride=1, keep_first=False, path="auto"):
        _keep_arguments(self, locals())


class UMAP(_MapEstimator):
    __doc__ = """UMAP (McInnes et al. 2018, as umap-learn computes it): a neighbour embedding
    that keeps each frame's nearest neighbours together and the rest apart (docs/methods/umap.md).

    n_neighbors: UMAP's, the frame itself counted (k − 1 others); min_dist: the smallest map
    distance, in [0, 1]; n_epochs: layout epochs, None = 500 up to 10 000 frames, 200 above;
    random_state: the seed (an int ≥ 0; None = 0): one seed, one map, whatever the thread count.
    transform places new frames at the fuzzy-weighted mean of their n_neighbors nearest fitted
    frames (umap-learn's starting position; no further epochs).
    metric="precomputed": fit takes a distance matrix D instead of X.
    """ + _FEATURE_DOC
    _method = "umap"

    def __init__(self, n_neighbors=15, n_components=2, *, min_dist=0.1, n_epochs=None,
                 random_state=0, metric="euclidean", strict=False, features="quat",
                 distance="pointcloud", exclude=None, up="y", joints="all", frames=None,
                 stride=1, keep_first=False, path="auto"):
        _keep_arguments(self, locals())


class GPLVM(_MapEstimator):
    __doc__ = """Gaussian-process latent variable model (Lawrence 2005): the latent points whose GP
    mapping to X (an RBF-plus-bias kernel) has the greatest marginal likelihood, from PCA's map
    (docs/methods/gplvm.md). Fitted in X; there is no metric="precomputed".

    max_iter: L-BFGS iterations at most, in [1, 100000]; n_inducing: inducing points of the
    sparse model (DTC), 1 to #frames, or None = the full model up to 1 000 frames and 100
    inducing points above; lengthscale: > 0 holds the kernel's lengthscale at that value through
    the fit (in units of the latent points' prior N(0, I)) so that it can converge; 0 (default)
    fits it (the objective then has no optimum). transform places each new frame at the latent
    point that best explains
    it under the fitted GP, searched from the latent points of its nearest fitted frames.
    eigenvalues_: those of the PCA map the fit starts from.
    """ + _FEATURE_DOC
    _method = "gplvm"

    def __init__(self, n_components=2, *, max_iter=300, n_inducing=None, lengthscale=0.0,
                 features="quat", distance="pointcloud", exclude=None, up="y", joints="all",
                 frames=None, stride=1, keep_first=False, path="auto"):
        _keep_arguments(self, locals())


_ESTIMATORS = {cls._method: cls
               for cls in (PCA, SVD, MDS, Isomap, LaplacianEigenmap, LLE, UMAP, GPLVM)}


def synthesize(fitted, path_xy, times=None, *, speed=0.0, fps=0.0,
               smooth=_motionmap.default_smooth_seconds, blend=None, neighbors=12, reach=3.0,
               clean_feet=True, progress=None):
    """A new motion along a path on a fitted 2-D map of clips (what `motionmap synth` does;
    docs/synthesis.md): every frame blended at a point of the path, root motion integrated from
    the samples' own velocities. path_xy: #points by 2; times: seconds per point (strictly
    increasing) or None (drawn at `speed` map units per second, 0 = the clip's median map
    speed); fps: output frame rate (0 = the clip's); smooth: σ in seconds of a Gaussian
    smoothing of the weights over time, 0 = none (each neighbouring frame's moved in its clips
    by its distance in time first, so a retraced clip stays itself). blend, neighbors, reach: as inverse_transform;
    clean_feet: hold each foot still through its contacts with the floor (False: the blend as it
    is, e.g. to reproduce a clip along its own trajectory). Where the path leaves the data, or
    runs farther than half the reach from it, or where a gait's legs would stall mid-stride
    while the path moves on beside the clips' curves, the local blend plays the clips' own
    frames along it (docs/synthesis.md, "Outside the data"); the clip's warnings say how many
    frames lay outside, and carry the synthesis' notes (a stalled gait, feet out of reach).
    Returns a Clip (save() writes it as BVH)."""
    fitted._check_fitted()
    if not isinstance(fitted.map_, _motionmap._ClipMap):
        raise Error("synthesize: motions are blended from clips; this map was fitted on an array")
    return fitted.map_.synthesize(path_xy, None if times is None else [float(t) for t in times],
                                  float(speed), float(fps), float(smooth), blend or "", int(neighbors),
                                  float(reach), bool(clean_feet), progress)


def edit_path(fitted, path_xy, times=None, *, previous_xy, previous_times=None, speed=0.0,
              fps=0.0, smooth=_motionmap.default_smooth_seconds, blend=None, neighbors=12,
              reach=3.0, clean_feet=True, progress=None):
    """The motion along an edited path, re-made only where the edit changes it (what `motionmap
    synth --edit-of` does; docs/synthesis.md, "Editing a path"). previous_xy, previous_times: the
    path of the previous take, made by synthesize(fitted, previous_xy, previous_times, ...) with
    the same options (speed, fps, smooth, blend, neighbors, reach, clean_feet: as synthesize);
    path_xy, times: the edited path. Every frame outside the window is the previous take's, bit
    for bit. Returns (Clip, window): window is a dict with "first" and "end" (the frames
    [first, end) that may differ from the previous take), "blend_first" and "blend_end" (the
    frames blended anew), "whole" (True when the edit reached every frame and the motion was
    synthesized whole) and "feet_frames_changed" (frames the foot clean-up changed, over the
    whole motion)."""
    fitted._check_fitted()
    if not isinstance(fitted.map_, _motionmap._ClipMap):
        raise Error("edit_path: motions are blended from clips; this map was fitted on an array")
    return fitted.map_.edit_path(
        previous_xy, None if previous_times is None else [float(t) for t in previous_times],
        path_xy, None if times is None else [float(t) for t in times], float(speed), float(fps),
        float(smooth), blend or "", int(neighbors), float(reach), bool(clean_feet), progress)


def inbetween(fitted, keys, times=None, *, frames_between=None, route="clips", grid=0, smooth=True,
              blend=None, neighbors=12, reach=3.0, asf=None, fps=None, clean_feet=True,
              free_roots=False, progress=None):
    """A motion through key poses on a fitted 2-D map of clips (what `motionmap inbetween` does;
    docs/synthesis.md, "Key poses and in-betweening"): every key pose is hit exactly, root position
    and heading included (but with free_roots), and between keys the motion follows the cheapest
    route through the valid region of the map. keys: each (clip, frame) — a clip path (one that is
    no file: the end of a map clip's path, e.g. "walk.bvh") or Clip of the map's skeleton and a
    frame from 0; a frame that is not a sample of the map is placed on it
    as transform() places frames — or (x, y), a map point (the blend there, root free). times:
    seconds per key, or None; frames_between: frames between consecutive keys, or None (then the
    times, or the samples' own speed along each route, at least the time the clips take to walk the
    keys' distance; keys of one clip: its own time between them; keys of two clips: at least the
    0.6 s of a jump's crossfade, and of two gaits the nearest time at which the later key's gait
    phase comes round); route: "clips" (the clips' own frames played on, jumping between clips where
    their map points meet, crossfaded; where no jumps join two keys' clips, each played towards the
    middle) or "grid" (the cheapest path over a grid through the valid region); grid: cells along
    the map's longer side (0 = from its density); smooth: smooth the grid route; blend, neighbors,
    reach: as inverse_transform; asf, fps: for .amc keys; clean_feet: hold the feet still through
    their contacts, the keys' frames left exact (as synthesize); free_roots: only the first key's
    root stands where it stood in its clip, each later key's pose is still exact but its root
    stands where the clips carry it (keys of takes captured in different places). Returns (Clip,
    route): the clip's warnings say what went wrong (frames outside the data; keys standing further
    apart than the clips walk in the time given, or the clips carrying the root elsewhere or
    leaving it facing away, so that it glides or turns and the feet slide; a time out of step
    with the keys' gait, with the time in step; feet not cleaned); route is a dict with "points" (#frames by 2:
    each frame's map point), "key_frames", "routes" (per segment, the route polyline), "valid" (per
    frame) and "grid" (cells along x and y)."""
    fitted._check_fitted()
    if not isinstance(fitted.map_, _motionmap._ClipMap):
        raise Error("inbetween: motions are blended from clips; this map was fitted on an array")
    return fitted.map_.inbetween(
        list(keys), None if times is None else [float(t) for t in times],
        -1 if frames_between is None else int(frames_between), str(route), int(grid),
        bool(smooth), blend or "",
        int(neighbors), float(reach), "" if asf is None else os.fspath(asf),
        0.0 if fps is None else float(fps), bool(clean_feet), bool(free_roots), progress)


def read_map(path):
    """Reads a map file (`motionmap map --save`, write_map; docs/map-file.md) as a fitted
    estimator of its method, with the parameters it was made with: transform() places new clips
    on it. Raises motionmap.Error for a file that is missing, of another format or damaged. A file
    an older MotionMap wrote, without checksums, reads with a warning that says so."""
    state = _motionmap._read_map(path)
    for note in state.read_notes:
        warnings.warn(note, stacklevel=2)
    options = state.options
    cls = _ESTIMATORS[options.pop("method")]
    names = cls._get_param_names()
    params = {k: v for k, v in options.items() if k in names}
    if params.get("n_landmarks") == 0:
        params["n_landmarks"] = None
    if "frames" in params and tuple(params["frames"]) == (0, None):
        params["frames"] = None
    estimator = cls(**params)
    estimator.map_ = state
    estimator._set_fitted_attributes()
    return estimator


def write_map(estimator, path):
    """Writes a fitted map of clips as a map file (HDF5; h5py reads it too; docs/map-file.md)."""
    estimator._check_fitted()
    if not isinstance(estimator.map_, _motionmap._ClipMap):
        raise Error("write_map: map files hold maps of clips (with their clips' records); this "
                    "map was fitted on an array (pickle it instead)")
    estimator.map_.write_map(path)
