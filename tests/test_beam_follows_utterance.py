"""The recogniser's beam follows an utterance it began to listen to, when the voice turns out to be the
attended person's, still turned away (wlan_reorder seed 8: Ben calls with his back to the robot and the
beam went off for 0.3 s as his track began to explain the voice; over the slow link his greeting was lost)."""

from __future__ import annotations

import math

from robot.attention.fsm import AttentionFSM
from robot.attention.module import AttentionParams, PersonAttention


def _attention() -> PersonAttention:
    a = PersonAttention.__new__(PersonAttention)
    a.params = AttentionParams()
    a.fsm = AttentionFSM()
    a._voice_turn = None
    a._dominant = None
    a.partner = None
    a.partner_lost_sent = False
    a._caller = None
    return a


def test_an_utterance_listened_to_is_followed_to_the_attended_speaker_turned_away():
    a = _attention()
    a._dominant = (1.0, math.radians(-10))
    assert a.beam(1.0, None, 0) == math.radians(-10)  # an unexplained voice: listened to
    assert a.beam(1.3, None, 0) == math.radians(-10)  # its last reading still fresh
    # then his track explains it (no unexplained reading any more); he speaks, not facing the robot (category 2)
    assert a.beam(1.4, math.radians(-6), 2) == math.radians(-6)


def test_someone_tracked_talking_turned_away_is_not_listened_to_unless_the_beam_was_on_his_voice():
    a = _attention()
    assert a.beam(5.0, math.radians(20), 2) is None  # gated: not addressing the robot (docs/semantics.md §3)
    a._dominant = (1.0, math.radians(-10))
    a.beam(1.0, None, 0)
    assert a.beam(2.0, math.radians(-6), 2) is None  # a second after: a new utterance, gated again
