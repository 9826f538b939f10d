"""Torso colour per track (robot.attention.appearance): what tells the partner from someone who crossed."""

from __future__ import annotations

import math

from hypothesis import assume, given, settings
from hypothesis import strategies as st

from robot.attention.appearance import AppearanceSpec, Colours, anchor_torsos, same_clothes

bearing = st.floats(-math.pi / 2, math.pi / 2)
unit = st.floats(0.0, 1.0)
rgb = st.tuples(unit, unit, unit)
TOL = math.radians(8.0)


def _off(a: float, b: float) -> float:
    return abs((a - b + math.pi) % (2 * math.pi) - math.pi)


@settings(max_examples=300, deadline=None)
@given(tracks=st.lists(bearing, max_size=6), blobs=st.lists(bearing, max_size=6))
def test_a_torso_is_given_to_a_track_only_when_it_can_be_no_one_elses(tracks, blobs):
    pairs = anchor_torsos(tracks, blobs, TOL)
    assert len({j for j, _ in pairs}) == len(pairs)  # a blob to one track at most
    assert len({i for _, i in pairs}) == len(pairs)  # a track gets one blob at most
    for j, i in pairs:
        assert _off(tracks[i], blobs[j]) <= TOL  # within the tolerance
        # nobody else nearly in line with the blob, no second blob at the track
        assert all(_off(tb, blobs[j]) > 2 * TOL for k, tb in enumerate(tracks) if k != i)
        assert all(_off(tracks[i], b) > TOL for k, b in enumerate(blobs) if k != j)


def test_two_people_nearly_in_line_get_neither_torso():
    assert anchor_torsos([0.0, math.radians(10)], [math.radians(1)], TOL) == []
    assert anchor_torsos([0.0, math.radians(40)], [math.radians(1)], TOL) == [(0, 0)]


@settings(max_examples=300, deadline=None)
@given(a=rgb, b=rgb)
def test_same_clothes_is_symmetric_and_unknown_is_no_evidence(a, b):
    assert same_clothes(a, b) == same_clothes(b, a)
    assert same_clothes(a, a)
    assert same_clothes(a, None) and same_clothes(None, b)
    assert same_clothes(a, b) == (math.dist(a, b) <= AppearanceSpec().differ)


@settings(max_examples=200, deadline=None)
@given(seq=st.lists(rgb, min_size=1, max_size=40))
def test_a_tracks_colour_stays_within_what_the_camera_saw_and_counts_after_min_obs(seq):
    c = Colours()
    for k, x in enumerate(seq):
        c.observe(7, x)
        col = c.colour(7)
        assert (col is None) == (k + 1 < c.spec.min_obs)
        if col is not None:
            for ch in range(3):  # a running mean: never outside the observed range
                seen = [s[ch] for s in seq[: k + 1]]
                assert min(seen) - 1e-9 <= col[ch] <= max(seen) + 1e-9
    c.forget(set())
    assert c.colour(7) is None  # dead tracks are dropped (bounded memory)


def test_the_camera_noise_does_not_split_one_persons_clothes_but_red_and_green_differ():
    import numpy as np

    rng = np.random.default_rng(0)
    green, yellow, red = (0.1, 0.65, 0.2), (0.95, 0.85, 0.1), (0.85, 0.1, 0.1)
    a, b = Colours(), Colours()
    for _ in range(20):  # the camera's colour noise, 0.04 per channel
        a.observe(1, tuple(np.clip(np.array(green) + rng.normal(0, 0.04, 3), 0, 1)))
        b.observe(1, tuple(np.clip(np.array(green) + rng.normal(0, 0.04, 3), 0, 1)))
    assert same_clothes(a.colour(1), b.colour(1))
    assert not same_clothes(a.colour(1), yellow) and not same_clothes(a.colour(1), red)


# ------------------------------------------------------------ one person tracked twice
def _confirmed_tracks(positions):
    from robot.attention.tracker import Track, Tracks

    tr = Tracks()
    for k, (x, y) in enumerate(positions):
        tk = Track(k + 1, [x, y, 0.0, 0.0], [0.01, 0, 0, 0, 0.01, 0, 0, 0.1, 0, 0.1], 0.0)
        tk.confirmed = True
        tr.tracks.append(tk)
    tr._next = len(positions) + 1
    return tr


@settings(max_examples=200, deadline=None)
@given(gap=st.floats(0.0, 1.0), steps=st.integers(1, 30))
def test_two_confirmed_tracks_on_one_spot_for_longer_than_a_crossing_become_one_the_older(gap, steps):
    from robot.attention.tracker import TrackerSpec

    spec = TrackerSpec()
    assume(abs(gap - spec.merge_distance) > 1e-6)  # (not on the rounding edge)
    tr = _confirmed_tracks([(2.0, 0.0), (2.0 + gap, 0.0)])
    twins: set[int] = set()
    for k in range(steps + 1):
        for tk in tr.tracks:
            tk.last_update = 0.1 * k  # both measured every scan
        twins = tr._twins(0.1 * k)
    merged = gap < spec.merge_distance and 0.1 * steps >= spec.merge_time - 1e-9
    assert twins == ({2} if merged else set())  # the younger (id 2) goes, never the older
    tr._twins(0.1 * (steps + 1) + 10.0)
    assert len(tr._together) <= 1  # only pairs of tracks alive and close now are kept


def test_a_track_coasting_unseen_over_someone_else_is_not_their_twin():
    tr = _confirmed_tracks([(2.0, 0.0), (2.05, 0.0)])
    for k in range(40):
        tr.tracks[1].last_update = 0.1 * k  # only the younger is measured: the older coasts over it
        assert tr._twins(0.1 * k) == set()


@settings(max_examples=100, deadline=None)
@given(last=st.floats(0.0, 100.0), later=st.floats(0.0, 10.0))
def test_a_colour_not_seen_again_for_a_while_is_no_evidence(last, later):
    c = Colours()
    for k in range(c.spec.min_obs):
        c.observe(3, (0.1, 0.65, 0.2), last - 0.1 * (c.spec.min_obs - 1 - k))
    fresh = later <= c.spec.fresh
    assert (c.colour(3, last + later) is not None) == fresh
    assert same_clothes(c.colour(3, last + later), (0.95, 0.85, 0.1)) == (not fresh)  # stale: could be anyone


@settings(max_examples=100, deadline=None)
@given(gap=st.floats(0.0, 0.24), back=st.floats(0.0, 0.5), steps=st.integers(1, 30))
def test_a_track_held_by_her_torso_where_another_track_took_her_legs_is_one_person_with_it(gap, back, steps):
    """Her partner track, its legs taken by another track (a child's run coasted onto her), is kept by her
    torso without legs beside it: the two are one person after ``merge_time``, and the older keeps her."""
    from robot.attention.tracker import TrackerSpec

    spec = TrackerSpec()
    assume(abs(gap + back - spec.merge_distance) > 1e-6)  # (not on the rounding edge)
    tr = _confirmed_tracks([(2.0, 0.0), (2.0 + gap, 0.0)])
    tr.tracks[0].last_z = (2.0 - back, 0.0)  # last measured there, then coasted on
    twins: set[int] = set()
    for k in range(steps + 1):
        tr.tracks[1].last_update = 0.1 * k  # the younger has the legs
        tr.support([0], 0.1 * k)  # the older only her torso
        twins = tr._twins(0.1 * k)
    merged = gap + back < spec.merge_distance and 0.1 * steps >= spec.merge_time - 1e-9
    assert twins == ({2} if merged else set())
    assert tr._heir_of == ({2: 1} if merged else {})


def test_the_older_track_takes_over_the_legs_of_its_twin_and_keeps_its_id():
    from robot.attention.legs import PAIR
    from robot.attention.tracker import TrackerSpec

    spec = TrackerSpec()
    tr = _confirmed_tracks([(2.1, 0.0), (2.0, 0.05)])
    old, young = tr.tracks
    old.P = [0.5, 0, 0, 0, 0.5, 0, 0, 0.5, 0, 0.5]  # long without legs
    old.last_z = (2.05, 0.0)
    t = 0.0
    for k in range(int(spec.merge_time / 0.1) + 3):
        t = 0.1 * k
        tr.support([tr.row(1)], t)
        assigned = tr.step(t, [[2.0, 0.05]], [PAIR])
    assert [tk.id for tk in tr.tracks] == [1]
    assert assigned == [0]  # her legs now feed the older track
    assert abs(tr.tracks[0].x[0] - 2.0) < 0.05 and abs(tr.tracks[0].x[1] - 0.05) < 0.05
    assert t - tr.tracks[0].last_update < 1e-9


def test_a_track_held_by_a_torso_far_from_where_it_last_had_legs_is_no_ones_twin():
    """A partner track that coasted (unseen) onto someone else and is held there by that person's torso at
    its bearing: not merged with that person's track, whatever the time."""
    tr = _confirmed_tracks([(2.0, 0.0), (2.05, 0.0)])
    tr.tracks[0].last_z = (1.0, 0.0)  # last had legs a metre away
    for k in range(40):
        tr.tracks[1].last_update = 0.1 * k
        tr.support([0], 0.1 * k)
        assert tr._twins(0.1 * k) == set()
