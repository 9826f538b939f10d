"""The floor plan's walls and furniture as outline points round the robot: the map check where the laser is blind.

The PeopleBot's laser looks forwards only (180 degrees, 0.13 m ahead of the
centre). Turning on the spot, backing off, or passing a door frame or a bed
corner beside it, the footprint's rear corners sweep ground the laser does
not see, and a go-to through a 1.0 m corridor touched furniture there
(issue 26). The map server's floor plan knows what stands there: the outline
of every wall piece and every obstacle the robot cannot pass under, sampled
every :data:`SPACING` m, is handed to the dynamic window with the laser's
echoes, so every arc keeps the footprint off what the map holds all round.
Where the laser sees, it sees the same walls (within the localisation
error, a few centimetres); where it does not, the map is the only guard.
"""

from __future__ import annotations

import math

import numpy as np

from .grid import Plan2D

#: m: spacing of the sample points along each outline (the footprint check is per point).
SPACING = 0.04
#: m: outline points within this box round the robot's centre are handed out (the window looks ~1 m ahead).
NEAR = 1.5


def outline_points(plan: Plan2D, *, spacing: float = SPACING) -> np.ndarray:
    """(N, 2) map-frame points along every polygon's edges, no two further apart than ``spacing``."""
    out = []
    for poly in plan.polygons:
        nxt = np.roll(poly, -1, axis=0)
        for a, b in zip(poly, nxt):
            n = max(int(math.ceil(float(np.hypot(*(b - a))) / spacing)), 1)
            t = np.arange(n)[:, None] / n
            out.append(a + (b - a) * t)
    return np.concatenate(out) if out else np.zeros((0, 2))


class FloorOutline:
    """The floor plan's outline points; :meth:`around` gives those near a pose in its frame."""

    def __init__(self, plan: Plan2D, *, near: float = NEAR) -> None:
        self.points = outline_points(plan)
        self.near = near

    def around(self, pose: tuple[float, float, float]) -> np.ndarray:
        """Outline points within :attr:`near` m (box) of ``pose`` (map frame), in the robot frame, (K, 2)."""
        x, y, th = pose
        dx, dy = self.points[:, 0] - x, self.points[:, 1] - y
        keep = (np.abs(dx) < self.near) & (np.abs(dy) < self.near)
        dx, dy = dx[keep], dy[keep]
        c, s = math.cos(th), math.sin(th)
        return np.column_stack((c * dx + s * dy, -s * dx + c * dy))
