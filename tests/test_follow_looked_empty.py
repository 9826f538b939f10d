"""A partner's predicted point, or a coasting track, that the laser looks at and sees through is no body
(issue 26 item 1; flow/follow_while_looking as flowfix13 wrote it, 9d2dc38, seeds 0 and 8).

She walked past the robot's side and on behind it; her coasting track's prediction stood 0.6 m beside
it, in the laser's view, where the scan showed nothing. The follower searched at that point and its
turn toward where she went was refused for that predicted body (libflow14). Now a body the latest scan
looks at and sees through refuses no turn, and the search looks where her last measured velocity took
her from where she was last seen.
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from robot.navigation.follow import Follower
from robot.navigation.local import LatestScan, looked_empty

# --- a partner's predicted point the laser sees through is no body (flow/follow_while_looking, 9d2dc38 seed 8)

MIN_ANGLE, RES, OFFSET, N = -math.pi / 2, math.radians(0.5), 0.13, 361


@settings(max_examples=200, deadline=None)
@given(dist=st.floats(0.4, 6.0), bearing=st.floats(-1.5, 1.5), far=st.floats(0.0, 1.0), blocked=st.booleans())
def test_a_disc_is_looked_empty_exactly_when_in_view_and_every_beam_across_it_reaches_beyond(dist, bearing, far, blocked):
    x, y = OFFSET + dist * math.cos(bearing), dist * math.sin(bearing)
    ranges = np.full(N, dist + 0.25 + 0.01 + far)  # every beam past the disc's far side
    half = math.asin(min(1.0, 0.25 / dist))
    in_view = dist > 0.30 and bearing - half / 2 >= MIN_ANGLE and bearing + half / 2 <= MIN_ANGLE + RES * (N - 1)
    if blocked:  # a leg echo inside the disc, on the beam nearest its centre
        i = int(round((bearing - MIN_ANGLE) / RES))
        if 0 <= i < N and abs(MIN_ANGLE + RES * i - bearing) <= half:
            ranges[i] = dist
        else:
            blocked = False
    got = looked_empty(ranges, MIN_ANGLE, RES, OFFSET, x, y, 0.25)
    assert got == (in_view and not blocked)


def test_a_body_behind_the_laser_is_never_looked_empty():
    ranges = np.full(N, 8.0)  # nothing in front at all
    assert not looked_empty(ranges, MIN_ANGLE, RES, OFFSET, -0.8, 0.1)  # behind it: the laser does not look there
    assert not looked_empty(ranges, MIN_ANGLE, RES, OFFSET, 0.0, 0.7)  # straight beside its centre: half out of view
    assert not looked_empty(ranges, MIN_ANGLE, RES, OFFSET, 0.13, 0.4)  # straight beside the laser: its middle out of view
    assert looked_empty(ranges, MIN_ANGLE, RES, OFFSET, 0.7, -0.5)  # in front, beside: looked at, nobody


def test_a_turn_is_not_refused_for_a_predicted_body_the_laser_sees_through():
    f = Follower.__new__(Follower)
    f.odom, f.sim = (0.0, 0.0, 0.0), SimpleNamespace(now=1.0)
    f.people = SimpleNamespace(around=lambda odom, now: np.zeros((0, 3)))
    f.scan = LatestScan()
    msg = SimpleNamespace(xml=etree.Element("scan", min_angle=str(math.degrees(MIN_ANGLE)), resolution="0.5",
                                            max_range="8.0", offset=str(OFFSET)),
                          attachments={"ranges": np.full(N, 4.0)})
    f.scan.update(msg)
    assert len(f._bodies(0.3, -0.55)) == 0  # her stale prediction 0.6 m beside it, the laser sees 4 m there
    msg.attachments["ranges"] = np.full(N, 0.5)  # something 0.5 m off all round the front: she may be it
    assert len(f._bodies(0.3, -0.55)) == 1
    assert len(f._bodies(-0.6, 0.0)) == 1  # behind it: never dropped
