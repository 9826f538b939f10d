"""After "stop" the robot comes up to her facing her before her next request (issue 26 item 10; face20).

face19_stop_past_opening and fresh8/lflat_crossing_pair: the catch-up ended just past an opening, close to her;
the step aside out of the opening turned her to 85-95 deg, and every turn back to her was refused by the sonar
check: a flank transducer heard her legs beside the robot's front across its cone, and that arc runs on round
the flank, where a swung corner comes within the blind half's gap. Her request was handled with her at its side.

Now: (1) her legs, seen by the laser ahead of its line near her track, explain such a reading, as a wall of the
floor plan explains one; an echo nowhere near her seen legs is still kept clear of. (2) Giving way at the
catch-up's end keeps her within 60 deg (ahead of the laser's line), turning to her first when further off.
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from robot.navigation.follow import APPROACH_VIEW, BLIND_X, GIVE_WAY_BEARING, Follower


class _Scan:
    def __init__(self, pts: np.ndarray) -> None:
        self.pts = pts

    def points(self) -> np.ndarray:
        return self.pts

    def sees_through(self, x: float, y: float) -> bool:
        return False


def _follower(*, legs: list[tuple[float, float]], her: tuple[float, float] | None, arcs: list[np.ndarray]) -> Follower:
    f = Follower.__new__(Follower)
    f.odom, f.sim = (0.0, 0.0, 0.0), SimpleNamespace(now=5.0)
    f.partner_id = "t1"
    f.track = None if her is None else {"x": her[0], "y": her[1], "vx": 0.0, "vy": 0.0, "t": 5.0}
    f.scan = _Scan(np.array(legs, dtype=float).reshape(-1, 2))
    f.sonar = SimpleNamespace(arcs=lambda odom, now: list(arcs))
    f.route = SimpleNamespace(obstacles_near=lambda odom: np.zeros((0, 2)))
    f.people = SimpleNamespace(around=lambda *a, **k: np.zeros((0, 3)))
    f.limits = SimpleNamespace(max_turn=math.radians(100), max_speed=0.5)
    return f


def _flank_arc(r: float) -> np.ndarray:
    """The arc the left flank transducer (at the front corner, facing left) gives for a reading of ``r`` m:
    across its 30 deg cone, from ahead of the laser's line round to beside the footprint."""
    a = np.radians(np.linspace(75.0, 105.0, 5))
    return np.column_stack((0.1 + r * np.cos(a), 0.22 + r * np.sin(a)))


def test_her_legs_seen_explain_the_flank_reading_so_the_turn_to_her_is_not_refused():
    arc = _flank_arc(0.42)  # her near leg heard across the cone: points at x 0.21 .. -0.01, y ~0.63
    legs = [(0.2, 0.62), (0.33, 0.72)]  # the laser sees her legs ahead of its line
    f = _follower(legs=legs, her=(0.3, 0.75), arcs=[arc])
    assert f._blind_clear(0.0, 1.75)  # turning to her: her own legs, seen, are the reading
    # the same reading with nobody seen there (someone beside it, out of the laser's view): the turn is refused
    f = _follower(legs=[], her=(0.3, 0.75), arcs=[arc])
    assert not f._blind_clear(0.0, 1.75)
    # legs seen there, but her track elsewhere (someone else's legs): not hers, the reading stands
    f = _follower(legs=legs, her=(2.0, -1.0), arcs=[arc])
    assert not f._blind_clear(0.0, 1.75)
    f = _follower(legs=legs, her=None, arcs=[arc])
    assert not f._blind_clear(0.0, 1.75)


@settings(max_examples=150, deadline=None)
@given(bx=st.floats(-0.6, BLIND_X - 0.01), by=st.floats(0.3, 0.9), side=st.sampled_from([1.0, -1.0]),
       w=st.sampled_from([1.75, -1.75, 0.8, -0.8]), hx=st.floats(0.2, 1.5), hy=st.floats(-1.2, 1.2))
def test_an_echo_far_from_her_seen_legs_is_kept_clear_of_as_before(bx, by, side, w, hx, hy):
    """Her legs explain only a reading whose arc passes near them: an arc 0.15 m or more from every echo the laser
    sees near her is refused exactly as without her."""
    arc = np.array([(bx + 0.02 * k, side * by) for k in range(-2, 3)])
    legs = [(hx - 0.1, hy), (hx + 0.1, hy)]
    her_legs = [p for p in legs if p[0] >= BLIND_X]
    if her_legs and min(math.hypot(p[0] - a[0], p[1] - a[1]) for p in her_legs for a in arc) < 0.15:
        return
    with_her = _follower(legs=legs, her=(hx, hy), arcs=[arc])
    alone = _follower(legs=[], her=None, arcs=[arc])
    assert with_her._blind_clear(0.0, w) == alone._blind_clear(0.0, w)


class _Stepped(Exception):
    """The give-way went on to its step aside (the dynamic window reads the scan first)."""


class _StepScan(_Scan):
    def points(self) -> np.ndarray:
        raise _Stepped


def _giving_way(bearing_deg: float, view: float) -> tuple[float, float] | None:
    f = _follower(legs=[], her=None, arcs=[])
    b = math.radians(bearing_deg)
    px, py = 0.85 * math.cos(b), 0.85 * math.sin(b)
    f.route = SimpleNamespace(ready=True, obstacles_near=lambda odom: np.zeros((0, 2)), clearance=lambda p: 0.3)
    # a give-way spot chosen (its way leads off to the right, away from her)
    f._aside = ([(0.3, -0.2), (0.8, -0.9)], 100.0, False)
    f._leave_aside = False  # a give-way for her standing there, not one that makes way for her walking out (give24b)
    f.scan = _StepScan(np.zeros((0, 2)))
    try:
        return f._give_way(px, py, np.zeros((0, 2)), view=view)
    except _Stepped:
        return None


def test_giving_way_after_the_catch_up_keeps_her_ahead_of_the_laser_line():
    # she stands at 70 deg: following, the step aside goes on (within 80 deg); after the catch-up it turns to her first
    assert math.radians(70) < GIVE_WAY_BEARING and math.radians(70) > APPROACH_VIEW
    v, w = _giving_way(70.0, APPROACH_VIEW)
    assert v == 0.0 and w > 0.0  # on the spot, toward her (left)
    v, w = _giving_way(-70.0, APPROACH_VIEW)
    assert v == 0.0 and w < 0.0
    assert _giving_way(70.0, GIVE_WAY_BEARING) is None  # following: the step aside
    assert _giving_way(40.0, APPROACH_VIEW) is None  # within view: the step aside, not the turn to her
