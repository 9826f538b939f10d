"""An identity handed over on position alone stays open until the camera sees the clothes (docs/semantics.md §3):
a track taken for the partner while her clothes were known and its own were not (re-identification of her
dormant track, the leaving rule's reacquisition, her own track moved by the tracker's "stopped" hypothesis)
keeps her id only if the camera then sees her clothes on it. Other clothes: the wrong track gets an id of its
own, her track and her evidence (where and when she was last seen) are put back, and the wrong track is never
taken for her again (fresh7/split_children_cross: a running girl took the father's identity at a door)."""

from __future__ import annotations

import math

from hypothesis import given, settings
from hypothesis import strategies as st

from robot.attention.appearance import Colours
from robot.attention.fsm import AttentionFSM
from robot.attention.module import HANDOVER_UNMEASURED, AttentionParams, PersonAttention
from robot.attention.tracker import Track, Tracks, TrackerSpec

BLACK, YELLOW = (0.05, 0.05, 0.05), (0.9, 0.8, 0.1)
HER_LAST = (5.0, 2.0, 0.0, 0.5, 0.0, 0.0, 0.0)  # seen at t=5 at (2, 0) walking +x at 0.5 m/s; robot at the origin


def _attention(new: tuple[float, float] = (2.4, 0.3), t: float = 6.0, *, dormant: bool = True) -> PersonAttention:
    """Following: the partner (track 1, black clothes) last measured at (2, 0) at t=5, her track dormant (or
    dead), and a track (99) just confirmed at ``new`` whose clothes the camera has not seen."""
    a = PersonAttention.__new__(PersonAttention)
    a.params = AttentionParams()
    a.fsm = AttentionFSM()
    a.fsm.state = "Follow"
    a.tracks = Tracks(TrackerSpec())
    a.tracks._t = t
    a.colours = Colours()
    if dormant:
        her = Track(1, [2.0, 0.0, 0.5, 0.0], [0.05, 0, 0, 0, 0.05, 0, 0, 0.1, 0, 0.1], 0.0)
        her.confirmed, her.dormant, her.last_seen, her.last_update, her.last_z = True, True, 5.0, 5.0, (2.0, 0.0)
        a.tracks.tracks.append(her)
        for k in range(4):
            a.colours.observe(1, BLACK, 4.0 + 0.1 * k)
    tk = Track(99, [new[0], new[1], 0.0, 0.0], [0.01, 0, 0, 0, 0.01, 0, 0, 1.0, 0, 1.0], t - 0.3)
    tk.confirmed, tk.last_update, tk.last_seen = True, t, t
    a.tracks.tracks.append(tk)
    a.tracks._next = 100
    a.tracks.confirmed_now = [99]
    a.partner, a._partner_last, a._partner_colour = 1, HER_LAST, BLACK
    return a


def _seen_in(a: PersonAttention, tid: int, colour: tuple[float, float, float], t: float) -> None:
    for k in range(3):
        a.colours.observe(tid, colour, t - 0.2 + 0.1 * k)


def test_a_child_taken_for_her_by_reidentification_gives_her_identity_back_when_seen():
    a = _attention()
    a._reidentify(6.0, [1])
    assert [tk.id for tk in a.tracks.tracks] == [1] and a.partner == 1  # taken on position alone
    assert a.colours.colour(1, 6.0) is None  # the id's clothes are the new track's own, not hers
    a._partner_last = (6.2, 2.4, 0.3, -1.4, 0.0, 0.0, 0.0)  # what the wrong track added meanwhile
    _seen_in(a, 1, YELLOW, 6.4)
    a._check_handovers(6.4, [0])
    ids = {tk.id: tk for tk in a.tracks.tracks}
    assert set(ids) == {1, 100} and a.partner == 1
    assert ids[1].dormant and math.isclose(ids[1].x[0], 2.0 + 0.5 * 0.4, abs_tol=0.05)  # hers again, coasted on
    assert ids[100].x[0] == 2.4 and a.colours.colour(100, 6.4) is not None  # the child keeps her own clothes
    assert a._partner_last == HER_LAST and a._partner_colour == BLACK  # her evidence as it was
    assert 100 in a._not_her


def test_her_own_clothes_seen_the_hand_over_stands():
    a = _attention()
    a._reidentify(6.0, [1])
    _seen_in(a, 1, (0.07, 0.04, 0.06), 6.4)
    a._check_handovers(6.4, [0])
    assert [tk.id for tk in a.tracks.tracks] == [1] and a.partner == 1 and not a._handovers


def test_a_track_taken_for_her_by_the_leaving_rule_is_undone_and_never_retaken():
    a = _attention(new=(2.3, 0.2), dormant=False)
    a.tracks.confirmed_now = []
    assert a._reacquire(6.0) == 0 and a.partner == 99
    _seen_in(a, 99, YELLOW, 6.5)
    a._check_handovers(6.5, [])
    assert a.partner == 1 and a._partner_last == HER_LAST and 99 in a._not_her
    a.colours = Colours()  # her clothes no longer fresh on it: still not taken again
    assert a._reacquire(6.6) == -1 and a.partner == 1


def test_her_track_moved_by_the_stopped_hypothesis_is_hers_again_when_the_track_goes_unmeasured_first():
    a = _attention(dormant=False)
    her = Track(1, [2.0, 0.0, 0.5, 0.0], [0.05, 0, 0, 0, 0.05, 0, 0, 0.1, 0, 0.1], 0.0)
    her.confirmed, her.last_seen, her.last_update, her.last_z = True, 5.9, 5.9, (2.0, 0.0)
    before = Tracks.copy(her)
    her.x, her.last_z, her.last_update = [1.6, 0.6, 0.0, 0.0], (1.6, 0.6), 6.0  # the tracker put it on the child
    a.tracks.tracks.insert(0, her)
    a._restarted(6.0, before)
    assert 1 in a._handovers and a._handovers[1].restart
    a._check_handovers(6.0 + HANDOVER_UNMEASURED / 2, [])
    assert a.tracks.tracks[0].x[0] == 1.6  # measured a moment ago: still open
    a._check_handovers(6.0 + HANDOVER_UNMEASURED + 0.05, [])
    ids = {tk.id: tk for tk in a.tracks.tracks}
    assert ids[1].x[0] > 2.0 and ids[1].x[1] == 0.0 and a.partner == 1 and not a._handovers
    assert 1 not in a._not_her and all(i not in a._not_her for i in ids)  # unseen, not refuted


@settings(max_examples=100, deadline=None)
@given(n=st.integers(1, 5), who=st.integers(0, 4), since=st.floats(0.5, 5.0), later=st.floats(0.0, 40.0))
def test_give_back_keeps_ids_unique_and_the_old_track_under_its_id(n, who, since, later):
    tr = Tracks(TrackerSpec())
    for k in range(n):
        tr._birth_one(float(k) * 0.1, float(k), 0.0, 0.01)
    old_id = tr.tracks[who % n].id
    new_row = len(tr.tracks)
    tr._birth_one(since, 9.0, 9.0, 0.01)
    old = Tracks.copy(tr.tracks[who % n])
    assert tr.adopt(tr.tracks[new_row].id, old_id) >= 0
    fresh, at = tr.give_back(old_id, old, since, since + later)
    ids = [tk.id for tk in tr.tracks]
    assert len(ids) == len(set(ids)) and fresh not in (-1, old_id) and fresh in ids
    if later + since - old.last_seen <= tr.spec.hidden_timeout:
        assert at >= 0 and tr.tracks[at].id == old_id and tr.tracks[at] is old
        assert [tk.born for tk in tr.tracks] == sorted(tk.born for tk in tr.tracks)  # oldest first
    else:
        assert at == -1 and old_id not in ids
