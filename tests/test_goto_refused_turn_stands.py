"""A turn on the spot toward the leg that the sonar's blind-half guard refuses leaves the robot standing, and the
player counts it as standing (its stuck timer runs), so the wedged back-off can start from it (review17 F3: goto16
reset the timer on the window's turn before the guard refused it)."""
import math
from types import SimpleNamespace

import numpy as np

from tests.player_helpers import player_standing_at


def test_a_turn_the_sonar_refuses_counts_as_standing():
    # in the open, the first leg 70 degrees to the left; something unexplained heard just behind-left of the rear
    # corner the left turn would swing
    p = player_standing_at(4.6, 1.0, 0.0, (4.6 + math.cos(1.2), 1.0 + math.sin(1.2)), 0.0)
    arc = np.array([(-0.40 + 0.02 * k, 0.33) for k in range(-2, 3)])
    p.sonar = SimpleNamespace(arcs=lambda odom, now: [arc])
    clock = SimpleNamespace(now=10.0)
    p.sim = clock
    sent, stuck = [], []
    for k in range(30):  # 3 s at 10 Hz
        clock.now = 10.0 + 0.1 * k
        sent.append(p.control_step())
        stuck.append(p._stuck_since)
    standing = all(abs(v) < 0.02 and abs(w) < 1e-6 for v, w in sent)
    assert standing, "the probe's premise: the guard refuses the turn and the robot stands"
    assert stuck[-1] is not None and stuck[-1] <= 10.1, "stood 3 s with a refused turn, never counted as standing"
