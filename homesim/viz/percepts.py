"""What a robot believed at one moment, as plain data in the world frame (for drawing over the truth).

:class:`Percepts` holds the laser scan, the detected legs
(laser end points near a track), the person tracks with their ids and
covariances, the faces the camera saw, the selected person and the partner,
the attention state, the sound directions, and the robot's own pose
estimate. Tracks come in the ``odom`` frame; :func:`odom_to_world` places
them in the world frame through the robot's true pose and its odometry at
that moment (``world <- base <- odom``), which is what a viewer wants: where
the robot thought the people were, over where they were. Which bus messages
fill a :class:`Percepts` is the run package's business
(:mod:`homesim.tour.percepts`); this needs ground truth and is for plots only.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class Track:
    """One person track in the world frame: id, position, 2x2 covariance, flags."""

    id: str
    x: float
    y: float
    cov: np.ndarray
    confirmed: bool
    speaking: bool


@dataclass
class Percepts:
    """The robot's view at one moment, world frame (empty fields: not known yet)."""

    scan: tuple[np.ndarray, np.ndarray] | None = None  # robot-frame bearings (rad), ranges (m)
    sound_bearings: list[float] = field(default_factory=list)  # robot frame, radians
    tracks: list[Track] = field(default_factory=list)
    faces: list[tuple[float, float]] = field(default_factory=list)  # world x, y of each face seen
    selected: str | None = None
    partner: str | None = None
    attention: str | None = None
    estimate: tuple[float, float, float] | None = None  # the localiser's pose (map = world frame)


def odom_to_world(true_pose: Sequence[float], odom_pose: Sequence[float]) -> np.ndarray:
    """The 3x3 homogeneous transform taking odom-frame points to the world (world <- base <- odom)."""

    def h(x: float, y: float, th: float) -> np.ndarray:
        c, s = math.cos(th), math.sin(th)
        return np.array([[c, -s, x], [s, c, y], [0.0, 0.0, 1.0]])

    return h(*true_pose) @ np.linalg.inv(h(*odom_pose))
