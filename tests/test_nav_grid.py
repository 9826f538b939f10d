"""The planner's occupancy grid and paths, and the dynamic window, as pure functions."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from lxml import etree

from robot.navigation.config import Limits
from robot.navigation.grid import MapError, NoPathError, OccupancyGrid, parse_map, path_length, without_end_corner
from robot.navigation.local import DWAParams, dwa, footprint_distance, narrow_clusters, scan_points
from robot.navigation.planner import END_CORNER, find_place_pose, place_title
from robot.navigation.sequencer import steps_of

MAP = """<map frame="map">
  <wall x1="0" y1="0" x2="10" y2="0" thickness="0.1"/><wall x1="10" y1="0" x2="10" y2="4" thickness="0.1"/>
  <wall x1="10" y1="4" x2="0" y2="4" thickness="0.1"/><wall x1="0" y1="4" x2="0" y2="0" thickness="0.1"/>
  <wall x1="6" y1="0" x2="6" y2="1.5" thickness="0.1"/><wall x1="6" y1="2.5" x2="6" y2="4" thickness="0.1"/>
  <obstacle name="table" type="table" points="3,0.6 4.2,0.6 4.2,1.4 3,1.4" bottom="0.7" top="0.75"/>
  <obstacle name="lamp" type="lamp" points="8,3 8.2,3 8.2,3.2 8,3.2" bottom="1.6" top="1.8"/>
  <start x="1.5" y="1" theta="0"/>
</map>"""


@pytest.fixture(scope="module")
def grid():
    return OccupancyGrid(parse_map(etree.fromstring(MAP)), radius=0.30)


def _segments_clear(grid, pts, need):
    for a, b in zip(pts, pts[1:]):
        n = max(int(math.hypot(b[0] - a[0], b[1] - a[1]) / 0.01), 2)
        for t in np.linspace(0, 1, n):
            c = grid.cell_of((a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t))
            assert grid.clearance[c] > need, (a, b, t)


def test_the_path_goes_through_the_door_and_keeps_the_robot_clear(grid):
    pts = grid.plan((1.5, 1.0), (8.2, 1.2))
    assert pts[0] == (1.5, 1.0) and pts[-1] == (8.2, 1.2)
    door = [p for p in pts if 5.5 < p[0] < 6.5]
    assert all(1.5 + 0.3 < p[1] < 2.5 - 0.3 for p in door)  # through the gap, clear of its frame
    _segments_clear(grid, pts, 0.30 - grid.cell)
    assert path_length(pts) < 1.15 * math.hypot(8.2 - 1.5, 0.2) + 1.5


@settings(max_examples=40, deadline=None)
@given(st.floats(0.5, 9.5), st.floats(0.5, 3.5), st.floats(0.5, 9.5), st.floats(0.5, 3.5))
def test_every_path_between_free_points_stays_in_free_space(grid, sx, sy, gx, gy):
    if not (grid.is_free((sx, sy)) and grid.is_free((gx, gy))):
        return
    pts = grid.plan((sx, sy), (gx, gy))
    assert pts[0] == (sx, sy) and pts[-1] == (gx, gy)
    _segments_clear(grid, pts, 0.30 - grid.cell)
    assert path_length(pts) >= math.hypot(gx - sx, gy - sy) - 1e-9


def test_a_goal_inside_furniture_or_walled_in_is_refused_with_the_reason(grid):
    with pytest.raises(NoPathError) as e:
        grid.plan((1.5, 1.0), (3.6, 1.0))  # inside the table (nothing free within 0.5 m)
    assert e.value.reason == "goal_blocked"


def test_a_high_lamp_is_not_an_obstacle_but_a_table_is(grid):
    assert grid.is_free((8.1, 3.1 - 0.6)) and not grid.occupied[grid.cell_of((8.1, 3.1))]
    assert grid.occupied[grid.cell_of((3.6, 1.0))]


def test_a_malformed_map_is_refused_naming_the_problem():
    with pytest.raises(MapError, match="start"):
        parse_map(etree.fromstring('<map frame="map"><wall x1="0" y1="0" x2="1" y2="0" thickness="0.1"/></map>'))


def test_place_lookup_finds_the_last_taught_pose():
    stored = etree.fromstring('<reply ok="true" count="1"><doc id="2"><PLACE name="kitchen" x="8.2" y="1.2" theta="0.5" frame="map" taught="3.1"/></doc></reply>')
    assert find_place_pose(stored, "Kitchen") == (8.2, 1.2, 0.5)
    reply = etree.fromstring("""<reply ok="true" count="3">
      <PLACE><TITLE name="Kitchen"/><POSE x="1" y="2" theta="0.5" frame="map"/></PLACE>
      <place_doc><PLACE><TITLE name="window"/></PLACE><POSE x="4" y="5" theta="0"/></place_doc>
      <PLACE><TITLE name="kitchen"/><POSE x="7" y="8" theta="1" frame="map"/></PLACE></reply>""")
    assert find_place_pose(reply, "kitchen") == (7.0, 8.0, 1.0)
    assert find_place_pose(reply, "window") == (4.0, 5.0, 0.0)
    assert find_place_pose(reply, "garage") is None
    assert place_title(etree.fromstring('<PLACE><TITLE name="kitchen"/></PLACE>')) == "kitchen"


def test_plan_steps_head_along_each_leg_and_align_only_at_the_place():
    plan = etree.fromstring('<plan goal="kitchen" length="3"><waypoint x="0" y="0"/><waypoint x="1" y="1"/>'
                            '<waypoint x="2" y="1" theta="1.5"/></plan>')
    steps = steps_of(plan)
    assert [s["align"] for s in steps] == ["false", "true"]
    assert float(steps[0]["theta"]) == pytest.approx(math.pi / 4, abs=1e-4) and steps[1]["theta"] == "1.50000"


JAMB = """<map frame="map">
  <wall x1="0" y1="0" x2="6" y2="0" thickness="0.1"/><wall x1="6" y1="0" x2="6" y2="4" thickness="0.1"/>
  <wall x1="6" y1="4" x2="0" y2="4" thickness="0.1"/><wall x1="0" y1="4" x2="0" y2="0" thickness="0.1"/>
  <wall x1="3" y1="0" x2="3" y2="1.4" thickness="0.1"/><wall x1="3" y1="2.4" x2="3" y2="4" thickness="0.1"/>
  <start x="1" y="0.8" theta="0"/>
</map>"""


@pytest.fixture(scope="module")
def jamb():
    return OccupancyGrid(parse_map(etree.fromstring(JAMB)), radius=Limits().radius)


def _plan_xml(pts, theta=1.5):
    el = etree.Element("plan", goal="kitchen", length=f"{path_length(pts):.4f}")
    for k, (x, y) in enumerate(pts):
        wp = etree.SubElement(el, "waypoint", x=f"{x:.4f}", y=f"{y:.4f}")
        if k == len(pts) - 1:
            wp.set("theta", str(theta))
    return el


def test_a_corner_round_a_jamb_stays_a_step_however_near_the_place(jamb):
    """review9 item 2: the sequencer dropped any last corner within 0.40 m of the place; here the corner
    (0.33 m from a place just round the door's jamb) is what keeps the leg off the jamb."""
    pts = jamb.plan((1.0, 0.8), (3.45, 1.35))
    assert len(pts) == 4 and math.dist(pts[-2], pts[-1]) > END_CORNER  # the planner keeps it by distance alone
    kept = without_end_corner(pts, jamb, 0.40)  # and within the old 0.40 m, the leg's check keeps it too
    assert kept == pts and not jamb.line_free(pts[-3], pts[-1], roomy=False)
    steps = steps_of(_plan_xml(kept))
    assert len(steps) == 3 and (float(steps[1]["x"]), float(steps[1]["y"])) == pytest.approx(pts[-2], abs=1e-4)


def test_a_last_corner_a_few_centimetres_from_the_place_on_open_floor_is_no_step_of_its_own(jamb):
    pts = [(1.0, 2.0), (2.0, 2.5), (2.05, 2.43)]  # the grid's end slack: 9 cm, nothing between
    assert without_end_corner(pts, jamb, END_CORNER) == [(1.0, 2.0), (2.05, 2.43)]
    far = [(1.0, 2.0), (2.0, 2.5), (2.5, 2.5)]
    assert without_end_corner(far, jamb, END_CORNER) == far  # 0.5 m: a step of its own
    one = [(1.0, 2.0), (1.1, 2.0)]
    assert without_end_corner(one, jamb, END_CORNER) == one


@settings(max_examples=40, deadline=None)
@given(st.floats(0.4, 5.6), st.floats(0.4, 3.6), st.floats(0.4, 5.6), st.floats(0.4, 3.6))
def test_a_plan_without_its_end_corner_keeps_the_robot_clear(jamb, sx, sy, gx, gy):
    if not (jamb.is_free((sx, sy)) and jamb.is_free((gx, gy))):
        return
    pts = without_end_corner(jamb.plan((sx, sy), (gx, gy)), jamb, END_CORNER)
    assert pts[-1] == (gx, gy)
    _segments_clear(jamb, pts, jamb.radius - jamb.cell)


def test_every_plan_corner_is_a_step():
    plan = etree.fromstring('<plan goal="kitchen" length="3"><waypoint x="0" y="0"/><waypoint x="1" y="1"/>'
                            '<waypoint x="2" y="1"/><waypoint x="2.05" y="0.93" theta="1.5"/></plan>')
    assert len(steps_of(plan)) == 3  # the planner drops an end corner where it can see the floor; not here
    one = etree.fromstring('<plan goal="k" length="0.1"><waypoint x="0" y="0"/><waypoint x="0.1" y="0" theta="0"/></plan>')
    assert len(steps_of(one)) == 1


# ------------------------------------------------------------------ the dynamic window
LIM = Limits()


def test_dwa_drives_straight_to_a_free_goal_and_never_outruns_its_brakes_before_a_wall():
    free = dwa(0.3, 0.0, (3.0, 0.0), np.zeros((0, 2)), LIM, v_pref=0.5)
    assert free.ok and free.v > 0.3 and abs(free.w) < 0.2
    p = DWAParams()
    for gap in (0.12, 0.15, 0.2, 0.3, 0.5):  # free space between the bumper and a wall ahead
        wall = np.column_stack((np.full(81, 0.255 + gap), np.linspace(-2, 2, 81)))
        cmd = dwa(0.1, 0.0, (3.0, 0.0), wall, LIM, v_pref=0.5)
        if cmd.v > 0:
            assert cmd.v * p.period + cmd.v ** 2 / (2 * LIM.max_accel) <= gap - p.margin + 1e-9, gap


@settings(max_examples=60, deadline=None)
@given(st.floats(0.0, 0.5), st.floats(-1.0, 1.0), st.floats(-3, 3), st.floats(-3, 3),
       st.lists(st.tuples(st.floats(-2, 2), st.floats(-2, 2)), max_size=30))
def test_dwa_respects_the_limits_and_never_picks_an_arc_into_an_echo(v0, w0, gx, gy, obstacles):
    pts = np.array(obstacles, dtype=float).reshape(-1, 2)
    p = DWAParams()
    cmd = dwa(v0, w0, (gx, gy), pts, LIM, v_pref=0.4, params=p)
    assert -LIM.max_reverse - 1e-9 <= cmd.v <= LIM.max_speed + 1e-9 and abs(cmd.w) <= LIM.max_turn + 1e-9
    assert abs(cmd.v - v0) <= LIM.max_accel * p.window + 1e-9 or cmd.v == 0.0
    here = footprint_distance(pts[:, 0], pts[:, 1]).min() if len(pts) else math.inf
    if cmd.ok and len(pts) and here > p.margin and cmd.v > 0:
        # the chosen arc, as far as the robot could go before it has braked, keeps off every echo
        t = np.linspace(0.0, p.period + cmd.v / (2 * LIM.max_accel), 8)
        th = cmd.w * t
        x = cmd.v * t if abs(cmd.w) < 1e-6 else cmd.v / cmd.w * np.sin(th)
        y = 0 * t if abs(cmd.w) < 1e-6 else cmd.v / cmd.w * (1 - np.cos(th))
        for xi, yi, ti in zip(x, y, th):
            dx, dy = pts[:, 0] - xi, pts[:, 1] - yi
            lx, ly = np.cos(ti) * dx + np.sin(ti) * dy, -np.sin(ti) * dx + np.cos(ti) * dy
            assert footprint_distance(lx, ly).min() > p.margin - 1e-9


def test_a_pair_of_legs_becomes_a_body_a_wall_does_not():
    angles = np.radians(np.linspace(-90, 90, 361))
    r = np.full(361, 3.0)  # a wall 3 m away all round
    for centre in (178, 186):  # two legs 1.5 m ahead, about 0.2 m apart
        r[centre - 2:centre + 3] = 1.5
    clusters = narrow_clusters(r, angles, 8.0)
    assert len(clusters) == 2
    pts = scan_points(r, -math.pi / 2, math.radians(0.5), 8.0, 0.13)
    plain = scan_points(r, -math.pi / 2, math.radians(0.5), 8.0, 0.13, bodies=False)
    extra = pts[len(plain):]
    assert len(extra) == 10  # one body ring between the legs
    centre = extra.mean(axis=0)
    assert centre[0] == pytest.approx(0.13 + 1.56, abs=0.05) and abs(centre[1]) < 0.1
    assert len(narrow_clusters(np.full(361, 3.0), angles, 8.0)) == 0


# ------------------------------------------------------------------ kept plans (fresh23 defect F)
def _fresh():
    return OccupancyGrid(parse_map(etree.fromstring(MAP)), radius=0.30)


_REFERENCE = []


@settings(max_examples=20, deadline=None)
@given(st.lists(st.tuples(st.floats(0.3, 9.7), st.floats(0.3, 3.7), st.floats(0.3, 9.7), st.floats(0.3, 3.7)),
                min_size=1, max_size=10),
       st.sampled_from([(0.6, 1.0), (1.5, 1.0), (8.0, 2.0)]))
def test_a_grid_that_keeps_its_searches_plans_as_a_fresh_one(questions, start):
    """Plans (and refusals) from one grid asked many questions, some from one start, some again, are
    exactly those of a grid asked each question once: keeping searches changes no path."""
    if not _REFERENCE:
        _REFERENCE.append(_fresh())
    ref = _REFERENCE[0]  # asked each question with nothing kept: a whole search every time
    kept = _fresh()
    asked = [((sx, sy), (gx, gy)) for sx, sy, gx, gy in questions]
    asked += [(start, (gx, gy)) for _, _, gx, gy in questions] + asked[:3]
    for a, b in asked:
        try:
            got = kept.plan(a, b)
        except NoPathError as e:
            got = ("refused", str(e), e.reason)
        ref._forget()
        try:
            want = ref.plan(a, b)
        except NoPathError as e:
            want = ("refused", str(e), e.reason)
        assert got == want, (a, b)


def test_a_grid_keeps_only_a_bounded_number_of_searches_and_paths(grid):
    """Nothing keeps an unbounded record of a run: a robot wedged for an hour asks the same few
    questions, a long tour many different ones; the grid keeps only the latest few of either."""
    from robot.navigation import grid as gridmod

    g = _fresh()
    for i, x in enumerate(np.linspace(0.6, 5.4, 12)):
        for goal in ((8.0, 2.0), (8.5, 2.0), (9.0, 2.0), (8.0, 3.0), (8.5, 3.0), (9.0, 3.0)):
            g.plan((float(x), 3.0 + 0.05 * (i % 3)), goal)
    assert len(g._trees) <= gridmod.TREES
    assert len(g._paths) <= gridmod.PATHS


def test_a_changed_copy_does_not_answer_with_the_originals_paths():
    """A copy with a person standing in the door (the replan's local costmap) must not reuse the
    original's kept search: the door is closed for it, open for the original."""
    g = _fresh()
    before = g.plan((1.5, 1.0), (8.2, 1.2))
    blocked = g.with_obstacles(np.array([(6.0, y) for y in np.linspace(1.4, 2.6, 25)]))
    with pytest.raises(NoPathError):
        blocked.plan((1.5, 1.0), (8.2, 1.2))
    costly = g.with_cost([(6.0, 2.0)], radius=0.6, cost=50.0)
    assert costly.plan((1.5, 1.0), (8.2, 1.2)) == _fresh().with_cost([(6.0, 2.0)], radius=0.6, cost=50.0).plan((1.5, 1.0), (8.2, 1.2))
    assert g.plan((1.5, 1.0), (8.2, 1.2)) == before


def test_a_kept_path_is_the_callers_own_to_change():
    g = _fresh()
    p = g.plan((1.5, 1.0), (8.2, 1.2))
    p.pop()
    p.append((0.0, 0.0))
    assert g.plan((1.5, 1.0), (8.2, 1.2))[-1] == (8.2, 1.2)
    start = np.array([1.55, 1.0])
    q = g.plan(start, (8.2, 1.2))
    q[0][0] = 99.0  # the caller's array, or a copy of it: never the grid's kept one
    again = g.plan((1.55, 1.0), (8.2, 1.2))
    assert float(again[0][0]) == 1.55
    again[0][0] = 98.0
    assert float(g.plan((1.55, 1.0), (8.2, 1.2))[0][0]) == 1.55
