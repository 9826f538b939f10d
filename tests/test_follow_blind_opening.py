"""The follower passes an opening it cannot see into at a speed it can stand from (issue 26's hard line).

fresh7 corr_hallway_crossing (4 contacts in 10 runs on main): the robot follows its partner west along a
1.1 m hallway at 0.45 m/s; a boy runs out of a side door across the hallway; the door's jamb hides him
until he is 0.6-0.7 m ahead, already in the robot's lane, and no braking from 0.45 m/s stops it in time.
The follower (following, approaching, searching), in a passage, now caps its speed where the scan shows a
corner of the floor plan ahead of its front that it cannot see round (robot/navigation/blind.py,
``follow_blind_limit``): whoever steps out there at up to ``FOLLOW_WALK`` is never reached by the moving robot.
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from robot.footprint import BODY, HALF_LENGTH, HALF_WIDTH, footprint_distance
from robot.navigation.blind import FOLLOW_CRAWL, FOLLOW_GAP, FOLLOW_REACT, FOLLOW_WALK, follow_blind_limit

DECEL = 1.0
TOP = 0.5
DT = 0.02  # the simulation's fine step
PERIOD = 0.1  # the follower's control period


def _air(rx: float, px: float, py: float) -> float:
    """Air between the footprint (centre at (rx, 0), heading +x) and a body centred at (px, py)."""
    return float(footprint_distance(np.array([px - rx]), np.array([py]))[0]) - BODY


@settings(max_examples=150, deadline=None)
@given(cx=st.floats(0.6, 4.0), lateral=st.floats(0.335, 1.5), side=st.sampled_from((-1.0, 1.0)),
       walk=st.floats(0.2, FOLLOW_WALK), heading=st.floats(-math.pi, math.pi), t_out=st.floats(0.0, 8.0),
       v0=st.floats(0.0, TOP))
def test_someone_stepping_out_of_an_opening_is_never_reached(cx, lateral, side, walk, heading, t_out, v0):
    """Closed loop: the robot drives along +x at its cap (re-reckoned every control period from the opening's
    corner, as long as the corner is ahead of its front); an opening beside its way (a door of a hallway
    ``lateral`` m of air beside its flank: a 1.1 m hallway leaves 0.335 m) hides someone who steps out at the
    corner at any moment, walking at up to FOLLOW_WALK in any direction toward its side of the way. Seen,
    the robot brakes after FOLLOW_REACT s at its deceleration. While it moves it never touches them (once it
    stands, someone who walks on into it is not reached by it). Someone stepping out beside its flank or behind
    it walks into its side: no speed but standing helps there, so the test ends when its front passes the corner."""
    cy = side * (HALF_WIDTH + lateral)
    ux, uy = math.cos(heading), math.sin(heading)
    assume(uy * side < -0.2)  # out of the opening, toward the robot's way
    cap0 = follow_blind_limit(np.array([[cx, cy]]), TOP, decel=DECEL)
    v = min(v0, cap0)
    rx, t, cmd = 0.0, 0.0, v
    seen_at = None
    px = py = math.nan
    steps_per_period = round(PERIOD / DT)
    for k in range(int(12.0 / DT)):
        if seen_at is None and t >= t_out:
            if cx - rx <= HALF_LENGTH:
                return  # its front passed the corner unmet
            seen_at = t  # they step out: their body's edge at the corner
            px, py = cx - BODY * ux, cy - BODY * uy
        if k % steps_per_period == 0:
            if seen_at is not None and t - seen_at >= FOLLOW_REACT - 1e-9:
                cmd = 0.0
            elif cx - rx > HALF_LENGTH:
                cmd = follow_blind_limit(np.array([[cx - rx, cy]]), TOP, decel=DECEL)
            else:
                cmd = TOP
        v = max(cmd, v - DECEL * DT) if cmd < v else min(cmd, v + DECEL * DT)
        rx += v * DT
        t += DT
        if seen_at is not None:
            px, py = px + walk * ux * DT, py + walk * uy * DT
            if v > 1e-9:
                assert _air(rx, px, py) > 0.0, (rx, v, px, py, t - seen_at)
            else:
                return  # it stands


def test_far_from_openings_and_past_them_it_is_not_slowed():
    """No corner, or only corners level with or behind its front or far off: the full speed (following at normal
    distance)."""
    assert follow_blind_limit(np.zeros((0, 2)), TOP, decel=DECEL) == TOP
    assert follow_blind_limit(np.array([[-0.1, 0.55]]), TOP, decel=DECEL) == TOP
    assert follow_blind_limit(np.array([[HALF_LENGTH - 0.01, 0.55]]), TOP, decel=DECEL) == TOP
    assert follow_blind_limit(np.array([[2.0, 1.0]]), TOP, decel=DECEL) == TOP


def test_a_side_door_of_a_hallway_slows_it_only_near_the_door():
    """A door in the wall of a 1.1 m hallway (0.335 m of air beside its flank): a metre before the jamb it drives
    at its top speed; just before its front reaches the jamb it is slowed (below 0.35 m/s) but never stands or
    crawls there (it must get past, keeping up with its partner); the closer the corner, never the faster."""
    lateral = HALF_WIDTH + 0.335
    far = follow_blind_limit(np.array([[HALF_LENGTH + 1.0, lateral]]), TOP, decel=DECEL)
    near = follow_blind_limit(np.array([[HALF_LENGTH + 0.02, lateral]]), TOP, decel=DECEL)
    assert far == TOP
    assert 0.2 <= near < 0.35
    caps = [follow_blind_limit(np.array([[x, lateral]]), TOP, decel=DECEL) for x in np.linspace(2.0, HALF_LENGTH + 0.01, 40)]
    assert all(b <= a + 1e-9 for a, b in zip(caps, caps[1:]))
    # through a 0.9 m door it drives through (jambs 0.235 m beside its flanks): slowly, but on
    assert FOLLOW_CRAWL <= follow_blind_limit(np.array([[HALF_LENGTH + 0.05, HALF_WIDTH + 0.235]]), TOP, decel=DECEL) < 0.25
    assert FOLLOW_GAP > 0.0
