"""Giving way to people (issue 26 items 1, 4, 10) and the social-navigation figures of a run.

Unit level: the dynamic window's rule for people (:func:`robot.navigation.local.social_mask`),
the remembered lost track (:class:`robot.navigation.people.People`). Run level: the scenarios of
``tests/scenarios/nav/`` written for these behaviours (new flats, other people), through the whole
robot.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from homesim.tour.runner import Run, RunOptions
from robot.navigation.config import Limits
from robot.navigation.local import SOCIAL_GAP, TURN_GAP, arcs, dwa, people_gaps, turn_clear
from robot.navigation.people import People

NAV = Path(__file__).resolve().parent / "scenarios" / "nav"
LIM = Limits()
coord = st.floats(-2.5, 2.5, allow_nan=False)


def _gap_along(v: float, w: float, people: np.ndarray, horizon: float = 1.6) -> tuple[float, float]:
    """(gap now, smallest gap over the arc's horizon) to the people for a constant (v, w)."""
    t = np.linspace(horizon / 6, horizon, 6)
    x, y, th = arcs(np.array([v]), np.array([w]), t)
    now = float(people_gaps(np.zeros(1), np.zeros(1), np.zeros(1), people)[0])
    return now, float(people_gaps(x, y, th, people).min())


@settings(max_examples=150, deadline=None)
@given(st.lists(st.tuples(coord, coord), min_size=1, max_size=3), st.floats(0.0, 0.5), st.floats(-1.0, 1.0),
       st.tuples(st.floats(0.3, 4.0), st.floats(-2.0, 2.0)))
def test_the_window_never_closes_in_on_a_person_inside_their_space(people, v0, w0, goal):
    pts = np.array(people)
    cmd = dwa(v0, w0, goal, np.zeros((0, 2)), LIM, v_pref=0.5, people=pts)
    now, along = _gap_along(cmd.v, cmd.w, pts)
    # the arc chosen keeps the social gap all along, or brings the robot no closer than it is, or
    # turns on the spot without swinging a corner within TURN_GAP of anyone (or nearer than it is)
    x, y, th = arcs(np.array([cmd.v]), np.array([cmd.w]), np.array([1.6 / 6]))  # the window's first pose
    turn_ok = cmd.v == 0.0 and float(people_gaps(x, y, th, pts).min()) >= min(now, TURN_GAP) - 1e-3
    assert along >= SOCIAL_GAP - 1e-6 or along >= min(now, SOCIAL_GAP) - 1e-3 or turn_ok or (cmd.v == 0.0 and cmd.w == 0.0)
    # and there is always an answer the base can take (braking within its window is waiting)
    assert cmd.ok or (cmd.v == 0.0 and cmd.w == 0.0)


def test_a_person_standing_ahead_is_waited_for_at_a_polite_distance():
    # someone 0.9 m straight ahead (a gap of 0.395 m to their body), the goal behind them
    cmd = dwa(0.3, 0.0, (3.0, 0.0), np.zeros((0, 2)), LIM, v_pref=0.5, people=np.array([[0.9, 0.0]]))
    now, along = _gap_along(cmd.v, cmd.w, np.array([[0.9, 0.0]]))
    assert along >= min(now, SOCIAL_GAP) - 1e-3 and cmd.v < 0.3
    # the same without the person: it drives on
    free = dwa(0.3, 0.0, (3.0, 0.0), np.zeros((0, 2)), LIM, v_pref=0.5)
    assert free.v > 0.2


def _tracks(t: float, *tracks: tuple[str, float, float, bool]) -> etree._Element:
    el = etree.Element("tracks", time=f"{t}", frame="odom")
    for tid, x, y, conf in tracks:
        etree.SubElement(el, "track", id=tid, x=f"{x}", y=f"{y}", vx="0", vy="0", confirmed="true" if conf else "false")
    return el


def test_a_lost_track_is_remembered_while_the_laser_still_sees_something_there():
    p = People()
    p.update(_tracks(1.0, ("t1", 2.0, 0.0, True), ("t2", 0.0, 2.0, False)))
    odom = (0.0, 0.0, 0.0)
    assert p.around(odom, 1.0).tolist() == [[2.0, 0.0]]  # tentative tracks are no people yet
    p.update(_tracks(1.1))  # the tracker dropped t1 (legs merged with a door jamb)
    echo_there = np.array([[1.95, 0.05], [3.0, 1.0]])
    assert p.around(odom, 1.2, echoes=echo_there).tolist() == [[2.0, 0.0]]
    assert p.around(odom, 1.2, echoes=echo_there, exclude="t1").tolist() == []  # the partner is never in the way
    assert p.around(odom, 1.3, echoes=np.array([[3.0, 1.0]])).tolist() == []  # nothing there any more: gone
    assert p.around(odom, 1.4, echoes=echo_there).tolist() == []  # and forgotten


def test_people_are_given_in_the_robot_frame_and_leave_out_the_partner():
    p = People()
    p.update(_tracks(5.0, ("t1", 1.0, 1.0, True), ("t2", 3.0, 1.0, True)))
    got = p.around((1.0, 0.0, math.pi / 2), 5.0, exclude="t2")
    assert np.allclose(got, [[1.0, 0.0]])  # straight ahead of a robot at (1, 0) facing +y
    assert p.around((1.0, 0.0, 0.0), 5.0, near=(3.1, 1.0)).shape == (1, 2)  # a second track on the partner's legs


def _run(name: str, seed: int = 0) -> dict:
    with Run.from_file(NAV / f"{name}.xml", RunOptions(seed=seed)) as run:
        run.run()
        return run.summary()


def test_a_person_blocking_the_door_is_waited_for_at_a_safe_distance_then_asked_for_help():
    # (whether Lena's second "go to the kitchen" then arrives depends on her getting round the
    # robot into the doorway: measured over seeds by the sweep, not asserted here)
    s = _run("goto_doorway_retry")
    said = [u["text"] for u in s["utterances"] if u["speaker"] == "robot"]
    assert any("help" in t for t in said)
    social = s["metrics"]["social"]
    assert social["collisions_people"] == 0 and social["min_person_clearance_moving_m"] >= 0.25
    assert social["goto"]["episodes"] >= 1


def test_every_run_summary_has_the_social_navigation_figures():
    with Run.from_file(NAV / "goto_corridor.xml", RunOptions(seed=0, until=30)) as run:
        run.run()
        social = run.summary()["metrics"]["social"]
    for key in ("collisions_people", "collisions_flat", "min_person_distance_m", "min_person_clearance_m",
                "personal_space_s", "identity_switches", "partner_kept", "request_distance_max_m"):
        assert key in social
    assert social["following"]["time_s"] > 0 and social["goto"]["episodes"] == 0
    assert social["collisions_people"] == 0 and social["partner_kept"] is True


def test_a_robot_with_someone_pressed_against_its_front_does_not_swing_a_corner_into_them():
    # she stands 0.53 m in front (2.5 cm of air to the bumper); the goal lies to the left
    pts = np.array([[0.53, 0.0]])
    cmd = dwa(0.0, 0.0, (0.0, 2.0), np.zeros((0, 2)), LIM, v_pref=0.3, people=pts)
    x, y, th = arcs(np.array([cmd.v]), np.array([cmd.w]), np.linspace(0.05, 0.5, 10))
    assert float(people_gaps(x, y, th, pts).min()) >= float(people_gaps(np.zeros(1), np.zeros(1), np.zeros(1), pts)[0]) - 1e-3
    assert not turn_clear(1.0, pts, duration=0.5)  # the follower's own turns are held to the same rule
    assert turn_clear(1.0, np.array([[1.5, 0.0]]), duration=0.5)
