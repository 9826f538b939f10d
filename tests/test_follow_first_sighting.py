"""A following robot stands for someone it sees for the first time close ahead (issue 26 item 1: never touch a person).

fresh7/corr_hallway_crossing seed 1 (integ 997c492): Sven leads the robot west along a 1.1 m hallway; the boy Theo
runs out of the kids' room at 1.5 m/s, across the hallway, at the robot. The jamb hides him until the tracker's
first sighting, a tentative track 1.13 m off, 40 deg to the right, with no velocity yet (one measurement). The
contact limit reckoned only with tentative tracks that walk (``People.emerging``), so that scan he did not count;
the follower drove on (0.38 -> 0.47 m/s), braked one scan later and touched him (closest 0.01 m).

Now the follower reckons with a tentative track seen for the first time within 1.5 m ahead of its centre, not
beside anyone already tracked, as running straight at it (``People.newborn``, ``in_the_way(first_seen=True)``)
until its second sighting measures how he moves: it brakes a scan earlier and stands clear.
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from robot.footprint import contact_speed_limit
from robot.navigation.people import NEWBORN_APART, NEWBORN_REACH, NEWBORN_WALK, TENTATIVE_VAR, People, in_the_way

ODOM = (2.85993, -1.54058, 0.04873)  # the robot at 44.1 s (seed 1), odom frame
SVEN = ("t1", 4.598, -1.617, 0.477, -0.020, True, 0.00182)  # the partner, walking on ahead
THEO = ("t4", 3.743, -2.237, 0.0, 0.0, False, 0.0036)  # the boy's first sighting
THEO_2 = ("t4", 3.661, -2.107, -0.604, 0.964, False, 0.00701)  # ... and his second, 0.1 s later


def _tracks(rows, time: float = 0.0) -> etree._Element:
    el = etree.Element("tracks", time=f"{time:.3f}", frame="odom")
    for tid, x, y, vx, vy, confirmed, var in rows:
        etree.SubElement(el, "track", id=tid, x=f"{x:.4f}", y=f"{y:.4f}", vx=f"{vx:.4f}", vy=f"{vy:.4f}",
                         cxx=f"{var:.5f}", cxy="0", cyy=f"{var:.5f}", confirmed="true" if confirmed else "false")
    return el


def _limit(people: People, **kw) -> float:
    return contact_speed_limit(in_the_way(people, ODOM, 0.0, **kw), 0.5, decel=1.0)


def test_the_boy_first_seen_out_of_the_side_door_stops_the_follower():
    people = People()
    people.update(_tracks([SVEN]))
    people.update(_tracks([SVEN, THEO]))
    assert _limit(people) > 0.4  # the go-to's reckoning (and the follower's before): he did not count
    assert _limit(people, first_seen=True, exclude="t1") == 0.0  # the follower's: it stands for him
    people.update(_tracks([SVEN, THEO_2]))  # his second sighting: measured, walking at it (People.emerging)
    assert len(people.newborn(ODOM, 0.0)) == 0
    assert _limit(people, first_seen=True, exclude="t1") == 0.0


def test_a_second_track_on_a_known_person_or_the_partner_found_again_does_not_stop_it():
    people = People()
    people.update(_tracks([SVEN]))
    # a new track 0.3 m from Sven's (his other leg): not a newcomer
    people.update(_tracks([SVEN, ("t5", SVEN[1] - 0.3, SVEN[2], 0.0, 0.0, False, 0.004)]))
    assert len(people.newborn(ODOM, 0.0)) == 0
    # the partner's own track, found again under a new id alone: left out by the follower (exclude)
    people = People()
    people.update(_tracks([]))
    people.update(_tracks([("t9", 3.9, -1.6, 0.0, 0.0, False, 0.004)]))
    assert len(people.newborn(ODOM, 0.0, exclude="t9")) == 0
    assert len(people.newborn(ODOM, 0.0)) == 1


_ROW = st.tuples(st.sampled_from(["t1", "t2", "t3"]), st.floats(-2.5, 2.5), st.floats(-2.5, 2.5),
                 st.floats(-1.0, 1.0), st.floats(-1.0, 1.0), st.booleans(), st.floats(0.0, 0.06))


@settings(max_examples=200, deadline=None)
@given(before=st.lists(_ROW, max_size=3, unique_by=lambda r: r[0]), now=st.lists(_ROW, max_size=3, unique_by=lambda r: r[0]))
def test_only_a_first_sighting_close_ahead_apart_from_others_counts_and_it_always_stops_the_robot(before, now):
    """Robot at the odom origin facing +x. A row of ``People.newborn`` is exactly a tentative, freshly measured
    track whose id the payload before did not hold, ahead of the centre within NEWBORN_REACH and NEWBORN_APART
    from every other track; it runs at the centre at NEWBORN_WALK; and the contact limit stands for it."""
    people = People()
    people.update(_tracks(before))
    people.update(_tracks(now))
    got = people.newborn((0.0, 0.0, 0.0), 0.0)
    old = {r[0] for r in before}

    def rounded(v: float, n: int) -> float:
        return float(f"{v:.{n}f}")

    want = []
    for tid, x, y, _vx, _vy, confirmed, var in now:
        x, y, var2 = rounded(x, 4), rounded(y, 4), 2 * rounded(var, 5)
        d = math.hypot(x, y)
        if (abs(d - NEWBORN_REACH) < 1e-3 or abs(var2 - TENTATIVE_VAR) < 1e-4 or abs(x) < 1e-3
                or any(abs(math.hypot(x - rounded(o[1], 4), y - rounded(o[2], 4)) - NEWBORN_APART) < 1e-3 for o in now if o[0] != tid)):
            return  # knife edges of the payload's rounding
        apart = all(math.hypot(x - rounded(o[1], 4), y - rounded(o[2], 4)) >= NEWBORN_APART for o in now if o[0] != tid)
        if tid not in old and not confirmed and var2 <= TENTATIVE_VAR and x > 0.0 and d <= NEWBORN_REACH and apart and d > 1e-6:
            want.append((x, y))
    assert len(got) == len(want)
    for (x, y), row in zip(want, got):
        assert np.allclose(row[:2], (x, y), atol=1e-6)
        assert math.isclose(math.hypot(row[2], row[3]), NEWBORN_WALK, rel_tol=1e-9)
        assert row[0] * row[2] + row[1] * row[3] < 0.0  # toward the centre
        assert contact_speed_limit(row[None, :], 0.5, decel=1.0) == 0.0
