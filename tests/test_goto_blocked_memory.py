"""The robot's own map of where a go-to was blocked (robot.navigation.planner, "Where it was blocked").

A go-to that failed ``blocked`` tells the planner; for a while its plans pay for the spot ahead of where the
robot stood, so a second way is tried before the blocked one (fresh7/split_goto_ramp_child seed 2 on main: it
drove up the same ramp three times, asking for help each time, and never tried the way through the utility
room). The spot is a cost, not an obstacle: where there is no other way the path still goes through it.
"""

from __future__ import annotations

import math
from collections import deque
from types import SimpleNamespace

import numpy as np
from hypothesis import example, given, settings, strategies as st
from lxml import etree

from robot.floorplan import wall_rectangle
from robot.navigation.grid import OccupancyGrid, Plan2D
from robot.navigation.planner import AVOID_AHEAD, AVOID_FOR, AVOID_MAX, AVOID_RADIUS, Planner, point_ahead


def _flat(*, second_way: bool = True) -> OccupancyGrid:
    """Room A (0-4 x 0-5) and room B (6-10 x 0-5) joined by a 1.0 m passage along the south wall (y 0-1.1,
    doors at both ends) and, with ``second_way``, by a 1.0 m corridor along the north wall (y 4-5), longer
    by the rooms' depth."""
    segs = [((0, 0), (10, 0)), ((10, 0), (10, 5)), ((10, 5), (0, 5)), ((0, 5), (0, 0)),
            ((4, 1.1), (4, 4.0) if second_way else (4, 5)), ((6, 1.1), (6, 4.0) if second_way else (6, 5)),
            ((4, 1.1), (6, 1.1))]
    if second_way:
        segs.append(((4, 4.0), (6, 4.0)))
    return OccupancyGrid(Plan2D(tuple(wall_rectangle(a, b, 0.1) for a, b in segs), (1.0, 1.0, 0.0)), radius=0.30)


TWO_WAYS = _flat()
ONE_WAY = _flat(second_way=False)


def _planner(grid: OccupancyGrid, pose: tuple[float, float, float], goal: tuple[float, float]) -> tuple[Planner, list]:
    """A planner (no bus, no scan) at ``pose`` that has planned to ``goal``; its clock is ``pl.sim.now``."""
    pl = Planner.__new__(Planner)
    pl.sim = SimpleNamespace(now=0.0)
    pl.grid = grid
    pl._pose_xml = etree.Element("pose", x=str(pose[0]), y=str(pose[1]), theta=str(pose[2]))
    pl.goal = ("bedroom", (goal[0], goal[1], 0.0))
    pl.scan = SimpleNamespace(points=lambda: np.zeros((0, 2)), bodies=lambda: np.zeros((0, 2)))
    pl.path, pl.avoid, pl.blockers = [], deque(maxlen=AVOID_MAX), deque()
    out: list = []

    def publish(title, points, theta=None, failed=None, replan=False, watch=False, look=None):  # noqa: ANN001, ANN202
        out.append(SimpleNamespace(points=points, failed=failed))
        if points and not failed and not watch:
            pl.path = list(points)
    pl._publish = publish  # type: ignore[method-assign]
    return pl, out


def _through_passage(points: list[tuple[float, float]]) -> bool:
    """Whether the path crosses x = 5 in the south passage (y below 1.1)."""
    for (ax, ay), (bx, by) in zip(points, points[1:]):
        if (ax - 5.0) * (bx - 5.0) <= 0 and ax != bx:
            y = ay + (by - ay) * (5.0 - ax) / (bx - ax)
            if y < 1.1:
                return True
    return False


@settings(max_examples=25, deadline=None)
@given(st.floats(0.8, 3.3), st.floats(0.8, 4.2), st.floats(6.7, 9.3), st.floats(0.8, 4.2), st.floats(0.6, 1.0))
@example(2.0, 2.5, 8.0, 2.5, 0.8)
def test_blocked_in_the_passage_the_next_plans_take_the_other_way(ax, ay, bx, by, x_in):
    # the robot stands blocked in the passage (someone in it ahead); from there and from anywhere in room A
    # the next plan to room B avoids the passage while the spot is remembered, and takes it again after
    pl, out = _planner(TWO_WAYS, (3.2 + x_in, 0.55, 0.0), (bx, by))
    pl.path = TWO_WAYS.plan((3.2 + x_in, 0.55), (bx, by))
    if not _through_passage(pl.path):
        return  # the short way is the north corridor for this goal: nothing blocked on it here
    spot = pl.remember_blocked()
    assert spot is not None and math.dist(spot, (3.2 + x_in, 0.55)) <= AVOID_AHEAD + 1e-6
    pl._pose_xml = etree.Element("pose", x=str(ax), y=str(ay), theta="0")
    path = pl.replan()
    assert path is not None and not _through_passage(path)
    pl.sim.now = AVOID_FOR + 1.0  # forgotten: the plan is the floor plan's own again
    assert pl.replan() == TWO_WAYS.plan((ax, ay), (bx, by))


@settings(max_examples=25, deadline=None)
@given(st.floats(4.2, 5.8))
def test_with_a_single_way_the_blocked_spot_is_still_passed(sx):
    # a cost, not an obstacle: where the blocked way is the only one, the robot can still go (once it clears)
    pl, out = _planner(ONE_WAY, (2.0, 2.5, 0.0), (8.0, 2.5))
    pl.avoid.append((sx, 0.55, 0.0))
    path = pl.replan()
    assert path is not None and not out[-1].failed and _through_passage(path)


def test_no_blocked_spot_changes_no_plan():
    pl, _ = _planner(TWO_WAYS, (2.0, 2.5, 0.0), (8.0, 2.5))
    assert pl.replan() == TWO_WAYS.plan((2.0, 2.5), (8.0, 2.5))


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.floats(0, 10), st.floats(0, 10)), min_size=2, max_size=6),
       st.tuples(st.floats(0, 10), st.floats(0, 10)), st.floats(0.0, 3.0))
def test_the_point_ahead_lies_on_the_path_no_further_than_asked(path, at, ahead):
    p = point_ahead(path, at, ahead)
    on = min(_seg_dist(p, a, b) for a, b in zip(path, path[1:]))
    assert on < 1e-6
    # never further than ``ahead`` from the path's point nearest to ``at`` (along the path, so in a straight line too)
    near = min((_closest(at, a, b) for a, b in zip(path, path[1:])), key=lambda q: math.dist(q, at))
    assert math.dist(p, near) <= ahead + 1e-6


def test_the_spot_is_within_the_avoided_radius_of_what_stood_ahead():
    # the player stops about a body's length short of what blocks it: the spot ahead is what is avoided
    pl, _ = _planner(TWO_WAYS, (4.4, 0.55, 0.0), (8.0, 2.5))
    pl.path = [(2.0, 0.55), (8.0, 0.55)]
    spot = pl.remember_blocked()
    assert spot is not None and abs(spot[0] - (4.4 + AVOID_AHEAD)) < 1e-9 and AVOID_RADIUS >= 0.5


def _closest(p, a, b):  # noqa: ANN001, ANN202
    dx, dy = b[0] - a[0], b[1] - a[1]
    n2 = dx * dx + dy * dy
    t = 0.0 if n2 == 0 else min(max(((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / n2, 0.0), 1.0)
    return a[0] + t * dx, a[1] + t * dy


def _seg_dist(p, a, b) -> float:  # noqa: ANN001
    return math.dist(p, _closest(p, a, b))
