"""A go-to whose first leg lies behind the robot while a wall stands at its back (open_island_goto seeds 0, 3,
5, 7: just outside the bedroom door after giving way, its centre 0.31 m from the wall): the player turns to a
first leg on the spot (TURN_FIRST), but no turn on the spot keeps the corners off the wall, and it stood
``blocked`` for a minute with the way free. Where the window finds no such turn it arcs round instead."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from robot.navigation.local import HALF_LENGTH
from tests.player_helpers import moving_player


class _Wall:
    """The floor plan round the robot: a straight wall ``gap`` m behind its rear, 4 m long (robot frame)."""

    def __init__(self, gap: float) -> None:
        ys = np.linspace(-2.0, 2.0, 81)
        self.points = np.column_stack((np.full_like(ys, -(HALF_LENGTH + gap)), ys))

    def around(self, pose):  # noqa: ANN001, ANN201
        return self.points


@settings(max_examples=25, deadline=None)
@given(st.floats(0.03, 0.08), st.floats(1.9, 2.6), st.booleans())
def test_with_a_wall_at_its_back_and_the_leg_behind_it_arcs_round_instead_of_standing(gap, off, left):
    angle = off if left else -off
    goal = (3.0 * np.cos(angle), 3.0 * np.sin(angle))
    p = moving_player(goal, 0.0)
    p._facing = True  # a first leg, from where it stood
    p.outline = _Wall(gap)  # type: ignore[assignment]
    cmd = p.control_step()
    assert cmd is not None
    v, w = cmd
    # it moves: forward away from the wall, turning toward the leg's side, never backing into the wall
    assert v > 0.0 and (w > 0.0) == left and w != 0.0


@settings(max_examples=25, deadline=None)
@given(st.floats(0.03, 0.08), st.floats(1.9, 2.6), st.booleans(), st.floats(0.2, 0.65), st.floats(-0.4, 0.4))
def test_arcing_round_it_is_never_faster_than_a_blind_corner_allows(gap, off, left, ahead, side):
    """review14 F2: the arc's speed stays within the blind-corner speed (a door's jamb ahead that someone
    may step out from behind), as every other drive does, and it still moves."""
    from robot.navigation.blind import CRAWL, blind_speed_limit

    angle = off if left else -off
    goal = (3.0 * np.cos(angle), 3.0 * np.sin(angle))
    p = moving_player(goal, 0.2)
    p._facing = True
    p.outline = _Wall(gap)  # type: ignore[assignment]
    corner = np.array([[HALF_LENGTH + ahead, side]])
    p._blind_corners = lambda mapped: corner  # type: ignore[method-assign]
    limit = blind_speed_limit(corner, p.limits.max_speed, decel=p.limits.max_accel)
    assert CRAWL <= limit < 0.2  # below the social speed: only the blind-corner rule holds it back
    cmd = p.control_step()
    assert cmd is not None
    v, w = cmd
    assert 0.0 < v <= limit + 1e-9 and w != 0.0
