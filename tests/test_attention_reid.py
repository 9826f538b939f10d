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


# ------------------------------------------------- following: the partner found again on her way on
def _following(new: tuple[float, float], *, state: str = "Follow", velocity: tuple[float, float] = (0.8, 0.0),
               t: float = 10.0, dormant: bool = True) -> PersonAttention:
    """The partner (track 1) last measured at (2, 0) at t=5 walking at ``velocity``, now dormant (or dead),
    and a track just confirmed at ``new`` (first seen there) at ``t``; the attention in ``state``."""
    a = _attention([(2.0, 0.0)] if dormant else [], new, t=t)
    a.fsm.state = state
    a.partner, a._partner_last, a._partner_colour = 1, (5.0, 2.0, 0.0, velocity[0], velocity[1], 0.0, 0.0), None
    return a


def test_following_a_faster_partner_she_is_taken_back_where_she_walked_on_to():
    """u_catch_up_slow seed 0: Cora (0.8 m/s) went out of view ahead of a 0.3 m/s robot and was seen
    again 4 m on along her way 5 s later; the old rule (2.5 m round where she disappeared) made her a
    stranger and the robot lost her while it saw her."""
    a = _following((6.1, 0.3))
    a._reidentify(10.0, [])
    assert [tk.id for tk in a.tracks.tracks] == [1] and a.partner == 1  # the dormant track adopted
    b = _following((6.1, 0.3), dormant=False)  # her track died: the reacquisition takes the new one
    assert b._reacquire(10.0) == 0 and b.partner == 99


def test_her_way_on_is_only_for_a_partner_who_leads():
    # in Interaction she stepped aside, she did not lead: only the radius round where she was
    a = _following((6.1, 0.3), state="Interaction")
    a._reidentify(10.0, [])
    assert sorted(tk.id for tk in a.tracks.tracks) == [1, 99]
    # standing (her velocity only noise) or someone behind her, where she did not go: not her
    for v, p in (((0.1, 0.0), (6.1, 0.3)), ((0.8, 0.0), (-2.5, 0.0))):
        b = _following(p, velocity=v, dormant=False)
        assert b._reacquire(10.0) == -1 and b.partner == 1


@settings(max_examples=200, deadline=None)
@given(dx=st.floats(-6, 8), dy=st.floats(-4, 4), vx=st.floats(-1.2, 1.2), vy=st.floats(-1.2, 1.2),
       unseen=st.floats(0.0, 20.0))
def test_following_taken_exactly_within_the_radius_of_her_way_on(dx, dy, vx, vy, unseen):
    """Following, without colours: the new track takes her id iff it lies within the reacquisition
    radius (reacquire_radius + reacquire_speed per s unseen, at most 2.5 m) of the segment from where she
    was last measured to where her last velocity carried her in the time unseen (at most 15 s), or of that
    point alone when she stood (slower than leave_speed)."""
    a = _following((2.0 + dx, dy), velocity=(vx, vy), t=5.0 + unseen)
    a._reidentify(5.0 + unseen, [])
    p = a.params
    radius = min(2.5, p.reacquire_radius + p.reacquire_speed * unseen)
    h = min(unseen, 15.0) if math.hypot(vx, vy) >= p.leave_speed else 0.0
    s = np.linspace(0.0, 1.0, 4001)  # dense points on her way: the reference distance
    d = float(np.min(np.hypot(dx - s * vx * h, dy - s * vy * h)))
    if abs(d - radius) > 0.01:
        assert ([tk.id for tk in a.tracks.tracks] == [1]) == (d <= radius)
