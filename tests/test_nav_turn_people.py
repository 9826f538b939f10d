"""A turn on the spot is judged per person: someone else close by never makes a turn into a body clear."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from robot.navigation.local import turn_clear

body = st.tuples(st.floats(0.0, 1.2), st.floats(-math.pi, math.pi)).map(lambda rb: (rb[0] * math.cos(rb[1]), rb[0] * math.sin(rb[1])))


@settings(max_examples=300, deadline=None)
@given(w=st.floats(-1.75, 1.75).filter(lambda w: abs(w) > 1e-3), a=body, others=st.lists(body, min_size=1, max_size=3))
def test_adding_people_never_makes_a_turn_clear(w, a, others):
    """Monotone in the people: clear with everyone implies clear with each alone."""
    if turn_clear(w, np.array([a, *others]), duration=0.6):
        assert turn_clear(w, np.array([a]), duration=0.6)
        assert all(turn_clear(w, np.array([o]), duration=0.6) for o in others)


def test_a_man_beside_the_robot_blocks_a_turn_toward_him_whoever_stands_on_it():
    """cross_studio_four seed 0: a track lying on the robot (0.3 m) made a turn into Lou (0.52 m, 22
    degrees right, held up beside it) clear; turning left swings the front right corner into him."""
    lou = (0.52 * math.cos(-0.39), 0.52 * math.sin(-0.39))
    assert not turn_clear(1.5, np.array([lou]), duration=0.6)
    assert not turn_clear(1.5, np.array([(0.26, 0.2), lou]), duration=0.6)
