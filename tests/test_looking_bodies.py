"""A body with its back to the camera is someone: the voice search does not turn away from it.

wlan_reorder: Ben calls "Hello BIRON" with his back to the robot as he steps out from behind a
sideboard. The camera sees his torso but no frontal face; counting that direction as "looked at,
nobody there" turned the robot round to the mirrored reading behind it while he spoke, and the
greeting was lost.
"""

from __future__ import annotations

import math

from hypothesis import given, settings
from hypothesis import strategies as st

from robot.attention.looking import LookedAt, angle_between

HALF = math.radians(25)
TOL = math.radians(10)


@settings(max_examples=200, deadline=None)
@given(st.floats(-math.pi, math.pi), st.floats(-HALF, HALF), st.floats(0.0, 5.0))
def test_a_torso_in_view_makes_its_direction_not_empty(centre, offset, t):
    looked = LookedAt()
    body = centre + offset
    looked.observe(t, centre, HALF, [], TOL)  # no frontal face anywhere in the frame
    looked.bodies(t, [body], TOL)  # but a torso
    assert not looked.empty_since(body, t)
    assert looked.body_since(body, t)


@settings(max_examples=200, deadline=None)
@given(st.floats(-math.pi, math.pi), st.floats(-HALF, HALF), st.floats(math.radians(30), math.pi))
def test_a_torso_elsewhere_leaves_an_empty_direction_empty(centre, offset, away):
    looked = LookedAt()
    looked.observe(1.0, centre, HALF, [], TOL)
    here = centre + offset
    looked.bodies(1.0, [here + away], TOL)
    assert angle_between(here, here + away) > TOL
    assert looked.empty_since(here, 1.0)


def test_a_body_seen_before_a_later_empty_look_does_not_hold_the_direction():
    looked = LookedAt()
    looked.bodies(1.0, [0.0], TOL)
    looked.observe(3.0, 0.0, HALF, [], TOL)  # she walked off: looked again, nobody
    assert looked.empty_since(0.0, 2.0)
