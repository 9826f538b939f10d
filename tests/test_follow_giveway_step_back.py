"""A stalled give-way with no back-out path backs straight away from her instead of standing in her way for good
(issue 26 items 1, 2, 10; reports/long23.md "Cause of that deadlock": tests/scenarios/follow/long23_hall_rooms_both_sides.xml
on integ: come up to her just inside the sewing room's 0.9 m door, she says "follow me" and walks back to the door past
its front corner; the give-way spot lies deeper in the room, its first turn is refused by her body, `back_out_spot`
finds no path, and the follower stood at speed 0, "giving_way", for the rest of the run while she waited for it).

Run closed loop on Follower._unstall (the forward give-way's stall handler) with the refused turn as its command,
the robot's pose following each command for a tenth of a second; the floor plan and her body seen from the new pose."""

from __future__ import annotations

import math
from collections import deque
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import robot.navigation.follow as follow
from robot.navigation.config import Limits
from robot.navigation.follow import SWEEP_TIME, Follower, sweep_allowed
from robot.navigation.local import SOCIAL_GAP, people_sweep_clear
from tests.test_follow_backout_door import _clearance, _to_robot

#: a room's wall 0.45 m to the robot's right with the 0.9 m door it came in by (its centre beside the robot's),
#: and the room's back wall 1.6 m behind (odom = robot frame at start)
WALLS = np.array([(x, -0.45) for x in np.arange(-1.6, 1.2, 0.05) if abs(x) > 0.45] + [(-1.6, y) for y in np.arange(-0.45, 1.5, 0.05)])
#: her, 0.55 m ahead and a little to the left: on her way back to that door past its front corner
HER = (0.55, 0.08)
#: it came in through the door from the hall (1.5 m beyond it), then turned to face her
CAME = [(0.0, -1.5 + 0.05 * k) for k in range(31)]


class _Scan:
    def points(self) -> np.ndarray:
        return np.zeros((0, 2))

    def sees_through(self, *_: float) -> bool:
        return False


class _Nobody:
    def around(self, *_: object, **__: object) -> np.ndarray:
        return np.zeros((0, 2))


class _Route:
    grid = object()  # a floor plan is there (back_out_spot is patched: it finds no way)

    @staticmethod
    def to_map(p: tuple[float, float]) -> tuple[float, float]:
        return (float(p[0]), float(p[1]))


def _follower() -> Follower:
    f = Follower.__new__(Follower)
    f.limits = Limits()
    f.scan = _Scan()  # type: ignore[assignment]
    f.people = _Nobody()  # type: ignore[assignment]
    f.route = _Route()  # type: ignore[assignment]
    f.odom = (0.0, 0.0, 0.0)
    f.sim = SimpleNamespace(now=0.0)  # type: ignore[assignment]
    f.band = (0.9, 1.4)
    f.partner_id = None
    f.crumbs = deque(CAME)
    f.seen = SimpleNamespace(clear=lambda *_, **__: True)  # the room's floor behind it was seen free as it turned in  # type: ignore[assignment]
    f._aside_stall = None
    f._aside_moving = None
    f._backout_failed = None
    f._aside = None
    return f


@pytest.fixture
def no_way_out(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(follow, "back_out_spot", lambda *_, **__: None)


def test_its_turn_refused_and_no_way_out_it_backs_off_her_way_instead_of_standing_for_good(no_way_out):
    f = _follower()
    pose = (0.0, 0.0, 0.0)
    start_her = _clearance(np.array([HER]))
    moved_at = None
    for k in range(60):  # 6 s
        f.sim.now = k * 0.1
        f.odom = pose
        v, w = f._unstall((0.0, 0.0), *HER, _to_robot(WALLS, pose), step_back=True)
        x, y, th = pose
        pose = (x + v * 0.1 * math.cos(th), y + v * 0.1 * math.sin(th), th + w * 0.1)
        assert _clearance(_to_robot(WALLS, pose)) > 0.0  # never touching the walls
        if moved_at is None and math.hypot(pose[0], pose[1]) > 0.05:
            moved_at = f.sim.now
    assert moved_at is not None, f"still standing in her way at {pose}"
    assert moved_at <= 2.5  # the give-way's 2 s stall, then back
    assert pose[0] < -0.2  # back, away from her
    assert _clearance(_to_robot(np.array(HER), pose)) > start_her + 0.2  # room made for her
    way = np.array([(HER[0] * (1 - t), HER[1] + (-1.5 - HER[1]) * t) for t in np.linspace(0, 1, 30)])
    assert _clearance(_to_robot(way, pose)) > _clearance(way) + 0.2  # and off her way to the door
    assert _clearance(_to_robot(WALLS, pose)) > 0.0


def test_a_give_way_that_moves_is_left_alone(no_way_out):
    f = _follower()
    assert f._unstall((0.2, 0.1), *HER, WALLS, step_back=True) == (0.2, 0.1)


def test_with_her_beside_it_backing_would_not_take_it_away_from_her_so_it_does_not(no_way_out):
    f = _follower()
    for k in range(40):
        f.sim.now = k * 0.1
        assert f._unstall((0.0, 0.0), 0.05, 0.6, WALLS, step_back=True) == (0.0, 0.0)


@settings(max_examples=80, deadline=None)
@given(st.floats(0.35, 1.2), st.floats(-0.8, 0.8), st.floats(-0.3, 0.3), st.floats(-0.25, 0.25), st.floats(-0.6, 0.6))
def test_the_step_back_never_goes_toward_her_nor_into_the_floor_plan(hx, hy, dx, dy, turn):
    """Wherever she and the walls are, the step back is either the give-way's own command or a step back (never
    forward, never a turn on the spot), its sweep off the floor plan (no nearer than now within the margin) and off
    her body (the social gap, or no nearer than now), only while she stands ahead, and it leaves the footprint
    further from her way to the door than it is."""
    c, s = math.cos(turn), math.sin(turn)
    walls = WALLS @ np.array([[c, s], [-s, c]]) + (dx, dy)
    here = _clearance(walls)
    if here <= 0.0:
        return
    f = _follower()
    cmd = (0.0, 0.0)
    v, w = f._step_back(cmd, hx, hy, walls)
    if (v, w) == cmd:
        return
    assert v < 0.0
    assert follow.back_off_away(hx, hy)
    way = f._her_way(hx, hy)
    x, y, th = follow.arcs(np.array([v]), np.array([w]), np.array([SWEEP_TIME]))
    after = _to_robot(way, (float(x[0][0]), float(y[0][0]), float(th[0][0])))
    assert _clearance(after) > _clearance(way)
    # its footprint keeps 5 cm from the walls all along the step (or, closer already, no nearer than now)
    for t in np.linspace(0.05, SWEEP_TIME, 10):
        x, y, th = follow.arcs(np.array([v]), np.array([w]), np.array([t]))
        pose = (float(x[0][0]), float(y[0][0]), float(th[0][0]))
        assert _clearance(_to_robot(walls, pose)) >= min(0.05, here) - 1e-6
        # and her body its social gap (or no nearer than now)
        gap = _clearance(_to_robot(np.array([(hx, hy)]), pose)) - follow.BODY
        assert gap >= min(SOCIAL_GAP, _clearance(np.array([(hx, hy)])) - follow.BODY) - 1e-6


class _Behind:
    """Someone the attention tracks, standing behind the robot (robot frame)."""

    def __init__(self, x: float, y: float) -> None:
        self.at = np.array([(x, y)])

    def around(self, *_: object, **__: object) -> np.ndarray:
        return self.at


@settings(max_examples=60, deadline=None)
@given(st.floats(0.35, 1.2), st.floats(-0.5, 0.5), st.floats(-0.95, -0.45), st.floats(-0.3, 0.3))
def test_the_step_back_never_backs_toward_someone_standing_behind_it(hx, hy, bx, by):
    """review24 F9: a person 0.45-0.95 m behind its centre (the laser does not look there; the attention tracks
    them): no step back, wherever she stands ahead and with no wall anywhere near."""
    f = _follower()
    f.people = _Behind(bx, by)  # type: ignore[assignment]
    assert f._step_back((0.0, 0.0), hx, hy, np.zeros((0, 2))) == (0.0, 0.0)


def test_with_nobody_behind_and_her_ahead_on_her_way_out_it_does_step_back(no_way_out):
    """The counterpart of the above (so that test cannot pass by a step back that never happens): the same
    follower with nobody behind steps back from her, 0.55 m ahead on her way to the door."""
    f = _follower()
    v, w = f._step_back((0.0, 0.0), *HER, np.zeros((0, 2)))
    assert v < 0.0
