"""The leaving rule told from evidence (aside24; docs/semantics.md §6, docs/subsystems.md person attention).

fresh12 A: a partner who said "one moment" and walked about 2 m through the other balcony door, out of view behind the
wall, was "You left" 2 s later (walking away was evidence enough). fresh12 G: a partner who said good-bye (doubted) and
walked out of the flat's front door was not taken as gone. The rule now weighs where her way leads (the robot's map:
the flat is its rooms) and what she said (a wait request or a step aside asked for lengthens its patience, a good-bye
shortens it)."""

from __future__ import annotations

import math

from hypothesis import assume, given, settings
from hypothesis import strategies as st
from lxml import etree

from robot.attention.module import BYE_VOICE_SLACK, AttentionParams, PersonAttention

# A flat: a room 6 m x 4 m (robot at 3, 2) with the flat's exit door in its east wall (y 1.5-2.5) and a door in its
# north wall (x 2-3) to a second room 6 m x 3 m.
ROOMS = ((( 0.0, 0.0), (6.0, 0.0), (6.0, 4.0), (0.0, 4.0)), ((0.0, 4.0), (6.0, 4.0), (6.0, 7.0), (0.0, 7.0)))
WALLS = ((0.0, 0.0, 6.0, 0.0), (6.0, 0.0, 6.0, 1.5), (6.0, 2.5, 6.0, 4.0), (0.0, 4.0, 2.0, 4.0), (3.0, 4.0, 6.0, 4.0),
         (0.0, 0.0, 0.0, 7.0), (0.0, 7.0, 6.0, 7.0), (6.0, 4.0, 6.0, 7.0))
ROBOT = (3.0, 2.0)


class _Fsm:
    def __init__(self, state: str) -> None:
        self.state = state


def _attention(state: str, last: tuple[float, ...], *, plan: bool = True) -> PersonAttention:
    import numpy as np

    pa = PersonAttention.__new__(PersonAttention)  # the rule only: no bus
    pa.params = AttentionParams()
    pa.fsm = _Fsm(state)  # type: ignore[assignment]
    pa._partner_last = last  # type: ignore[assignment]
    pa._driven, pa._drive_start, pa._player_drives = 0.0, None, False
    if plan:
        pa._rooms = tuple(np.array(r) for r in ROOMS)
        pa._walls = WALLS
        pa.furniture = object()  # type: ignore[assignment]  # (a map is loaded)
        pa._odom_point_in_map = lambda x, y: (x, y)  # type: ignore[method-assign]  # odometry = map here
    else:
        pa.furniture = None
    return pa


def _last(seen: float, x: float, y: float, heading: float, speed: float) -> tuple[float, ...]:
    return (seen, x, y, speed * math.cos(heading), speed * math.sin(heading), ROBOT[0], ROBOT[1])


said = st.sampled_from(["nothing", "wait", "aside", "bye"])


def _say(pa: PersonAttention, what: str, when: float) -> None:
    if what == "wait":
        pa._said_wait = when
    elif what == "aside":
        pa._asked_aside = when
    elif what == "bye":
        pa._said_bye = when


@settings(max_examples=300, deadline=None)
@given(r=st.floats(0.0, 3.0), a=st.floats(-math.pi, math.pi), heading=st.floats(-math.pi, math.pi), speed=st.floats(0.0, 1.5),
       what=said, when=st.floats(-20.0, 20.0), unseen=st.floats(0.0, 60.0), state=st.sampled_from(["Interaction", "Object"]),
       plan=st.booleans(), voice=st.floats(-20.0, 1.0))
def test_seen_within_the_interaction_space_never_gone_unseen_past_the_longest_patience_always_gone(
        r, a, heading, speed, what, when, unseen, state, plan, voice):
    x, y = ROBOT[0] + r * math.cos(a), ROBOT[1] + r * math.sin(a)
    pa = _attention(state, _last(10.0, x, y, heading, speed), plan=plan)
    _say(pa, what, 10.0 + when)
    pa._her_voice = 10.0 + voice  # (her voice heard last then; no frame of her words since)
    p = pa.params
    left = pa.partner_left(10.0 + unseen)
    if unseen < p.partner_lost_after:
        assert not left  # seen (a moment ago) within the interaction space: never gone, whatever she said
    if unseen >= p.wait_patience:
        assert left  # unseen longer than the longest patience: always gone, whatever she said or was asked
    if left:  # once gone, gone later too (nothing but new evidence brings her back)
        assert pa.partner_left(10.0 + unseen + 0.5) and pa.partner_left(10.0 + max(unseen, p.wait_patience) + 1.0)


@settings(max_examples=150, deadline=None)
@given(y=st.floats(1.7, 2.3), x=st.floats(4.3, 5.8), speed=st.floats(0.35, 1.2), unseen=st.floats(2.0, 30.0))
def test_walking_away_to_the_exit_door_is_leaving(y, x, speed, unseen):
    # last seen within 3 m walking east, straight at the flat's exit door: gone once unseen partner_lost_after
    pa = _attention("Interaction", _last(0.0, x, y, 0.0, speed))
    assert pa.partner_left(unseen)


@settings(max_examples=150, deadline=None)
@given(x=st.floats(2.2, 2.8), y=st.floats(3.0, 3.9), speed=st.floats(0.35, 1.2), unseen=st.floats(0.0, 30.0),
       what=st.sampled_from(["nothing", "wait", "aside"]))
def test_walking_away_into_the_next_room_is_an_errand_waited_for(x, y, speed, unseen, what):
    # fresh12 A: through an inner door (not the exit), within the interaction space: she is waited for as long as it
    # takes to walk back from the next room (come_back_after), and after a wait request or a step aside asked for,
    # the longest patience (wait_patience); a good-bye said instead makes the same walk leaving
    pa = _attention("Interaction", _last(0.0, x, y, math.pi / 2, speed))
    _say(pa, what, -1.0)
    p = pa.params
    d = math.hypot(x - ROBOT[0], y - ROBOT[1])
    away = speed * (y - ROBOT[1]) / d >= p.leave_speed  # (walking, if not away from it: still an errand)
    patience = p.wait_patience if what != "nothing" else p.come_back_after
    if abs(unseen - patience) > 1e-6 and abs(unseen - p.partner_lost_after) > 1e-6:
        assert pa.partner_left(unseen) == (unseen >= patience)
    bye = _attention("Interaction", _last(0.0, x, y, math.pi / 2, speed))
    _say(bye, "bye", -1.0)
    gone_after = p.partner_lost_after if away else p.bye_patience
    if abs(unseen - gone_after) > 1e-6:
        assert bye.partner_left(unseen) == (unseen >= gone_after)


def test_without_a_map_walking_away_is_leaving_as_before():
    pa = _attention("Interaction", _last(0.0, 2.6, 3.5, math.pi / 2, 0.6), plan=False)
    assert not pa.partner_left(1.9)
    assert pa.partner_left(2.0)


@settings(max_examples=100, deadline=None)
@given(x=st.floats(5.0, 5.8), y=st.floats(1.7, 2.3), speed=st.floats(0.35, 1.2), unseen=st.floats(2.0, 29.0))
def test_out_through_the_exit_door_after_a_wait_request_is_still_leaving(x, y, speed, unseen):
    # her way on (at her pace over the time unseen, at most exit_reach) leads out of the rooms through the door gap
    pa = _attention("Interaction", _last(0.0, x, y, 0.0, speed))
    _say(pa, "wait", -1.0)
    p = pa.params
    assume(abs(x + min(p.exit_reach, speed * unseen) - 6.0) > 1e-6)  # (exactly on the door line: either answer)
    beyond = x + min(p.exit_reach, speed * unseen) > 6.0
    assert pa.partner_left(unseen) == (beyond or unseen >= p.wait_patience)


def test_a_frame_of_hers_is_noted_when_she_began_to_say_it():
    pa = _attention("Interaction", _last(0.0, 2.6, 3.5, math.pi / 2, 0.6))
    pa.sim = type("S", (), {"now": 95.0})()  # (the module's clock)

    def frame(act: str, start: float, end: float, tag: str = "understood") -> object:
        xml = etree.fromstring(f'<{tag} start="{start}" end="{end}" confidence="0.4"><SPEECH><{act}/></SPEECH></{tag}>')
        return type("M", (), {"xml": xml})()

    pa._on_frame(frame("WAIT", 86.8, 91.5))  # type: ignore[arg-type]
    assert pa._said_wait == 86.8 and pa._words_end == 91.5
    pa._her_voice = 92.5  # (her own voice heard during the words: review25 F-B)
    pa._on_frame(frame("GOODBYE", 92.0, 93.0))  # type: ignore[arg-type]
    assert pa._said_bye == 92.0
    pa.fsm.state = "Follow"
    pa._on_frame(frame("WAIT", 96.0, 97.0))  # type: ignore[arg-type]
    assert pa._said_wait == 86.8  # (a wait while she leads is the follower's pause, not this rule's)


@settings(max_examples=100, deadline=None)
@given(spoke=st.floats(-1.5, 0.0), unseen=st.floats(2.0, 12.0))
def test_her_words_on_their_way_are_waited_for(spoke, unseen):
    # she spoke as she walked off (her voice from her track up to voice_hold before her last sighting): walking away
    # to the exit is not taken as leaving until her words' frame came, at most words_wait after her voice
    pa = _attention("Interaction", _last(0.0, 5.0, 2.0, 0.0, 0.4))
    pa._odom_point_in_map = lambda x, y: (x, y)  # type: ignore[method-assign]
    pa.params = AttentionParams(exit_reach=0.0)  # (never predicted past the door: only her way towards it counts)
    pa._her_voice = spoke
    p = pa.params
    assert pa.partner_left(unseen) == (unseen - spoke > p.words_wait)
    pa._words_end = spoke  # her words came (not a wait, not a good-bye): the rule as without them
    assert pa.partner_left(unseen)


def _bye(start: float, *, partial: bool = False) -> object:
    mark = ' partial="true"' if partial else ""
    xml = etree.fromstring(f'<understood start="{start}" end="{start + 1.0}" confidence="0.8"{mark}><SPEECH><GOODBYE/></SPEECH></understood>')
    return type("M", (), {"xml": xml})()


@settings(max_examples=100, deadline=None)
@given(voice=st.one_of(st.just(-math.inf), st.floats(-20.0, 7.6)), partial=st.booleans(), unseen=st.floats(4.0, 18.0))
def test_a_good_bye_not_hers_or_doubted_never_shortens_her_errand(voice, partial, unseen):
    """review25 F-B: a bystander's "bye everyone" (her voice not heard while the words were said) or a doubted good-bye
    ("hang on, don't say goodbye yet": partial) left her errand patience cut to ``bye_patience``. She walks through the
    inner door into the next room (an errand): waited for ``come_back_after`` s whatever good-bye frame came that was
    not hers and whole."""
    pa = _attention("Interaction", _last(10.0, 2.5, 3.5, math.pi / 2, 0.6))
    pa.sim = type("S", (), {"now": 10.0})()
    pa._her_voice = voice
    pa._on_frame(_bye(8.0, partial=partial))  # type: ignore[arg-type]
    if voice >= 8.0 - BYE_VOICE_SLACK and not partial:
        return  # (hers and whole: the next test)
    assert pa._said_bye is None
    assert not pa.partner_left(10.0 + unseen)


def test_her_own_whole_good_bye_still_shortens_her_patience():
    pa = _attention("Interaction", _last(10.0, 2.5, 3.5, math.pi / 2, 0.6))
    pa.sim = type("S", (), {"now": 10.0})()
    pa._her_voice = 8.4  # her voice heard while she said it
    pa._on_frame(_bye(8.0))  # type: ignore[arg-type]
    assert pa._said_bye == 8.0
    assert pa.partner_left(10.0 + pa.params.bye_patience + 0.5)
