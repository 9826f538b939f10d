"""Person attention places the floor plan with the localiser's pose, scan after scan.

Leg-like echoes inside a wall's footprint (a door jamb's end seen end on) or a piece of furniture are
the flat, not people (robot.attention.clutter); the candidates are put into the map frame with the
localiser's last pose moved on by odometry (``PersonAttention._robot_in_map``). The turn check added
a per-scan map pose under the same attribute name as the localiser's pose and reset it on every scan,
so the floor plan was placed by dead reckoning alone: once odometry had drifted a few centimetres,
door jambs passed the filter and a partner's coasting track jumped onto one (u_catch_up_slow seed 0,
25.2 s, the bedroom door's jamb; 9/10 -> 0/4 on the seeds bisected, merge 7eb321e).
"""

from __future__ import annotations

import math
from types import SimpleNamespace

from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from homesim.sim import Simulation
from robot.attention.clutter import FurnitureLegs
from robot.attention.module import PersonAttention
from robot.floorplan import FloorPlan, MapWall
from tests.test_attention_turn_people import BEARINGS, scan

#: a wall 0.1 m thick along y at x = 2.0 from y = 0.6 (its end: a door jamb) to 3.0, map frame
WALL = MapWall(2.0, 0.6, 2.0, 3.0, 0.1)


def _run(true_pose: tuple[float, float, float], legs_map: list[tuple[float, float]], scans: int = 15) -> PersonAttention:
    """Person attention whose odometry says it stands at the start (0, 0, 0) while the localiser says
    ``true_pose`` (map frame), shown ``scans`` scans of legs standing at ``legs_map`` (map frame)."""
    a = PersonAttention(Simulation(seed=0, scenario="map_pose"))
    a.furniture = FurnitureLegs(FloorPlan(walls=(WALL,), obstacles=(), rooms=(), start=(0.0, 0.0, 0.0)))
    a._bearings = BEARINGS
    x0, y0, th0 = true_pose
    c, s = math.cos(th0), math.sin(th0)
    robot = [(c * (x - x0) + s * (y - y0), -s * (x - x0) + c * (y - y0)) for x, y in legs_map]
    still = {"x": "0", "y": "0", "theta": "0", "v": "0", "w": "0"}
    a._on_odometry(SimpleNamespace(created=0.0, xml=etree.Element("odometry", still)))
    a._on_pose(SimpleNamespace(created=0.0, xml=etree.Element("pose", x=f"{x0}", y=f"{y0}", theta=f"{th0}")))
    for k in range(scans):
        t = 0.1 * (k + 1)
        a._on_odometry(SimpleNamespace(created=t, xml=etree.Element("odometry", still)))
        a.process(t, scan(robot))
    return a


def test_a_jamb_is_the_flat_after_odometry_drifted():
    """Odometry 0.3 m off: two leg-sized echoes at the jamb's end are filtered on every scan, and
    the pose the filter uses is still the localiser's after the scans."""
    a = _run((0.0, 0.3, 0.0), [(2.0, 0.65), (2.0, 0.85)])
    assert a.tracks.tracks == []
    assert a._robot_in_map(1.5) == (0.0, 0.3, 0.0)


@settings(max_examples=25, deadline=None)
@given(dx=st.floats(-0.5, 0.5), dy=st.floats(-0.5, 0.5), dth=st.floats(-0.3, 0.3), along=st.floats(0.65, 1.2))
def test_legs_inside_a_wall_never_make_a_track_whatever_the_dead_reckoning_error(dx, dy, dth, along):
    """Wherever the localiser has corrected the robot to (odometry still at the start), legs inside the
    wall's footprint (as the localiser places them) never become a track."""
    a = _run((dx, dy, dth), [(2.0, along), (2.0, along + 0.2)])
    assert a.tracks.tracks == []


def test_the_same_legs_in_the_room_are_a_person():
    """The filter is the wall's, not the pose's: the same legs 0.5 m off the wall are tracked."""
    a = _run((0.0, 0.3, 0.0), [(1.5, 0.65), (1.5, 0.85)])
    assert [tk.confirmed for tk in a.tracks.tracks] == [True]
