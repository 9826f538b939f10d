"""The robot makes way for its partner unasked when she turns to leave a small room by the door it stands in
(fresh23's defect E; tests/scenarios/follow/long23_hall_rooms_both_sides.xml on main 5a86edb: having followed her
into the sewing room it stood in the 0.9 m door's mouth; "now follow me to the bedroom" walked her back to the door
past its front corner, it gave way too late with her 0.5 m away, and stood there for the rest of the run while she
waited for it).

* :func:`robot.navigation.giveway.give_way_spot` with ``way`` (where she walks out to): the spot lies off her way
  out (the segment from her to that point), roomy, on free ground reached on a free path that never passes her
  closer than she stands (or 0.7 m), not further down her way than the robot;
* :meth:`robot.navigation.follow.Follower._leaving`: only a partner walking toward the way the robot came in by,
  with the robot standing on it between her and it, is made way for before she reaches it.
"""

from __future__ import annotations

import math
from collections import deque
from types import SimpleNamespace

import numpy as np
from hypothesis import given, settings, strategies as st

from robot.floorplan import wall_rectangle
from robot.navigation.config import Limits
from robot.navigation.follow import CAME_FROM, LEAVE_NEAR, Follower
from robot.navigation.giveway import LATERAL, ROOM, give_way_spot, way_distance
from robot.navigation.grid import OccupancyGrid, Plan2D
from robot.navigation.local import DWAParams


def _hall_and_room() -> OccupancyGrid:
    """A hall (y 0-1.1, 1.0 m clear) and a small room north of it (x 2-5.5, y 1.1-4.5) behind a 0.9 m door
    at x 3.0-3.9 in the wall y = 1.1 (long23's sewing room, moved)."""
    walls = [wall_rectangle(a, b, 0.1) for a, b in (
        ((0, 0), (8, 0)), ((8, 0), (8, 1.1)), ((0, 1.1), (0, 0)),
        ((0, 1.1), (3.0, 1.1)), ((3.9, 1.1), (8, 1.1)),
        ((2.0, 1.1), (2.0, 4.5)), ((5.5, 1.1), (5.5, 4.5)), ((2.0, 4.5), (5.5, 4.5)))]
    return OccupancyGrid(Plan2D(tuple(walls), (1.0, 1.0, 0.0)), radius=0.30)


GRID = _hall_and_room()
#: the robot came in through the door from the hall: where it drove from, 1.5 m back
OUT = (3.45, 0.55)


def test_a_robot_in_the_door_mouth_steps_beside_the_mouth_on_the_room_side_not_deeper_on_her_way():
    # it stands just inside the door, a little east of its middle; she stands 1.7 m in, NE, and walks out
    robot, her = (3.7, 1.5), (4.2, 3.2)
    path = give_way_spot(GRID, robot, her, keep=1.0, way=OUT)
    assert path is not None and path[0] == robot
    sx, sy = path[-1]
    assert sy > 1.1 + 0.3  # in the room, not out in the hall ahead of her
    assert float(way_distance(np.array([sx]), np.array([sy]), her, OUT)[0]) >= LATERAL


@settings(max_examples=60, deadline=None)
@given(st.floats(3.2, 3.8), st.floats(1.35, 1.9), st.floats(2.6, 5.0), st.floats(2.2, 4.0))
def test_every_spot_off_her_way_out_is_roomy_out_of_her_path_not_at_her_and_reached_on_a_free_way(rx, ry, px, py):
    robot, her = (rx, ry), (px, py)
    path = give_way_spot(GRID, robot, her, keep=1.0, way=OUT)
    if path is None:
        return
    spot = path[-1]
    i, j = GRID.cell_of(spot)
    assert GRID.clearance[i, j] >= ROOM  # inside free space, turnable there
    assert float(way_distance(np.array([spot[0]]), np.array([spot[1]]), her, OUT)[0]) >= LATERAL - 1e-9  # out of her path
    wx, wy = OUT[0] - px, OUT[1] - py
    n = math.hypot(wx, wy)
    assert ((spot[0] - px) * wx + (spot[1] - py) * wy) / n <= ((rx - px) * wx + (ry - py) * wy) / n + 1e-9
    assert math.hypot(spot[0] - px, spot[1] - py) >= 1.0  # not at her
    d = math.hypot(rx - px, ry - py)
    for a, b in zip(path, path[1:]):  # reachable: every leg free on the grid, never nearer her than 0.7 m (or now)
        assert GRID.line_free(a, b, roomy=False) or a == robot
        for t in np.linspace(0.0, 1.0, 11):
            q = (a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]))
            assert math.hypot(q[0] - px, q[1] - py) >= min(0.7, d) - 0.01 - 1e-9


class _Route:
    ready = True


def _follower(robot: tuple[float, float, float]) -> Follower:
    """A follower that came in through the door (its own trail from the hall) and stands at ``robot`` (odom = map)."""
    f = Follower.__new__(Follower)
    f.route = _Route()  # type: ignore[assignment]
    f.odom = robot
    f.sim = SimpleNamespace(now=0.0)  # type: ignore[assignment]
    trail = ([(1.5 + 0.05 * k, 0.55) for k in range(39)]  # along the hall, then up through the door
             + [(3.45, 0.55 + 0.05 * k) for k in range(int((robot[1] - 0.55) / 0.05) + 1)] + [robot[:2]])
    f.crumbs = deque(trail)
    f.band = (1.0, 1.5)
    return f


def _track(vx: float, vy: float) -> dict[str, float]:
    return {"vx": vx, "vy": vy}


def test_she_walks_toward_the_door_it_stands_in_it_makes_way_before_she_reaches_it():
    f = _follower((3.5, 1.55, math.pi / 2))
    her = (3.9, 3.0)
    out = f._leaving(her[0], her[1], _track(-0.1, -0.45))  # toward the door
    assert out is not None and math.hypot(out[0] - 3.5, out[1] - 1.55) >= CAME_FROM - 1e-9
    assert f._leaving(her[0], her[1], _track(0.1, 0.45)) is None  # walking away, deeper into the room
    assert f._leaving(her[0], her[1], _track(0.0, 0.05)) is None  # standing
    assert f._leaving(her[0], her[1], _track(-0.05, -0.2)) is None  # turning round where she stands (her track moves a little)
    assert f._leaving(her[0], her[1], _track(0.45, 0.0)) is None  # walking across the room, not toward the door
    assert f._leaving(3.9, 1.55 + LEAVE_NEAR + 0.3, _track(0.0, -0.45)) is None  # still far off
    assert f._leaving(3.6, 2.4, _track(0.0, -0.45)) is None  # already within the near band: its own give-way acts


@settings(max_examples=80, deadline=None)
@given(st.floats(2.6, 5.2), st.floats(1.3, 2.2), st.floats(2.4, 5.2), st.floats(1.0, 4.2),
       st.floats(-math.pi, math.pi), st.floats(0.0, 0.8))
def test_it_makes_way_only_standing_on_her_way_out_between_her_and_it_while_she_walks_toward_it(rx, ry, px, py, heading, speed):
    f = _follower((rx, ry, 0.0))
    vx, vy = speed * math.cos(heading), speed * math.sin(heading)
    out = f._leaving(px, py, _track(vx, vy))
    if out is None:
        return
    wx, wy = out[0] - px, out[1] - py
    n = math.hypot(wx, wy)
    assert speed >= 0.3 and 1.0 < math.hypot(px - rx, py - ry) <= LEAVE_NEAR
    assert vx * wx + vy * wy >= math.cos(math.radians(45)) * speed * n - 1e-9  # she walks toward the way out
    assert 0.0 < ((rx - px) * wx + (ry - py) * wy) / n < n  # it stands between her and it
    assert float(way_distance(np.array([rx]), np.array([ry]), (px, py), out)[0]) < LATERAL  # on her way: she cannot pass


class _NoScan:
    @staticmethod
    def points() -> np.ndarray:
        return np.zeros((0, 2))

    @staticmethod
    def sees_through(*_a: object) -> bool:
        return False


class _Nobody:
    @staticmethod
    def around(*_a: object, **_k: object) -> np.ndarray:
        return np.zeros((0, 5))


@settings(max_examples=60, deadline=None)
@given(st.floats(0.75, 1.2), st.floats(0.3, 0.6), st.floats(-1.7, 0.0), st.floats(-math.pi / 2, -math.pi / 6),
       st.booleans())
def test_making_way_she_is_kept_in_the_lasers_view_while_she_walks_past_its_side(offset, speed, turning, aside, left):
    """During the step aside for her walking out (``_leave_aside``), she walks past the robot's side ``offset`` m
    from its centre at ``speed`` m/s while the step's way leads ``aside`` off the direction to her (and the robot
    already turns away from her at ``turning`` rad/s): her bearing stays within the laser's view (90 deg) until
    she is past it, so her track is kept through the pass (give24: the step turned it away, she passed 0.7 m from
    its side out of view, and it lost her). Mirrored with ``left``."""
    sign = 1.0 if left else -1.0
    f = Follower.__new__(Follower)
    f.route = SimpleNamespace(ready=True)  # type: ignore[assignment]
    f.sim = SimpleNamespace(now=0.0)  # type: ignore[assignment]
    f.limits, f.params = Limits(), DWAParams()
    f.scan, f.people = _NoScan(), _Nobody()  # type: ignore[assignment]
    f._unstall = lambda out, *a, **k: out  # type: ignore[method-assign]
    f._leave_aside = True
    x, y, th = 0.0, 0.0, 0.0
    v, w = 0.15, sign * turning
    # the spot 1.0 m off along ``aside`` (away from her side), reached on a straight leg
    spot = (math.cos(sign * aside), math.sin(sign * aside))
    hx, hy = 2.0, sign * offset  # she walks from 2 m ahead past its side, toward -x
    dt = 0.1
    for _ in range(60):
        f.odom, f.v, f.w = (x, y, th), v, w
        f.track = {"vx": -speed, "vy": 0.0}
        f._aside = ([(x, y), spot], 10.0, False)
        cmd = f._give_way(hx, hy, np.zeros((0, 2)))
        if cmd is None:
            break  # there: it waits facing her (the follower's wait turns to her)
        # the base: the turn rate changes at most max_turn_accel * dt a step
        dw = f.limits.max_turn_accel * dt
        w = max(w - dw, min(w + dw, cmd[1]))
        v = cmd[0]
        th += w * dt
        x, y = x + v * math.cos(th) * dt, y + v * math.sin(th) * dt
        hx -= speed * dt
        rx = math.cos(th) * (hx - x) + math.sin(th) * (hy - y)
        ry = -math.sin(th) * (hx - x) + math.cos(th) * (hy - y)
        if hx < x - 0.2:
            break  # she is past it
        assert abs(math.atan2(ry, rx)) <= math.radians(90), (hx, hy, x, y, th)
