"""A go-to whose first leg lies a little to one side while someone stands close beside and behind the robot's other
side (fresh5/stair_names_snug seeds 0, 2: Hanne stood 0.64 m off its right flank after "Stop there"; the leg
through the utility door lay 30 degrees to its left). The window's turn on the spot swings the rear corner
toward her body, which the sonar hears in the laser's blind half, so the guard stopped it; it stood
``blocked`` until it asked for help, with the way ahead free. Now it arcs forward onto the leg, away from her,
as gently as the guard needs, and never toward what the sonar hears."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from robot.blindside import BLIND_X, blind_clear, blind_points
from robot.navigation.player import SWEEP_TIME
from tests.player_helpers import moving_player


def _heard(p, x: float, y: float) -> None:  # noqa: ANN001
    """A sonar echo of a body at (x, y) (robot frame at the origin: the odometry frame here), fresh now."""
    side = np.linspace(-0.1, 0.1, 5)
    p.sonar._latest[0] = (p.now, np.column_stack((x + side, np.full(5, y))))


@settings(max_examples=25, deadline=None)
@given(st.floats(0.42, 0.6), st.floats(-0.15, 0.05), st.floats(math.radians(20), math.radians(55)), st.booleans())
def test_someone_close_behind_its_flank_it_arcs_onto_the_leg_away_from_them(side, x, off, left):
    # the leg off to one side, the body heard beside-behind the other flank
    angle = off if left else -off
    y = -side if left else side
    p = moving_player((3.0 * math.cos(angle), 3.0 * math.sin(angle)), 0.0)
    p._facing = True  # a first leg, from where it stood
    _heard(p, x, y)
    cmd = p.control_step()
    assert cmd is not None
    v, w = cmd
    # it moves forward (away from her flank, never backing or swinging toward her), turning toward the leg's
    # side no faster than the guard allows
    assert v > 0.0 and w * angle >= 0.0
    arcs = p.sonar.arcs((0.0, 0.0, 0.0), p.now)
    assert all(x < BLIND_X for x in np.concatenate(arcs)[:, 0])  # the echo is the sonar's alone (blind half)
    assert blind_clear(v, w, blind_points(arcs, lambda arc: False), duration=SWEEP_TIME)


def test_with_nobody_heard_it_turns_on_the_spot_to_a_first_leg_as_before():
    p = moving_player((3.0 * math.cos(0.8), 3.0 * math.sin(0.8)), 0.0)
    p._facing = True
    v, w = p.control_step()
    assert v == 0.0 and w > 0.0
