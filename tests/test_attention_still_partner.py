"""A partner who stands still side-on to the laser while the robot looks at the thing she shows it
(fresh5/row_partners_hand_over seeds 0, 6, 9: Tom's track died 8 s into the look at his book, one leg
seen, the camera on the book, and the robot said "You left"). In Object her legs where she stood renew
her track; a partner who moves away, or a lone leg outside Object, is left to the tracker's rules."""

from __future__ import annotations

from hypothesis import given, settings, strategies as st

from robot.attention.fsm import AttentionFSM
from robot.attention.legs import PAIR, SINGLE
from robot.attention.module import AttentionParams, PersonAttention
from robot.attention.tracker import Tracks, TrackerSpec


def _attention(state: str) -> PersonAttention:
    a = PersonAttention.__new__(PersonAttention)
    a.params = AttentionParams()
    a.fsm = AttentionFSM()
    a.fsm.state = state
    a.tracks = Tracks(TrackerSpec())
    a.partner = None
    return a


def _run(a: PersonAttention, leg_at, until: float) -> bool:
    """Confirm a track on a pair at (1.1, 0), make it the partner, then feed single legs at ``leg_at(t)``
    every 0.1 s up to ``until``; whether the partner's track is still alive."""
    t = 0.0
    for k in range(6):
        t = 0.1 * k
        a.tracks.step(t, [[1.1, 0.0]], [PAIR])
    a.partner = a.tracks.tracks[0].id
    while t < until:
        t += 0.1
        assigned = a.tracks.step(t, [list(leg_at(t))], [SINGLE])
        a._keep_still_partner(t, assigned)
    return a.tracks.row(a.partner) >= 0


@settings(max_examples=20, deadline=None)
@given(dx=st.floats(-0.12, 0.12), dy=st.floats(-0.12, 0.12))
def test_a_still_partner_showing_one_leg_is_kept_while_the_camera_looks_at_her_thing(dx, dy):
    spec = TrackerSpec()
    assert _run(_attention("Object"), lambda t: (1.1 + dx, dy), spec.single_support + 6.0)
    # the same lone leg outside Object (no camera looking away on the ES's order): the tracker's allowance holds
    assert not _run(_attention("Interaction"), lambda t: (1.1 + dx, dy), spec.single_support + 6.0)


def test_a_partner_who_walks_off_on_one_leg_is_not_held():
    spec = TrackerSpec()
    # she sidles away at 0.1 m/s, only one leg seen: past ``still_radius`` her track is the tracker's again
    assert not _run(_attention("Object"), lambda t: (1.1, 0.1 * max(0.0, t - 0.5)), spec.single_support + 8.0)
