"""Never deaf by a silent followed track (issue 26; generated tour 1000-010: a fast leader walked past a silent
guest in the guest room, the track the robot followed went over to him, and her "Please stop now", "Stop now
BIRON" and every later word came from another track while the followed one stayed silent: the beam gate shut
each of them out as a bystander's, to the end of the run).

Once the follower has stood by the track it follows for ``STOOD_FOR`` s (its status ``waiting``: the walk is
over), a voice from elsewhere while that track is silent is listened to, a stop is taken from it, and the stop's
speaker becomes the partner. Before that (she walks, a bystander talks: scenarios/distractor.xml) nothing changes:
the beam stays off a bystander's voice and his words are not taken."""

from __future__ import annotations

import math
from collections import deque
from types import SimpleNamespace

from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from robot.attention.fsm import AttentionFSM
from robot.attention.module import AttentionParams, PersonAttention
from robot.dialog.module import Dialog
from robot.partner_search import STOOD_FOR

from tests.follow_dialog_probe import attention_following, dialog_hearing_off_track


# ------------------------------------------------------------------ the dialog: a stop from off her bearing
def _following(waiting_from: float | None, said_at: float, act: str = "STOP", words: str = "stop now") -> tuple[Dialog, list[str]]:
    """A dialog in Following; the follower said ``waiting`` every 0.1 s from ``waiting_from`` (None: it
    follows); words (``act``) begin at ``said_at`` from 60 degrees off the followed track, which is silent."""
    states = [(t / 10.0, "following") for t in range(0, int(said_at * 10))]
    if waiting_from is not None:
        states = [(t, "waiting" if t >= waiting_from else s) for t, s in states]
    return dialog_hearing_off_track(states, said_at, act, words)


@settings(max_examples=60, deadline=None)
@given(st.integers(100, 300), st.floats(0.0, 20.0))
def test_a_stop_from_another_voice_ends_following_once_the_follower_stood_by_the_silent_track(tenths, extra):
    waited_from = tenths / 10.0 - 0.01  # (its status comes every 0.1 s)
    said_at = waited_from + STOOD_FOR + extra + 0.05
    _, taken = _following(waited_from, said_at)
    assert taken == ["STOP"]


@settings(max_examples=60, deadline=None)
@given(st.floats(0.0, STOOD_FOR - 0.15))
def test_a_stop_from_another_voice_while_she_walks_or_just_stopped_stays_a_bystanders(stood):
    _, taken = _following(None, 20.0)  # she walks: a bystander's "stop" does not end her walk
    assert taken == []
    _, taken = _following(20.0 - stood, 20.0)  # it has just come up to her
    assert taken == []


def test_other_words_from_off_the_followed_track_are_not_taken_even_when_it_stood():
    # only a stop: a bystander's remark (Tom in scenarios/distractor.xml) stays his
    d, taken = _following(10.0, 20.0, act="GOODBYE")
    assert taken == [] and d.not_addressed == 1


# ------------------------------------------------------------------ the attention: where the beam listens


@settings(max_examples=60, deadline=None)
@given(st.floats(-1.4, 1.4), st.floats(0.0, 10.0))
def test_the_beam_listens_to_another_voice_when_the_followed_track_stood_silent(voice, after):
    a = attention_following(waiting_since=30.0)
    t = 30.0 + STOOD_FOR + after
    a._voices = (t, False, True, voice)  # the followed track silent, someone else talks
    assert a.beam(t, 0.0, 2) == voice


@settings(max_examples=60, deadline=None)
@given(st.floats(-1.4, 1.4), st.floats(0.0, STOOD_FOR - 0.01))
def test_the_beam_stays_off_a_bystander_while_she_walks_or_just_stopped(voice, stood):
    t = 40.0
    walking = attention_following(waiting_since=None)
    walking._voices = (t, False, True, voice)
    assert walking.beam(t, 0.0, 2) is None
    just = attention_following(waiting_since=t - stood)
    just._voices = (t, False, True, voice)
    assert just.beam(t, 0.0, 2) is None
    # and when she talks herself the beam is on her, stood or not
    both = attention_following(waiting_since=t - 10.0)
    both._voices = (t, True, True, voice)
    assert both.beam(t, 0.25, 2) == 0.25


def _tracked(partner_spoke: float, other_spoke: float) -> PersonAttention:
    a = attention_following(waiting_since=20.0)
    tracks = [SimpleNamespace(id=1, confirmed=True, dormant=False), SimpleNamespace(id=4, confirmed=True, dormant=False)]
    a.tracks = SimpleNamespace(tracks=tracks, row=lambda i: next((k for k, tk in enumerate(tracks) if tk.id == i), -1))
    spoke = {1: partner_spoke, 4: other_spoke}
    a.speaking = SimpleNamespace(last=lambda i: spoke.get(i, -math.inf))
    a._partner_last = a._partner_colour = None
    a.now = 30.0
    return a


def test_the_stop_speaker_becomes_the_partner_when_the_followed_track_was_silent():
    a = _tracked(partner_spoke=5.0, other_spoke=29.0)
    a._stop_speaker()
    assert a.partner == 4


def test_her_own_stop_keeps_her_the_partner():
    a = _tracked(partner_spoke=29.2, other_spoke=28.0)  # a bystander spoke too, but her track said the stop
    a._stop_speaker()
    assert a.partner == 1
    quiet = _tracked(partner_spoke=5.0, other_spoke=10.0)  # nobody else heard lately: nothing to go by
    quiet._stop_speaker()
    assert quiet.partner == 1


# ------------------------------------------------------------------ review18 F2: only a whole stop said to the robot
@settings(max_examples=30, deadline=None)
@given(st.sampled_from(["stop", "stop now", "stop here", "you can stop", "you can stop now", "stop now biron",
                        "please stop", "ok stop here"]))
def test_a_whole_stop_to_the_robot_is_taken_from_another_voice_once_it_stood(words):
    d, taken = _following(10.0, 20.0, words=words)
    assert taken == ["STOP"] and d._stood_stop_cause == "m1"  # its stop event will say stood="true"


@settings(max_examples=30, deadline=None)
@given(st.sampled_from(["stop it", "stop that", "oh stop it", "stop it now", "stop that please", "stop talking"]))
def test_stop_it_from_another_voice_is_said_to_someone_else_even_when_it_stood(words):
    # review18 F2: a guest's "stop it" (to the other guest) ended her walk once the robot had stood 2 s
    d, taken = _following(10.0, 20.0, words=words)
    assert taken == [] and d.not_addressed == 1 and d._stood_stop_cause is None


def test_the_stop_speaker_is_looked_for_only_after_a_stop_the_dialog_took_through_the_exception():
    a = _tracked(partner_spoke=5.0, other_spoke=29.0)
    a._stood_stop_at = -math.inf
    assert not a._took_stood_stop()  # a stop taken from her own bearing (or a button): no switch
    a._on_es_event(SimpleNamespace(xml=etree.Element("event", name="stop"), created=29.5))
    assert not a._took_stood_stop()
    a._on_es_event(SimpleNamespace(xml=etree.Element("event", name="stop", stood="true"), created=29.5))
    assert a._took_stood_stop()
    a.now = 29.5 + 5.0  # an old one does not count
    assert not a._took_stood_stop()
