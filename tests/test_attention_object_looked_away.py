"""In Object the camera looks at what she shows, not at her: that look away is no evidence she left (gen23).

Generated tours 9100-11 and 9100-16 (main 7c02cc4): the partner stood within 1-2 m of the robot where the laser
could not tell her legs from the furniture beside her (behind an armchair, against a shelf), her track living on
her face; she showed an object, the robot's camera turned to where she pointed, asked her to step aside, and
10 s later (``out_of_view_after``) said "You left, so I will look around" in the middle of its own search.
Time in Object does not count towards that out-of-view clause; the clause runs again, from naught, once the
camera is back on her, and a partner last seen walking away is still lost after ``partner_lost_after``.
"""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from tests.test_attention_other_clothes import _interacting


def _scans(a, tid: int, t0: float, t1: float, seen: bool, dt: float = 0.1) -> list[float]:
    """Scans from ``t0`` to ``t1``, her track seen (renewed) or not; the times partner_lost went out."""
    lost, t = [], t0
    tk = next(k for k in a.tracks.tracks if k.id == tid)
    while t < t1 - 1e-9:
        if seen:
            tk.last_seen = tk.last_update = t
        before = len(a.events)
        a._top_down(t, {tid: 1})
        lost += [t for name, _ in a.events[before:] if name == "partner_lost"]
        t += dt
    return lost


def test_unseen_while_the_camera_looks_at_her_object_she_is_waited_for_then_looked_for_again():
    a, tid = _interacting()
    assert _scans(a, tid, 0.0, 5.0, seen=True) == []
    a.fsm.order("focus_object")
    # 20 s of search with her out of the camera's view (twice out_of_view_after): no "You left"
    assert _scans(a, tid, 5.0, 25.0, seen=False) == []
    assert a.partner == tid
    a.fsm.order("interact")
    # back in Interaction the camera looks at her again: gone after out_of_view_after of that, not at once
    lost = _scans(a, tid, 25.0, 40.0, seen=False)
    limit = a.params.out_of_view_after
    assert len(lost) == 1 and 25.0 + limit - 0.15 <= lost[0] <= 25.0 + limit + 0.15


def test_in_interaction_the_out_of_view_clause_is_unchanged():
    a, tid = _interacting()
    _scans(a, tid, 0.0, 5.0, seen=True)
    lost = _scans(a, tid, 5.0, 20.0, seen=False)
    assert len(lost) == 1 and abs(lost[0] - (5.0 + a.params.out_of_view_after)) <= 0.15


def test_last_seen_walking_away_during_object_she_is_still_lost():
    a, tid = _interacting()
    tk = next(k for k in a.tracks.tracks if k.id == tid)
    _scans(a, tid, 0.0, 5.0, seen=True)
    a.fsm.order("focus_object")
    tk.x[2], tk.x[3] = 0.6, 0.0  # walking straight away from the robot (it stands at the origin facing +x)
    _scans(a, tid, 5.0, 5.15, seen=True)
    lost = _scans(a, tid, 5.2, 12.0, seen=False)
    assert len(lost) == 1 and lost[0] <= 5.1 + a.params.partner_lost_after + 0.3


@settings(max_examples=30, deadline=None)
@given(st.floats(0.0, 30.0), st.floats(0.0, 16.0))
def test_lost_exactly_when_the_time_unseen_outside_object_reaches_the_limit(in_object, after):
    """Whatever the time the search took, she is lost when, and only when, the time unseen with the camera free
    to look at her reaches ``out_of_view_after`` (within a scan either side)."""
    a, tid = _interacting()
    _scans(a, tid, 0.0, 5.0, seen=True)
    a.fsm.order("focus_object")
    assert _scans(a, tid, 5.0, 5.0 + in_object, seen=False) == []
    a.fsm.order("interact")
    lost = _scans(a, tid, 5.0 + in_object, 5.0 + in_object + after, seen=False)
    limit = a.params.out_of_view_after
    if after < limit - 0.2:
        assert lost == []
    elif after > limit + 0.2:
        assert len(lost) == 1
