"""Weights side by side with libigl's Python package: harmonic and bounded biharmonic weights of
the same meshes and handles by both, how far apart they are and how long each takes.

    pip install ./python libigl==2.6.3
    python python/examples/versus_libigl.py [DATA_DIR]

The meshes: libigl's reference meshes (``DATA_DIR/reference-igl``, the bar and the U shape) and
a domain of about 20 000 vertices of the paper authors' seven turtles with their three handles
(``DATA_DIR/vectorskinning``). DATA_DIR defaults to ``../shared/data`` next to the checkout.
Prints one row per mesh; timings are medians of repeated runs on this machine, no assertion.
Both packages solve BBW's programs on several threads (libigl inside its active set, ours one
handle per core), so BBW is given as wall time and as processor time summed over threads.
"""

from __future__ import annotations

import json
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import splineskin

REPO = Path(__file__).resolve().parents[2]
TURTLES = "vectorskinning/turtle-seven-stack/comparison/shepard ours/turtles-seven-deformation.json"
# The turtles' domain refined to triangles of at most this fraction of its area: 19 727
# vertices with the drawing's curve samples (the default, 1/5000, gives 17 745).
TURTLES_AREA_FRACTION = 1e-4
# Active-set rounds libigl's BBW may take (it stops earlier when it converges).
BBW_MAX_ITER = 1000


@dataclass
class Row:
    """One mesh compared: sizes, largest differences and median seconds of both."""

    name: str
    n_vertices: int
    n_handles: int
    harmonic_gap: float
    harmonic_ours: float
    harmonic_igl: float
    bbw_gap: float
    bbw_ours: float
    bbw_igl: float
    bbw_ours_cpu: float
    bbw_igl_cpu: float


def median_seconds(run, repeats: int) -> tuple[float, np.ndarray]:
    """The median wall time of `repeats` calls of `run`, and its last result."""
    wall, _, result = median_times(run, repeats)
    return wall, result


def median_times(run, repeats: int) -> tuple[float, float, np.ndarray]:
    """The median wall time and processor time (this process's threads summed) of `repeats`
    calls of `run`, and its last result."""
    walls, cpus = [], []
    result = None
    for _ in range(repeats):
        start, start_cpu = time.perf_counter(), time.process_time()
        result = run()
        walls.append(time.perf_counter() - start)
        cpus.append(time.process_time() - start_cpu)
    return float(np.median(walls)), float(np.median(cpus)), result


def compare(name: str, V: np.ndarray, F: np.ndarray, b: np.ndarray, repeats: int = 5) -> Row:
    """Harmonic (k = 1) and BBW weights of (V, F) with handles at vertices b, by both."""
    import igl

    V = np.ascontiguousarray(V, dtype=np.float64)
    F = np.ascontiguousarray(F, dtype=np.int64)
    b = np.ascontiguousarray(b, dtype=np.int64)
    bc = np.eye(len(b))
    h_ours_s, h_ours = median_seconds(lambda: splineskin.harmonic(V, F, b, bc, 1), repeats)
    h_igl_s, h_igl = median_seconds(lambda: igl.harmonic(V, F, b, bc, 1), repeats)
    bbw_repeats = max(1, repeats // 2)
    w_ours_s, w_ours_cpu, w_ours = median_times(lambda: splineskin.bbw(V, F, b, bc), bbw_repeats)
    # libigl stops its active set after `max_iter` rounds, 100 by default: on the turtles'
    # domain that leaves one column 4.6e-4 away from the minimiser (its energy 3e-6 higher
    # than ours). Given room, it stops when it converges, on ours to 3e-10.
    w_igl_s, w_igl_cpu, w_igl = median_times(lambda: igl.bbw(V, F, b, bc, max_iter=BBW_MAX_ITER), bbw_repeats)
    return Row(
        name, len(V), len(b),
        float(np.abs(h_ours - h_igl).max()), h_ours_s, h_igl_s,
        float(np.abs(w_ours - w_igl).max()), w_ours_s, w_igl_s, w_ours_cpu, w_igl_cpu,
    )


def reference_meshes(data: Path):
    """(name, V, F, b) of libigl's reference meshes present under `data`."""
    for shape in ["bar", "ushape"]:
        path = data / "reference-igl" / f"{shape}.json"
        if path.exists():
            ref = json.loads(path.read_text())
            yield shape, np.array(ref["mesh"]["V"]), np.array(ref["mesh"]["F"]), np.array(ref["handles"]["indices"])


def turtles_domain(data: Path):
    """The turtles' domain with their handles, or None without the data."""
    path = data / TURTLES
    if not path.exists():
        return None
    scene = splineskin.Scene.load(path)
    V, F, b = scene.drawing().domain(scene.handles, max_area_fraction=TURTLES_AREA_FRACTION)
    return "turtles domain", V, F, b


def table(rows: list[Row]) -> str:
    """The rows as a table (milliseconds, and libigl's time over ours; for BBW also the ratio of
    processor times)."""
    lines = [
        f"{'mesh':<16}{'V':>7}{'h':>3} | {'harmonic gap':>12}{'ours ms':>9}{'libigl ms':>10}{'×':>6}"
        f" | {'bbw gap':>9}{'ours ms':>9}{'libigl ms':>10}{'×':>6}{'cpu ×':>7}"
    ]
    for r in rows:
        lines.append(
            f"{r.name:<16}{r.n_vertices:>7}{r.n_handles:>3} | {r.harmonic_gap:>12.1e}{1e3 * r.harmonic_ours:>9.1f}"
            f"{1e3 * r.harmonic_igl:>10.1f}{r.harmonic_igl / r.harmonic_ours:>6.1f} | {r.bbw_gap:>9.1e}"
            f"{1e3 * r.bbw_ours:>9.1f}{1e3 * r.bbw_igl:>10.1f}{r.bbw_igl / r.bbw_ours:>6.1f}"
            f"{r.bbw_igl_cpu / r.bbw_ours_cpu:>7.1f}"
        )
    return "\n".join(lines)


def main() -> None:
    data = Path(sys.argv[1]) if len(sys.argv) > 1 else REPO.parent / "shared" / "data"
    meshes = list(reference_meshes(data))
    turtles = turtles_domain(data)
    if turtles:
        meshes.append(turtles)
    if not meshes:
        print(f"no meshes: {data} has neither reference-igl/ nor {TURTLES}")
        return
    rows = [compare(*m) for m in meshes]
    print(table(rows))
    print("(gap: largest difference of any weight; ×: libigl's wall time over ours; cpu ×: the same"
          " of processor time, all threads)")


if __name__ == "__main__":
    main()
