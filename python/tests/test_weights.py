"""Weights on a triangle mesh in libigl's conventions: against values derived by hand, the
invariants of the families, and libigl's own results (the reference data and, when installed,
libigl's Python package side by side)."""

from __future__ import annotations

import json

import numpy as np
import pytest

import splineskin
from conftest import data_file


def square_grid(n: int = 3):
    """The unit square as an n × n grid of vertices, two counter-clockwise triangles a cell."""
    xs = np.linspace(0.0, 1.0, n)
    V = np.array([[x, y] for y in xs for x in xs])
    F = np.array([t for j in range(n - 1) for i in range(n - 1) for a in [j * n + i]
                  for t in ([a, a + 1, a + n + 1], [a, a + n + 1, a + n])])
    return V, F


def test_harmonic_on_a_small_grid_matches_the_values_worked_out_by_hand():
    # 3 × 3 grid, handles at opposite corners. The interior vertex 4 is the centre: by the
    # mesh's symmetry (a reflection across the other diagonal swaps the handles) its weights
    # are exactly 1/2. The cotangent Laplacian on this mesh gives 5/8 at the edge midpoints
    # next to handle 0 (k = 1); the biharmonic weights 0.7.
    V, F = square_grid(3)
    W1 = splineskin.harmonic(V, F, [0, 8])
    assert W1.shape == (9, 2)
    assert np.allclose(W1[:, 0], [1, 0.625, 0.5, 0.625, 0.5, 0.375, 0.5, 0.375, 0], atol=1e-12)
    W2 = splineskin.harmonic(V, F, [0, 8], k=2)
    assert np.allclose(W2[:, 0], [1, 0.7, 0.5, 0.7, 0.5, 0.3, 0.5, 0.3, 0], atol=1e-12)
    assert np.allclose(W1.sum(axis=1), 1.0) and np.allclose(W2.sum(axis=1), 1.0)


def test_conventions_of_libigl_are_accepted():
    V, F = square_grid(5)
    W = splineskin.harmonic(V, F, [0, 24])
    # n × 3 planar vertices, int32 faces, clockwise triangles, an explicit bc: the same.
    V3 = np.hstack([V, np.full((len(V), 1), 2.5)])
    assert np.allclose(splineskin.harmonic(V3, F.astype(np.int32), np.array([0, 24], dtype=np.int32)), W, atol=1e-14)
    assert np.allclose(splineskin.harmonic(V, F[:, [0, 2, 1]], [0, 24]), W, atol=1e-14)
    assert np.allclose(splineskin.harmonic(V, F, [0, 24], np.eye(2)), W, atol=1e-14)
    # A constant boundary value gives that constant everywhere.
    assert np.allclose(splineskin.harmonic(V, F, [0, 4, 20, 24], np.full((4, 1), 0.3)), 0.3)


def test_bbw_is_bounded_and_partitions_unity_when_asked():
    V, F = square_grid(9)
    b = [0, 8, 80, 40]
    W = splineskin.bbw(V, F, b)
    assert W.min() >= -1e-12 and W.max() <= 1 + 1e-12
    assert np.allclose(W[b], np.eye(4))
    Wn = splineskin.bbw(V, F, b, partition_unity=True)
    assert np.allclose(Wn.sum(axis=1), 1.0)
    # Each column is its own program: on one thread, the same to the last bit.
    assert np.array_equal(splineskin.bbw(V, F, b, parallel=False), W)


def test_bad_meshes_are_clear_errors():
    V, F = square_grid(3)
    with pytest.raises(ValueError, match="F\\[0, 1\\] = 99"):
        splineskin.harmonic(V, np.array([[0, 99, 4]]), [0])
    with pytest.raises(ValueError, match="planar"):
        splineskin.harmonic(np.hstack([V, np.arange(9.0)[:, None]]), F, [0, 8])
    with pytest.raises(ValueError, match="bc: 1 rows"):
        splineskin.harmonic(V, F, [0, 8], np.ones((1, 2)))
    with pytest.raises(splineskin.SplineSkinError):
        splineskin.harmonic(V, F, [0, 0])  # a handle repeated
    with pytest.raises(splineskin.SplineSkinError):
        mixed = F.copy()
        mixed[0] = mixed[0, [0, 2, 1]]
        splineskin.harmonic(V, mixed, [0, 8])


@pytest.mark.parametrize("shape", ["bar", "ushape"])
def test_the_reference_meshes_give_libigls_weights(shape):
    ref = json.loads(data_file(f"reference-igl/{shape}.json").read_text())
    V = np.array(ref["mesh"]["V"])
    F = np.array(ref["mesh"]["F"])
    b = np.array(ref["handles"]["indices"])
    weights = ref["weights"]
    assert np.abs(splineskin.harmonic(V, F, b) - np.array(weights["harmonic_k1"]["W"])).max() <= 1e-8
    assert np.abs(splineskin.harmonic(V, F, b, k=2) - np.array(weights["harmonic_k2"]["W"])).max() <= 1e-8
    assert np.abs(splineskin.bbw(V, F, b) - np.array(weights["bbw_raw"]["W"])).max() <= 1e-4
    assert np.abs(splineskin.bbw(V, F, b, partition_unity=True) - np.array(weights["bbw_normalized"]["W"])).max() <= 1e-4


def test_mean_value_coordinates_reproduce_points_and_sum_to_one():
    cage = np.array([[0.0, 0.0], [4.0, 0.0], [5.0, 3.0], [2.0, 5.0], [-1.0, 2.0]])
    points = np.array([[2.0, 2.0], [0.5, 0.3], [6.0, -2.0], [3.0, 4.5]])  # two inside, two outside
    W = splineskin.mvc(cage, points)
    assert W.shape == (4, 5)
    assert np.allclose(W.sum(axis=1), 1.0)
    assert np.allclose(W @ cage, points)
    with pytest.raises(splineskin.SplineSkinError):
        splineskin.mvc(cage[::-1], points)  # clockwise


def test_handles_by_position_are_the_vertices_there():
    V, F = square_grid(5)
    by_index = splineskin.bbw(V, F, [0, 12, 24])
    assert np.array_equal(splineskin.bbw(V, F, V[[0, 12, 24]]), by_index)
    assert np.array_equal(splineskin.harmonic(V, F, [[0.0, 0.0], [1.0, 1.0]]), splineskin.harmonic(V, F, [0, 24]))
    with pytest.raises(ValueError, match=r"b\[1\] = \(0.3, 0.3\): no vertex there"):
        splineskin.harmonic(V, F, [[0.0, 0.0], [0.3, 0.3]])
