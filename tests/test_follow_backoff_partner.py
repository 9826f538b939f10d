"""Backing off from a partner too close never reverses into her (fresh12 defect 12, issue 26 items 1, 9:
ring_long_tour seed 3, Vera walked past the robot's side within the band's near end; the follower backed
straight off while her lagging estimate still said "close in front", and the footprint came within 0.03 m
of her as she passed behind it). Backing is allowed only while she is ahead, within 60 degrees of its
heading (``robot.navigation.follow.back_off_away``); beside or behind it, it stands and turns to her."""

from __future__ import annotations

import math

from hypothesis import given, settings
from hypothesis import strategies as st

from robot.navigation.follow import BACK_OFF_BEARING, back_off_away


@settings(max_examples=300, deadline=None)
@given(d=st.floats(0.3, 1.5), bearing=st.floats(-math.pi, math.pi), step=st.floats(0.01, 0.3),
       lag=st.floats(0.0, math.radians(30)))
def test_whenever_it_may_back_off_backing_takes_it_away_from_her_even_if_her_bearing_lags(d, bearing, step, lag):
    """Allowed at her estimated bearing, backing ``step`` m straight increases the distance to where she
    really is, even when the estimate lags her true bearing by up to 30 degrees either way."""
    rx, ry = d * math.cos(bearing), d * math.sin(bearing)
    if not back_off_away(rx, ry):
        assert abs(bearing) > BACK_OFF_BEARING - 1e-9
        return
    for true in (bearing + lag, bearing - lag):
        tx, ty = d * math.cos(true), d * math.sin(true)
        assert math.hypot(tx + step, ty) > math.hypot(tx, ty)


@given(d=st.floats(0.3, 1.5), bearing=st.floats(math.pi / 2, math.pi))
def test_beside_or_behind_it_never_backs_toward_her(d, bearing):
    for b in (bearing, -bearing):
        assert not back_off_away(d * math.cos(b), d * math.sin(b))
