"""A partner beside or behind the robot, out of the laser's forward half-circle, is looked for where the
sonar hears her (issue 26 item 1; flow/follow_while_looking seed 1).

After the robot gave way she walked past its side and on behind it. The search stood: her guessed point
0.6 m beside it refused the turn as a body, and the turn toward her (the short way round) swung the rear
corner at her legs, which the sonar heard. Now the search turns to look at the unexplained echo beside
or behind nearest to where it looks for her (the other way round when the short way is refused), and
her guessed point is a body only where the laser looks and has an echo near it.
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from robot.navigation.follow import BLIND_X, Follower
from robot.navigation.local import LatestScan

MIN_ANGLE, OFFSET, N = -math.pi / 2, 0.13, 361


def _follower(ranges: float = 4.0, arcs: list[np.ndarray] | None = None, mapped: np.ndarray | None = None) -> Follower:
    f = Follower.__new__(Follower)
    f.odom, f.sim = (0.0, 0.0, 0.0), SimpleNamespace(now=1.0)
    f.partner_id = "t1"
    f.people = SimpleNamespace(around=lambda odom, now, exclude=None: np.zeros((0, 3)))
    f.scan = LatestScan()
    f.scan.update(SimpleNamespace(xml=etree.Element("scan", min_angle=str(math.degrees(MIN_ANGLE)), resolution="0.5",
                                                    max_range="8.0", offset=str(OFFSET)),
                                  attachments={"ranges": np.full(N, ranges)}))
    f.sonar = SimpleNamespace(arcs=lambda odom, now: list(arcs or []))
    f.route = SimpleNamespace(obstacles_near=lambda odom: mapped if mapped is not None else np.zeros((0, 2)))
    f.limits = SimpleNamespace(max_turn=math.radians(100))
    f._seen_pos = (0.0, -0.6, 0.5)  # a scan saw her last beside it, half a second ago
    return f


def _arc(x: float, y: float) -> np.ndarray:
    return np.array([(x + 0.02 * k, y - 0.02 * k) for k in range(-2, 3)])


def test_her_guessed_point_is_a_body_only_where_the_laser_looks_and_has_an_echo_near_it():
    f = _follower(ranges=4.0)
    assert len(f._bodies(0.05, -0.65, guess=True)) == 0  # beside, behind the laser's line: the sonar's business
    assert len(f._bodies(-0.7, 0.2, guess=True)) == 0  # behind
    assert len(f._bodies(-0.7, 0.2)) == 1  # not searching: her tracked point stays a body wherever it is
    assert len(f._bodies(1.0, 0.0, guess=True)) == 0  # in view, nothing within 0.5 m (the laser sees 4 m there)
    f = _follower(ranges=1.0)  # echoes 1 m off all round the front
    assert len(f._bodies(1.0, 0.0, guess=True)) == 1  # in view, an echo near: she may stand there


@settings(max_examples=100, deadline=None)
@given(bearing=st.floats(math.radians(100), math.radians(260)), dist=st.floats(0.6, 1.1))
def test_the_search_looks_at_an_echo_behind_the_laser_line(bearing, dist):
    ex, ey = dist * math.cos(bearing), dist * math.sin(bearing)
    if ex > BLIND_X - 0.05:
        return
    f = _follower(arcs=[_arc(ex, ey)])
    f._seen_pos = (0.5 * ex, 0.5 * ey - 0.3, 0.5)  # she was last seen on her way there
    got = f._heard_there(-0.2, -0.7)  # she is looked for beside it, behind the laser's line
    assert got is not None and math.hypot(got[0] - ex, got[1] - ey) < 0.05
    # the floor plan explains the echo (a wall there): nobody heard
    f = _follower(arcs=[_arc(ex, ey)], mapped=np.array([(ex, ey)]))
    assert f._heard_there(-0.2, -0.7) is None


def test_an_echo_she_cannot_have_walked_to_is_not_her():
    f = _follower(arcs=[_arc(-0.7, 0.3)])
    f._seen_pos = (3.0, -1.0, 0.0)  # last seen 3 m ahead a second ago: the echo behind the robot is not her
    assert f._heard_there(-0.2, -0.7) is None
    f._seen_pos = (0.2, -0.6, 0.0)
    assert f._heard_there(-0.2, -0.7) is not None


def test_no_echo_is_looked_at_while_she_may_stand_where_the_laser_looks():
    f = _follower(ranges=1.0, arcs=[_arc(-0.6, -0.4)])
    assert f._heard_there(1.0, 0.0) is None  # her point is in view with echoes there: the search goes on as before
    f = _follower(ranges=4.0, arcs=[_arc(-0.6, -0.4)])
    assert f._heard_there(1.0, 0.0) is not None  # the laser sees through her point beside it: she is not there
    # looked for out of the sonar's hearing (she went on round the corner ahead: u_catch_up_slow seed 3, an
    # echo 1.3 m beside the robot turned it round), the search goes on where she went
    f._seen_pos, f._heard = (0.0, -0.6, 0.9), None
    assert f._heard_there(3.0, 0.0) is None


def test_refused_the_short_way_round_it_turns_the_other_way_and_keeps_to_it():
    f = _follower()
    f._turn_way = 0.0
    allowed = {"left": True, "right": False}
    f._blind_clear = lambda v, w: allowed["left" if w > 0 else "right"]
    bearing = math.radians(-150)  # behind on the right: the short way is a right turn
    w = f._search_turn(-1.75, bearing, -0.6, -0.35, np.zeros((0, 2)))
    assert w > 0.0  # the sonar refused the right turn: round to the left
    allowed["right"] = True  # the right turn is clear again: it does not turn to and fro
    assert f._search_turn(-1.75, math.radians(-170), -0.6, -0.1, np.zeros((0, 2))) > 0.0
    assert f._search_turn(0.5, math.radians(30), 0.8, 0.4, np.zeros((0, 2))) == 0.5  # ahead: the turn as it was
    assert f._turn_way == 0.0
    allowed["left"] = allowed["right"] = False
    assert f._search_turn(-1.75, bearing, -0.6, -0.35, np.zeros((0, 2))) == 0.0  # both refused: it stands
