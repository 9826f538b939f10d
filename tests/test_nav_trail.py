"""The partner's trail the follower steers along (issue 26 item 2, hall_follow_doors).

Points of the trail the robot is already past (where she walked while it stood wedged, approached
or gave way; predicted points while she was unseen) must not be steered back to: in the study door
a stale point in the hall turned the robot away from her, then into her.
"""

from __future__ import annotations

import math
from collections import deque

from hypothesis import given, settings
from hypothesis import strategies as st

from robot.navigation.follow import Follower


def _follower(pose: tuple[float, float, float], trail: list[tuple[float, float]]) -> Follower:
    f = Follower.__new__(Follower)  # _trim_trail reads only the pose and the trail
    f.odom = pose
    f.trail = deque(trail, maxlen=200)
    return f


def test_a_stale_point_behind_the_robot_is_not_steered_back_to_with_her_ahead():
    # the robot at (2, 0) facing +x; the trail still holds where she walked in the hall behind it
    trail = [(0.0, 0.5), (0.5, 0.3), (1.0, 0.0), (3.0, 0.0), (3.5, 0.0), (4.0, 0.0)]
    f = _follower((2.0, 0.0, 0.0), trail)
    rx, _ = f._to_robot(*trail[-1])
    f._trim_trail(rx)
    assert list(f.trail) == [(3.0, 0.0), (3.5, 0.0), (4.0, 0.0)]


def test_the_trail_round_a_corner_ahead_is_kept():
    # she went round a corner ahead: the robot comes up to it, every point is still before it
    trail = [(1.0, 0.0), (2.0, 0.0), (2.0, 1.0), (2.0, 2.0)]
    f = _follower((0.0, 0.0, 0.0), trail)
    f._trim_trail(2.0)
    assert list(f.trail) == trail


_pt = st.tuples(st.floats(-5, 5), st.floats(-5, 5))


@settings(max_examples=300, deadline=None)
@given(trail=st.lists(_pt, min_size=1, max_size=30), pose=st.tuples(st.floats(-5, 5), st.floats(-5, 5),
                                                                  st.floats(-math.pi, math.pi)))
def test_trimming_keeps_her_latest_point_and_drops_only_a_prefix(trail, pose):
    f = _follower(pose, trail)
    rx, _ = f._to_robot(*trail[-1])
    f._trim_trail(rx)
    kept = list(f.trail)
    assert kept and kept[-1] == trail[-1]  # her latest point is never dropped
    assert kept == trail[len(trail) - len(kept):]  # only points she walked before (a prefix) go
    if len(kept) > 1:
        first = f._to_robot(*kept[0])
        assert math.hypot(*first) >= 0.6  # the point steered at is not within reach
        assert rx <= 0.0 or first[0] >= 0.0  # with her ahead, never a point behind the robot
        # nothing kept before the point nearest the robot (pure pursuit) but when it was dropped for reach
        near = [math.hypot(*f._to_robot(*p)) for p in trail]
        assert len(trail) - len(kept) >= near.index(min(near)) or len(trail) <= 2
