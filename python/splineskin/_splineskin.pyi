"""Type stubs of the extension module (python/src/*.rs); the docstrings at run time are the
Rust doc comments."""

from __future__ import annotations

import os
from typing import Any, Callable, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

__version__: str

class SplineSkinError(Exception):
    """An error of the library: bad input, with its message naming the file and element."""

class Drawing:
    """A drawing of cubic Bézier paths read from an SVG document."""

    @staticmethod
    def from_svg(source: Union[str, os.PathLike[str]], /) -> Drawing:
        """Reads an SVG document: its text (a string starting with ``<``) or a path to it."""
    @property
    def name(self) -> str: ...
    @property
    def n_paths(self) -> int: ...
    @property
    def n_curves(self) -> int: ...
    @property
    def n_points(self) -> int: ...
    @property
    def points(self) -> npt.NDArray[np.float64]:
        """Rest control points of every path, concatenated: ``n_points × 2``."""
    @property
    def offsets(self) -> list[int]:
        """Where each path's rows start in ``points`` (``n_paths + 1`` numbers)."""
    @property
    def closed(self) -> list[bool]: ...
    @property
    def joints(self) -> list[list[str]]:
        """Junction kinds per path: ``end``, ``C0``, ``C1``, ``G1`` or ``angle``."""
    @property
    def diagonal(self) -> float: ...
    def to_svg(self, points: npt.NDArray[np.float64], *, viewbox: str = "keep") -> str:
        """The SVG document with ``points`` in place of the drawing's control points."""
    def domain(
        self,
        handles: npt.NDArray[np.float64],
        *,
        max_area_fraction: Optional[float] = None,
        max_vertices: Optional[int] = None,
        min_angle: Optional[float] = None,
        holes: bool = False,
        shape: str = "enclosing",
        margin: Optional[float] = None,
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.int64], npt.NDArray[np.int64]]:
        """The triangulated domain with a vertex at each handle: ``(V, F, b)``;
        ``shape="art"`` for the art's own shape grown by ``margin``."""

class Scene:
    """A scene file (ours or the paper authors'): drawing, handles, weights, poses."""

    @staticmethod
    def load(path: Union[str, os.PathLike[str]], /) -> Scene: ...
    @staticmethod
    def from_json(text: str, /, name: str = "<scene>") -> Scene: ...
    @property
    def name(self) -> str: ...
    @property
    def handles(self) -> npt.NDArray[np.float64]:
        """Point handles' rest positions, ``n × 2``."""
    @property
    def n_handles(self) -> int: ...
    @property
    def weights(self) -> str: ...
    @property
    def flexible(self) -> bool: ...
    @property
    def n_poses(self) -> int: ...
    @property
    def pose_names(self) -> list[Optional[str]]: ...
    def pose(self, index: Union[int, str] = 0) -> npt.NDArray[np.float64]:
        """Pose ``index`` (or named so): ``n_handles × 2 × 3`` affine maps."""
    def drawing(self, *, compat: Optional[str] = None) -> Drawing: ...

class SplineRig:
    """The spline fit of a skinning deformation, precomputed."""

    def __init__(
        self,
        drawing: Drawing,
        handles: npt.NDArray[np.float64],
        *,
        weights: str = "bbw",
        exponent: float = 2.0,
        junctions: Optional[Sequence[tuple[int, int, str]]] = None,
        flexible: bool = False,
        engine: str = "ours",
        margin: Optional[float] = None,
    ) -> None: ...
    @staticmethod
    def from_scene(
        scene: Union[Scene, str, os.PathLike[str]],
        *,
        compat: Optional[str] = None,
        flexible: bool = False,
    ) -> SplineRig: ...
    def update(
        self,
        transforms: npt.NDArray[np.float64],
        out: Optional[npt.NDArray[np.float64]] = None,
    ) -> npt.NDArray[np.float64]:
        """Control points (``n_points × 2``) for one affine map per handle
        (``n_handles × 2 × 3``), written into ``out`` when given."""
    def metrics(
        self,
        transforms: npt.NDArray[np.float64],
        points: Optional[npt.NDArray[np.float64]] = None,
    ) -> dict[str, Any]:
        """Energy, max and RMS distance (/ diagonal) of ``points`` from the skinned target."""
    def to_svg(
        self,
        transforms: npt.NDArray[np.float64],
        *,
        viewbox: str = "keep",
        scale_strokes: bool = False,
    ) -> str:
        """The SVG document deformed by ``transforms`` as ``splineskin deform`` writes it: ids,
        styles and structure kept; gradients, text and images carried by the deformation."""
    def weights_at(self, points: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]: ...
    @property
    def flexible(self) -> bool: ...
    @property
    def engine(self) -> str: ...
    @property
    def drawing(self) -> Drawing: ...
    @property
    def n_handles(self) -> int: ...
    @property
    def n_points(self) -> int: ...
    @property
    def operator(self) -> npt.NDArray[np.float64]:
        """``O``: ``(2 · n_points) × (6 · n_handles)``, a copy."""

class Cage:
    """A Catmull–Clark control cage."""

    @staticmethod
    def from_obj(source: Union[str, os.PathLike[str]], /) -> Cage:
        """Reads a cage: a path, or OBJ text (a string with a line break)."""
    @property
    def positions(self) -> npt.NDArray[np.float64]: ...
    @property
    def faces(self) -> list[list[int]]: ...
    @property
    def n_vertices(self) -> int: ...
    @property
    def n_faces(self) -> int: ...
    def to_obj(self, positions: Optional[npt.NDArray[np.float64]] = None) -> str: ...
    def limit(
        self,
        ptex: Sequence[int],
        uv: npt.NDArray[np.float64],
        positions: Optional[npt.NDArray[np.float64]] = None,
    ) -> npt.NDArray[np.float64]:
        """Limit-surface points at ptex faces ``ptex`` and parameters ``uv`` (``m × 2``)."""

class SubdivRig:
    """The rig of a subdivision scene."""

    @staticmethod
    def from_scene(path: Union[str, os.PathLike[str]], /) -> SubdivRig: ...
    def update(
        self,
        transforms: npt.NDArray[np.float64],
        out: Optional[npt.NDArray[np.float64]] = None,
    ) -> npt.NDArray[np.float64]:
        """Cage positions (``n_vertices × 3``) for one 3 × 4 map per handle."""
    def pose(self, index: int = 0) -> npt.NDArray[np.float64]: ...
    def animation(self) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """Frame times (``n_frames``) and fitted cages (``n_frames × n_vertices × 3``)."""
    def write_animation(
        self, path: Union[str, os.PathLike[str]], *, level: int = 3, up: str = "y"
    ) -> None:
        """Writes the animation as ``.usda`` (Catmull-Clark cage) or ``.glb`` (limit surface)."""
    @property
    def n_poses(self) -> int: ...
    @property
    def cage(self) -> Cage: ...
    @property
    def n_handles(self) -> int: ...
    @property
    def n_vertices(self) -> int: ...

class Operator:
    """A deformation operator on a triangle mesh, driven by point handles."""

    @staticmethod
    def train(
        V: npt.ArrayLike,
        F: npt.ArrayLike,
        b: npt.ArrayLike,
        *,
        energy: str = "sarap",
        samples: int = 100,
        seed: int = 1,
        progress: Optional[Callable[[int, int, int, int], object]] = None,
    ) -> Operator:
        """Trains on ``(V, F)`` with handles at ``b``; ``progress(solved, to_solve, stage,
        n_stages)`` after each solve. An exception from ``progress``, or Ctrl-C, stops it."""
    @staticmethod
    def from_scene(
        scene: Union[Scene, str, os.PathLike[str]],
        *,
        energy: Optional[str] = None,
        samples: Optional[int] = None,
        seed: Optional[int] = None,
        cover: Optional[str] = None,
        progress: Optional[Callable[[int, int, int, int], object]] = None,
    ) -> Operator: ...
    @staticmethod
    def load(path: Union[str, os.PathLike[str]], /) -> Operator: ...
    def save(self, path: Union[str, os.PathLike[str]], /) -> None: ...
    def evaluate(self, Q: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
        """The mesh's vertices for handle positions ``Q`` (``n_handles × 2``)."""
    def join(self, drawing: Union[Drawing, Scene]) -> OperatorRig: ...
    @property
    def V(self) -> npt.NDArray[np.float64]: ...
    @property
    def F(self) -> npt.NDArray[np.int64]: ...
    @property
    def b(self) -> npt.NDArray[np.int64]: ...
    @property
    def rest_handles(self) -> npt.NDArray[np.float64]: ...
    @property
    def n_handles(self) -> int: ...
    @property
    def metadata(self) -> dict[str, Any]: ...

class OperatorRig:
    """A drawing joined to an operator."""

    def update(
        self, Q: npt.NDArray[np.float64], out: Optional[npt.NDArray[np.float64]] = None
    ) -> npt.NDArray[np.float64]: ...
    @property
    def operator(self) -> npt.NDArray[np.float64]: ...
    @property
    def n_handles(self) -> int: ...
    @property
    def n_points(self) -> int: ...

def harmonic(
    V: npt.ArrayLike,
    F: npt.ArrayLike,
    b: npt.ArrayLike,
    bc: Optional[npt.ArrayLike] = None,
    k: int = 1,
) -> npt.NDArray[np.float64]:
    """Order-``k`` polyharmonic weights on the mesh ``(V, F)`` with ``w = bc`` at ``b``
    (vertex indices, or handle positions ``k × 2`` matched to the vertices there)."""

def bbw(
    V: npt.ArrayLike,
    F: npt.ArrayLike,
    b: npt.ArrayLike,
    bc: Optional[npt.ArrayLike] = None,
    *,
    partition_unity: bool = False,
    parallel: bool = True,
) -> npt.NDArray[np.float64]:
    """Bounded biharmonic weights on the mesh ``(V, F)`` with ``w = bc`` at ``b``; the columns
    solved on all cores unless ``parallel=False`` (the same result either way)."""

def mvc(cage: npt.NDArray[np.float64], points: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """Mean value coordinates of ``points`` (``m × 2``) for the polygon ``cage`` (``n × 2``)."""
