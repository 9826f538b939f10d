"""The floor plan guards what the laser cannot see, and the follower gives way in a door.

* :mod:`robot.navigation.outline`: the map's walls and furniture as outline points round the
  robot (the go-to's dynamic window gets them with the laser's echoes);
* the player at a goal too tight to turn in (a niche between a bed and a wardrobe): it backs
  out the way it came, turns, and touches nothing (issue 26: goto_corridor touched the
  wardrobe turning on the spot at the goal);
* :func:`robot.navigation.giveway.give_way_spot`: where a robot standing in a door steps aside
  for a partner who wants through.
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings, strategies as st

from robot.floorplan import wall_rectangle
from robot.navigation.giveway import (BACK_FACE, BACK_GAIN, LATERAL, PASSAGE_ROOM, ROOM, back_out_spot, give_way_spot,
                                      reverse_command)
from robot.navigation import giveway
from robot.navigation.grid import OccupancyGrid, Plan2D
from robot.navigation.local import arcs
from robot.navigation.outline import FloorOutline, outline_points

from tests.nav_helpers import start_run


def _box(x0: float, y0: float, x1: float, y1: float) -> np.ndarray:
    return np.array([(x0, y0), (x1, y0), (x1, y1), (x0, y1)], dtype=float)


def _edge_distance(p: np.ndarray, poly: np.ndarray) -> float:
    best = math.inf
    for a, b in zip(poly, np.roll(poly, -1, axis=0)):
        ab = b - a
        t = min(1.0, max(0.0, float(np.dot(p - a, ab) / np.dot(ab, ab))))
        best = min(best, float(np.hypot(*(a + t * ab - p))))
    return best


@settings(max_examples=40, deadline=None)
@given(st.floats(0.0, 5.0), st.floats(0.0, 5.0), st.floats(0.05, 3.0), st.floats(0.05, 3.0), st.floats(0.01, 0.2))
def test_outline_points_lie_on_the_edges_and_leave_no_gap_wider_than_the_spacing(x, y, w, h, spacing):
    poly = _box(x, y, x + w, y + h)
    pts = outline_points(Plan2D((poly,), (0.0, 0.0, 0.0)), spacing=spacing)
    assert all(_edge_distance(p, poly) < 1e-9 for p in pts)
    # every point of the outline is within half a spacing of a sample
    for a, b in zip(poly, np.roll(poly, -1, axis=0)):
        for t in np.linspace(0.0, 1.0, 7):
            q = a + t * (b - a)
            assert float(np.hypot(*(pts - q).T).min()) <= spacing / 2 + 1e-9


def test_the_outline_round_a_pose_is_in_the_robot_frame_and_near_only():
    plan = Plan2D((_box(2.0, -0.5, 2.2, 0.5), _box(9.0, 0.0, 9.5, 0.5)), (0.0, 0.0, 0.0))
    around = FloorOutline(plan, near=1.5).around((1.0, 0.0, math.pi / 2))  # facing +y: the box lies to its right
    assert len(around)
    assert np.all(around[:, 1] < -0.99) and np.all(around[:, 1] > -1.21)  # 1.0-1.2 m to the right
    assert np.all(np.abs(around[:, 0]) <= 0.5 + 1e-9)  # nothing of the far box


# ---------------------------------------------------------------- the player at a tight goal
NICHE = """<?xml version="1.0" encoding="UTF-8"?>
<scenario name="nav_niche" seed="4" duration="60">
  <flat>
    <room name="bedroom" points="0,0 6,0 6,4 0,4"/>
    <walls thickness="0.1">
      <wall from="0 0" to="6 0"/>
      <wall from="6 0" to="6 4"/>
      <wall from="6 4" to="0 4"/>
      <wall from="0 4" to="0 0"/>
    </walls>
    <furniture name="bed" type="bed" points="3.0,0.1 5.0,0.1 5.0,1.5 3.0,1.5" height="0.5"/>
    <furniture name="wardrobe" type="shelf" points="4.4,2.2 5.7,2.2 5.7,2.8 4.4,2.8" height="2.0"/>
  </flat>
  <robot x="1.2" y="1.9" heading="0"/>
  <humans/>
  <expect><no-collision/></expect>
</scenario>
"""


def test_a_goal_too_tight_to_turn_in_is_backed_out_of_turned_at_and_nothing_is_touched():
    # the place (goto_corridor's bedroom, seen from the robot: 0.7 m between the bed and the end of a
    # wardrobe, 0.3 m from the wardrobe) faces back the way the robot comes: it arrives facing in,
    # and turning there would sweep a corner (0.33 m from the centre) into the wardrobe
    run = start_run("nav_niche", text=NICHE)
    at_reached: list[tuple[float, float, float]] = []  # the true pose when the player says reached
    run.sim.bus.participant("player_watch").subscribe(
        "/robot/player/status", lambda m: at_reached.append(run.world.robot.pose) if m.xml.get("state") == "reached" else None)
    run.at(0.5, run.engage)
    run.at(1.0, lambda: run.teach_place("wardrobe corner", 4.45, 1.9, math.pi))
    run.at(1.5, lambda: run.goto("wardrobe corner"))
    run.until(40.0)
    try:
        assert "goal_reached" in [e[1] for e in run.events]
        assert run.world.contacts == []
        x, y, th = at_reached[-1]  # the last step's (the plan's earlier waypoints are reached too)
        assert abs(math.remainder(th - math.pi, 2 * math.pi)) < math.radians(12)  # it faces out, as taught
        assert x < 4.45 - 0.15  # it backed out (to where the corners clear the wardrobe's end) ...
        assert math.hypot(x - 4.45, y - 1.9) <= 0.15 + 0.6 + 0.05  # ... no further than it may (ALIGN_BACK)
    finally:
        run.close()


# ---------------------------------------------------------------- giving way in a door
def _two_rooms() -> OccupancyGrid:
    """Room A (0-4 x 0-4) and room B (4-8 x 0-4), a 0.9 m door at y 1.55-2.45 in the wall x = 4."""
    walls = [wall_rectangle(a, b, 0.1) for a, b in (((0, 0), (8, 0)), ((8, 0), (8, 4)), ((8, 4), (0, 4)), ((0, 4), (0, 0)),
                                                     ((4, 0), (4, 1.55)), ((4, 2.45), (4, 4)))]
    return OccupancyGrid(Plan2D(tuple(walls), (1.0, 1.0, 0.0)), radius=0.30)


GRID = _two_rooms()


def test_a_robot_in_the_door_steps_aside_into_the_partners_room_out_of_her_way():
    robot, partner = (4.25, 2.0), (5.0, 1.6)
    path = give_way_spot(GRID, robot, partner, keep=1.0)
    assert path is not None and path[0] == robot
    spot = path[-1]
    assert spot[0] > 4.0  # her side of the door: not ahead of her on her way through it
    i, j = GRID.cell_of(spot)
    assert GRID.clearance[i, j] >= ROOM  # out of the door frame
    assert math.hypot(spot[0] - partner[0], spot[1] - partner[1]) >= 1.0


@settings(max_examples=60, deadline=None)
@given(st.floats(4.1, 4.4), st.floats(1.8, 2.2), st.floats(4.6, 6.5), st.floats(0.6, 3.4))
def test_every_give_way_spot_is_roomy_off_her_way_not_at_her_and_reached_on_a_free_way_past_her(rx, ry, px, py):
    robot, partner = (rx, ry), (px, py)
    path = give_way_spot(GRID, robot, partner, keep=1.0)
    if path is None:
        return
    spot = path[-1]
    i, j = GRID.cell_of(spot)
    assert GRID.clearance[i, j] >= ROOM
    d = math.hypot(rx - px, ry - py)
    ux, uy = (rx - px) / d, (ry - py) / d
    sx, sy = spot[0] - px, spot[1] - py
    assert abs(sx * uy - sy * ux) >= LATERAL - 1e-9  # to the side of the line from her through the robot
    assert sx * ux + sy * uy <= d + 1e-9  # not further down her way than the robot stands
    assert math.hypot(sx, sy) >= 1.0
    # the way there: free on the grid, never nearer her than she stands now (or 0.7 m), first leg toward her side
    for a, b in zip(path, path[1:]):
        assert GRID.line_free(a, b, roomy=False) or a == robot
        for t in np.linspace(0.0, 1.0, 11):
            q = (a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]))
            assert math.hypot(q[0] - px, q[1] - py) >= min(0.7, d) - 0.01 - 1e-9
    lx, ly = path[1][0] - rx, path[1][1] - ry
    assert -(ux * lx + uy * ly) >= math.cos(math.radians(100)) * math.hypot(lx, ly) - 1e-9


def test_no_give_way_spot_when_there_is_no_room_anywhere_near():
    corridor = OccupancyGrid(Plan2D((wall_rectangle((0, 0), (6, 0), 0.1), wall_rectangle((0, 1.0), (6, 1.0), 0.1)),
                                    (1.0, 0.5, 0.0)), radius=0.30)
    assert give_way_spot(corridor, (3.0, 0.5), (3.8, 0.5)) is None  # a 0.9 m corridor: nowhere roomy


# ---------------------------------------------------------------- yielding to someone walking at it
def test_someone_near_walking_at_the_robot_makes_it_yield_but_not_someone_walking_away_or_past():
    from robot.navigation.people import closing_in

    at_it = np.array([[1.2, 0.1, -0.6, 0.0]])  # ahead, walking toward the robot
    away = np.array([[1.2, 0.1, 0.6, 0.0]])
    across = np.array([[1.2, 0.0, 0.0, 0.7]])  # crossing in front, not toward the centre
    far = np.array([[3.0, 0.0, -0.8, 0.0]])
    behind = np.array([[-1.0, 0.0, 0.8, 0.0]])  # overtaking from behind: the laser does not see there
    assert closing_in(at_it, near=1.6, speed=0.15)
    assert not any(closing_in(p, near=1.6, speed=0.15) for p in (away, across, far, behind))
    assert not closing_in(np.zeros((0, 4)), near=1.6, speed=0.15)


@settings(max_examples=60, deadline=None)
@given(st.floats(-0.29, 1.5), st.floats(-1.5, 1.5), st.floats(0.16, 1.2), st.floats(-0.5, 0.5))
def test_whoever_walks_straight_at_it_from_near_is_yielded_to_and_whoever_walks_away_is_not(x, y, speed, skew):
    from robot.navigation.people import closing_in

    d = math.hypot(x, y)
    if not 0.3 < d < 1.6:
        return
    a = math.atan2(-y, -x) + skew  # toward the centre, up to ~30 degrees off
    toward = speed * math.cos(skew)
    vx, vy = speed * math.cos(a), speed * math.sin(a)
    assert closing_in(np.array([[x, y, vx, vy]]), near=1.6, speed=0.15) == (toward > 0.15)
    assert not closing_in(np.array([[x, y, -vx, -vy]]), near=1.6, speed=0.15)



# ---------------------------------------------------------------- backing out of a door (doors5)
def _storeroom() -> OccupancyGrid:
    """A kitchen (0-5 x 0-4) and a small storeroom (5-7.6 x 0-2.6) behind a 1.0 m door at y 0.8-1.8,
    a freezer along the storeroom's side and shelves along its far wall: nowhere roomy to step aside in it."""
    walls = [wall_rectangle(a, b, 0.1) for a, b in (((0, 0), (7.6, 0)), ((0, 4), (5, 4)), ((0, 0), (0, 4)),
                                                     ((5, 0), (5, 0.8)), ((5, 1.8), (5, 4)), ((5, 2.6), (7.6, 2.6)),
                                                     ((7.6, 0), (7.6, 2.6)))]
    furniture = [_box(7.1, 0.1, 7.5, 2.5), _box(5.9, 0.1, 6.9, 0.6)]
    return OccupancyGrid(Plan2D(tuple(walls + furniture), (1.0, 1.0, 0.0)), radius=0.30)


STOREROOM = _storeroom()


def test_a_robot_in_a_storeroom_door_with_her_inside_backs_out_into_the_kitchen_beside_the_door():
    robot, partner = (5.3, 1.19), (5.7, 1.55)  # it faces her; she wants out through the door behind it
    assert give_way_spot(STOREROOM, robot, partner, keep=1.0) is None  # nowhere ahead
    path = back_out_spot(STOREROOM, robot, partner, keep=1.0)
    assert path is not None and path[0] == robot
    spot = path[-1]
    assert spot[0] < 4.95  # through the door, in the kitchen
    i, j = STOREROOM.cell_of(spot)
    assert STOREROOM.clearance[i, j] >= ROOM
    assert abs(spot[1] - 1.3) >= 0.5  # beside the door's mouth, not on along her way out of it


@settings(max_examples=40, deadline=None)
@given(st.floats(5.1, 5.5), st.floats(1.0, 1.6), st.floats(5.9, 6.6), st.floats(0.9, 2.2))
def test_every_back_out_path_leads_away_from_her_to_a_roomy_spot_further_off_and_never_nearer_her(rx, ry, px, py):
    robot, partner = (rx, ry), (px, py)
    path = back_out_spot(STOREROOM, robot, partner, keep=1.0)
    if path is None:
        return
    spot = path[-1]
    i, j = STOREROOM.cell_of(spot)
    # a roomy spot when there is one (the rule of doors5); else one where it still turns, off the door's
    # line, first leg away from her (yield9: a dead-end room's door onto a corridor has no roomy spot)
    roomy = giveway._spot(STOREROOM, robot, partner, keep=1.0, room=ROOM, lateral=LATERAL, reach=giveway.REACH,
                          backing=True)
    assert roomy is None or path == roomy
    assert STOREROOM.clearance[i, j] >= (ROOM if roomy is not None else PASSAGE_ROOM)
    d = math.hypot(rx - px, ry - py)
    assert math.hypot(spot[0] - px, spot[1] - py) >= max(1.0, d + BACK_GAIN) - 1e-9
    ux, uy = (rx - px) / d, (ry - py) / d
    lx, ly = path[1][0] - rx, path[1][1] - ry
    face = BACK_FACE if roomy is not None else giveway.PASSAGE_FACE
    assert ux * lx + uy * ly >= math.cos(face) * math.hypot(lx, ly) - 1e-9  # it reverses away from her
    if roomy is None:  # off the line it backs out along
        assert abs((spot[0] - rx) * ly - (spot[1] - ry) * lx) >= LATERAL * math.hypot(lx, ly) - 1e-9
    for a, b in zip(path, path[1:]):
        for t in np.linspace(0.0, 1.0, 11):
            q = (a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]))
            assert math.hypot(q[0] - px, q[1] - py) >= min(0.7, d) - 0.01 - 1e-9


@settings(max_examples=60, deadline=None)
@given(st.floats(-3.0, -0.1), st.floats(-2.0, 2.0))
def test_reversing_steers_the_rear_toward_a_goal_behind_and_never_drives_forwards(gx, gy):
    v, w = reverse_command((gx, gy), speed=0.2, max_turn=1.0)
    assert -0.2 - 1e-9 <= v <= 0.0
    off = math.atan2(-gy, -gx)
    if abs(off) > 1e-6:
        assert w * off > 0  # turning so the rear swings toward it
    if abs(off) >= math.pi / 2:
        assert v == 0.0
    x, y, _ = arcs(np.array([v]), np.array([w]), np.array([0.3]))
    assert math.hypot(gx - x[0, 0], gy - y[0, 0]) <= math.hypot(gx, gy) + 1e-9  # no further from it


# ---------------------------------------------------------------- backing out of a door into a corridor (yield9)
def _corridor_study() -> OccupancyGrid:
    """A corridor 1.0 m wide between its walls (x 0-8, walls on y = 0 and y = 1.1, 0.1 m thick) and a
    study (x 3-6, y 1.1-4) behind a 0.9 m door at x 4.05-4.95: the study is a dead end, the corridor has
    no cell 0.5 m from every wall (issue 26, galley_follow_bend: the robot stood in the study door
    while its partner waited to come out)."""
    walls = [wall_rectangle(a, b, 0.1) for a, b in (((0, 0), (8, 0)), ((0, 1.1), (4.05, 1.1)), ((4.95, 1.1), (8, 1.1)),
                                                     ((0, 0), (0, 1.1)), ((8, 0), (8, 1.1)), ((3, 1.1), (3, 4)),
                                                     ((6, 1.1), (6, 4)), ((3, 4), (6, 4)))]
    return OccupancyGrid(Plan2D(tuple(walls), (1.0, 0.5, 0.0)), radius=0.30)


CORRIDOR_STUDY = _corridor_study()


def test_a_robot_in_a_dead_end_rooms_door_backs_out_along_the_corridor_to_the_side_it_did_not_come_by():
    robot = (4.5, 1.2)  # in the door, facing her; she wants out through it
    for partner, came, east in (((4.75, 1.75), (1.5, 0.55), True), ((4.75, 1.75), (7.0, 0.55), False),
                                # she stands diagonally in the room, on the side it did not come by
                                ((5.0, 1.6), (1.5, 0.55), True), ((4.0, 1.6), (7.0, 0.55), False)):
        assert give_way_spot(CORRIDOR_STUDY, robot, partner, keep=1.0) is None
        path = back_out_spot(CORRIDOR_STUDY, robot, partner, keep=1.0, came=came)
        assert path is not None and path[0] == robot  # (None on the old code: no cell has ROOM)
        x, y = path[-1]
        assert 0.1 < y < 1.0  # in the corridor
        assert (x > 4.5) == east  # the way it did not come by: she leads it back the way it came
        assert abs(x - 4.5) >= LATERAL  # off the door's line: she walks out of the door past it
        i, j = CORRIDOR_STUDY.cell_of((x, y))
        assert CORRIDOR_STUDY.clearance[i, j] >= PASSAGE_ROOM


@settings(max_examples=40, deadline=None)
@given(st.floats(4.3, 4.7), st.floats(1.1, 1.3), st.floats(4.2, 5.6), st.floats(1.7, 2.6))
def test_backing_out_into_a_corridor_never_takes_the_side_it_came_by_when_the_other_has_a_spot(rx, ry, px, py):
    robot, partner = (rx, ry), (px, py)
    west = back_out_spot(CORRIDOR_STUDY, robot, partner, keep=1.0, came=(1.0, 0.55))
    east = back_out_spot(CORRIDOR_STUDY, robot, partner, keep=1.0, came=(8.0, 0.55))
    assert (west is None) == (east is None)  # where it came from only orders the spots
    if west is None or east is None:
        return
    # came from the west it takes the east unless the east has none (then the call from the east, which
    # prefers the west, takes the west too), and the other way round
    assert not (west[-1][0] < rx and east[-1][0] > rx)
    d = math.hypot(rx - px, ry - py)
    for path in (west, east):
        x, y = path[-1]
        i, j = CORRIDOR_STUDY.cell_of((x, y))
        assert CORRIDOR_STUDY.clearance[i, j] >= PASSAGE_ROOM
        assert math.hypot(x - px, y - py) >= max(1.0, d + BACK_GAIN) - 1e-9  # further from her
        lx, ly = path[1][0] - rx, path[1][1] - ry
        assert abs((x - rx) * ly - (y - ry) * lx) >= LATERAL * math.hypot(lx, ly) - 1e-9  # off the line out of the door
        for a, b in zip(path, path[1:]):
            for t in np.linspace(0.0, 1.0, 11):
                q = (a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]))
                assert math.hypot(q[0] - px, q[1] - py) >= min(0.7, d) - 0.01 - 1e-9  # never nearer her


def test_a_give_way_that_cannot_move_for_two_seconds_backs_out_into_the_corridor_instead():
    """galley_follow_bend seeds 2, 5, 6: the approach ended just inside the study, the forward give-way
    spot lay beside her and every step toward it swung a corner into her, so the robot stood there
    with her 0.5 m in front for the rest of the run. Its command zero for GIVE_WAY_STALL s, it takes
    the back-out path into the corridor (the side it did not come by) instead."""
    from collections import deque

    from robot.navigation.follow import GIVE_WAY_STALL, Follower

    class _Follower(Follower):
        now = 0.0  # (the simulation's clock, set by hand)

    f = _Follower.__new__(_Follower)

    class _Route:
        grid = CORRIDOR_STUDY
        to_map = to_odom = staticmethod(lambda p: p)

    f.route, f.odom, f.band = _Route(), (4.5, 1.2, math.pi / 2), (1.0, 1.5)
    f.crumbs = deque([(x, 0.55) for x in np.arange(1.0, 4.4, 0.05)] + [(4.5, 1.0)])  # it came from the west
    f._aside, f._aside_stall = None, None
    f.now = 0.0
    assert f._unstall((0.1, 0.2), 4.75, 1.75, np.zeros((0, 2))) == (0.1, 0.2)  # moving: nothing changes
    while f.now < GIVE_WAY_STALL - 0.05:
        f._unstall((0.0, 0.0), 4.75, 1.75, np.zeros((0, 2)))
        assert f._aside is None  # (not yet)
        f.now += 0.1
    f.now = GIVE_WAY_STALL + 0.05
    f._unstall((0.0, 0.0), 4.75, 1.75, np.zeros((0, 2)))
    assert f._aside is not None and f._aside[2]  # backing out
    x, y = f._aside[0][-1]
    assert 0.1 < y < 1.0 and x >= 4.5 + LATERAL  # along the corridor, east: the way it did not come by
    f._aside, f._aside_stall, f.now = None, None, 10.0  # a stall that was interrupted starts again
    f._unstall((0.0, 0.0), 4.75, 1.75, np.zeros((0, 2)))
    f.now = 11.0
    f._unstall((0.0, 0.0), 4.75, 1.75, np.zeros((0, 2)))  # (a second later, not 0.1 s: a new stall)
    f.now = 11.5
    f._unstall((0.0, 0.0), 4.75, 1.75, np.zeros((0, 2)))
    assert f._aside is None
