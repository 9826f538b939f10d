"""The follower's own commands (waiting, backing off, turning to face her) next to the floor plan's
walls and furniture (issue 26 item 2: wedged in door frames and at a table).

:meth:`Follower._swept` makes such a command safe against the mapped obstacles all round (the laser
looks ahead only). Its rule (:func:`robot.navigation.follow.sweep_allowed`): the footprint keeps
``SWEEP_MARGIN`` from them, or, closer already, no pose after the start comes closer than it is.
Before, "further off than now" was measured with the start pose in the sweep, so it never held:
2 cm from the kitchen table's edge, backing straight away was refused and the robot stood there
until its partner was lost (hall_follow_doors).
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import example, given, settings
from hypothesis import strategies as st

from robot.navigation.follow import SWEEP_MARGIN, SWEEP_TIME, TURN_ROOM, Follower, sweep_allowed
from robot.navigation.local import arcs, footprint_distance, sweep_clearance


def _swept(v: float, w: float, mapped: np.ndarray) -> tuple[float, float]:
    return Follower._swept(None, v, w, mapped)  # type: ignore[arg-type]  # uses no state of the follower


def _edge(y0: float, x0: float = -1.0, x1: float = 1.0) -> np.ndarray:
    """A straight obstacle edge (a wall's or a table's) at robot-frame y = y0, as mapped outline points."""
    xs = np.arange(x0, x1 + 1e-9, 0.05)
    return np.column_stack((xs, np.full(len(xs), y0)))


def _closest_after_start(v: float, w: float, pts: np.ndarray, steps: int = 20) -> float:
    """The footprint's smallest distance to ``pts`` along the arc, finely sampled, start excluded."""
    t = np.linspace(SWEEP_TIME / steps, SWEEP_TIME, steps)
    x, y, th = arcs(np.array([v]), np.array([w]), t)
    c, s = np.cos(th[0])[:, None], np.sin(th[0])[:, None]
    dx, dy = pts[None, :, 0] - x[0][:, None], pts[None, :, 1] - y[0][:, None]
    return float(footprint_distance(c * dx + s * dy, -s * dx + c * dy).min())


def test_wedged_two_centimetres_from_a_table_in_front_it_may_back_away():
    # the table's edge 2 cm beyond the front of the footprint, across the robot's heading
    table = _edge(0.0, -1.0, 1.0)[:, ::-1] + np.array([0.255 + 0.02, 0.0])
    assert sweep_clearance(0.0, 0.0, table, 0.0, steps=1) < SWEEP_MARGIN
    v, w = _swept(-0.1, 0.0, table)
    assert v < 0.0  # backing straight away from it: allowed (the old rule refused every command)
    assert _swept(0.1, 0.0, table)[0] <= 0.0  # never on into it


def test_wedged_beside_a_wall_it_may_turn_away_but_not_into_it():
    # a wall 2 cm left of the footprint, alongside: turning left swings the front-left corner into it
    wall = _edge(0.215 + 0.02)
    assert not sweep_allowed(0.0, 0.8, wall)
    assert sweep_allowed(-0.1, 0.0, wall)  # straight back along it: never closer


def test_touching_already_only_standing_is_allowed():
    wall = _edge(0.215)
    assert not sweep_allowed(-0.1, 0.0, wall) and not sweep_allowed(0.0, -0.5, wall)


@settings(max_examples=200, deadline=None)
@given(gap=st.floats(0.001, 0.3), side=st.sampled_from([-1.0, 1.0]), ahead=st.floats(-0.6, 0.6),
       v=st.floats(-0.2, 0.3), w=st.floats(-1.0, 1.0))
# the dev profile's counterexample (a wall's end 2 mm right of the flank; backing while turning left first
# swings the flank 5e-5 m nearer, between the sweep's evenly spaced poses): robot.navigation.follow.SWEEP_START
@example(gap=0.001953125, side=-1.0, ahead=0.49609375, v=-0.1875, w=0.5)
def test_no_command_sweeps_the_footprint_closer_to_the_floor_plan_than_allowed(gap, side, ahead, v, w):
    # a wall (or a jamb: a short piece) beside the robot at any gap, the follower asking any command
    wall = _edge(side * (0.215 + gap), ahead - 0.5, ahead + 0.5)
    here = sweep_clearance(0.0, 0.0, wall, 0.0, steps=1)
    cv, cw = _swept(v, w, wall)
    assert (cv, cw) in ((v, w), (v, 0.0), (0.0, w), (0.0, 0.0))  # only ever less of what was asked
    if (cv, cw) != (0.0, 0.0):
        swept = sweep_clearance(cv, cw, wall, SWEEP_TIME)
        # keeps the margin, or comes no closer than it is (straight edges: the samples see the closest)
        assert swept >= SWEEP_MARGIN - 1e-9 or _closest_after_start(cv, cw, wall) >= here - 1e-6
    if cv < 0.0:  # a back-off leaves room to turn (or takes it further off than it is)
        x = cv * SWEEP_TIME if abs(cw) < 1e-6 else cv / cw * math.sin(cw * SWEEP_TIME)
        y = 0.0 if abs(cw) < 1e-6 else cv / cw * (1.0 - math.cos(cw * SWEEP_TIME))
        after = float(np.hypot(wall[:, 0] - x, wall[:, 1] - y).min())
        assert after >= TURN_ROOM - 1e-9 or after >= float(np.hypot(wall[:, 0], wall[:, 1]).min()) - 1e-9
