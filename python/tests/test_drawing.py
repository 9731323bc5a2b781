"""Drawings: reading SVG text and files, control points as arrays, writing the document back."""

from __future__ import annotations

import numpy as np
import pytest

import splineskin
from conftest import ASSETS

STROKE = '<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 50"><path id="s" d="M0 0 C30 40 70 40 100 0" stroke="red" fill="none"/></svg>'


def test_text_and_file_give_the_same_drawing():
    fish = splineskin.Drawing.from_svg(ASSETS / "demo.svg")
    again = splineskin.Drawing.from_svg((ASSETS / "demo.svg").read_text())
    assert fish.n_curves == again.n_curves > 10
    assert np.array_equal(fish.points, again.points)
    assert fish.points.shape == (fish.n_points, 2) and fish.points.dtype == np.float64
    assert fish.offsets[0] == 0 and fish.offsets[-1] == fish.n_points
    assert len(fish.closed) == len(fish.joints) == fish.n_paths
    assert str(ASSETS / "demo.svg") in repr(fish)


def test_one_cubic_is_read_as_written():
    d = splineskin.Drawing.from_svg(STROKE)
    assert (d.n_paths, d.n_curves, d.n_points) == (1, 1, 4)
    assert np.array_equal(d.points, [[0, 0], [30, 40], [70, 40], [100, 0]])
    assert d.joints == [["end", "end"]] and d.closed == [False]
    assert d.diagonal == pytest.approx(np.hypot(100, 40))


def test_to_svg_writes_the_document_with_the_points_given():
    d = splineskin.Drawing.from_svg(STROKE)
    moved = d.points + [5.0, -2.0]
    svg = d.to_svg(moved)
    assert 'id="s"' in svg and 'stroke="red"' in svg  # the document is kept
    back = splineskin.Drawing.from_svg(svg)
    assert np.allclose(back.points, moved, rtol=0, atol=1e-12 * d.diagonal)
    # Far from the origin and tiny, the same (tolerances are relative).
    for scale, shift in [(1e-6, 0.0), (1e6, 1e7), (1.0, 3e7)]:
        points = d.points * scale + shift
        back = splineskin.Drawing.from_svg(d.to_svg(points, viewbox="fit"))
        assert np.allclose(back.points, points, rtol=0, atol=1e-12 * scale * d.diagonal + 1e-15 * shift)


def test_paths_of_gives_views_of_each_path():
    fish = splineskin.Drawing.from_svg(ASSETS / "demo.svg")
    points = fish.points
    parts = splineskin.paths_of(fish, points)
    assert len(parts) == fish.n_paths
    assert sum(len(p) for p in parts) == fish.n_points
    parts[0][0, 0] = -7.0
    assert points[0, 0] == -7.0  # a view, not a copy


def test_bad_input_is_a_clear_error():
    with pytest.raises(FileNotFoundError, match="nowhere.svg"):
        splineskin.Drawing.from_svg("nowhere.svg")
    with pytest.raises(splineskin.SplineSkinError, match="svg text"):
        splineskin.Drawing.from_svg("<svg><path d='M0 0 C")
    d = splineskin.Drawing.from_svg(STROKE)
    with pytest.raises(ValueError, match=r"\(4, 2\)"):
        d.to_svg(np.zeros((3, 2)))
    with pytest.raises(ValueError, match="finite"):
        d.to_svg(np.full((4, 2), np.nan))
    # Any memory order is read as numpy shows it.
    moved = d.points + [[0.0, 1.0]]
    assert d.to_svg(np.asfortranarray(moved)) == d.to_svg(moved) == d.to_svg(moved[::-1][::-1])
    with pytest.raises(ValueError, match="keep"):
        d.to_svg(d.points, viewbox="grow")


TWO_DISCS = (
    '<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 40">'
    '<circle cx="10" cy="20" r="8"/><circle cx="50" cy="20" r="8"/><circle cx="90" cy="20" r="8"/></svg>'
)


def test_domain_of_the_art_covers_the_pinned_shapes_only():
    d = splineskin.Drawing.from_svg(TWO_DISCS)
    handles = np.array([[10.0, 20.0], [50.0, 20.0]])
    V, F, b = d.domain(handles, shape="art")
    assert np.array_equal(V[b], handles)
    # Nothing between the discs, nothing of the third (unpinned) one.
    assert np.all((V[:, 0] < 25) | ((V[:, 0] > 35) & (V[:, 0] < 65)))
    # Triangle areas: two discs grown by the margin and a cell and a half (to a few percent).
    e1, e2 = V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]
    area = 0.5 * np.sum(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    diagonal = np.hypot(96.0, 16.0)
    grown = 8 + 0.01 * diagonal + 1.5 * diagonal / 500
    assert abs(area / (2 * np.pi * grown**2) - 1) < 0.02
    # A larger margin joins the discs 24 units apart (margin 0.2 of the diagonal: about 19).
    V2, _, _ = d.domain(handles, shape="art", margin=0.2)
    assert np.any((V2[:, 0] > 25) & (V2[:, 0] < 35))
    # The paper's domain (the default) is the padded box: it covers the gap too.
    V3, _, _ = d.domain(handles)
    assert np.any((V3[:, 0] > 25) & (V3[:, 0] < 35))
    with pytest.raises(ValueError, match="enclosing"):
        d.domain(handles, shape="box")
    with pytest.raises(splineskin.SplineSkinError, match="margin"):
        d.domain(handles, shape="art", margin=2.0)
