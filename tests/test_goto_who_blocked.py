"""Who stood in the way is remembered there until seen gone (robot.navigation.planner, "Who stood in the way").

A replan round a person standing on the way ahead remembers where he stood. Later plans (the next replan when
something else holds the robot up, a new request) pay for that place while the laser has not looked at it and
found it empty: out of the laser's sight he has not gone. Without this the robot dithered between two ways
(tests/scenarios/nav/goto_two_ways_passage_end on main: blocked by a man at the passage's end it took the
kitchen way; held up there by its partner it replanned with the man out of sight, back to the passage, and so
on four times: 217 s for a 7.4 m way).
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
from hypothesis import example, given, settings, strategies as st
from lxml import etree

from robot.navigation.planner import BLOCKER_FOR, near_path_ahead
from tests.test_goto_blocked_memory import ONE_WAY, TWO_WAYS, _planner, _through_passage


def _scan(pl, people_map: list[tuple[float, float]], *, sees: bool) -> None:  # noqa: ANN001
    """The planner's latest scan: ``people_map`` (map frame) as pairs of legs, and whether it looks through
    every remembered place and finds it empty (``sees``)."""
    x, y, th = pl.pose
    c, s = np.cos(th), np.sin(th)
    rel = np.array([(c * (px - x) + s * (py - y), -s * (px - x) + c * (py - y)) for px, py in people_map]).reshape(-1, 2)
    pl.scan = SimpleNamespace(points=lambda: np.zeros((0, 2)), bodies=lambda: rel,
                              sees_through=lambda rx, ry, radius=0.25: sees)


def _at(pl, x: float, y: float, th: float = 0.0) -> None:  # noqa: ANN001
    pl._pose_xml = etree.Element("pose", x=str(x), y=str(y), theta=str(th))


@settings(max_examples=25, deadline=None)
@given(st.floats(5.2, 5.9), st.floats(0.8, 3.3), st.floats(0.8, 3.5), st.floats(6.8, 9.3), st.floats(1.0, 3.5))
@example(5.6, 3.6, 1.8, 8.0, 2.5)
def test_a_person_in_the_passage_keeps_the_next_plans_on_the_other_way_until_seen_gone(px, ax, ay, gx, gy):
    pl, out = _planner(TWO_WAYS, (4.6, 0.55, 0.0), (gx, gy))
    pl.path = TWO_WAYS.plan((4.6, 0.55), (gx, gy))
    if not _through_passage(pl.path):
        return  # the short way is the north corridor for this goal: nobody stands on it here
    _scan(pl, [(px, 0.55)], sees=False)
    pl.replan()  # round him (the north corridor)
    assert len(pl.blockers) == 1
    # held up in room A by something else, he is out of sight: the plan still goes round where he stood
    _at(pl, ax, ay)
    _scan(pl, [], sees=False)
    path = pl.replan()
    assert path is not None and not _through_passage(path)
    # the laser looks at his place and finds it empty: he has gone, the short way again
    _scan(pl, [], sees=True)
    assert pl.replan() == TWO_WAYS.plan((ax, ay), (gx, gy)) and not pl.blockers


@settings(max_examples=15, deadline=None)
@given(st.floats(0.8, 3.3), st.floats(0.8, 3.5))
def test_a_remembered_person_is_forgotten_in_time(ax, ay):
    pl, _ = _planner(TWO_WAYS, (ax, ay, 0.0), (8.0, 2.5))
    pl.blockers.append((5.5, 0.55, 0.0))
    _scan(pl, [], sees=False)
    pl.sim.now = BLOCKER_FOR + 0.5
    assert pl.replan() == TWO_WAYS.plan((ax, ay), (8.0, 2.5)) and not pl.blockers


@settings(max_examples=15, deadline=None)
@given(st.floats(4.3, 5.8))
def test_with_a_single_way_the_place_of_who_stood_there_is_still_passed(px):
    # a cost, not an obstacle: he may still stand there (out of sight), but it is the only way
    pl, out = _planner(ONE_WAY, (2.0, 2.5, 0.0), (8.0, 2.5))
    pl.blockers.append((px, 0.55, 0.0))
    _scan(pl, [], sees=False)
    path = pl.replan()
    assert path is not None and not out[-1].failed and _through_passage(path)


@settings(max_examples=25, deadline=None)
@given(st.floats(-3.0, 3.0), st.floats(0.0, 1.0))
def test_only_people_on_the_way_ahead_are_remembered(bx, by):
    # a straight path east from (0, 0) to (6, 0), the robot at (2, 0): someone behind it or well off the way is
    # nobody who stands in it
    path, at = [(0.0, 0.0), (6.0, 0.0)], (2.0, 0.0)
    person = (2.0 + bx, by)
    ahead = near_path_ahead(path, at, person, 0.8)
    if bx < -0.8 or by > 0.8:
        assert not ahead
    if 0.0 <= bx <= 3.0 and by <= 0.8:
        assert ahead


def test_nobody_in_the_way_changes_no_plan():
    pl, _ = _planner(TWO_WAYS, (4.6, 0.55, 0.0), (8.0, 2.5))
    pl.path = TWO_WAYS.plan((4.6, 0.55), (8.0, 2.5))
    _scan(pl, [(2.0, 4.0)], sees=False)  # someone far off the way, behind it
    pl.replan()
    assert not pl.blockers


def test_the_watch_answers_from_what_it_sees_not_from_whom_it_remembers():
    # asking for help, the way of the only door is watched: someone remembered there out of sight does not make
    # the answer "no path" (which carries no bearing to look along); the way is judged where the laser looks
    pl, out = _planner(ONE_WAY, (4.0 - 1.0, 0.55, 0.0), (8.0, 2.5))
    pl.blockers.append((5.0, 0.55, 0.0))
    _scan(pl, [], sees=False)
    pl.replan(watch=True)
    assert out[-1].failed != "no_path"
