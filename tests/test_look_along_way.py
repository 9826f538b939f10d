"""Asking for help, the robot keeps watching its blocked way (the sequencer's watch, the planner's
answer): a way the laser does not look along is never known to be clear (``failed="unseen"``).
fresh5/stair_goto_passage_person: it asked for help facing the living-room door, its way north
through the passage outside the laser's view; every answer was "unseen" for the whole watch and it
never went on after the lodger had left. Now the unseen answer says where the way lies (``look``)
and the attention, asking for help with nobody to attend to, turns the base to look along it."""

from __future__ import annotations

import math
from types import SimpleNamespace

from hypothesis import given
from hypothesis import strategies as st
from lxml import etree

from robot.attention.module import WAY_LOOK_AGE
from robot.navigation.planner import WATCH_FIELD, in_view, way_bearing
from tests.test_attention_help import _asking


@given(st.floats(-math.pi + 0.01, math.pi - 0.01), st.floats(1.6, 6.0), st.floats(-math.pi, math.pi))
def test_the_look_of_a_straight_way_is_its_bearing_from_the_heading(phi, length, th):
    pose = (1.0, 2.0, th)
    end = (1.0 + length * math.cos(th + phi), 2.0 + length * math.sin(th + phi))
    b = way_bearing([(1.0, 2.0), end], pose)
    assert b is not None and abs(math.remainder(b - phi, 2 * math.pi)) < 1e-6
    # turned by that bearing, the way lies where the laser looks (the watch can see it clear)
    assert in_view([(1.0, 2.0), end], (1.0, 2.0, th + b), reach=3.0)
    if abs(phi) > WATCH_FIELD + 0.01:
        assert not in_view([(1.0, 2.0), end], pose, reach=3.0)


def test_a_way_that_ends_at_the_robot_has_no_look():
    assert way_bearing([(0.0, 0.0), (0.1, 0.1)], (0.0, 0.0, 0.0)) is None


class _Clock:
    now = 10.0


def _answer(a, **attrs) -> None:
    el = etree.Element("plan", goal="kitchen", length="0", replan="true", watch="true", **attrs)
    a._on_plan(SimpleNamespace(xml=el))


def _attention(seeking: bool):
    a = _asking(seeking, track=None)
    a.sim = _Clock()
    a._way_look = None
    return a


@given(st.floats(-math.pi + 0.01, math.pi - 0.01))
def test_asking_for_help_an_unseen_way_is_looked_along(look):
    a = _attention(True)
    _answer(a, failed="unseen", look=f"{look:.5f}")
    b = a._look_along_way(10.0)
    assert b is not None and abs(math.remainder(b - look, 2 * math.pi)) < 1e-4
    # the answer is a moment's: an old one is not turned to
    assert a._look_along_way(10.0 + WAY_LOOK_AGE + 0.1) is None


def test_a_clear_or_blocked_answer_or_not_asking_for_help_is_not_looked_along():
    a = _attention(True)
    _answer(a, failed="unseen", look="2.0")
    _answer(a)  # the way seen clear (the sequencer resumes the go-to)
    assert a._look_along_way(10.0) is None
    _answer(a, failed="unseen", look="2.0")
    _answer(a, failed="no_path")  # someone seen in the way: nothing to look for, it looks at people
    assert a._look_along_way(10.0) is None
    b = _attention(False)
    _answer(b, failed="unseen", look="2.0")
    assert b._look_along_way(10.0) is None
