"""The partner's track in someone else's clothes is not her (gen22).

Generated tours 8800-01 and -19 (main 89146ce): following her into a room, her track went over to a
bystander she walked past (a guest standing in the doorway); after her "stop" the robot stood in
Interaction facing that silent guest as its partner, and the beam gate shut out every word of hers as
a bystander's talk, for the rest of the tour (a mute robot for 400 s). Clothes do not change during a
tour: in Interaction and Object, the partner's track showing other clothes than it showed when it
became hers for ``other_clothes_after`` s is someone else, and she is lost (known again by her own
clothes when she comes back). Following (ident23), the same evidence means her track went over to someone who
passed her close (coming the other way): that track gets an id of its own, and she is searched for and found again
by her clothes where she walked on (no loss declared for it).
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from robot.attention.appearance import Colours, same_clothes
from robot.attention.cues import CueSpec, Hysteresis
from robot.attention.fsm import AttentionFSM
from robot.attention.looking import HeardFrom, LookedAt
from robot.attention.module import AttentionParams, PersonAttention
from robot.attention.tracker import Tracks, TrackerSpec
from robot.partner_search import Closing

HERS, OTHER = (0.95, 0.95, 0.95), (0.9, 0.55, 0.1)  # her white top; the guest's orange one (camera RGB, 0-1)


def _interacting(state: str = "interact") -> tuple[PersonAttention, int]:
    """A person attention in Interaction (or the state ``state`` orders) with its partner standing 1 m in
    front of the robot, seen every scan."""
    a = PersonAttention.__new__(PersonAttention)
    a.params = AttentionParams()
    a.fsm = AttentionFSM()
    a.fsm.order(state)
    a.tracks = Tracks(TrackerSpec())
    a.tracks._birth(0.0, np.array([(1.0, 0.1)], dtype=float), np.full(1, 0.01))
    tk = a.tracks.tracks[0]
    tk.confirmed = True
    a.partner, a.partner_lost_sent, a._partner_last = tk.id, False, None
    a._partner_colour = a._lost_colour = None
    a._her_clothes = a._other_clothes_since = None
    a._handovers, a._not_her = {}, set()
    a.colours = Colours()
    a._odom = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    a._alone_since = None
    a._voice_turn = None
    a.looked, a.heard = LookedAt(), HeardFrom()
    a.facing = Hysteresis(CueSpec().facing_on, CueSpec().facing_off)
    a._drive_start, a._driven, a._yielded, a._yield_t = None, 0.0, 0.0, None
    a._closing = Closing()
    a._partner_pace = (-math.inf, 0.0)
    a._follow_searching, a._follow_ended, a._follow_stopped = None, -math.inf, None
    a._caller = None
    a.events = []
    a._event = lambda name, children=(): a.events.append((name, [dict(c.attrib) for c in children]))
    return a, tk.id


def _run(a: PersonAttention, tid: int, clothes, t0: float, t1: float, dt: float = 0.1) -> list[float]:
    """Scans from ``t0`` to ``t1``: the camera sees the partner's track in ``clothes(t)`` (RGB or None: no blob),
    her legs measured; the times partner_lost went out."""
    lost, t = [], t0
    while t < t1 - 1e-9:
        tk = next((k for k in a.tracks.tracks if k.id == tid), None)
        if tk is not None:
            tk.last_seen = t
            rgb = clothes(t)
            if rgb is not None:
                a.colours.observe(tid, rgb, t)
        before = len(a.events)
        a._top_down(t, {tid: 1})
        lost += [t for name, _ in a.events[before:] if name == "partner_lost"]
        t += dt
    return lost


def test_her_track_on_a_guest_in_other_clothes_is_a_loss_and_she_is_known_by_hers():
    a, tid = _interacting()
    assert _run(a, tid, lambda t: HERS, 0.0, 5.0) == []
    lost = _run(a, tid, lambda t: OTHER, 5.0, 12.0)
    # the running colour leaves hers within a few blobs; other_clothes_after later she is lost, once
    assert len(lost) == 1 and 5.0 + a.params.other_clothes_after <= lost[0] < 5.0 + a.params.other_clothes_after + 1.0
    assert a.partner is None and tid in a._not_her
    assert a._lost_colour is not None and np.allclose(a._lost_colour, HERS, atol=0.02)  # her own, not the guest's


def test_someone_in_other_clothes_passing_in_front_of_her_for_a_moment_is_not():
    a, tid = _interacting()
    passing = lambda t: OTHER if 5.0 <= t < 5.0 + a.params.other_clothes_after - 1.0 else HERS  # noqa: E731
    assert _run(a, tid, passing, 0.0, 15.0) == []
    assert a.partner == tid


def _walk(a: PersonAttention, tid: int, t0: float, t1: float, at, clothes, dt: float = 0.1) -> int:
    """Scans from ``t0`` to ``t1`` following: the track holding ``tid`` measured at ``at(t)`` (odom) in ``clothes(t)``,
    the camera's blob anchored to it (her evidence kept as the module's torso handler keeps it); returns the
    number of partner_lost events."""
    lost, t = 0, t0
    while t < t1 - 1e-9:
        tk = next((k for k in a.tracks.tracks if k.id == tid), None)
        if tk is not None:
            x, y = at(t)
            tk.x, tk.last_z, tk.last_seen = [x, y, tk.x[2], tk.x[3]], (x, y), t
            rgb = clothes(t)
            a.colours.observe(tid, rgb, t)
            if tid == a.partner and a._her_clothes is not None and same_clothes(a._her_clothes, rgb):
                a._her_seen = a._partner_state()
        before = len(a.events)
        a._top_down(t, {tid: 1})
        lost += sum(1 for name, _ in a.events[before:] if name == "partner_lost")
        t += dt
    return lost


def test_following_her_track_in_other_clothes_is_someone_else_and_she_is_searched_for():
    """fresh11/rail_fast_crossing seed 1: Tim stood in a doorway (he answered "slow down"), his flatmate came the other
    way through it, and the two tracks swapped; the robot then followed her back into the dining room and never heard
    him again. Following, her track showing other clothes for ``other_clothes_after`` s is someone else: that track
    gets an id of its own (not hers, never taken back as hers), her id has no track, nobody is declared lost yet, and
    her evidence is where the camera last saw her clothes on her track, not where the other person walked to."""
    a, tid = _interacting("follow")
    her_walk = lambda t: (1.0 + 0.8 * t, 0.1)  # noqa: E731 (she leads along +x)
    assert _walk(a, tid, 0.0, 5.0, her_walk, lambda t: HERS) == 0
    swapped = lambda t: (4.9 - 0.8 * (t - 5.0), 0.3)  # noqa: E731 (the other person walks back toward the robot)
    assert _walk(a, tid, 5.0, 5.0 + a.params.other_clothes_after + 2.0, swapped, lambda t: OTHER) == 0
    assert a.partner == tid and a.tracks.row(tid) < 0  # her identity is not on the other person
    fresh = [tk.id for tk in a.tracks.tracks]
    assert len(fresh) == 1 and fresh[0] != tid and fresh[0] in a._not_her
    assert a._partner_last is not None and abs(a._partner_last[1] - 4.9) < 0.2  # where she was last seen in her clothes
    assert np.allclose(a._partner_colour, HERS, atol=0.05)
    # she is found again ahead, in her clothes, on her way on: hers (and the other person's track never is)
    ahead = _another_track(a, (6.0, 0.1), HERS, 10.5)
    a._top_down(10.6, {ahead: 1, fresh[0]: 1})
    assert a.partner == ahead


def test_following_someone_in_other_clothes_passing_her_for_a_moment_keeps_her_track():
    a, tid = _interacting("follow")
    passing = lambda t: OTHER if 5.0 <= t < 5.0 + a.params.other_clothes_after - 1.0 else HERS  # noqa: E731
    assert _walk(a, tid, 0.0, 15.0, lambda t: (1.0 + 0.5 * t, 0.1), passing) == 0
    assert a.partner == tid and a.tracks.row(tid) >= 0


LAG = 0.5  # s: how much longer the running colour (alpha 0.25 per blob) takes to come back to hers than to leave it


@settings(max_examples=30, deadline=None)
@given(st.lists(st.tuples(st.booleans(), st.floats(0.2, 6.0)), min_size=1, max_size=6))
def test_following_never_keeps_her_identity_on_other_clothes_longer_than_the_rule_allows(spells):
    """Whatever spells of her clothes and others her track shows while she leads, her identity is never on a track
    whose running colour has shown other clothes for more than ``other_clothes_after`` s (plus the scan), and it
    leaves a track only after other clothes were shown that long."""
    a, tid = _interacting("follow")
    _walk(a, tid, 0.0, 1.0, lambda u: (1.0 + 0.5 * u, 0.1), lambda u: HERS)
    t, run = 1.0, 0.0  # run: how long other clothes have been shown without a break
    for hers, span in spells:
        shown = HERS if hers else OTHER
        _walk(a, tid, t, t + span, lambda u: (1.0 + 0.5 * u, 0.1), lambda u, c=shown: c)
        t += span
        # her clothes shown again end a run, but the rule reads the running colour, which takes a few blobs to
        # leave hers and a few more to come back (LAG): a run about that long may still end her identity early
        # in the spell of hers that follows it
        before, run = run, (0.0 if hers else run + span)
        if hers and a.tracks.row(tid) < 0:
            assert before >= a.params.other_clothes_after - LAG
            break
        row = a.tracks.row(tid)
        if row >= 0 and a._other_clothes_since is not None:
            assert t - a._other_clothes_since <= a.params.other_clothes_after + 0.1 + 1e-9
        if row < 0:  # the identity left its track: only after other clothes shown long enough
            assert run >= a.params.other_clothes_after
            break
    else:
        assert run < a.params.other_clothes_after + 2.0  # (the running colour leaves hers within 2 s)


@settings(max_examples=40, deadline=None)
@given(st.tuples(st.floats(0, 1), st.floats(0, 1), st.floats(0, 1)), st.tuples(st.floats(0, 1), st.floats(0, 1), st.floats(0, 1)),
       st.floats(0.5, 8.0), st.integers(0, 2**31 - 1))
def test_a_loss_exactly_when_her_track_showed_other_clothes_long_enough(hers, other, hold, seed):
    """With camera noise on every blob: lost exactly when the second colour is other clothes (further than the
    appearance's ``differ`` from hers, with margin for the noise) and was shown at least ``other_clothes_after``
    s; never when it is her own colour."""
    rng = np.random.default_rng(seed)
    noisy = lambda rgb: tuple(float(np.clip(c + rng.normal(0.0, 0.01), 0.0, 1.0)) for c in rgb)  # noqa: E731
    gap = float(np.linalg.norm(np.subtract(hers, other)))
    a, tid = _interacting()
    differ = a.colours.spec.differ
    if abs(gap - differ) < 0.08:
        return  # within the noise of the threshold: either answer is right
    lost = _run(a, tid, lambda t: noisy(hers) if t < 3.0 else noisy(other), 0.0, 3.0 + hold)
    # the running mean needs a few blobs to leave hers (alpha 0.25): up to 2 s on top of the hold
    if gap < differ:
        assert lost == []
    elif hold < a.params.other_clothes_after:
        assert lost == []
    elif hold >= a.params.other_clothes_after + 2.0:
        assert len(lost) == 1


def _another_track(a: PersonAttention, at: tuple[float, float], clothes, t: float) -> int:
    a.tracks._birth(t, np.array([at], dtype=float), np.full(1, 0.01))
    tk = a.tracks.tracks[-1]
    tk.confirmed = True
    for k in range(a.colours.spec.min_obs):
        a.colours.observe(tk.id, clothes, t - 0.3 + 0.1 * k)
    return tk.id


def test_her_identity_passed_to_another_track_keeps_her_clothes():
    """The identity passes between track ids (re-identification, the leaving rule's reacquisition): that is where
    someone else takes her place, so her clothes go with the identity, not with a track id."""
    a, tid = _interacting()
    assert _run(a, tid, lambda t: HERS, 0.0, 5.0) == []
    guest = _another_track(a, (1.1, 0.2), OTHER, 5.0)
    a.tracks.tracks = [tk for tk in a.tracks.tracks if tk.id != tid]
    a.partner = guest  # as _reacquire hands her role over (the guest's clothes were already seen: no hand-over open)
    lost = _run(a, guest, lambda t: OTHER, 5.0, 12.0)
    assert len(lost) == 1 and lost[0] >= 5.0 + a.params.other_clothes_after - 1e-9


def test_whoever_takes_the_place_after_the_loss_is_known_by_their_own_clothes():
    """After the loss the next partner (speaking facing the robot close by) starts a record of their own: the
    guest who answers is not lost again for not wearing hers."""
    a, tid = _interacting()
    _run(a, tid, lambda t: HERS, 0.0, 5.0)
    assert len(_run(a, tid, lambda t: OTHER, 5.0, 10.0)) == 1
    a._lost_colour = None  # (taken back within conversation distance whatever the clothes)
    a.partner_lost_sent, a.events = True, []
    other = _another_track(a, (1.2, -0.3), OTHER, 10.0)
    a._top_down(10.1, {other: 3})
    assert a.partner == other
    assert _run(a, other, lambda t: OTHER, 10.2, 20.0) == []


def _her_track_drifted_onto_a_guest_while_following() -> tuple[PersonAttention, int]:
    """Following, her track shows HERS for 5 s, then OTHER for a little less than ``other_clothes_after`` (the
    Follow rule, ident23, has not taken it off her yet): it went over to a guest she walked past. Then that track
    dies."""
    a, tid = _interacting("follow")
    assert _run(a, tid, lambda t: HERS if t < 5.0 else OTHER, 0.0, 5.0 + a.params.other_clothes_after - 0.5) == []
    assert not np.allclose(a._partner_colour, HERS, atol=0.1)  # the running colour went with the track
    a.tracks.tracks = [tk for tk in a.tracks.tracks if tk.id != tid]
    return a, tid


def test_after_her_track_drifted_every_check_of_her_clothes_uses_hers_not_the_guests():
    """review22 R5: one reference for "her clothes". Her track found again is hers; the guest's is not."""
    a, _ = _her_track_drifted_onto_a_guest_while_following()
    assert np.allclose(a._hers(), HERS, atol=0.02)
    guest = _another_track(a, (1.05, 0.1), OTHER, 10.1)
    her = _another_track(a, (1.0, 0.2), HERS, 10.1)
    row = a._reacquire(10.2)
    assert row >= 0 and a.tracks.tracks[row].id == her and a.partner == her
    assert a.partner != guest


def test_a_hand_over_opened_after_the_drift_is_undone_on_the_guests_clothes():
    a, old = _her_track_drifted_onto_a_guest_while_following()
    a.tracks._birth(10.1, np.array([(1.05, 0.1)], dtype=float), np.full(1, 0.01))
    tk = a.tracks.tracks[-1]
    tk.confirmed = True  # a track whose clothes the camera has not seen yet: taken on position alone
    assert a._reacquire(10.2) >= 0 and a.partner == tk.id
    h = a._handovers[tk.id]
    assert np.allclose(h.colour, HERS, atol=0.02)  # judged against hers, not the drifted running colour
    for k in range(a.colours.spec.min_obs):
        a.colours.observe(tk.id, OTHER, 10.3 + 0.1 * k)
    a._check_handovers(10.6, [])
    assert a.partner == old and tk.id in a._not_her  # the guest in orange is not her: undone


def test_renew_gives_the_track_an_id_of_its_own_and_leaves_hers_without_a_track():
    tr = Tracks(TrackerSpec())
    tr._birth(0.0, np.array([(1.0, 0.0), (3.0, 0.0)], dtype=float), np.full(2, 0.01))
    a_id, b_id = (tk.id for tk in tr.tracks)
    fresh = tr.renew(a_id)
    assert fresh not in (a_id, b_id) and tr.row(a_id) < 0 and tr.row(fresh) == 0 and tr.row(b_id) == 1
    assert tr.renew(a_id) == -1  # nobody holds it any more
    tr._birth(0.1, np.array([(5.0, 0.0)], dtype=float), np.full(1, 0.01))
    assert tr.tracks[-1].id not in (a_id, b_id, fresh)  # ids are never given twice
