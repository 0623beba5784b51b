"""Type stubs of the compiled module motionmap._motionmap (MotionMap's C++ library through
pybind11). Use the package motionmap; the names starting with '_' are its internals."""
import os
from typing import Any, Callable, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

_Path = Union[str, os.PathLike]
_Progress = Optional[Union[Callable[[float, str], None], Any]]  # a callable or a tqdm bar
_Clips = Union["Clip", _Path, Sequence[Union["Clip", _Path]]]

class Error(ValueError):
    """Every error of the library; parse errors read 'path:line:col: error: …'."""

class Skeleton:
    """The joints of a clip, parents before children."""
    @property
    def names(self) -> list[str]: ...
    @property
    def parents(self) -> npt.NDArray[np.int_]: ...
    @property
    def offsets(self) -> npt.NDArray[np.float64]: ...
    @property
    def channels(self) -> list[list[str]]: ...
    @property
    def end_sites(self) -> list[npt.NDArray[np.float64]]: ...
    @property
    def num_joints(self) -> int: ...
    @property
    def roots(self) -> list[int]: ...
    def find(self, name: str) -> int: ...
    def __len__(self) -> int: ...

class Clip:
    """A motion clip: skeleton, frame time, per-frame local rotations and translations."""
    @property
    def path(self) -> str: ...
    @property
    def warnings(self) -> list[str]: ...
    @property
    def skeleton(self) -> Skeleton: ...
    @property
    def frame_time(self) -> float: ...
    @property
    def fps(self) -> float: ...
    @property
    def num_frames(self) -> int: ...
    @property
    def duration(self) -> float: ...
    @property
    def rotations(self) -> npt.NDArray[np.float64]:
        """#frames by #joints by 4 (w, x, y, z)."""
    @property
    def translations(self) -> npt.NDArray[np.float64]:
        """#frames by #joints by 3."""
    @property
    def root_translations(self) -> npt.NDArray[np.float64]:
        """#frames by 3."""
    def positions(self) -> npt.NDArray[np.float64]:
        """#frames by (#joints + #end sites) by 3 world positions."""
    def info(self) -> dict[str, Any]:
        """What `motionmap info --json` prints."""
    def save(self, path: _Path) -> None:
        """Writes the clip as BVH."""
    def __len__(self) -> int: ...

def load(path: _Path, asf: Optional[_Path] = None, fps: Optional[float] = None) -> Clip:
    """Loads a .bvh, or an .amc with its .asf."""

class _ClipMap:
    coordinates: npt.NDArray[np.float64]
    eigenvalues: npt.NDArray[np.float64]
    clip_of: list[int]
    frame_of: list[int]
    paths: list[str]
    parameters: str
    notes: list[str]
    read_notes: list[str]
    warnings: list[str]
    k_used: int
    heat_used: float
    x_columns: int
    options: dict[str, Any]
    def transform(self, clips: _Clips, options: dict[str, Any], asf: str, fps: float,
                  progress: _Progress) -> npt.NDArray[np.float64]: ...
    def place_clips(self, clips: _Clips, options: dict[str, Any], asf: str, fps: float,
                    progress: _Progress) -> list[_PlacedClip]: ...
    def write_placed_map(self, placed: list[_PlacedClip], path: _Path,
                         fitted_name: str) -> None: ...
    labels: dict[str, npt.NDArray[np.object_]]
    def label_accuracy(self, k: int, sample: int) -> dict[str, dict[str, Any]]: ...
    def write_csv(self, path: _Path) -> None: ...
    def poses_at(self, Y: npt.ArrayLike, blend: str, neighbors: int, reach: float,
                 progress: _Progress) -> Clip: ...
    def inbetween(self, keys: list[Any], times: Optional[list[float]], frames_between: int,
                  grid: int, smooth: bool, blend: str, neighbors: int, reach: float, asf: str,
                  fps: float, clean_feet: bool, progress: _Progress) -> tuple[Clip, dict[str, Any]]: ...
    def synthesize(self, path_xy: npt.ArrayLike, times: Optional[list[float]], speed: float,
                   fps: float, smooth: float, blend: str, neighbors: int, reach: float,
                   clean_feet: bool, progress: _Progress) -> Clip: ...
    def edit_path(self, previous_xy: npt.ArrayLike, previous_times: Optional[list[float]],
                  path_xy: npt.ArrayLike, times: Optional[list[float]], speed: float, fps: float,
                  smooth: float, blend: str, neighbors: int, reach: float, clean_feet: bool,
                  progress: _Progress) -> tuple[Clip, dict[str, Any]]: ...
    def write_map(self, path: _Path) -> None: ...

class _PlacedClip:
    """A clip placed on a map, with its record (map_library's tasks)."""
    path: str
    frames: list[int]
    coordinates: npt.NDArray[np.float64]

class _MatrixMap:
    coordinates: npt.NDArray[np.float64]
    eigenvalues: npt.NDArray[np.float64]
    warnings: list[str]
    k_used: int
    heat_used: float
    x_columns: int
    precomputed: bool
    def transform(self, X: npt.ArrayLike, progress: _Progress) -> npt.NDArray[np.float64]: ...

def _features(clips: _Clips, options: dict[str, Any], distances: bool, neighbors: int, asf: str,
              fps: float, progress: _Progress) -> tuple[Any, Any, Any, Any, str]: ...
def _fit_clips(clips: _Clips, options: dict[str, Any], asf: str, fps: float,
               progress: _Progress, labels_from_name: str = ..., labels: str = ...) -> _ClipMap: ...
def _fit_matrix(X: npt.ArrayLike, precomputed: bool, options: dict[str, Any],
                progress: _Progress) -> _MatrixMap: ...
def _read_map(path: _Path) -> _ClipMap: ...
