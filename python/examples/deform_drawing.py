"""Deforms the bundled fish by each of its scene's poses, writes the SVGs next to this script's
output folder, and plots the rest and first pose with matplotlib if it is installed.

    pip install ./python
    python python/examples/deform_drawing.py [OUT_DIR]
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

import splineskin

ASSETS = Path(__file__).resolve().parents[2] / "crates" / "splineskin" / "assets"


def main() -> None:
    out_dir = Path(sys.argv[1] if len(sys.argv) > 1 else "out")
    out_dir.mkdir(parents=True, exist_ok=True)
    scene = splineskin.Scene.load(ASSETS / "demo-scene.json")
    rig = splineskin.SplineRig.from_scene(scene)
    drawing = rig.drawing
    points = np.empty((rig.n_points, 2))  # written in place by every update
    for k, name in enumerate(scene.pose_names):
        rig.update(scene.pose(k), points)
        path = out_dir / f"fish-{name or k}.svg"
        path.write_text(drawing.to_svg(points))
        print(f"{path}: {drawing.n_curves} curves, pose {name or k}")
    try:
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is not installed: no plot")
        return
    rig.update(scene.pose(0), points)
    fig, ax = plt.subplots(figsize=(6, 4))
    for shape, colour in [(drawing.points, "0.7"), (points, "tab:blue")]:
        for part in splineskin.paths_of(drawing, shape):
            ax.plot(*bezier_polyline(part).T, color=colour, lw=1)
    ax.plot(*scene.handles.T, "o", color="tab:red")
    ax.set_aspect("equal")
    ax.invert_yaxis()  # SVG's y points down
    fig.savefig(out_dir / "fish.png", dpi=120)
    print(f"{out_dir / 'fish.png'}: rest (grey) and pose {scene.pose_names[0]} (blue)")


def bezier_polyline(chain: np.ndarray, samples: int = 24) -> np.ndarray:
    """Points along a path's cubics (its chain points: anchors every third)."""
    t = np.linspace(0.0, 1.0, samples)[:, None]
    basis = [(1 - t) ** 3, 3 * (1 - t) ** 2 * t, 3 * (1 - t) * t**2, t**3]
    pieces = [sum(b * chain[k + i] for i, b in enumerate(basis)) for k in range(0, len(chain) - 1, 3)]
    return np.vstack(pieces)


if __name__ == "__main__":
    main()
