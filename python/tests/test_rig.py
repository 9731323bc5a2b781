"""Rigs: the same numbers as the command line, the invariants of the fit, numpy in and out."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

import splineskin
from conftest import ASSETS, data_file, run_cli

FISH_SCENE = ASSETS / "demo-scene.json"
# The paper authors' scenes (their format: flexible G¹, as their solver), with a pose each.
AUTHORS_SCENES = [
    "vectorskinning/turtle-seven-stack/comparison/shepard ours/turtles-seven-deformation.json",
    "vectorskinning/clam-songrun/clam-Our-shepard/clam-songrun-deformation.json",
]


def cli_points(scene, pose: int, tmp_path) -> np.ndarray:
    """The chain points `splineskin deform SCENE --pose N -o out.json` writes, concatenated."""
    out = tmp_path / f"pose{pose}.json"
    run_cli("deform", str(scene), "--pose", str(pose), "-o", str(out))
    paths = json.loads(out.read_text())["paths"]
    return np.array([p for path in paths for p in path["points"]], dtype=np.float64)


def test_the_bundled_scene_deforms_as_the_command_line_does(tmp_path):
    scene = splineskin.Scene.load(FISH_SCENE)
    rig = splineskin.SplineRig.from_scene(scene)
    assert (rig.engine, rig.flexible) == ("ours", scene.flexible)
    for k in range(scene.n_poses):
        ours = rig.update(scene.pose(k))
        cli = cli_points(FISH_SCENE, k, tmp_path)
        assert ours.shape == cli.shape
        gap = np.abs(ours - cli).max() / rig.drawing.diagonal
        assert gap <= 1e-12, f"pose {k}: {gap:.2e} of the diagonal"


@pytest.mark.parametrize("relative", AUTHORS_SCENES)
def test_the_authors_scenes_deform_as_the_command_line_does(relative, tmp_path):
    path = data_file(relative)
    rig = splineskin.SplineRig.from_scene(path)
    scene = splineskin.Scene.load(path)
    assert rig.flexible  # their format asks for flexible G¹
    ours = rig.update(scene.pose(0))
    cli = cli_points(path, 0, tmp_path)
    gap = np.abs(ours - cli).max() / rig.drawing.diagonal
    assert gap <= 1e-12, f"{relative}: {gap:.2e} of the diagonal"


@pytest.fixture(scope="module")
def fish_rig():
    drawing = splineskin.Drawing.from_svg(ASSETS / "demo.svg")
    handles = splineskin.Scene.load(FISH_SCENE).handles
    return splineskin.SplineRig(drawing, handles, weights="shepard")


def test_identity_gives_the_drawing_back(fish_rig):
    rest = fish_rig.drawing.points
    out = fish_rig.update(splineskin.identity_pose(fish_rig.n_handles))
    assert np.abs(out - rest).max() <= 1e-12 * fish_rig.drawing.diagonal


def test_one_similarity_on_every_handle_is_that_map(fish_rig):
    # A similarity (turn, uniform scale, move): every junction relation of the fit (C¹, G¹ and
    # fixed angles with their ratios) survives it, so the fit is the map itself. (A shear
    # would not keep the fish's fixed-angle junctions' angles: the fit then departs from it.)
    rest = fish_rig.drawing.points
    c, s = 1.3 * np.cos(0.5), 1.3 * np.sin(0.5)
    a = np.array([[c, -s, 40.0], [s, c, -7.0]])
    pose = np.repeat(a[None], fish_rig.n_handles, axis=0)
    out = fish_rig.update(pose)
    expected = rest @ a[:, :2].T + a[:, 2]
    assert np.abs(out - expected).max() <= 1e-12 * fish_rig.drawing.diagonal * 2
    # The same map given 3 × 3.
    full = np.zeros((fish_rig.n_handles, 3, 3))
    full[:, :2] = a
    full[:, 2, 2] = 1.0
    assert np.array_equal(fish_rig.update(full), out)


def test_update_writes_into_the_callers_array(fish_rig):
    out = np.empty((fish_rig.n_points, 2))
    pose = splineskin.translations(np.ones((fish_rig.n_handles, 2)) * 3.0)
    result = fish_rig.update(pose, out)
    assert result is out  # no copy: the caller's array, written in place
    assert np.allclose(out, fish_rig.drawing.points + 3.0, rtol=0, atol=1e-12 * fish_rig.drawing.diagonal)
    # The operator's product, restated in numpy.
    coefficients = np.stack([pose[:, 0, 0], pose[:, 1, 0], pose[:, 0, 1], pose[:, 1, 1], pose[:, 0, 2], pose[:, 1, 2]], axis=1)
    assert np.allclose(fish_rig.operator @ coefficients.reshape(-1), out.reshape(-1), rtol=0, atol=1e-9)


def test_weights_sum_to_one_and_are_one_at_their_handle(fish_rig):
    handles = splineskin.Scene.load(FISH_SCENE).handles
    w = fish_rig.weights_at(handles + 1e-3)
    assert w.shape == (len(handles), fish_rig.n_handles)
    assert np.allclose(w.sum(axis=1), 1.0)
    assert np.all(np.argmax(w, axis=1) == np.arange(len(handles)))


def test_a_drawing_with_junction_kinds_and_mesh_weights():
    stroke = splineskin.Drawing.from_svg(
        '<svg xmlns="http://www.w3.org/2000/svg"><path d="M0 0 C10 20 30 20 40 0 C50 -20 70 -20 80 0 Z" fill="blue"/></svg>')
    handles = np.array([[10.0, 5.0], [70.0, -5.0]])
    rig = splineskin.SplineRig(stroke, handles, weights="bbw", junctions=[(0, 1, "C0")])
    assert rig.drawing.n_curves == 3
    out = rig.update(splineskin.identity_pose(2))
    assert np.abs(out - rig.drawing.points).max() <= 1e-9 * rig.drawing.diagonal


def test_bad_input_is_a_clear_error(fish_rig, tmp_path):
    with pytest.raises(ValueError, match=r"\(5, 2, 3\)"):
        fish_rig.update(np.zeros((4, 2, 3)))
    with pytest.raises(ValueError, match="finite"):
        fish_rig.update(np.full((5, 2, 3), np.inf))
    with pytest.raises(ValueError, match="out"):
        fish_rig.update(splineskin.identity_pose(5), np.empty((3, 2)))
    with pytest.raises(ValueError, match="C order"):
        fish_rig.update(splineskin.identity_pose(5), np.asfortranarray(np.empty((fish_rig.n_points, 2))))
    with pytest.raises(TypeError):
        fish_rig.update(splineskin.identity_pose(5), np.empty((fish_rig.n_points, 2), dtype=np.float32))
    with pytest.raises(ValueError, match="last row"):
        bad = np.zeros((5, 3, 3))
        bad[:, 0, 0] = bad[:, 1, 1] = 1.0
        fish_rig.update(bad)
    with pytest.raises(ValueError, match="weights"):
        splineskin.SplineRig(fish_rig.drawing, np.zeros((2, 2)), weights="gaussian")
    with pytest.raises(ValueError, match="kind"):
        splineskin.SplineRig(fish_rig.drawing, np.array([[1.0, 2.0]]), weights="shepard", junctions=[(0, 0, "C9")])
    with pytest.raises(FileNotFoundError, match="missing.json"):
        splineskin.SplineRig.from_scene(tmp_path / "missing.json")
    broken = tmp_path / "broken.json"
    broken.write_text('{"splineskin_scene": 1, "svg_text": "<svg/>", "handles": [{"position": [0, "x"]}]}')
    with pytest.raises(splineskin.SplineSkinError, match="broken.json"):
        splineskin.Scene.load(broken)


def test_the_fit_beats_the_naive_baselines_on_the_fish(fish_rig):
    scene = splineskin.Scene.load(FISH_SCENE)
    baselines = {
        engine: splineskin.SplineRig(fish_rig.drawing, scene.handles, weights="shepard", engine=engine)
        for engine in ["fourcontrols", "twoendpoints", "jacobian"]
    }
    for k in range(scene.n_poses):
        pose = scene.pose(k)
        ours = fish_rig.metrics(pose)
        assert ours["per_curve"].shape == (fish_rig.drawing.n_curves, 3)
        # Measured on the result given or on the rig's own: the same.
        again = fish_rig.metrics(pose, fish_rig.update(pose))
        assert all(again[key] == ours[key] for key in ["energy", "max", "rms"])
        assert np.array_equal(again["per_curve"], ours["per_curve"])
        for engine, rig in baselines.items():
            assert rig.engine == engine
            theirs = rig.metrics(pose)
            assert ours["energy"] < theirs["energy"], f"pose {k}: {engine}"
    still = fish_rig.metrics(splineskin.identity_pose(fish_rig.n_handles))
    assert still["max"] <= 1e-12
    with pytest.raises(ValueError, match="engine"):
        splineskin.SplineRig(fish_rig.drawing, scene.handles, engine="best")


def test_to_svg_is_the_document_splineskin_deform_writes(tmp_path):
    """Pins on the fish (its text label and gradients carried), one moved and one turned:
    the document, byte for byte, with the domain's margin given as `deform --margin` takes it."""
    pins = [(150.0, 200.0), (300.0, 160.0), (450.0, 220.0)]
    rig = splineskin.SplineRig(splineskin.Drawing.from_svg(ASSETS / "demo.svg"), np.array(pins),
                               weights="bbw", margin=0.02)
    turn = np.radians(20.0)
    c, s = np.cos(turn), np.sin(turn)
    px, py = pins[1]
    transforms = np.array([[[1, 0, 12], [0, 1, -30]],
                           [[c, -s, px - c * px + s * py], [s, c, py - s * px - c * py]],
                           [[1, 0, 0], [0, 1, 0]]], dtype=np.float64)
    out = tmp_path / "native.svg"
    run_cli("deform", str(ASSETS / "demo.svg"), *[f for p in pins for f in ("--pin", f"{p[0]},{p[1]}")],
            "--weights", "bbw", "--margin", "0.02", "--move", "0:12,-30", "--rotate", "1:20", "-o", str(out))
    ours, native = rig.to_svg(transforms), out.read_text()
    assert 'id="label"' in ours and "transform=" in ours
    number = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
    # The same document, its numbers to rounding (the turn's matrix computed here, not there).
    assert re.sub(number, "#", ours) == re.sub(number, "#", native)
    a, b = (np.array([float(v) for v in re.findall(number, t)]) for t in (ours, native))
    assert np.abs(a - b).max() <= 1e-9 * rig.drawing.diagonal
    # A control: the identity pose writes other numbers.
    rest = np.array([float(v) for v in re.findall(number, rig.to_svg(np.tile(np.eye(3)[:2], (3, 1, 1))))])
    assert np.abs(rest - b).max() > 1e-3 * rig.drawing.diagonal


def test_a_margin_out_of_range_or_without_a_domain_is_refused():
    drawing = splineskin.Drawing.from_svg(ASSETS / "demo.svg")
    with pytest.raises(ValueError, match="margin=2: expected a fraction"):
        splineskin.SplineRig(drawing, np.array([[100.0, 100.0]]), margin=2.0)
    with pytest.raises(ValueError, match="shepard weights have no domain"):
        splineskin.SplineRig(drawing, np.array([[100.0, 100.0]]), weights="shepard", margin=0.1)
