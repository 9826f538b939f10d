"""The too-fast warning (issue 26 item 10): the robot says she walks too fast only when she walks
faster than it can drive (its top speed is a scenario value), not when she walks at its top speed
and the gap grows on a turn or in a door frame (hall_follow_doors: "Please slow down" to a partner
at 0.5 m/s behind a robot whose top speed is 0.5 m/s)."""

from __future__ import annotations

import math
from collections import deque
from types import SimpleNamespace

from hypothesis import given, settings
from hypothesis import strategies as st

from robot.navigation.config import Limits
from robot.navigation.follow import TOO_FAST_RATIO, Follower


def _follower(max_speed: float) -> tuple[Follower, list[float]]:
    f = Follower.__new__(Follower)  # _too_fast reads only these
    warned: list[float] = []
    clock = SimpleNamespace(now=0.0)
    f.sim = clock
    f.bus = SimpleNamespace(publish=lambda ch, el: warned.append(clock.now))
    f.limits = Limits(max_speed=max_speed)
    f.too_fast_time, f.too_fast_distance, f.warn_every = 1.0, 2.0, 5.0
    f._limit_since, f._history, f._warned_at = None, deque(maxlen=64), -math.inf
    return f, warned


def _walk(f: Follower, speeds: list[float], gap_rate: float, d0: float = 2.2) -> None:
    for i, v in enumerate(speeds):  # 10 Hz, at the speed limit all along, the gap growing
        f.sim.now = 0.1 * i
        f._too_fast(d0 + gap_rate * 0.1 * i, True, v)


def test_a_partner_at_the_robots_top_speed_is_not_told_to_slow_down():
    f, warned = _follower(0.5)
    _walk(f, [0.5] * 30 + [0.6] * 30, gap_rate=0.1)  # the gap grows (turns, a door frame); she walks at
    # 0.5 m/s, her track a little faster once it found her again
    assert warned == []


def test_a_partner_faster_than_the_robot_is_told_so():
    f, warned = _follower(0.3)
    _walk(f, [0.8] * 60, gap_rate=0.5)
    assert warned and warned[0] >= 1.0  # after a second at the limit
    assert all(b - a >= 5.0 for a, b in zip(warned, warned[1:]))


@settings(max_examples=200, deadline=None)
@given(top=st.floats(0.2, 1.0), speeds=st.lists(st.floats(0.0, 2.0), min_size=1, max_size=80),
       gap_rate=st.floats(-0.5, 1.0))
def test_a_warning_always_follows_a_second_of_her_walking_faster_than_the_robot(top, speeds, gap_rate):
    f, warned = _follower(top)
    _walk(f, speeds, gap_rate)
    for t in warned:
        i = round(t / 0.1)
        window = [v for j, v in enumerate(speeds[: i + 1]) if 0.1 * i - 0.1 * j <= 1.0]  # as the follower keeps it
        assert t >= 1.0 - 1e-9  # a second at the limit first
        assert sum(window) / len(window) > top * TOO_FAST_RATIO  # she was faster than it can drive
        assert gap_rate > 0.0  # and the gap was growing
