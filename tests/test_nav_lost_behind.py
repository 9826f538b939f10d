"""Someone the tracker lost sight of may stand behind the robot (the laser does not look behind):
the player backs off only when nobody lost from view in the last LOST_MAX s could have walked within
reach (goto_l_flat seed 0: Ben, lost as the robot turned to the door, was touched by a back-off)."""

from __future__ import annotations

import math

from hypothesis import given
from hypothesis import strategies as st
from lxml import etree

from robot.navigation.people import LOST_MAX, WALK, People, maybe_behind


def tracks(t: float, *people: tuple[str, float, float, float]) -> etree._Element:
    xml = etree.Element("tracks", time=f"{t}", frame="odom")
    for tid, x, y, vx in people:
        etree.SubElement(xml, "track", id=tid, x=f"{x}", y=f"{y}", vx=f"{vx}", vy="0", confirmed="true")
    return xml


@given(x=st.floats(-6.0, 6.0), y=st.floats(-6.0, 6.0), speed=st.floats(0.0, 1.5), dt=st.floats(0.0, 14.0),
       reach=st.floats(0.2, 1.5))
def test_someone_lost_from_view_is_maybe_behind_exactly_while_they_could_have_walked_there(x, y, speed, dt, reach):
    people = People()
    people.update(tracks(10.0, ("t1", x, y, speed)))
    people.update(tracks(10.1))  # the track vanished (walking or standing)
    now = 10.1 + dt
    got = maybe_behind(people, (0.0, 0.0, 0.0), now, reach=reach)
    since = now - 10.1  # as the clock has it (10.1 + 10.0 - 10.1 is a hair over 10.0)
    expected = since <= LOST_MAX and math.hypot(x, y) <= reach + WALK * since
    assert got == expected


def test_a_person_seen_again_is_no_longer_lost_and_a_tracked_one_never_was():
    people = People()
    people.update(tracks(0.0, ("t1", -0.8, 0.0, 0.9), ("t2", 3.0, 0.0, 0.0)))
    assert not maybe_behind(people, (0.0, 0.0, 0.0), 0.0, reach=1.0)
    people.update(tracks(0.1, ("t2", 3.0, 0.0, 0.0)))
    assert maybe_behind(people, (0.0, 0.0, 0.0), 0.5, reach=1.0)
    people.update(tracks(0.2, ("t1", -0.8, 0.0, 0.0), ("t2", 3.0, 0.0, 0.0)))
    assert not maybe_behind(people, (0.0, 0.0, 0.0), 0.5, reach=1.0)
    people.clear()
    assert not people.lost
