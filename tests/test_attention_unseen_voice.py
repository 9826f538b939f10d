"""The partner out of view who talks on (voice25; docs/subsystems.md person attention, the leaving rule).

aside24's "Left": a partner who stepped behind a wall or a shelf and talked on from there was declared gone after the
longest patience (30 s unseen), because her voice was matched to tracks only and her track had died. A voice nobody
seen explains, read from where her legs were last measured, is now hers: it keeps her the partner, and the robot turns
toward it; a voice from elsewhere (someone else out of view) is not hers and changes nothing."""

from __future__ import annotations

import math

from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from robot.attention.cues import CueSpec, sound_bearing_span, sound_bearings_from
from robot.attention.module import AttentionParams, PersonAttention

ROBOT = (3.0, 2.0)


class _Fsm:
    def __init__(self, state: str) -> None:
        self.state = state


class _NoTracks:
    tracks: list = []

    def row(self, tid: int) -> int:
        return -1  # her track has died


def _attention(state: str, seen: float, x: float, y: float, vx: float, vy: float, heading: float) -> PersonAttention:
    pa = PersonAttention.__new__(PersonAttention)  # the rule only: no bus
    pa.params = AttentionParams()
    pa.cues = CueSpec()
    pa.fsm = _Fsm(state)  # type: ignore[assignment]
    pa.tracks = _NoTracks()  # type: ignore[assignment]
    pa.partner, pa.partner_lost_sent = 7, False
    pa._partner_last = (seen, x, y, vx, vy, ROBOT[0], ROBOT[1])  # type: ignore[assignment]
    pa._driven, pa._drive_start, pa._player_drives = 0.0, None, False
    pa._odom = (0.0, ROBOT[0], ROBOT[1], heading, 0.0, 0.0)  # (standing: the pose at any time)
    pa.furniture = None
    return pa


def _reading(pa: PersonAttention, x: float, y: float) -> float:
    """The front reading the microphone pair gives for a voice from the odom point (x, y)."""
    th = pa._odom[3]
    dx, dy = x - ROBOT[0], y - ROBOT[1]
    c, s = math.cos(th), math.sin(th)
    return sound_bearings_from([(c * dx + s * dy, -s * dx + c * dy)], pa.cues)[0]


where = dict(r=st.floats(0.8, 2.9), a=st.floats(-math.pi, math.pi), heading=st.floats(-math.pi, math.pi),
             speed=st.floats(0.0, 1.2), walk=st.floats(-math.pi, math.pi), state=st.sampled_from(["Interaction", "Object"]))


@settings(max_examples=200, deadline=None)
@given(**where, gaps=st.lists(st.floats(0.5, 19.0), min_size=3, max_size=8).filter(lambda g: sum(g) > 31.0), said=st.sampled_from(["nothing", "wait"]))
def test_talking_on_from_where_she_went_out_of_view_she_is_never_gone(r, a, heading, speed, walk, state, gaps, said):
    x, y = ROBOT[0] + r * math.cos(a), ROBOT[1] + r * math.sin(a)
    pa = _attention(state, 0.0, x, y, speed * math.cos(walk), speed * math.sin(walk), heading)
    if said == "wait":
        pa._said_wait = -0.5
    p = pa.params
    t = p.partner_lost_after + 0.5  # (she has been out of view a moment: until then her voice goes to her track)
    for g in gaps:  # she speaks every g s (less than come_back_after), long past the longest patience in all
        pa._voice_from_where_she_went(t, [_reading(pa, x, y)])
        assert pa._heard_unseen[0] == t
        for k in range(1, 9):
            assert not pa.partner_left(t + g * k / 8)
        # and the robot turns toward her voice (Interaction): the reading nearer where she stood
        if state == "Interaction":
            b = pa._where_she_stood(t + g)
            own = math.atan2(y - ROBOT[1], x - ROBOT[0]) - heading
            assert b is not None and abs(math.remainder(b - own, 2 * math.pi)) < math.radians(45)
        t += g
    assert t > p.wait_patience + 1.0  # (she talked on past the longest patience)
    # silent from then on: gone once her patience after her last word has run out
    patience = p.wait_patience if said == "wait" else p.come_back_after
    last = t - gaps[-1]
    assert pa.partner_left(last + patience + 0.01)


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.filter_too_much])
@given(**where, b=st.floats(-math.pi / 2, math.pi / 2), unseen=st.floats(2.0, 60.0))
def test_a_voice_from_elsewhere_is_not_hers(r, a, heading, speed, walk, state, b, unseen):
    x, y = ROBOT[0] + r * math.cos(a), ROBOT[1] + r * math.sin(a)
    pa = _attention(state, 0.0, x, y, speed * math.cos(walk), speed * math.sin(walk), heading)
    p = pa.params
    # someone else's voice (front reading b), clearly elsewhere: b (either way round: the pair cannot tell front from
    # back) is further off every reading her voice can give from where she was last measured (her unknown height)
    # than her steps since, seen from the robot, can explain (the reacquisition radius, at most unseen_voice_spread)
    th = heading
    dx, dy = x - ROBOT[0], y - ROBOT[1]
    lo, hi = sound_bearing_span(math.cos(th) * dx + math.sin(th) * dy, -math.sin(th) * dx + math.cos(th) * dy, pa.cues)
    off = min(max(0.0, lo - v, v - hi) for v in (b, math.remainder(math.pi - b, 2 * math.pi)))
    reach = min(2.5, p.reacquire_radius + p.reacquire_speed * 2.5)
    assume(off > pa.cues.sound_tolerance + min(math.asin(min(1.0, reach / r)), p.unseen_voice_spread) + math.radians(2))
    quiet = _attention(state, 0.0, x, y, speed * math.cos(walk), speed * math.sin(walk), heading)
    pa._voice_from_where_she_went(2.5, [b])
    assert pa._heard_unseen[0] == -math.inf
    assert pa.partner_left(unseen) == quiet.partner_left(unseen)
    # ... while the same voice from where she went is hers
    mine = _reading(pa, x, y)
    pa._voice_from_where_she_went(3.0, [mine])
    assert pa._heard_unseen[0] == 3.0


@given(state=st.sampled_from(["Follow", "Listen", "Alertness"]))
def test_only_in_interaction_and_object(state):
    pa = _attention(state, 0.0, 4.0, 2.5, 0.0, 0.0, 0.0)
    pa._voice_from_where_she_went(3.0, [_reading(pa, 4.0, 2.5)])
    assert pa._heard_unseen[0] == -math.inf
    seen = _attention("Interaction", 0.0, 4.0, 2.5, 0.0, 0.0, 0.0)  # (the same voice in Interaction is hers)
    seen._voice_from_where_she_went(3.0, [_reading(seen, 4.0, 2.5)])
    assert seen._heard_unseen[0] == 3.0


def test_after_a_good_bye_her_voice_keeps_her_only_a_moment():
    pa = _attention("Interaction", 0.0, 4.0, 2.5, 0.0, 0.0, 0.0)
    pa._said_bye = 5.0
    pa._words_end = 6.0
    pa._voice_from_where_she_went(5.5, [_reading(pa, 4.0, 2.5)])
    assert pa._heard_unseen[0] == 5.5
    p = pa.params
    assert not pa.partner_left(5.5 + p.partner_lost_after - 0.1)
    assert pa.partner_left(5.5 + p.bye_patience + 0.1)
