"""SeenGround: the ground a robot without a rear sensor may back over (laser seen free, echoes and the unseen never)."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings, strategies as st

from robot.navigation.seen import SeenGround, footprint_samples


def _wall_scan(sx: float, sy: float, th: float, wall_x: float, n: int = 181):
    """A 180-degree scan from (sx, sy) heading ``th`` of a wall along x = wall_x (max range 8 m)."""
    a = th + np.linspace(-math.pi / 2, math.pi / 2, n)
    with np.errstate(divide="ignore"):
        r = np.where(np.cos(a) > 1e-6, (wall_x - sx) / np.cos(a), 8.0)
    return np.minimum(r, 8.0), -math.pi / 2, math.pi / (n - 1)


@settings(max_examples=60, deadline=None)
@given(st.floats(-20, 20), st.floats(-20, 20), st.floats(-0.6, 0.6), st.floats(1.0, 3.0), st.floats(-0.5, 0.5))
def test_between_the_sensor_and_a_wall_is_free_the_wall_and_beyond_it_never(sx, sy, th, gap, dy):
    g = SeenGround()
    r, a0, res = _wall_scan(sx, sy, th, sx + gap)
    g.add(r, a0, res, 8.0, (sx, sy, th), stride=1)
    assert g.clear([sx + 0.5 * gap], [sy + dy])  # straight ahead, half way: seen free
    assert not g.clear([sx + gap + 0.02], [sy + dy])  # the wall's cell (an echo)
    assert not g.clear([sx + gap + 0.5], [sy + dy])  # behind the wall: never seen
    assert not g.clear([sx - 0.5], [sy])  # behind the sensor: never seen


def test_unseen_ground_is_never_clear_and_what_was_seen_survives_the_window_moving():
    g = SeenGround()
    assert not g.clear([0.0], [0.0])
    r, a0, res = _wall_scan(0.0, 0.0, 0.0, 2.0)
    g.add(r, a0, res, 8.0, (0.0, 0.0, 0.0), stride=1)
    assert g.clear([1.0], [0.0])
    # the robot drives 4 m on: the window follows it, the first scan's free ground is kept
    g.add(np.full(181, 8.0), a0, res, 8.0, (4.0, -3.0, math.pi / 2), stride=1)
    assert g.clear([1.0], [0.0])
    # far away: the old ground falls out of the window (constant memory) and is unknown again
    g.add(np.full(181, 8.0), a0, res, 8.0, (40.0, 0.0, 0.0), stride=1)
    assert not g.clear([1.0], [0.0])
    assert g.grid.shape == (100, 100)


def test_footprint_samples_cover_the_rectangle():
    xs, ys = footprint_samples(1.0, 2.0, math.pi / 2, length=0.5, width=0.4, margin=0.0)
    assert math.isclose(min(ys), 1.75) and math.isclose(max(ys), 2.25)
    assert math.isclose(max(xs), 1.2) and math.isclose(min(xs), 0.8)
