"""A leader faster than the robot when last seen is searched for longer (issue 26 item 10; follow17,
tests/scenarios/follow/fast_leader_into_library): the gap she opens in 4 s more, capped as every search."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

@settings(max_examples=200, deadline=None)
@given(st.floats(0.0, 8.0), st.floats(0.0, 2.0), st.floats(0.0, 2.0))
def test_a_leader_faster_than_the_robot_is_searched_for_longer_never_shorter(distance, pace, faster):
    from robot.partner_search import SEARCH_BASE, SEARCH_CAP, SEARCH_SPEED, follow_search_time
    slow = follow_search_time(distance, pace=min(pace, SEARCH_SPEED))
    assert slow == follow_search_time(distance)  # no faster than the robot: the rule as before
    fast = follow_search_time(distance, pace=pace + faster)
    assert SEARCH_BASE <= slow <= fast <= SEARCH_CAP


def test_a_fast_leader_last_seen_2_6_m_ahead_is_searched_for_until_the_next_room():
    # fast_leader_into_library seed 0: last seen 2.58 m ahead walking 1.2 m/s; the robot (0.4 m/s
    # searching) was still 1.2 m short of the library door when the 8.7 s search ran out
    from robot.partner_search import follow_search_time
    assert follow_search_time(2.58) < 9.0
    assert follow_search_time(2.58, pace=1.2) >= 14.0
