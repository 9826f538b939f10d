"""Pure geometry: simple polygons and overlapping rooms (Hypothesis properties)."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from homesim.geometry import polygon_problem, polygons_overlap
from tests.conftest import examples

_coord = st.integers(min_value=-20, max_value=20).map(lambda v: v / 2)


def _rect(x0: float, y0: float, x1: float, y1: float) -> np.ndarray:
    return np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]], dtype=float)


@settings(max_examples=examples(80, 400))
@given(n=st.integers(3, 12), r=st.floats(0.5, 10), cx=_coord, cy=_coord, turn=st.floats(0, 2 * math.pi))
def test_convex_polygons_are_simple(n, r, cx, cy, turn):
    a = turn + 2 * math.pi * np.arange(n) / n
    poly = np.stack((cx + r * np.cos(a), cy + r * np.sin(a)), axis=1)
    assert polygon_problem(poly) is None
    assert polygon_problem(poly[::-1]) is None


@settings(max_examples=examples(80, 400))
@given(n=st.integers(4, 12), r=st.floats(0.5, 10), i=st.integers(0, 11))
def test_swapping_two_vertices_of_a_regular_polygon_makes_it_self_intersecting(n, r, i):
    a = 2 * math.pi * np.arange(n) / n
    poly = np.stack((r * np.cos(a), r * np.sin(a)), axis=1)
    i %= n
    j = (i + 1) % n
    poly[[i, j]] = poly[[j, i]]
    assert polygon_problem(poly) is not None


def test_bow_tie_repeated_vertex_and_fold_back_are_reported():
    assert "cross" in polygon_problem(np.array([[0, 0], [8, 6], [8, 0], [0, 6]]))
    assert "same point" in polygon_problem(np.array([[0, 0], [4, 0], [4, 4], [4, 0.0]]))
    assert "fold back" in polygon_problem(np.array([[0, 0], [4, 0], [2, 0], [2, 3]]))


@settings(max_examples=examples(150, 800))
@given(a=st.tuples(_coord, _coord, _coord, _coord), b=st.tuples(_coord, _coord, _coord, _coord))
def test_rectangles_overlap_exactly_when_both_intervals_overlap(a, b):
    ax0, ax1 = sorted(a[:2])
    ay0, ay1 = sorted(a[2:])
    bx0, bx1 = sorted(b[:2])
    by0, by1 = sorted(b[2:])
    if min(ax1 - ax0, ay1 - ay0, bx1 - bx0, by1 - by0) <= 0:
        return
    p, q = _rect(ax0, ay0, ax1, ay1), _rect(bx0, by0, bx1, by1)
    want = min(ax1, bx1) > max(ax0, bx0) and min(ay1, by1) > max(ay0, by0)
    assert polygons_overlap(p, q) == want
    assert polygons_overlap(q, p) == want


def test_rooms_sharing_a_wall_do_not_overlap_an_identical_room_does():
    living, kitchen = _rect(0, 0, 6, 5), _rect(6, 0, 9.5, 5)
    assert not polygons_overlap(living, kitchen)
    assert polygons_overlap(living, living.copy())
    # An L-shaped room around a square one touches it without overlapping.
    ell = np.array([[0, 0], [4, 0], [4, 2], [2, 2], [2, 4], [0, 4]], dtype=float)
    assert not polygons_overlap(ell, _rect(2, 2, 4, 4))
    assert polygons_overlap(ell, _rect(1, 1, 3, 3))


# point_in_polygon is plain Python (room_of runs it every physics step); it must answer exactly
# as the vectorised even-odd test does, points on edges and corners included (grid coordinates
# make those common).
_coord = st.integers(-6, 6).map(lambda v: v / 2)


@given(st.lists(st.tuples(_coord, _coord), min_size=3, max_size=8), st.tuples(_coord, _coord))
def test_point_in_polygon_agrees_with_the_vectorised_test(corners, point):
    from homesim.geometry import point_in_polygon, points_in_polygon

    poly = np.array(corners, dtype=float)
    want = bool(points_in_polygon(np.array([point]), poly)[0])
    assert point_in_polygon(point, poly) is want
    assert point_in_polygon(point, corners) is want
