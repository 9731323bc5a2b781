"""Subdivision surfaces from Python: cages from OBJ, the limit surface, and the rig giving the
command line's cages."""

from __future__ import annotations

import numpy as np
import pytest

import splineskin
from conftest import ASSETS, run_cli

TUBE = ASSETS / "subdiv" / "tube-scene.json"


def obj_vertices(text: str) -> np.ndarray:
    return np.array([[float(x) for x in line.split()[1:4]] for line in text.splitlines() if line.startswith("v ")])


def test_the_rig_gives_the_command_lines_cage(tmp_path):
    rig = splineskin.SubdivRig.from_scene(TUBE)
    rest = rig.cage.positions
    diagonal = np.linalg.norm(rest.max(axis=0) - rest.min(axis=0))
    for k in range(rig.n_poses):
        out = tmp_path / f"pose{k}.obj"
        run_cli("subdiv", "deform", str(TUBE), "--pose", str(k), "-o", str(out))
        cli = obj_vertices(out.read_text())
        ours = np.empty((rig.n_vertices, 3))
        assert rig.update(rig.pose(k), ours) is ours
        assert np.abs(ours - cli).max() <= 1e-12 * diagonal, f"pose {k}"


def test_identity_and_one_affine_map_are_reproduced():
    rig = splineskin.SubdivRig.from_scene(TUBE)
    rest = rig.cage.positions
    diagonal = np.linalg.norm(rest.max(axis=0) - rest.min(axis=0))
    identity = np.repeat(np.eye(4)[None, :3], rig.n_handles, axis=0)
    assert np.abs(rig.update(identity) - rest).max() <= 1e-9 * diagonal
    a = np.array([[1.1, 0.2, 0.0, 3.0], [-0.1, 0.9, 0.3, -1.0], [0.0, 0.1, 1.2, 0.5]])
    moved = rig.update(np.repeat(a[None], rig.n_handles, axis=0))
    assert np.abs(moved - (rest @ a[:, :3].T + a[:, 3])).max() <= 1e-9 * diagonal


def test_a_cage_from_obj_text_and_its_limit_surface():
    # A flat 3 × 3 grid of quads: its limit surface is flat too, and linear in the positions.
    lines = [f"v {x} {y} 0" for y in range(4) for x in range(4)]
    lines += [f"f {j * 4 + i + 1} {j * 4 + i + 2} {j * 4 + i + 6} {j * 4 + i + 5}" for j in range(3) for i in range(3)]
    cage = splineskin.Cage.from_obj("\n".join(lines) + "\n")
    assert (cage.n_vertices, cage.n_faces) == (16, 9)
    assert cage.faces[0] == [0, 1, 5, 4]
    uv = np.array([[0.5, 0.5], [0.25, 0.75], [0.0, 0.0]])
    points = cage.limit([4, 4, 0], uv)
    assert points.shape == (3, 3) and np.all(points[:, 2] == 0.0)
    assert np.allclose(points[0], [1.5, 1.5, 0.0])  # the middle of the middle face, by symmetry
    doubled = cage.limit([4, 4, 0], uv, positions=2.0 * cage.positions)
    assert np.allclose(doubled, 2.0 * points, rtol=0, atol=1e-12)
    again = splineskin.Cage.from_obj(cage.to_obj())
    assert np.array_equal(again.positions, cage.positions)


def test_bad_input_is_a_clear_error(tmp_path):
    with pytest.raises(FileNotFoundError):
        splineskin.Cage.from_obj(str(tmp_path / "none.obj"))
    with pytest.raises(splineskin.SplineSkinError, match="obj text"):
        splineskin.Cage.from_obj("v 0 0 0\nf 1 2 3\n")
    rig = splineskin.SubdivRig.from_scene(TUBE)
    with pytest.raises(ValueError, match=r"3, 4\)"):
        rig.update(np.zeros((rig.n_handles, 2, 4)))
    with pytest.raises(ValueError, match="last row"):
        rig.update(np.zeros((rig.n_handles, 4, 4)))
    cage = rig.cage
    with pytest.raises(splineskin.SplineSkinError, match="ptex"):
        cage.limit([10_000], np.array([[0.5, 0.5]]))
