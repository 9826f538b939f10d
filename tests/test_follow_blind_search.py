"""Searching for a lost partner, the follower slows round a corner it cannot see behind, and that slowing
is not search time (issue 26 item 2; fresh/u_catch_up_slow seeds 4, 9).

Cora's "Stop" was not heard from the next room; her script turned her back round the U's corner toward
the robot, which was searching at its top speed, 0.3 m/s. Her track first appeared 0.85 m off, and the
robot touched her (one contact in each run, on main too). The go-to already drives no faster than it can
stop from round such a corner (robot/navigation/blind.py); the search now does too. Applied alone
(c497cc1) that cap made the search slower but not longer, and both runs lost her earlier. The time the
cap takes off the search (:func:`robot.partner_search.held_time`: driving at the capped speed, only
the time the full speed would have needed for the same way counts) is now subtracted from the
follower's clock and, through its status (``held``), from the attention's.
"""

from __future__ import annotations

from types import SimpleNamespace

from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from homesim.message import Message
from robot.navigation.follow import Follower
from robot.partner_search import follow_search_time, held_time
from tests.test_follow_reacquire import SEEN, _following

speeds = st.floats(min_value=0.0, max_value=1.0, allow_nan=False)


@settings(max_examples=200, deadline=None)
@given(dt=st.floats(min_value=0.0, max_value=2.0, allow_nan=False), capped=speeds,
       full=st.floats(min_value=0.05, max_value=1.0, allow_nan=False))
def test_the_search_counts_only_the_time_its_full_speed_needed_for_the_way_driven(dt, capped, full):
    held = held_time(dt, capped, full)
    assert 0.0 <= held <= dt
    if capped >= full:
        assert held == 0.0  # not slowed: every second is search time
    else:
        # the way driven at the capped speed took (dt - held) s at the full speed
        assert abs((dt - held) * full - dt * capped) < 1e-9


def _follower() -> Follower:
    f = Follower.__new__(Follower)
    f.sim = SimpleNamespace(now=0.0)
    f._held, f._held_t, f._capped = 0.0, None, None
    return f


def test_the_follower_does_not_count_time_slowed_at_a_blind_corner_and_forgets_it_when_she_is_seen():
    f = _follower()
    for k in range(41):  # 4 s searching, capped to 0.12 m/s of its 0.3
        f.sim.now = k * 0.1
        f._count_held(approaching=False, seen=False)
        f._capped = (0.12, 0.3)
    assert abs(f._held - 4.0 * (1.0 - 0.12 / 0.3)) < 1e-6
    f.sim.now += 0.1
    f._count_held(approaching=False, seen=False)  # a step not capped (the corner is behind it now)
    before = f._held
    f.sim.now += 0.1
    f._count_held(approaching=False, seen=False)
    assert f._held == before
    f._capped = (0.12, 0.3)
    f.sim.now += 0.1
    assert f._count_held(approaching=False, seen=True) == 0.0  # she is seen: a new search starts from nothing


def _status(held: float | None, t: float) -> Message:
    el = etree.Element("follow", distance="1.0", speed="0.1", at_limit="false", state="searching")
    if held is not None:
        el.set("held", f"{held:.3f}")
    return SimpleNamespace(xml=el, created=t)


def test_the_attention_waits_as_long_as_the_follower_was_held_back_at_blind_corners():
    a = _following([], SEEN)
    a._yielded, a._driven, a._drive_start = 0.0, 0.0, None
    search = follow_search_time(2.0, base=a.params.follow_lost_after, top_speed=a.params.robot_top_speed)
    a._on_follow_status(_status(None, SEEN + search - 1.0))
    assert a.partner_left(SEEN + search + 0.1)  # not held back: lost when the search time is over
    a._on_follow_status(_status(2.5, SEEN + search - 1.0))
    assert not a.partner_left(SEEN + search + 2.0)  # held back 2.5 s: still searching 2 s later
    assert a.partner_left(SEEN + search + 2.6)
    a._on_follow_status(_status(None, SEEN + search + 2.7))  # she was seen by the follower: nothing held
    assert a._follow_held == 0.0
