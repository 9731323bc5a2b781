"""The example script runs and writes what it says: one SVG per pose of the fish, each read back
with the drawing's curves, the first the command line's deformation."""

from __future__ import annotations

import subprocess
import sys

import numpy as np

import splineskin
from conftest import ASSETS, REPO


def test_the_example_deforms_the_bundled_drawing(tmp_path):
    done = subprocess.run([sys.executable, str(REPO / "python" / "examples" / "deform_drawing.py"), str(tmp_path)],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    scene = splineskin.Scene.load(ASSETS / "demo-scene.json")
    rig = splineskin.SplineRig.from_scene(scene)
    for k, name in enumerate(scene.pose_names):
        back = splineskin.Drawing.from_svg(tmp_path / f"fish-{name}.svg")
        assert back.n_curves == rig.drawing.n_curves
        gap = np.abs(back.points - rig.update(scene.pose(k))).max()
        assert gap <= 1e-9 * rig.drawing.diagonal, f"{name}: {gap}"
