"""The follower's way on the floor plan (issue 26 items 2 and 10): :mod:`robot.navigation.route`.

Unit level: frames, the path through a 0.9 m door, the floor plan's walls round the robot and
the safety check of the follower's own turns and back-offs. Run level (the whole robot):
``tests/scenarios/nav/catch_up_l_flat.xml``, a slow robot that comes up to its partner through
a 0.9 m door into a 1.0 m corridor before her next request is handled.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from hypothesis import example, given, settings
from hypothesis import strategies as st

from homesim.tour.runner import Run, RunOptions
from robot.navigation.follow import SWEEP_MARGIN, SWEEP_TIME, Follower, sweep_allowed
from robot.navigation.grid import OccupancyGrid, Plan2D
from robot.navigation.local import footprint_distance, sweep_clearance
from robot.navigation.route import NEAR, Route

NAV = Path(__file__).resolve().parent / "scenarios" / "nav"


def _box(x0: float, y0: float, x1: float, y1: float) -> np.ndarray:
    return np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]], dtype=float)


def _two_rooms(door: float = 0.9) -> OccupancyGrid:
    """Two 4 x 4 m rooms side by side, a wall at x = 4 with a ``door`` m opening centred at y = 2."""
    lo, hi = 2.0 - door / 2, 2.0 + door / 2
    walls = [_box(-0.05, -0.05, 8.05, 0.05), _box(-0.05, 3.95, 8.05, 4.05), _box(-0.05, -0.05, 0.05, 4.05),
             _box(7.95, -0.05, 8.05, 4.05), _box(3.95, -0.05, 4.05, lo), _box(3.95, hi, 4.05, 4.05)]
    return OccupancyGrid(Plan2D(tuple(walls), (1.0, 2.0, 0.0)), radius=0.30)


def _route(grid: OccupancyGrid, map_pose=(0.0, 0.0, 0.0), odom=(0.0, 0.0, 0.0)) -> Route:
    r = Route()
    r.set_grid(grid)
    r.on_pose(map_pose, odom)
    return r


def _drive(route: Route, start: tuple[float, float], target: tuple[float, float], step: float = 0.04) -> list[tuple[float, float]]:
    """Walk a point along the route's goals (a perfect pure-pursuit robot) until it is 0.5 m from the target."""
    p, out, t = start, [start], 0.0
    for _ in range(2000):
        if math.hypot(target[0] - p[0], target[1] - p[1]) < 0.5:
            break
        g = route.goal(t, p, target) or target
        d = math.hypot(g[0] - p[0], g[1] - p[1])
        if d < 1e-9:
            break
        p = (p[0] + step * (g[0] - p[0]) / d, p[1] + step * (g[1] - p[1]) / d)
        out.append(p)
        t += 0.1
    return out


def _jamb_clearance(path: list[tuple[float, float]], door: float) -> float:
    """The smallest distance (m) from the footprint, heading along ``path``, to the jambs' outline
    (the wall boxes at x 3.95-4.05 either side of a ``door`` m opening, sampled every 1 cm)."""
    lo, hi = 2.0 - door / 2, 2.0 + door / 2
    xs = np.arange(3.95, 4.0501, 0.01)
    ys_lo, ys_hi = np.arange(lo - 0.6, lo + 1e-9, 0.01), np.arange(hi, hi + 0.6, 0.01)
    jamb = np.array([(x, y) for x in xs for y in np.concatenate((ys_lo, ys_hi))])
    best = math.inf
    for (x0, y0), (x1, y1) in zip(path, path[1:]):
        th = math.atan2(y1 - y0, x1 - x0)
        c, s = math.cos(th), math.sin(th)
        dx, dy = jamb[:, 0] - x1, jamb[:, 1] - y1
        best = min(best, float(footprint_distance(c * dx + s * dy, -s * dx + c * dy).min()))
    return best


@settings(max_examples=12, deadline=None)
@given(st.floats(0.5, 3.3), st.floats(0.5, 3.5), st.floats(4.7, 7.5), st.floats(0.5, 3.5))
@example(2.332, 3.219, 6.0, 3.0)  # a steep way in: its points near the wall were 0.15+ m off the door's axis
def test_the_way_to_her_through_a_09_m_door_keeps_the_robot_clear_of_the_jambs(rx, ry, px, py):
    # wherever she stands in the next room, the way goes through the door with the robot's
    # footprint, heading along the way, clear of the jambs all along
    grid = _two_rooms(0.9)
    route = _route(grid)
    path = _drive(route, (rx, ry), (px, py))
    assert math.hypot(path[-1][0] - px, path[-1][1] - py) < 0.6  # it got there
    assert any(3.95 <= p[0] <= 4.05 for p in path)  # through the door
    assert _jamb_clearance(path, 0.9) >= 0.05  # the sweep margin of the follower's own checks


@settings(max_examples=60, deadline=None)
@given(st.tuples(st.floats(-5, 5), st.floats(-5, 5), st.floats(-3.2, 3.2)),
       st.tuples(st.floats(-5, 5), st.floats(-5, 5), st.floats(-3.2, 3.2)),
       st.tuples(st.floats(-5, 5), st.floats(-5, 5)))
def test_map_and_odom_frames_are_inverse(map_pose, odom_pose, p):
    r = _route(_two_rooms(), map_pose, odom_pose)
    q = r.to_odom(r.to_map(p))
    assert math.hypot(q[0] - p[0], q[1] - p[1]) < 1e-9


def test_a_clear_line_leaves_the_trail_to_the_follower_and_no_plan_is_made():
    r = _route(_two_rooms())
    assert r.goal(0.0, (1.0, 2.0), (3.0, 2.2)) is None and r.plans == 0
    assert r.goal(0.0, (1.0, 1.0), (6.0, 3.0)) is not None and r.plans == 1


@settings(max_examples=40, deadline=None)
@given(st.floats(0.4, 7.6), st.floats(0.4, 3.6), st.floats(-3.2, 3.2))
def test_the_walls_round_the_robot_come_in_the_robot_frame(x, y, th):
    grid = _two_rooms()
    r = _route(grid)
    pts = r.obstacles_near((x, y, th))
    assert len(pts) == 0 or (np.abs(pts) <= NEAR * math.sqrt(2) + 1e-9).all()
    i, j = grid.cell_of((x, y))
    if grid.clearance[i, j] < NEAR - 0.1:
        # the nearest outline point is as far as the grid says the nearest wall is (cells of 5 cm)
        assert abs(float(np.hypot(pts[:, 0], pts[:, 1]).min()) - float(grid.clearance[i, j])) < 0.08


def test_the_floor_plan_is_behind_the_robot_too():
    # the robot faces away from the wall x = 4, its back 0.1 m from it: the map points behind it
    r = _route(_two_rooms())
    pts = r.obstacles_near((3.65, 1.0, math.pi))
    assert (pts[:, 0] < 0).any()  # behind (robot frame: x forward)
    assert footprint_distance(pts[:, 0], pts[:, 1]).min() < 0.12


@settings(max_examples=150, deadline=None)
@given(st.floats(-0.2, 0.0), st.floats(-1.7, 1.7),
       st.lists(st.tuples(st.floats(-1.0, 1.0), st.floats(-1.0, 1.0)), min_size=1, max_size=12))
def test_the_followers_own_turns_and_back_offs_never_sweep_into_the_floor_plan(v, w, pts):
    pts = np.array(pts)
    here = float(footprint_distance(pts[:, 0], pts[:, 1]).min())
    f = Follower.__new__(Follower)  # _swept reads nothing but its arguments
    cv, cw = f._swept(v, w, pts)
    gap = sweep_clearance(cv, cw, pts, SWEEP_TIME)
    # what it does keeps its margin, or (closer already, not touching) comes no closer than it is, or is standing
    assert (cv, cw) == (0.0, 0.0) or gap >= SWEEP_MARGIN - 1e-9 or (here > 0.0 and sweep_allowed(cv, cw, pts, here))
    assert cv in (0.0, v) and cw in (0.0, w)


def test_the_sweep_of_standing_still_is_the_distance_now():
    pts = np.array([[0.5, 0.0], [0.0, -0.6]])
    assert math.isclose(sweep_clearance(0.0, 0.0, pts, 0.5), float(footprint_distance(pts[:, 0], pts[:, 1]).min()))
    assert sweep_clearance(0.0, 1.0, np.zeros((0, 2)), 0.5) == math.inf


def test_a_slow_robot_catches_up_through_the_door_before_her_next_request():
    with Run.from_file(NAV / "catch_up_l_flat.xml", RunOptions(seed=0)) as run:
        run.run()
        verdicts = run.finish()
        s = run.summary()
    said = [u["text"] for u in s["utterances"] if u["speaker"] == "robot"]
    assert any("slow down" in t or "too fast" in t for t in said)
    social = s["metrics"]["social"]
    assert social["request_distance_max_m"] <= 2.0 and social["request_bearing_max_deg"] <= 30
    assert social["collisions_people"] == 0 and social["collisions_flat"] == 0
    assert all(v.passed for v in verdicts), [v.detail for v in verdicts if not v.passed]


@given(st.integers(1, 25), st.integers(1, 25), st.integers(0, 2**32 - 1), st.floats(0.0, 1.0))
@settings(max_examples=80, deadline=None)
def test_the_routes_erosion_is_scipys(rows, cols, seed, share):
    """The floor plan's outline cells: numpy's erosion equals ``scipy.ndimage.binary_erosion(border_value=1)``."""
    from scipy import ndimage

    from robot.navigation.route import _eroded

    occ = np.random.default_rng(seed).random((rows, cols)) < share
    assert (_eroded(occ) == ndimage.binary_erosion(occ, border_value=1)).all()


@settings(max_examples=300, deadline=None)
@given(st.tuples(st.floats(-1.0, 9.0), st.floats(-1.0, 5.0)), st.tuples(st.floats(-1.0, 9.0), st.floats(-1.0, 5.0)),
       st.tuples(st.floats(-2.0, 2.0), st.floats(-2.0, 2.0), st.floats(-math.pi, math.pi)),
       st.tuples(st.floats(-2.0, 2.0), st.floats(-2.0, 2.0), st.floats(-math.pi, math.pi)))
@example((1.0, 2.0), (7.0, 2.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))  # through the door
@example((1.0, 1.0), (7.0, 1.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))  # through the wall
@example((-0.9, 2.0), (-0.5, 2.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))  # off the grid
def test_in_sight_and_to_map_are_the_vectorised_answers(a, b, map_pose, odom) -> None:
    """The follower asks ``in_sight`` and ``to_map`` hundreds of times a control step (its walk-on search), so
    they run in plain floats with the pose pair's cosine and sine kept: the answers must be exactly the
    vectorised reference's and ``_rebase``'s (a step's free or not decides where the robot looks for her)."""
    from robot.navigation.grid import _inside
    from robot.navigation.route import _in_sight_reference, _rebase

    route = _route(_two_rooms(), map_pose, odom)
    rooms = (_box(0.0, 0.0, 4.0, 4.0), np.array([[4.0, 0.0], [8.0, 0.0], [8.0, 4.0], [6.0, 2.0], [4.0, 4.0]]))  # one not convex
    route.set_rooms(rooms)
    g = route.grid
    for _ in range(2):  # the second time with the kept transform and cells
        ma, mb = _rebase(a, odom, map_pose), _rebase(b, odom, map_pose)
        assert route.to_map(a) == ma
        assert route.to_map(b) == mb
        assert route.in_sight(a, b) == _in_sight_reference(g, ma, mb)
        i, j = g.cell_of(mb)
        assert route.clearance(b) == (float(g.clearance[i, j]) if g.inside((i, j)) else 0.0)
        held = [r for r in rooms if bool(_inside(np.array([mb[0]]), np.array([mb[1]]), r)[0])]
        assert route.room_at(b) is (None if not held else route.rooms[[id(r) for r in rooms].index(id(held[0]))])
    moved = (odom[0] + 0.3, odom[1], odom[2] + 0.1)
    route.on_pose(map_pose, moved)  # a new pose pair: the transform follows it
    assert route.to_map(a) == _rebase(a, moved, map_pose)
