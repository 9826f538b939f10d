"""Giving way, the follower never drives toward someone already nearer than the social gap (issue 26 item 10;
review17 F4: follow/stops_beside_shelf seed 1 crept forward past the partner standing at a shelf 0.1-0.2 m off its
side, 0.124 m of air while moving, because "no nearer than now" let a sweep that kept that small gap through)."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from robot.footprint import BODY, HALF_LENGTH, HALF_WIDTH, SOCIAL_GAP
from robot.navigation.follow import Follower, _crowds

NO_ECHOES = np.zeros((0, 2))


def _gap(x: float, y: float) -> float:
    return math.hypot(max(abs(x) - HALF_LENGTH, 0.0), max(abs(y) - HALF_WIDTH, 0.0)) - BODY


# a body beside the robot and a little ahead of its centre (her at a shelf beside it), within the social gap
_close_ahead = st.tuples(st.floats(0.02, 0.5), st.floats(0.45, 0.68), st.sampled_from((-1.0, 1.0))).map(
    lambda t: (t[0], t[1] * t[2])).filter(lambda p: 0.0 <= _gap(*p) < SOCIAL_GAP)


@settings(max_examples=80, deadline=None)
@given(_close_ahead, st.floats(0.05, 0.35), st.floats(-1.5, 1.5))
def test_giving_way_it_stands_rather_than_drive_toward_her_within_the_social_gap(her, v, w):
    f = Follower.__new__(Follower)
    assert _crowds(v, np.array([her]))
    assert f._aside_clear(v, w, np.array([her]), NO_ECHOES) == (0.0, 0.0)


@settings(max_examples=80, deadline=None)
@given(_close_ahead, st.floats(0.05, 0.2))
def test_backing_away_from_her_or_turning_on_the_spot_is_not_crowding(her, v):
    # she is ahead of its centre: reversing goes away from her; turning on the spot drives toward nobody
    assert not _crowds(-v, np.array([her]))
    assert not _crowds(0.0, np.array([her]))


def test_someone_ahead_beyond_the_social_gap_is_no_reason_to_stand():
    far = np.array([(1.2, 0.0)])  # 0.7 m of air straight ahead
    assert not _crowds(0.2, far)
    f = Follower.__new__(Follower)
    assert f._aside_clear(0.2, 0.0, far, NO_ECHOES) == (0.2, 0.0)
