"""splineskin: deform vector art and keep it splines.

Linear blend skinning of a drawing's cubic Bézier curves, fitted back by cubics that keep the
drawing's junctions (the paper's closed-form fit), with the weights, meshes and solvers of the
Rust library behind the ``splineskin`` command line. Arrays are numpy ``float64`` in C order.

    >>> import numpy as np, splineskin
    >>> drawing = splineskin.Drawing.from_svg(
    ...     '<svg xmlns="http://www.w3.org/2000/svg"><path d="M0 0 C30 40 70 40 100 0"/></svg>')
    >>> rig = splineskin.SplineRig(drawing, np.array([[0.0, 0.0], [100.0, 0.0]]), weights="shepard")
    >>> lift = splineskin.translations([[0, 0], [0, 20]])
    >>> points = rig.update(lift)
    >>> points.shape
    (4, 2)
    >>> bool(np.allclose(rig.update(splineskin.translations([[5, 5], [5, 5]])), drawing.points + 5))
    True

Classes: :class:`Drawing` (a drawing read from SVG, written back with ``to_svg``),
:class:`Scene` (a scene file, ours or the paper authors'), :class:`SplineRig` (the
precomputed fit; ``update`` per frame, into the caller's array if given), :class:`Operator`
(a deformation operator approximating ARAP or symmetric ARAP, trained or read) and
:class:`OperatorRig` (a drawing joined to one), :class:`Cage` and :class:`SubdivRig`
(Catmull–Clark cages, their limit surface, the subdivision rig). Functions:
:func:`harmonic` and :func:`bbw` (weights on a triangle mesh, libigl's conventions),
:func:`mvc` (mean value coordinates of a polygon),
:func:`paths_of`, :func:`identity_pose`, :func:`translations`. Errors of the library raise
:class:`SplineSkinError` with its message.
"""

from __future__ import annotations

import numpy as np

from ._splineskin import (
    Cage,
    Drawing,
    Operator,
    OperatorRig,
    Scene,
    SplineRig,
    SplineSkinError,
    SubdivRig,
    __version__,
    bbw,
    harmonic,
    mvc,
)

__all__ = [
    "Cage",
    "Drawing",
    "Operator",
    "OperatorRig",
    "Scene",
    "SplineRig",
    "SplineSkinError",
    "SubdivRig",
    "__version__",
    "bbw",
    "harmonic",
    "identity_pose",
    "mvc",
    "paths_of",
    "posed_handles",
    "translations",
]


def paths_of(drawing: Drawing, points: np.ndarray) -> list[np.ndarray]:
    """Each path's rows of ``points`` (``drawing.n_points × 2``, as ``Drawing.points`` and
    ``SplineRig.update`` lay them out), as views: no copy."""
    offsets = drawing.offsets
    if points.shape[0] != offsets[-1]:
        raise ValueError(f"points: {points.shape[0]} rows, the drawing has {offsets[-1]} chain points")
    return [points[a:b] for a, b in zip(offsets[:-1], offsets[1:])]


def identity_pose(n_handles: int) -> np.ndarray:
    """``n_handles`` identity maps: a ``n_handles × 2 × 3`` array of ``[[1, 0, 0], [0, 1, 0]]``."""
    pose = np.zeros((n_handles, 2, 3))
    pose[:, 0, 0] = 1.0
    pose[:, 1, 1] = 1.0
    return pose


def translations(offsets) -> np.ndarray:
    """A pose moving handle ``i`` by ``offsets[i]`` (``n × 2``): ``n × 2 × 3`` affine maps."""
    offsets = np.asarray(offsets, dtype=np.float64)
    if offsets.ndim != 2 or offsets.shape[1] != 2:
        raise ValueError(f"offsets: an array of shape (n, 2) expected, got {offsets.shape}")
    pose = identity_pose(offsets.shape[0])
    pose[:, :, 2] = offsets
    return pose


def posed_handles(handles, pose) -> np.ndarray:
    """Where ``pose`` (``n × 2 × 3`` affine maps) takes the point handles ``handles``
    (``n × 2``): the configuration ``Q`` an :class:`Operator` follows."""
    handles = np.asarray(handles, dtype=np.float64)
    pose = np.asarray(pose, dtype=np.float64)
    return np.einsum("nij,nj->ni", pose[:, :2, :2], handles) + pose[:, :2, 2]
