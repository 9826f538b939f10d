"""A fast leader's stop lands while the follower searches for her (follow19; fresh7 corr_fast_walker_goto,
fresh8 terr_fast_walker_passage: a leader at 1.25 m/s went on through a door or a 0.9 m passage, stopped and
said "Here, stop"; the follower, several metres behind, searched where her track was guessed (or the track had
gone over to a phantom behind it), the beam stayed on that guess, and none of her stops was heard).

While the follower says ``searching`` the beam listens to the loudest voice no person seen explains (else the
loudest voice off the followed track's bearing while that track is silent), and the dialog takes a stop (only a
stop) from off the track's bearing. While it follows her in sight nothing changes: a bystander's voice is not
listened to and his stop is not taken (scenarios/distractor.xml)."""

from __future__ import annotations

import math
from collections import deque
from types import SimpleNamespace

from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from robot.attention.fsm import AttentionFSM
from robot.attention.module import AttentionParams, PersonAttention
from tests.follow_dialog_probe import attention_following, dialog_hearing_off_track


def _following(searching_from: float | None, said_at: float, act: str = "STOP") -> list[str]:
    """A dialog in Following; the follower said ``following`` every 0.1 s, then ``searching`` from
    ``searching_from`` (None: never); words (``act``) begin at ``said_at`` from 60 degrees off the followed
    track, which is silent. Returns the acts taken."""
    states = [(k / 10.0, "searching" if searching_from is not None and k / 10.0 >= searching_from else "following")
              for k in range(0, int(said_at * 10) + 5)]
    return dialog_hearing_off_track(states, said_at, act, words="w")[1]


@settings(max_examples=50, deadline=None)
@given(st.floats(5.0, 20.0), st.floats(0.0, 10.0))
def test_a_stop_from_off_the_track_is_taken_while_the_follower_searches(since, after):
    assert _following(since, since + 0.1 + after) == ["STOP"]


@settings(max_examples=30, deadline=None)
@given(st.floats(1.0, 5.0))
def test_a_stop_begun_before_the_search_or_while_she_is_in_sight_stays_a_bystanders(early):
    assert _following(None, 20.0) == []  # she walks in its sight: a bystander's stop does not end her walk
    assert _following(20.0 + early, 20.0) == []  # (the search began after the words did)


def test_other_words_from_off_the_track_are_not_taken_while_it_searches():
    assert _following(10.0, 15.0, act="GOODBYE") == []




@settings(max_examples=60, deadline=None)
@given(st.floats(-1.4, 1.4), st.floats(-1.4, 1.4))
def test_searching_the_beam_listens_to_a_voice_nobody_seen_explains(voice, guess):
    t = 40.0
    a = attention_following(searching_since=35.0)
    a._dominant = (t - 0.1, voice)
    assert a.beam(t, guess, 2) == voice
    # and to a voice off the followed track while that track is silent (she is the person seen speaking)
    b = attention_following(searching_since=35.0)
    b._voices = (t, False, True, voice)
    assert b.beam(t, guess, 2) == voice


@settings(max_examples=60, deadline=None)
@given(st.floats(-1.4, 1.4), st.floats(-1.4, 1.4))
def test_following_her_in_sight_the_beam_stays_off_other_voices(voice, her):
    t = 40.0
    a = attention_following(searching_since=None)
    a._voices = (t, False, True, voice)
    assert a.beam(t, her, 2) is None  # a bystander talks while she walks: not for the robot
    quiet = attention_following(searching_since=35.0)  # searching, nobody speaks: the beam stays on the guess
    assert quiet.beam(t, her, 2) == her
