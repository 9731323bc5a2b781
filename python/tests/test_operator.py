"""Deformation operators from Python: trained with progress, reproducing their rest and their
handles, saved and read back bit for bit, joined with a drawing as `splineskin defop deform`
joins it (the same numbers), and bad input refused."""

from __future__ import annotations

import json

import numpy as np
import pytest

import splineskin
from conftest import ASSETS, run_cli
from test_weights import square_grid

FISH_SCENE = ASSETS / "demo-scene.json"


@pytest.fixture(scope="module")
def bar():
    """An operator on a 9 × 3 grid of the unit square's strip [0, 4] × [0, 1], three handles."""
    xs = np.linspace(0.0, 4.0, 9)
    ys = np.linspace(0.0, 1.0, 3)
    V = np.array([[x, y] for y in ys for x in xs])
    F = np.array([t for j in range(2) for i in range(8) for a in [j * 9 + i]
                  for t in ([a, a + 1, a + 10], [a, a + 10, a + 9])])
    b = np.array([9, 13, 17])
    calls = []
    op = splineskin.Operator.train(V, F, b, energy="arap", samples=12, seed=3,
                                   progress=lambda *p: calls.append(p))
    return V, F, b, op, calls


def test_training_reports_progress_and_reproduces_rest_and_handles(bar):
    V, F, b, op, calls = bar
    assert len(calls) >= 12
    solved, to_solve, stage, n_stages = calls[-1]
    assert solved == to_solve >= 12 and n_stages >= 1
    assert np.array_equal(op.V, V) and np.array_equal(op.F, F) and np.array_equal(op.b, b)
    diagonal = np.hypot(4.0, 1.0)
    assert np.abs(op.evaluate(V[b]) - V).max() <= 1e-9 * diagonal  # the rest is a sample
    Q = V[b] + [[0.0, 0.3], [0.1, -0.2], [0.4, 0.5]]
    moved = op.evaluate(Q)
    assert np.abs(moved[b] - Q).max() <= 1e-9 * diagonal  # handles interpolated
    assert op.metadata["energy"] == "arap" and op.metadata["n_samples"] == 12


def test_save_and_load_give_the_same_operator(bar, tmp_path):
    V, F, b, op, _ = bar
    op.save(tmp_path / "bar.op")
    back = splineskin.Operator.load(tmp_path / "bar.op")
    Q = V[b] + 0.2
    assert np.array_equal(back.evaluate(Q), op.evaluate(Q))


def test_a_scene_operator_joined_is_what_the_command_line_draws(tmp_path):
    scene = splineskin.Scene.load(FISH_SCENE)
    op = splineskin.Operator.from_scene(scene, samples=12, energy="arap")
    path = tmp_path / "fish.op"
    op.save(path)
    rig = op.join(scene)
    out = tmp_path / "cli.json"
    run_cli("defop", "deform", str(FISH_SCENE), "--operator", str(path), "--pose", "0", "-o", str(out))
    cli = np.array([p for path in json.loads(out.read_text())["paths"] for p in path["points"]])
    Q = splineskin.posed_handles(scene.handles, scene.pose(0))
    ours = np.empty((rig.n_points, 2))
    assert rig.update(Q, ours) is ours
    diagonal = scene.drawing().diagonal
    assert np.abs(ours - cli).max() <= 1e-12 * diagonal
    # The product G_spline · ψ(Q) is the operator the page evaluates: at rest, the drawing.
    rest = rig.update(scene.handles)
    assert np.abs(rest - scene.drawing().points).max() <= 1e-6 * diagonal


def test_bad_input_is_a_clear_error(bar, tmp_path):
    V, F, b, op, _ = bar
    with pytest.raises(ValueError, match="energy"):
        splineskin.Operator.train(V, F, b, energy="elastic")
    with pytest.raises(ValueError, match="b\\[1\\] = 999"):
        splineskin.Operator.train(V, F, [0, 999])
    with pytest.raises(ValueError, match=r"\(3, 2\)"):
        op.evaluate(np.zeros((2, 2)))
    with pytest.raises(FileNotFoundError):
        splineskin.Operator.load(tmp_path / "none.op")
    junk = tmp_path / "junk.op"
    junk.write_bytes(b"not an operator")
    with pytest.raises(splineskin.SplineSkinError, match="not a splineskin operator file"):
        splineskin.Operator.load(junk)

    def stop(*_):
        raise KeyboardInterrupt("stop")

    grid_V, grid_F = square_grid(4)
    with pytest.raises(KeyboardInterrupt):
        splineskin.Operator.train(grid_V, grid_F, [0, 15], samples=4, energy="arap", progress=stop)


def test_an_exception_in_the_progress_callback_stops_the_training(bar):
    V, F, b, _, _ = bar
    calls = []

    def stop_after_three(solved, to_solve, stage, n_stages):
        calls.append(solved)
        if solved >= 3:
            raise RuntimeError("enough")

    with pytest.raises(RuntimeError, match="enough"):
        splineskin.Operator.train(V, F, b, energy="arap", samples=400, progress=stop_after_three)
    # Once it raised, it is not called again (solves run on several threads, so the counts may
    # come out of order): the call that raised is the last, and no solve starts after it.
    assert calls[-1] >= 3 and all(c < 3 for c in calls[:-1]) and len(calls) <= 3


def test_ctrl_c_interrupts_a_training():
    import _thread
    import threading

    # Large enough that training the whole would take minutes: 20 000 symmetric ARAP solves.
    V, F = square_grid(12)
    calls = []
    timer = threading.Timer(0.5, _thread.interrupt_main)  # as Ctrl-C or a notebook's interrupt
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            splineskin.Operator.train(V, F, [0, 11, 143], samples=20_000, progress=lambda s, *_: calls.append(s))
    finally:
        timer.cancel()
    assert 0 < len(calls) < 20_000, "interrupted midway, and it had started"
