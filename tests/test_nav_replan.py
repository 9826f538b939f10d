"""Replanning round what the map does not hold, and the social speed limit near people.

Scenario ``tests/scenarios/nav_two_doors.xml``: two doors into the kitchen, Tom stands in the
nearer one (the planned way) and stays. The robot slows down near him, is blocked, replans
with him marked in a local costmap and drives through the far door: it arrives, no help
request. The attention is stood in for by ``tests.nav_helpers.Oracle`` (Tom is track ``t2``
on ``/robot/attention/tracks``).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st

from robot.navigation.grid import NoPathError, OccupancyGrid, Plan2D
from robot.navigation.local import SOCIAL_NEAR, SOCIAL_SPEED, carrot, heading_speed, social_speed_limit
from tests.nav_helpers import start_run


@pytest.fixture(scope="module")
def detour():
    run = start_run("nav_two_doors", tracks={"tom": "t2"})
    run.plans = []
    run.sim.bus.participant("plan_watch").subscribe("/robot/navigation/plan", lambda m: run.plans.append(m.xml))
    run.at(0.5, run.engage)
    run.at(1.0, lambda: run.teach_place("kitchen", 8.2, 1.5))
    run.at(1.5, lambda: run.goto("kitchen"))
    run.until(50.0)
    yield run
    run.close()


def test_a_person_standing_in_the_planned_door_is_driven_round_through_the_other(detour):
    first, *later = detour.plans
    assert first.get("replan") is None and max(float(w.get("y")) for w in first.findall("waypoint")) < 3.0  # the near door
    again = [p for p in later if p.get("replan") == "true" and not p.get("failed")]
    assert again, "the robot never found the way round"
    ys = [float(w.get("y")) for w in again[0].findall("waypoint")]
    assert max(ys) > 3.4  # through the far door (3.5-4.5 m)
    names = [e[1] for e in detour.events]
    assert "goal_reached" in names and "navigation_failed" not in names
    assert "need_help" not in detour.condition_names() and "arrived" in detour.condition_names()
    ep = detour.metric("navigation")["goto"][0]
    assert ep["outcome"] == "reached" and ep["replans_found"] >= 1 and ep["collisions"] == 0 and ep["goal_error"] < 0.25
    assert detour.world.contacts == []


def test_near_a_person_the_robot_slows_to_the_social_speed(detour):
    ep = detour.metric("navigation")["goto"][0]
    assert ep["closest_person"] < SOCIAL_NEAR  # it did come near Tom
    assert 0.0 < ep["speed_near_person_max"] <= SOCIAL_SPEED + 0.02  # measured from the true speed


@settings(max_examples=60, deadline=None)
@given(st.floats(0.0, 6.0), st.floats(0.0, 6.0), st.floats(0.1, 1.5))
def test_social_speed_limit_is_low_near_people_and_never_falls_as_they_get_further(d1, d2, vmax):
    a, b = sorted((d1, d2))
    la, lb = social_speed_limit(a, vmax), social_speed_limit(b, vmax)
    assert 0.0 < la <= lb <= vmax
    if a <= SOCIAL_NEAR:
        assert la <= SOCIAL_SPEED
    assert social_speed_limit(math.inf, vmax) == vmax


@settings(max_examples=60, deadline=None)
@given(st.tuples(st.floats(-5, 5), st.floats(-5, 5)), st.tuples(st.floats(-5, 5), st.floats(-5, 5)),
       st.tuples(st.floats(-5, 5), st.floats(-5, 5)), st.floats(0.0, 2.0))
def test_the_carrot_lies_on_the_leg_ahead_of_the_robot(a, b, p, look):
    c = carrot(a, b, p, look)
    ab = math.hypot(b[0] - a[0], b[1] - a[1])
    assert math.hypot(c[0] - a[0], c[1] - a[1]) + math.hypot(b[0] - c[0], b[1] - c[1]) == pytest.approx(ab, abs=1e-6)


@given(st.floats(0.0, 1.0), st.floats(-math.pi, math.pi))
def test_heading_speed_turns_on_the_spot_for_a_goal_off_to_the_side(v, bearing):
    out = heading_speed(v, bearing)
    assert 0.0 <= out <= v
    if abs(bearing) >= math.pi / 3:
        assert out == 0.0


def _room() -> OccupancyGrid:
    """A 6 x 4 m room split by a wall at x=3 with one 1.2 m door (y 1.4-2.6)."""
    walls = [np.array(p, dtype=float) for p in (
        [(0, 0), (6, 0), (6, 0.1), (0, 0.1)], [(0, 3.9), (6, 3.9), (6, 4), (0, 4)],
        [(0, 0), (0.1, 0), (0.1, 4), (0, 4)], [(5.9, 0), (6, 0), (6, 4), (5.9, 4)],
        [(2.95, 0), (3.05, 0), (3.05, 1.4), (2.95, 1.4)], [(2.95, 2.6), (3.05, 2.6), (3.05, 4), (2.95, 4)])]
    return OccupancyGrid(Plan2D(polygons=tuple(walls), start=(1.0, 2.0, 0.0)), radius=0.3)


GRID = _room()


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(st.floats(0.5, 5.5), st.floats(0.5, 3.5)), min_size=0, max_size=6))
def test_a_replan_keeps_the_robots_radius_clear_of_every_marked_point(obstacles):
    pts = np.array(obstacles, dtype=float).reshape(-1, 2)
    ends = np.array([[1.0, 2.0], [5.0, 2.0]])
    assume(all(np.min(np.hypot(*(ends - p).T)) > 0.6 for p in pts))  # start and goal themselves are free
    free_before = GRID.free.copy()
    grid = GRID.with_obstacles(pts)
    assert (GRID.free == free_before).all()  # the map's own grid is not changed
    try:
        path = grid.plan((1.0, 2.0), (5.0, 2.0))
    except NoPathError:
        return
    for (ax, ay), (bx, by) in zip(path, path[1:]):
        for t in np.linspace(0.0, 1.0, 40):
            x, y = ax + t * (bx - ax), ay + t * (by - ay)
            if len(pts):  # a cell's width of slack: the point may sit anywhere in its cell
                assert np.min(np.hypot(pts[:, 0] - x, pts[:, 1] - y)) > grid.radius - grid.cell * 1.5


def test_a_person_in_the_only_door_leaves_no_way_round():
    with pytest.raises(NoPathError):
        GRID.with_obstacles(np.array([[3.0, 2.0], [3.0, 1.7], [3.0, 2.3]])).plan((1.0, 2.0), (5.0, 2.0))
