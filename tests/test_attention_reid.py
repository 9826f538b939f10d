"""Re-identification of a person found again (issue 26 item 1): a track just confirmed takes the id of
the one dormant track (kept while its person was hidden) whose person it could be, by the
reacquisition rule (where they were last measured, their clothes). Back in view, a person is the
same track, not a new one: no identity switch; two candidates decide nothing."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from robot.attention.appearance import Colours
from robot.attention.fsm import AttentionFSM
from robot.attention.module import AttentionParams, PersonAttention
from robot.attention.tracker import Track, Tracks, TrackerSpec

GREEN, RED = (0.1, 0.65, 0.2), (0.85, 0.1, 0.1)


def _attention(dormant: list[tuple[float, float]], new: tuple[float, float], t: float = 10.0) -> PersonAttention:
    """Dormant tracks 1.. last measured at ``dormant`` at t=5 (odom), a track just confirmed at ``new`` at ``t``."""
    a = PersonAttention.__new__(PersonAttention)
    a.params = AttentionParams()
    a.fsm = AttentionFSM()
    a.tracks = Tracks(TrackerSpec())
    a.colours = Colours()
    for k, (x, y) in enumerate(dormant):
        tk = Track(k + 1, [x, y, 0.0, 0.0], [1.0, 0, 0, 0, 1.0, 0, 0, 0.1, 0, 0.1], 0.0)
        tk.confirmed, tk.dormant, tk.last_seen, tk.last_z = True, True, 5.0, (x, y)
        a.tracks.tracks.append(tk)
    tk = Track(99, [new[0], new[1], 0.0, 0.0], [0.01, 0, 0, 0, 0.01, 0, 0, 1.0, 0, 1.0], t - 0.3)
    tk.confirmed = True
    a.tracks.tracks.append(tk)
    a.tracks.confirmed_now = [99]
    a.partner, a._partner_last, a._partner_colour = None, None, None
    return a


def test_a_bystander_back_in_view_where_he_stood_keeps_his_id():
    a = _attention([(3.4, 1.0)], (3.45, 0.9))
    assigned = a._reidentify(10.0, [1, -1])  # candidate 0 fed row 1 (the new track)
    assert [tk.id for tk in a.tracks.tracks] == [1] and assigned == [0, -1]


def test_someone_far_from_where_anyone_went_out_of_view_is_new():
    a = _attention([(3.4, 1.0)], (7.0, 1.0))
    a._reidentify(10.0, [1])
    assert sorted(tk.id for tk in a.tracks.tracks) == [1, 99]


def test_two_dormant_candidates_decide_nothing():
    a = _attention([(3.4, 1.0), (3.6, 1.4)], (3.5, 1.2))
    a._reidentify(10.0, [2])
    assert sorted(tk.id for tk in a.tracks.tracks) == [1, 2, 99]


def test_other_clothes_are_someone_else():
    a = _attention([(3.4, 1.0)], (3.45, 0.9))
    for k in range(3):
        a.colours.observe(1, GREEN, 4.0 + 0.1 * k)
        a.colours.observe(99, RED, 9.7 + 0.1 * k)
    a._reidentify(10.0, [1])
    assert sorted(tk.id for tk in a.tracks.tracks) == [1, 99]


def test_the_partner_found_again_stays_the_partner():
    a = _attention([(9.4, 3.7)], (9.6, 4.6))
    a.partner, a._partner_last, a._partner_colour = 1, (5.0, 9.4, 3.7, 0.0, 0.5, 7.0, 2.4), RED
    a._reidentify(10.0, [])
    assert [tk.id for tk in a.tracks.tracks] == [1] and a.partner == 1


@settings(max_examples=150, deadline=None)
@given(dx=st.floats(-3, 3), dy=st.floats(-3, 3), unseen=st.floats(0.0, 20.0))
def test_taken_exactly_within_the_reacquisition_radius(dx, dy, unseen):
    """Without colours: the new track takes the dormant id iff it lies within reacquire_radius plus
    reacquire_speed per second unseen (at most 2.5 m) of where the dormant person was last measured."""
    a = _attention([(2.0, 0.0)], (2.0 + dx, dy), t=5.0 + unseen)
    a._reidentify(5.0 + unseen, [])
    p = a.params
    radius = min(2.5, p.reacquire_radius + p.reacquire_speed * unseen)
    d = math.hypot(dx, dy)
    if abs(d - radius) > 1e-6:
        assert ([tk.id for tk in a.tracks.tracks] == [1]) == (d <= radius)


def test_adopt_keeps_the_new_state_under_the_old_id():
    tr = Tracks()
    tr._birth(0.0, np.array([[1.0, 0.0], [1.2, 0.1]]), np.array([0.01, 0.01]))
    assert tr.adopt(2, 1) == 0
    assert [tk.id for tk in tr.tracks] == [1] and tr.tracks[0].x[0] == 1.2
    assert tr.adopt(5, 1) == -1 and tr.adopt(1, 1) == -1
