"""A search for a lost partner ends on evidence, not on a clock set when she went out of view (issue 26
item 10, fresh7 corr_fast_walker_goto: a leader at 1.3 m/s went through a door 6 m ahead of a 0.45 m/s robot
and stopped in the next room; the search ran out while the robot still drove along the hallway toward that
door). The time the robot spends on its way to where it looks for her, further than ``CLOSING_NEAR`` and
coming nearer, is not search time (``robot.partner_search.Closing``), for the follower's search and the
attention's ``partner_lost`` alike (the attention reads the follower's distances from its status)."""

from __future__ import annotations

import math

from hypothesis import example, given, settings
from hypothesis import strategies as st
from lxml import etree

from robot.partner_search import CLOSING_CAP, CLOSING_NEAR, CLOSING_SPEED, Closing, follow_search_time

from tests.test_follow_reacquire import SEEN, _following


class _Msg:
    def __init__(self, t: float, **attrs: str) -> None:
        self.created, self.xml = t, etree.Element("follow", **attrs)


@settings(max_examples=150, deadline=None)
@given(st.lists(st.tuples(st.floats(0.01, 1.5), st.floats(0.0, 12.0)), min_size=1, max_size=60))
@example([(1.3461107644248524, 2.0), (1.0, 0.0)])
def test_only_time_spent_coming_nearer_from_afar_is_not_counted_and_never_more_than_elapsed_or_the_cap(steps):
    """Whatever the distances: the time not counted never exceeds the time elapsed (nor the cap), and a step
    counts exactly when it came at least CLOSING_SPEED nearer per second from beyond CLOSING_NEAR."""
    c, t, expected, last = Closing(), 0.0, 0.0, None
    for step, d in steps:
        dt = (t + step) - t  # the step as the clock's times give it (1.346 + 1.0 - 1.346 is 1.0000000000000002)
        t += step
        before = c.total
        c.update(t, d)
        gained = c.total - before
        if last is not None and dt <= 1.0 and last[1] > CLOSING_NEAR and last[1] - d >= CLOSING_SPEED * dt:
            expected = min(CLOSING_CAP, expected + dt)
        assert math.isclose(c.total, expected, abs_tol=1e-9)
        assert gained <= dt + 1e-12
        last = (t, d)
    assert c.total <= min(t, CLOSING_CAP) + 1e-9


def test_standing_where_it_looks_or_driving_away_the_clock_runs():
    c = Closing()
    for k in range(50):  # stands 0.8 m from the point (it is there, looking): every second counts
        c.update(k * 0.1, 0.8)
    assert c.total == 0.0
    for k in range(50):  # driving away from it
        c.update(5.0 + k * 0.1, 2.0 + 0.04 * k)
    assert c.total == 0.0
    c.reset()
    for k in range(51):  # 6 m away, driving there at 0.4 m/s for 5 s
        c.update(10.0 + k * 0.1, 6.0 - 0.04 * k)
    assert math.isclose(c.total, 5.0, abs_tol=1e-9)


def test_the_attention_does_not_declare_her_lost_while_the_follower_drives_to_where_she_went():
    """She was last seen 4 m ahead walking 1.3 m/s; the follower drives to where it looks for her at 0.4 m/s
    (its status: searching, distance shrinking from 7 m). The loss waits for the time it drove, and comes
    when it has stood there as long as the search allows."""
    a = _following([], SEEN)
    a._partner_last = (SEEN, 4.0, 0.0, 1.3, 0.0, 0.0, 0.0)
    a._closing, a._yielded, a._driven, a._drive_start = Closing(), 0.0, 0.0, None
    a._follow_waiting = a._follow_searching = None
    search = follow_search_time(4.0, base=a.params.follow_lost_after, top_speed=a.params.robot_top_speed, pace=1.3)
    t, d = SEEN, 7.0
    while d > 0.6:  # on its way: 16 s at 0.4 m/s
        a._on_follow_status(_Msg(t, state="searching", distance=f"{d:.4f}"))
        t, d = t + 0.1, d - 0.04
    assert t - SEEN > search  # longer than the search time on main
    assert not a.partner_left(t)
    arrived = t
    while not a.partner_left(t):
        a._on_follow_status(_Msg(t, state="searching", distance="0.6000"))
        t += 0.1
    closed = a._closing.total
    assert closed > 0.0
    assert math.isclose(t - SEEN - closed, search, abs_tol=0.25)  # the search proper: from when it came there
    assert t - arrived <= search


def test_without_the_follower_on_its_way_the_loss_comes_as_on_main():
    a = _following([], SEEN)
    a._partner_last = (SEEN, 4.0, 0.0, 1.3, 0.0, 0.0, 0.0)
    a._closing, a._yielded, a._driven, a._drive_start = Closing(), 0.0, 0.0, None
    search = follow_search_time(4.0, base=a.params.follow_lost_after, top_speed=a.params.robot_top_speed, pace=1.3)
    assert not a.partner_left(SEEN + search - 0.05)
    assert a.partner_left(SEEN + search + 0.05)
