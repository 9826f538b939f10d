"""Asking for help, the robot keeps watching its blocked way (the sequencer's watch, the planner's
answer): a way the laser does not look along is never known to be clear (``failed="unseen"``).
fresh5/stair_goto_passage_person: it asked for help facing the living-room door, its way north
through the passage outside the laser's view; every answer was "unseen" for the whole watch and it
never went on after the lodger had left. Now the unseen answer says where the way lies (``look``)
and the attention, asking for help with nobody speaking to it, turns the base to look along it."""

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


def _acting(seeking: bool, speaking: bool):
    """The attention asking for help (or not), a confirmed person 1.5 m off at 120 deg to its left, attended to
    (selected): silent (Alertness) or speaking to it (Listen); the base's turns recorded."""
    a = _asking(seeking, track=(1.5 * math.cos(2.1), 1.5 * math.sin(2.1)))
    a.fsm.bottom_up(0.0, True, 3 if speaking else 1)
    a.sim = _Clock()
    a._way_look = None
    a._partner_last = None  # no partner measured yet (voice25's turn toward her voice reads it)
    a._turning = False
    a.turned_away = False
    a._player_drives = a._follower_drives = False
    a._focus = None
    turns: list[float] = []
    a._turn = turns.append  # type: ignore[method-assign]
    a._base = lambda w: None  # type: ignore[method-assign]
    a._ptu = lambda t, pan, tilt: None  # type: ignore[method-assign]
    a._steer = lambda b: None  # type: ignore[method-assign]
    a._voice_heading = lambda t, row, category: None  # type: ignore[method-assign]
    a._focus_turn = lambda target: None  # type: ignore[method-assign]
    a._candidate = lambda t: -1  # type: ignore[method-assign]
    a.beam = lambda t, bearing, category, **kw: None  # type: ignore[method-assign]
    return a, turns


@given(st.floats(-2.8, -0.6))
def test_asking_for_help_it_looks_along_its_way_while_the_one_it_attends_to_stays_silent(look):
    """nav/goto_passage_lodger_leaves: Hedda stood silent behind it, attended to; it never looked along its way
    and never saw it clear after the lodger had left. Silent, she is no reason not to look; speaking, she is
    turned to (the base turns to a speaker)."""
    a, turns = _acting(True, speaking=False)
    assert a.fsm.state == "Alertness"
    _answer(a, failed="unseen", look=f"{look:.5f}")
    a._act(10.0, 0, [2.1], [1.5], 1)
    assert turns and abs(math.remainder(turns[-1] - look, 2 * math.pi)) < 1e-4
    b, turns = _acting(True, speaking=True)
    assert b.fsm.state == "Listen"
    _answer(b, failed="unseen", look=f"{look:.5f}")
    b._act(10.0, 0, [2.1], [1.5], 3)
    assert turns and abs(turns[-1] - 2.1) < 1e-6  # to her, not along the way


def test_not_asking_for_help_a_silent_person_is_not_a_reason_to_turn():
    a, turns = _acting(False, speaking=False)
    _answer(a, failed="unseen", look="-1.5")  # (no watch while not asking; and none subscribed)
    a._act(10.0, 0, [2.1], [1.5], 1)
    assert not turns
