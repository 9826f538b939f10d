"""Go-to among people (issue 26 items 2 and 4): the replan gives standing people their space, the
player faces a first leg before it drives it, and never swings a corner into a tracked body.

goto_standing_person seed 2: the replan's path passed Ida 0.55 m centre to centre (her body and the
robot's radius), nearer than the player's window drives past anyone (GOTO_SOCIAL_GAP of air), so the
robot stood blocked beside her for 14 s and replanned three times. goto_l_flat seeds 7 and 9: the
first leg, begun with a forward arc 47 degrees off, swung the robot 8 cm off the line to a door jamb,
where it stood wedged and then backed into a man it could not see.
"""

from __future__ import annotations

import math
from collections import deque
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest
from hypothesis import assume, event, example, given, settings
from hypothesis import strategies as st
from lxml import etree

from homesim.sim import Simulation
from robot.navigation.grid import NoPathError, OccupancyGrid, Plan2D
from robot.navigation.local import BODY, HALF_WIDTH, DWAParams, LatestScan, footprint_distance, social_mask, turn_clear
from robot.navigation.planner import PERSON_CLEAR, Planner, social_grid
from robot.navigation.people import BACK_GAP, passing_close, standing_in_the_way
from robot.navigation.player import GOTO_SOCIAL_GAP, SQUEEZE_GAP, SQUEEZE_SPEED, TURN_FIRST, WAIT_GAP, Player, arc_air


def _walls(*rects: tuple[float, float, float, float]) -> OccupancyGrid:
    polys = tuple(np.array([(x0, y0), (x1, y0), (x1, y1), (x0, y1)], dtype=float) for x0, y0, x1, y1 in rects)
    return OccupancyGrid(Plan2D(polygons=polys, start=(1.0, 2.0, 0.0)), radius=0.3)


#: an open 6 x 4 m room
ROOM = _walls((0, 0, 6, 0.1), (0, 3.9, 6, 4), (0, 0, 0.1, 4), (5.9, 0, 6, 4))
#: the same split at x = 3 by a wall with one 1.2 m door (y 1.4-2.6)
DOOR = _walls((0, 0, 6, 0.1), (0, 3.9, 6, 4), (0, 0, 0.1, 4), (5.9, 0, 6, 4), (2.95, 0, 3.05, 1.4), (2.95, 2.6, 3.05, 4))


def _min_distance(path: list[tuple[float, float]], p: tuple[float, float]) -> float:
    best = math.inf
    for (ax, ay), (bx, by) in zip(path, path[1:]):
        for t in np.linspace(0.0, 1.0, 60):
            best = min(best, math.hypot(ax + t * (bx - ax) - p[0], ay + t * (by - ay) - p[1]))
    return best


@pytest.mark.parametrize("side", [1.0, -1.0])
def test_the_window_drives_past_someone_at_the_person_clearance_and_not_nearer(side):
    """The planner's PERSON_CLEAR is the nearest the player's window drives past a person: a straight
    drive passing her centre at PERSON_CLEAR is admitted by the window's social rule (GOTO_SOCIAL_GAP of
    air from her body), one passing 5 cm nearer is not (review9 item 7: this was the formula restated)."""
    x = np.linspace(0.0, 3.0, 61)
    zeros = np.zeros_like(x)
    for lateral, admitted in ((PERSON_CLEAR, True), (PERSON_CLEAR - 0.05, False)):
        person = np.array([[1.5, side * lateral]])  # robot-frame: she stands beside the line it drives
        ok, gaps = social_mask(x[None, :], zeros[None, :], zeros[None, :], person, gap=GOTO_SOCIAL_GAP)
        assert bool(ok[0]) == admitted, (lateral, float(gaps[0]))


def _social_path_is_clear(people: list[tuple[float, float]]) -> None:
    path = social_grid(ROOM, np.array(people, dtype=float)).plan((0.6, 2.0), (5.4, 2.0))
    for p in people:  # a cell and a half of slack: the marked disc and the free cells are rasterised
        assert _min_distance(path, p) >= PERSON_CLEAR - 1e-6, (p, _min_distance(path, p))


def _away_from_the_ends(people: list[tuple[float, float]]) -> bool:
    return all(min(math.hypot(x - 0.6, y - 2.0), math.hypot(x - 5.4, y - 2.0)) > PERSON_CLEAR + 0.1 for x, y in people)


@settings(max_examples=40, deadline=None)
@given(st.tuples(st.floats(0.8, 5.2), st.floats(0.6, 3.4)))
def test_a_social_path_past_one_person_always_exists_and_keeps_her_clear(person):
    # the 4 m room always leaves a way past one person with her space (so no draw is skipped)
    assume(_away_from_the_ends([person]))
    _social_path_is_clear([person])


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(st.floats(0.8, 5.2), st.floats(0.6, 3.4)), min_size=2, max_size=3))
def test_a_social_path_keeps_every_person_clear_by_what_the_window_drives_past(people):
    assume(_away_from_the_ends(people))
    try:
        _social_path_is_clear(people)
    except NoPathError:
        # no way past them all with their space: the planner falls back to their bodies (below). Such
        # draws are counted (hypothesis --hypothesis-show-statistics); the one-person property above and the
        # fixed cases below must plan, so the property cannot pass by every draw finding no path
        event("no way with everyone's space")


@pytest.mark.parametrize("people", [[(2.0, 1.0), (4.0, 3.0)], [(2.5, 2.0), (4.0, 2.2)], [(1.5, 3.2), (3.0, 0.8), (4.5, 3.2)]])
def test_a_social_path_past_people_standing_apart_is_found_and_keeps_them_clear(people):
    _social_path_is_clear(people)  # raises NoPathError if their space were taken to close the room


def _planner(grid: OccupancyGrid, pose: tuple[float, float, float], goal: tuple[float, float],
             person: tuple[float, float]) -> tuple[Planner, list[etree._Element]]:
    """A planner (no bus) that has planned to ``goal`` and whose latest scan shows one person standing
    at ``person`` (map frame): her legs and the ring of her body, as :func:`scan_points` gives them."""
    pl = Planner.__new__(Planner)
    pl.avoid, pl.path, pl.blockers = deque(), [], deque()  # no spot where a go-to was blocked, nobody who stood in the way
    pl.grid = grid
    pl._pose_xml = etree.Element("pose", x=str(pose[0]), y=str(pose[1]), theta=str(pose[2]))
    pl.goal = ("kitchen", (goal[0], goal[1], 0.0))
    x, y, th = pose
    c, s = math.cos(-th), math.sin(-th)
    dx, dy = person[0] - x, person[1] - y
    centre = np.array([[c * dx - s * dy, s * dx + c * dy]])
    a = np.linspace(0.0, 2 * math.pi, 24, endpoint=False)
    ring = np.concatenate([centre + 0.25 * np.column_stack((np.cos(a), np.sin(a))),
                           centre + [[0.0, 0.1]], centre + [[0.0, -0.1]]])
    pl.scan = SimpleNamespace(points=lambda: ring, bodies=lambda: centre)
    published: list[etree._Element] = []

    def publish(title, points, theta=None, failed=None, replan=False):  # noqa: ANN001, ANN202
        published.append(SimpleNamespace(points=points, failed=failed, replan=replan))
    pl._publish = publish  # type: ignore[method-assign]
    return pl, published


@pytest.mark.parametrize("pose, person", [((5.0, 2.15, math.pi), (4.12, 2.0)), ((4.5, 2.0, math.pi), (3.7, 1.9))])
def test_a_replan_passes_a_person_standing_on_the_way_with_the_go_tos_air(pose, person):
    # the robot stopped about 0.9 m before her (blocked), the goal beyond her; the room leaves space
    # round her. The old replan kept only her body and the robot's radius clear: its first leg passed
    # her 0.68 m centre to centre, nearer than the window drives past anyone, and the robot stood
    pl, out = _planner(ROOM, pose, (1.2, 1.8), person)
    path = pl.replan()
    assert path is not None and out[-1].replan and not out[-1].failed
    assert _min_distance(path, person) >= PERSON_CLEAR - 1.5 * ROOM.cell


def test_a_person_in_a_door_with_no_room_for_her_space_still_gets_the_bodies_path():
    # she stands 0.45 m off the middle of the 1.2 m door: the far side leaves the robot's centre 0.6 m
    # from hers, less than PERSON_CLEAR; the way past her body is still planned (the window then waits)
    pl, out = _planner(DOOR, (1.5, 2.0, 0.0), (5.0, 2.0), (3.0, 2.45))
    path = pl.replan()
    assert path is not None and not out[-1].failed
    assert _min_distance(path[1:], (3.0, 2.45)) < PERSON_CLEAR


def _scan(ranges: np.ndarray) -> SimpleNamespace:
    xml = etree.Element("scan", min_angle="-90.0", resolution="0.5", max_range="8.19", offset="0.13")
    return SimpleNamespace(xml=xml, attachments={"ranges": ranges})


def test_a_pair_of_legs_in_a_scan_is_one_person_and_a_lone_table_leg_none():
    r = np.full(361, 8.19)
    r[176:179], r[183:186] = 2.0, 2.0  # two legs 2 m ahead, about 0.2 m apart
    latest = LatestScan()
    latest.update(_scan(r))
    got = latest.bodies()
    assert got.shape == (1, 2) and abs(got[0, 1]) < 0.05 and 2.0 < got[0, 0] < 2.3
    r = np.full(361, 8.19)
    r[100:103] = 1.5  # one narrow cluster: a table leg, or one leg hiding the other
    latest.update(_scan(r))
    assert latest.bodies().shape == (0, 2)


class _Bus:
    def __init__(self) -> None:
        self.sent: list[tuple[str, etree._Element]] = []

    def publish(self, channel: str, el: etree._Element) -> None:
        self.sent.append((channel, el))


def _player(goal: tuple[float, float], *, facing: bool, tracks: list[tuple[float, ...]] = ()) -> Player:
    """A player standing at the origin facing +x with a ``move_to`` under way (no bus, no map)."""
    sim = Simulation(seed=0)
    p = Player(sim)
    p.bus = _Bus()  # type: ignore[assignment]
    pose = etree.Element("pose", x="0", y="0", theta="0")
    p._pose_xml = pose
    odo = etree.Element("odometry", x="0", y="0", theta="0", v="0", w="0")
    p.odo.update(odo)
    p._odo_xml_at_pose = odo
    p.goal = (goal[0], goal[1], 0.0, 0.2, False)
    p.leg_start = (0.0, 0.0)
    p._facing = facing
    p._best, p._best_t = math.inf, 0.0
    el = etree.Element("tracks", time="0", frame="odom")
    for i, (x, y, *v) in enumerate(tracks):
        vx, vy = v if v else (0.0, 0.0)
        etree.SubElement(el, "track", id=f"t{i}", x=str(x), y=str(y), vx=str(vx), vy=str(vy), confirmed="true")
    p.people.update(el)
    p.state = "moving"
    return p


@pytest.mark.parametrize("bearing", [40.0, 55.0, 75.0, 120.0])
def test_a_first_leg_off_the_heading_is_turned_to_on_the_spot_before_the_robot_drives(bearing):
    goal = (3.0 * math.cos(math.radians(bearing)), 3.0 * math.sin(math.radians(bearing)))
    v, w = _player(goal, facing=True).control_step()
    assert v == 0.0 and w > 0.0  # turns left, toward it, standing
    assert math.radians(bearing) > TURN_FIRST


def test_a_leg_after_a_corner_is_driven_in_an_arc():
    # the robot came along the previous leg: no stop to turn (the rear corners would swing through
    # ground the laser does not see)
    v, w = _player((3.0 * math.cos(math.radians(40)), 3.0 * math.sin(math.radians(40))), facing=False).control_step()
    assert v > 0.0 and w > 0.0


def test_a_turn_on_the_spot_never_swings_a_corner_into_a_tracked_person():
    # she stands pressed to the rear left corner, 3 cm of air; the goal lies to the left: turning left
    # swings that corner into her (the window lets every turn on the spot pass people)
    x, y = -0.255 - BODY - 0.03, 0.2
    assert footprint_distance(np.array([x]), np.array([y]))[0] - BODY > 0.0
    v, w = _player((0.0, 3.0), facing=True, tracks=[(x, y)]).control_step()
    assert v == 0.0 and w == 0.0
    v, w = _player((0.0, 3.0), facing=True, tracks=[(3.0, -2.0)]).control_step()
    assert v == 0.0 and w > 0.0  # with her far away it turns


@settings(max_examples=200, deadline=None)
@given(x=st.floats(-3.0, 3.0), y=st.floats(-2.0, 2.0), vx=st.floats(-1.0, 1.0), vy=st.floats(-1.0, 1.0),
       travel=st.floats(0.0, 0.1))
def test_the_go_to_waits_outside_the_personal_space_of_exactly_those_standing_in_its_lane(x, y, vx, vy, travel):
    got = standing_in_the_way(np.array([[x, y, vx, vy]]), half_length=0.255, half_width=0.215, travel=travel, gap=WAIT_GAP)
    # driving straight on ``travel`` m: the air between the footprint's front and her body
    in_lane = x > 0.0 and abs(y) < 0.215 + BODY and math.hypot(vx, vy) < 0.3
    air = x - 0.255 - BODY - travel
    assert got == (in_lane and air < WAIT_GAP)
    if not got and in_lane:
        assert air >= BACK_GAP  # never inside her personal space (Hall's 0.45 m, body to body)


def test_someone_standing_in_the_lane_is_waited_for_outside_their_personal_space():
    # she stands 1.0 m ahead (0.495 m of air to the bumper): the window would drive on to 0.30 m
    v, w = _player((4.0, 0.0), facing=False, tracks=[(1.0, 0.0)]).control_step()
    assert v == 0.0
    v, w = _player((4.0, 0.0), facing=False, tracks=[(1.4, 0.0)]).control_step()
    assert v > 0.0  # further off it drives on (slowly, near a person)
    v, w = _player((4.0, 0.0), facing=False, tracks=[(1.0, 0.8)]).control_step()
    assert v > 0.0  # beside the lane: passed, at the window's air


@settings(max_examples=200, deadline=None)
@given(x=st.floats(-3.0, 3.0), y=st.floats(-2.0, 2.0), vx=st.floats(-1.2, 1.2), vy=st.floats(-1.2, 1.2))
def test_someone_walking_by_within_arms_length_is_let_pass_and_nobody_else_stops_the_robot(x, y, vx, vy):
    people = np.array([[x, y, vx, vy]])
    air = footprint_distance(np.array([x]), np.array([y])) - BODY
    got = passing_close(people, air, gap=GOTO_SOCIAL_GAP, speed=0.15)
    assert got == (math.hypot(vx, vy) > 0.15 and x > -0.3 and float(air[0]) < GOTO_SOCIAL_GAP)


def test_the_go_to_stands_while_someone_walks_by_it_close():
    # Max walks past its left side, 0.185 m of air, not toward its centre (goto_standing_person seed 8:
    # it crept on beside him); the goal straight ahead
    v, _ = _player((4.0, 0.0), facing=False, tracks=[(0.02, 0.65, -0.7, 0.0)]).control_step()
    assert v == 0.0
    v, _ = _player((4.0, 0.0), facing=False, tracks=[(0.02, 1.5, -0.7, 0.0)]).control_step()
    assert v > 0.0  # further off he does not hold it up


def _first_plan(grid: OccupancyGrid, start: tuple[float, float, float], person: tuple[float, float]) -> tuple[Any, list[Any]]:
    """The planner's first plan of a go-to to the kitchen at (5, 2) on ``grid``, with ``person`` standing in
    the fresh scan it waits for: (the path, the plans it published)."""
    import asyncio

    pl, out = _planner(grid, start, (5.0, 2.0), person)
    pl.goal = None
    pl._request = 1
    pl.scan.update = lambda msg: None

    async def place(title):  # noqa: ANN001, ANN202
        return (5.0, 2.0, 0.0)

    async def floor():  # noqa: ANN202
        return grid

    async def scan():  # noqa: ANN202
        return object()

    pl._place, pl._map, pl._next_scan = place, floor, scan  # type: ignore[method-assign]
    path = asyncio.run(pl.plan_for(etree.fromstring('<PLACE><TITLE name="kitchen"/></PLACE>')))
    return path, out


@pytest.mark.parametrize("person", [(3.0, 2.0), (2.4, 1.85), (3.6, 2.2)])
def test_the_first_plan_of_a_go_to_gives_a_person_standing_on_the_way_their_space(person):
    """Only replans used to see people: the first plan ran straight through someone standing between
    the robot and the goal, and the robot met her in its window. The first plan reads a fresh scan as
    a replan does."""
    path, out = _first_plan(ROOM, (1.0, 2.0, 0.0), person)
    assert path is not None and not out[-1].failed and not out[-1].replan
    assert _min_distance(path, person) >= PERSON_CLEAR - 1.5 * ROOM.cell


def test_a_person_in_the_only_door_does_not_fail_the_first_plan():
    """Where her space closes every way (she stands in the only door), the first plan is the floor
    plan's: people move, and the player waits for her at a polite distance."""
    path, out = _first_plan(DOOR, (1.5, 2.0, 0.0), (3.0, 2.0))
    assert path is not None and not out[-1].failed


def test_the_turn_to_the_goals_heading_never_swings_a_corner_into_someone_beside_the_goal():
    """At the goal the player turns on the spot to the place's heading; the floor plan checks that
    turn, and now the people too: she stands 3 cm off the rear left corner."""
    x, y = -0.255 - BODY - 0.03, 0.2
    p = _player((0.05, 0.0), facing=False, tracks=[(x, y)])
    p.goal = (0.05, 0.0, math.pi / 2, 0.2, True)  # within tolerance; align to face +y: turn left
    v, w = p.control_step()
    assert w == 0.0 and v <= 0.0
    p = _player((0.05, 0.0), facing=False, tracks=[(3.0, -2.0)])
    p.goal = (0.05, 0.0, math.pi / 2, 0.2, True)
    v, w = p.control_step()
    assert w > 0.0  # with her far away it turns


def _drive(p: Player, steps: int) -> list[tuple[float, float, float, float, float]]:
    """``steps`` control steps of ``p`` with the base doing exactly what it is told: (x, y, theta, v, w) each."""
    x = y = th = 0.0
    out = []
    for _ in range(steps):
        v, w = p.control_step() or (0.0, 0.0)
        out.append((x, y, th, v, w))
        th_mid = th + 0.5 * w * p.period
        x, y, th = x + v * p.period * math.cos(th_mid), y + v * p.period * math.sin(th_mid), th + w * p.period
        p.odo.update(etree.Element("odometry", x=f"{x:.6f}", y=f"{y:.6f}", theta=f"{th:.6f}", v=f"{v:.6f}", w=f"{w:.6f}"))
    return out


def _air(pose: tuple[float, float, float], person: tuple[float, float]) -> float:
    """Air (m) between the footprint at ``pose`` and the body of the person standing at ``person``."""
    x, y, th = pose
    dx, dy = person[0] - x, person[1] - y
    c, s = math.cos(th), math.sin(th)
    return float(footprint_distance(np.array([c * dx + s * dy]), np.array([-s * dx + c * dy]))[0]) - BODY


@pytest.mark.parametrize("side", [1.0, -1.0])
def test_a_person_standing_just_inside_the_lane_is_gone_round_when_the_leg_points_past_them(side):
    """lang_names seed 0: Ben stood 1 m ahead, 0.33 m left of the robot's heading, the replanned leg
    20 degrees right of it, past him. The robot was held by him in the lane of its heading and stood,
    neither driving nor turning, until it asked for help. It turns on the spot toward the leg (he then
    stands beside its lane) and drives round him, keeping its social air, never swinging into him."""
    person = (0.98, side * 0.33)
    leg = math.radians(-20.0) * side
    goal = (1.3 * math.cos(leg), 1.3 * math.sin(leg))
    p = _player(goal, facing=False, tracks=[person])
    v, w = p.control_step()
    assert v == 0.0 and w * side < 0.0  # turns toward the leg, away from him
    p = _player(goal, facing=False, tracks=[person])
    path = _drive(p, 200)
    assert all(_air(pose[:3], person) >= GOTO_SOCIAL_GAP - 0.02 for pose in path)
    assert p.state == "reached"  # round him, never reported blocked on the way
    assert min(pose[1] * side for pose in path) < -0.3  # by the way round, his side of it kept clear


def test_a_person_squarely_in_the_way_of_the_leg_is_still_waited_for():
    # the leg points 10 degrees right, but he stands in the lane toward it too: no turn helps, it waits
    leg = math.radians(-10.0)
    v, w = _player((3.0 * math.cos(leg), 3.0 * math.sin(leg)), facing=False, tracks=[(1.0, -0.1)]).control_step()
    assert v == 0.0 and w == 0.0


@settings(max_examples=150, deadline=None)
@given(x=st.floats(0.3, 2.0), y=st.floats(-0.8, 0.8), leg=st.floats(-80.0, 80.0))
def test_held_by_someone_standing_ahead_it_only_turns_where_no_corner_swings_into_them_and_never_drives_at_them(x, y, leg):
    assume(footprint_distance(np.array([x]), np.array([y]))[0] > BODY + 0.02)
    goal = (2.5 * math.cos(math.radians(leg)), 2.5 * math.sin(math.radians(leg)))
    v, w = _player(goal, facing=False, tracks=[(x, y)]).control_step()
    person = np.array([[x, y]])
    if v == 0.0 and w != 0.0:
        assert turn_clear(w, person, duration=0.5)
    if v > 0.0:
        assert not standing_in_the_way(np.array([[x, y, 0.0, 0.0]]), half_length=0.255, half_width=HALF_WIDTH,
                                       travel=v * 0.1, gap=WAIT_GAP)


class _Walls:
    """A laser stand-in: the echoes of wall segments (world frame: the robot starts at the origin facing
    +x) seen from the player's odometry pose, robot frame, every 2 cm along each segment within 3 m."""

    latest = None  # no raw ranges: no blind corners (robot/navigation/blind.py; test_goto_blind_corner.py)

    def __init__(self, p: Player, segments: list[tuple[float, float, float, float]]) -> None:
        self.p = p
        pts = []
        for x0, y0, x1, y1 in segments:
            n = max(int(math.hypot(x1 - x0, y1 - y0) / 0.02), 1)
            pts += [(x0 + (x1 - x0) * k / n, y0 + (y1 - y0) * k / n) for k in range(n + 1)]
        self.world = np.array(pts)

    def points(self) -> np.ndarray:
        x, y, th = self.p.odo.pose or (0.0, 0.0, 0.0)
        dx, dy = self.world[:, 0] - x, self.world[:, 1] - y
        c, s = math.cos(th), math.sin(th)
        local = np.column_stack((c * dx + s * dy, -s * dx + c * dy))
        return local[np.hypot(local[:, 0], local[:, 1]) < 3.0]


@pytest.mark.parametrize("side", [1.0, -1.0])
def test_someone_standing_by_a_door_jamb_is_passed_slowly_at_the_squeeze_gap_not_stood_at(side):
    """goto_corridor seeds 0, 2, 3, 4, 8: Nina stood 0.85 m inside the bedroom beside the 1.1 m door's
    jamb. Every line through the door passed her with 0.25-0.29 m of air, short of the go-to's 0.30,
    so the window turned to and fro on the spot until the go-to failed and it asked for help. It
    passes her slowly at SQUEEZE_GAP instead, touching neither her nor the jambs."""
    person = (0.58, -0.66 * side)
    lo, hi = sorted((-0.66 * side, 0.44 * side))
    walls = [(1.37, lo, 1.37, lo - 1.0), (1.37, hi, 1.37, hi + 1.0),  # the door's wall either side of it
             (1.37, lo, 4.5, lo), (1.37, hi, 4.5, hi)]  # the corridor beyond
    p = _player((4.0, 0.0), facing=False, tracks=[person])
    p.scan = _Walls(p, walls)  # type: ignore[assignment]
    path = _drive(p, 400)
    assert max(pose[0] for pose in path) > 3.0  # through the door and on, not stood at her
    assert min(_air(pose[:3], person) for pose in path) >= SQUEEZE_GAP - 0.02
    assert all(abs(pose[3]) <= SQUEEZE_SPEED + 1e-9 for pose in path if _air(pose[:3], person) < GOTO_SOCIAL_GAP - 0.02)  # slowly
    assert min(_wall_air(pose[:3], p.scan) for pose in path) > 0.0  # the jambs untouched


def _wall_air(pose: tuple[float, float, float], walls: _Walls) -> float:
    """Air (m) between the footprint at ``pose`` and the nearest wall point."""
    x, y, th = pose
    dx, dy = walls.world[:, 0] - x, walls.world[:, 1] - y
    c, s = math.cos(th), math.sin(th)
    return float(footprint_distance(c * dx + s * dy, -s * dx + c * dy).min())


@settings(max_examples=60, deadline=None)
@example(x=1.0, y=0.53125, vx=0.0, vy=0.0)  # by the far jamb
@example(x=0.58, y=-0.66, vx=0.0, vy=0.0)  # goto_corridor's Nina
@example(x=0.58, y=-0.66, vx=0.0, vy=0.3)  # the same, walking
@given(x=st.floats(0.3, 1.3), y=st.floats(-1.0, 1.0), vx=st.floats(-0.6, 0.6), vy=st.floats(-0.6, 0.6))
def test_by_a_door_a_go_to_passes_someone_nearer_than_its_gap_only_slowly_at_the_squeeze_gap_and_only_if_they_stand(x, y, vx, vy):
    """Whoever stands or walks near the door: a forward command whose arc (the window's horizon) passes
    them nearer than GOTO_SOCIAL_GAP, while they are now further than that (so not the window's "no
    nearer than now", which lets it move on from where it already stands near someone), is a squeeze:
    at most SQUEEZE_SPEED, SQUEEZE_GAP of air along the whole arc, and past someone standing only."""
    person = np.array([[x, y]])
    assume(arc_air(0.0, 0.0, person, DWAParams()) > GOTO_SOCIAL_GAP)
    walls = [(1.37, -0.66, 1.37, -1.66), (1.37, 0.44, 1.37, 1.44), (1.37, -0.66, 4.5, -0.66), (1.37, 0.44, 4.5, 0.44)]
    p = _player((4.0, 0.0), facing=False, tracks=[(x, y, vx, vy)])
    p.scan = _Walls(p, walls)  # type: ignore[assignment]
    v, w = p.control_step()
    air = arc_air(v, w, person, DWAParams())
    event("passes nearer than the go-to's gap" if v > 0.02 and air < GOTO_SOCIAL_GAP - 1e-3 else "keeps the gap or stands")
    if v > 0.02 and air < GOTO_SOCIAL_GAP - 1e-3:
        assert v <= SQUEEZE_SPEED + 1e-9 and air >= SQUEEZE_GAP - 1e-9
        assert math.hypot(vx, vy) < 0.15
