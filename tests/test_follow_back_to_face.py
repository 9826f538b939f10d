"""Giving way with the partner beside it and no room to turn on the spot (face19, fresh8/lflat_crossing_pair
seed 7): the turn to keep her in view was refused (the sonar heard the partition end where a corner would
swing), and the robot stood 8 s sideways to her; her next request was handled at 68 deg. Now it backs
slowly while turning to her, where backing is allowed; otherwise it stands as before."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from robot.navigation.follow import BACK_TO_FACE, SWEEP_TIME
from robot.navigation.local import TURN_GAP, SOCIAL_GAP
from tests.test_nav_aside_people import _gaps, _stepping_aside


def _beside(d: float, bearing: float, *, may_back: bool, sonar_refuses_spot_turn: bool):
    hx, hy = d * math.cos(bearing), d * math.sin(bearing)
    f = _stepping_aside((hx, hy), (0.8, -0.6), 0.0, 0.0, None)
    f.can_back_off = lambda: may_back  # type: ignore[method-assign]
    f._blind_clear = lambda v, w: not (sonar_refuses_spot_turn and v == 0.0 and w != 0.0)  # type: ignore[method-assign]
    return f, (hx, hy)


def test_sideways_to_her_with_the_spot_turn_refused_it_backs_while_turning_to_her():
    f, (hx, hy) = _beside(0.77, math.radians(89), may_back=True, sonar_refuses_spot_turn=True)
    v, w = f._give_way(hx, hy, np.zeros((0, 2)))
    assert v == -BACK_TO_FACE and w >= 0.0  # back (turning left toward her where no corner swings into her)


def test_where_it_may_not_back_it_stands():
    f, (hx, hy) = _beside(0.77, math.radians(89), may_back=False, sonar_refuses_spot_turn=True)
    assert f._give_way(hx, hy, np.zeros((0, 2))) == (0.0, 0.0)


def test_with_room_to_turn_it_turns_on_the_spot_as_before():
    f, (hx, hy) = _beside(0.9, math.radians(-100), may_back=True, sonar_refuses_spot_turn=False)
    v, w = f._give_way(hx, hy, np.zeros((0, 2)))
    assert v == 0.0 and w < 0.0


@settings(max_examples=200, deadline=None)
@given(d=st.floats(0.55, 1.0), bearing=st.floats(math.radians(81), math.radians(179)),
       side=st.sampled_from([1.0, -1.0]), may_back=st.booleans(), refused=st.booleans())
def test_the_turn_to_her_never_sweeps_into_her(d, bearing, side, may_back, refused):
    """Whatever her place beside or behind it: the command keeps the swept footprint TURN_GAP from her
    (turning on the spot) or SOCIAL_GAP (backing), or no nearer than now; backing only where it may."""
    f, (hx, hy) = _beside(d, side * bearing, may_back=may_back, sonar_refuses_spot_turn=refused)
    v, w = f._give_way(hx, hy, np.zeros((0, 2)))
    if v < 0.0:
        assert may_back
    g = _gaps(v, w, np.array([(hx, hy)]), SWEEP_TIME)[:, 0]
    gap = TURN_GAP if v == 0.0 else SOCIAL_GAP
    assert g.min() >= min(g[0], gap) - 2e-3
