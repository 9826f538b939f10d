"""The PeopleBot's driving limits and the navigation's tuning, as the robot knows them.

Robot code must not import the world (``homesim.world.bodies`` is the simulated
truth); these are the figures a robot's configuration file would hold, the
same as the base's datasheet. :func:`limits_from_config` lets a run's robot
options (``run.config``: ``max_speed`` m/s, ``max_turn`` rad/s) override them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any


@dataclass(frozen=True)
class Limits:
    """Differential-drive limits (SI units) and the footprint the planners keep clear."""

    max_speed: float = 0.5  # m/s forward
    max_reverse: float = 0.2  # m/s backwards (no laser behind: slowly)
    max_turn: float = math.radians(100)  # rad/s
    max_accel: float = 1.0  # m/s^2
    max_turn_accel: float = math.radians(300)  # rad/s^2
    radius: float = 0.30  # the footprint's inscribed-ish radius used for inflation (0.51 x 0.43 m base)
    reach: float = 0.34  # the footprint's bounding circle (its corners)
    laser_offset: float = 0.13  # the laser is this far ahead of the centre


def limits_from_config(config: Any) -> Limits:
    """Limits with the run's ``max_speed``/``max_turn`` (when given) applied; anything else is ignored."""
    lim = Limits()
    get = config.get if isinstance(config, dict) else (lambda k, d=None: getattr(config, k, d))
    speed, turn = get("max_speed", None), get("max_turn", None)
    if speed is not None:
        lim = replace(lim, max_speed=float(speed))
    if turn is not None:
        lim = replace(lim, max_turn=float(turn))
    return lim
