"""Furniture legs from the a-priori floor plan: where leg-like segments are chairs and tables.

A real robot is given its flat's floor plan (``map_server/map``); raised
furniture (a table, a chair: ``bottom`` above the floor) stands on legs the
laser sees exactly like people's legs, 4-5 cm wide, as close together as a
person's. Leg candidates inside such a footprint (grown by ``margin``) are
furniture, not people. People can stand next to a table but not inside its
footprint (their legs are at least a body radius from its edge), so the
margin stays below that.

The candidates are put into the map frame with the robot's pose there: the
localiser's (``/robot/localisation/pose``) when it publishes, else the
start pose of the plan composed with odometry (what the robot was given at
start plus dead reckoning).
"""

from __future__ import annotations

import math

import numpy as np

from robot.floorplan import FloorPlan


class FurnitureLegs:
    """Convex footprints of raised furniture as half-planes, for a vectorised inside test."""

    def __init__(self, plan: FloorPlan, *, margin: float = 0.06, min_bottom: float = 0.05) -> None:
        self.start = plan.start
        normals, offsets, owner = [], [], []
        for k, ob in enumerate(o for o in plan.obstacles if o.bottom >= min_bottom):
            p = ob.polygon()
            x, y = p[:, 0], p[:, 1]
            if float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y)) < 0:
                p = p[::-1]
            e = np.roll(p, -1, axis=0) - p
            n = np.column_stack((e[:, 1], -e[:, 0]))  # outward for a counter-clockwise polygon
            n /= np.linalg.norm(n, axis=1, keepdims=True)
            normals.append(n)
            offsets.append(np.einsum("ij,ij->i", n, p) + margin)
            owner.append(np.full(len(p), k))
        self.count = len(normals)
        self.n = np.concatenate(normals) if normals else np.zeros((0, 2))
        self.c = np.concatenate(offsets) if offsets else np.zeros(0)
        self.owner = np.concatenate(owner) if owner else np.zeros(0, dtype=int)

    def inside(self, xy: np.ndarray) -> np.ndarray:
        """Which map-frame points (K, 2) lie in a (grown) raised-furniture footprint."""
        if self.count == 0 or xy.shape[0] == 0:
            return np.zeros(xy.shape[0], dtype=bool)
        outside_edge = (xy @ self.n.T) > self.c[None, :]  # (K, E): beyond an edge's line
        out = np.zeros((xy.shape[0], self.count), dtype=bool)
        np.logical_or.at(out.T, self.owner, outside_edge.T)
        return ~out.all(axis=1)

    def map_pose(self, odom: tuple[float, float, float]) -> tuple[float, float, float]:
        """The start pose composed with an odometry pose (odometry starts at 0, 0, 0 there)."""
        sx, sy, sth = self.start
        x, y, th = odom
        c, s = math.cos(sth), math.sin(sth)
        return sx + c * x - s * y, sy + s * x + c * y, sth + th
