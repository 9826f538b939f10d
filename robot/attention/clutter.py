"""Furniture legs from the a-priori floor plan: where leg-like segments are chairs and tables.

A real robot is given its flat's floor plan (``map_server/map``); raised
furniture (a table, a chair: ``bottom`` above the floor) stands on legs the
laser sees exactly like people's legs, 4-5 cm wide, as close together as a
person's. Leg candidates inside such a footprint (grown by ``margin``) are
furniture, not people. People can stand next to a table but not inside its
footprint (their legs are at least a body radius from its edge), so the
margin stays below that.

Wall pieces too (grown by ``wall_margin``): a door jamb's end, 10 cm of wall
seen end on, is a leg-sized segment, and its centre (pushed back by a leg
radius like every candidate's) lies inside the wall. A confirmed track that
coasted near a door took such a jamb as its person standing still (the
partner's track then stood in the door frame and the robot turned to it,
four_people seed 8). A person's leg centre is at least a leg radius (6 cm) off a
wall's surface, so person attention's leg filter grows the walls by that radius
(``AttentionParams.leg_wall_margin``): the candidates are placed with the robot's map pose,
which is a few centimetres off, and with a 2 cm margin a jamb's end 2 cm inside the wall came
out as a leg in front of it (hall_follow_doors seeds 3 and 8, passage_follow_doors seed 0: the
partner's coasting track jumped onto the jamb and the robot lost her behind it, doors9). A leg
centre nearer a wall than its own radius is the wall's echo, whatever the pose. (The attention's
turn check keeps the footprint's outline off the walls grown by the default 2 cm.)

The candidates are put into the map frame with the robot's pose there: the
localiser's (``/robot/localisation/pose``) when it publishes, else the
start pose of the plan composed with odometry (what the robot was given at
start plus dead reckoning).
"""

from __future__ import annotations

import math

import numpy as np

from robot.floorplan import FloorPlan

#: The side (m) of the grid index's cells. A cell lists the footprints whose bounding box overlaps it,
#: so a point is tested against the few near it, not against every wall piece of the flat.
CELL = 0.5

Footprint = tuple[float, float, float, float, list[tuple[float, float, float]]]


class FurnitureLegs:
    """Convex footprints of raised furniture as half-planes (grown by ``margin``), for an inside test.

    A point is inside a footprint when it lies on the inner side of all of its edges' lines. The
    test runs in plain floats per point (a scan has a handful of leg candidates, a home a few
    dozen edges: numpy's per-call cost is larger than the arithmetic), and only against the
    footprints whose bounding box holds the point. Those are found through a grid index
    (:data:`CELL`): a point's cell lists every footprint whose box could hold it. The cell of a
    coordinate is a monotone function of it, so a box that holds a point overlaps the point's
    cell, and the answer is the one a scan over every footprint gives.
    """

    def __init__(self, plan: FloorPlan, *, margin: float = 0.06, min_bottom: float = 0.05, wall_margin: float = 0.02) -> None:
        self.start = plan.start
        self._footprints: list[Footprint] = []
        polys = [(ob.polygon(), margin) for ob in plan.obstacles if ob.bottom >= min_bottom]
        # furniture standing on the floor (a cabinet, a sofa): its corner seen at an angle is a leg-sized
        # segment whose centre, pushed back by a leg radius, lies inside it (four_people seeds 3 and 5: a
        # cabinet's corner confirmed as a person); nobody stands inside it, so the wall's margin
        polys += [(ob.polygon(), wall_margin) for ob in plan.obstacles if ob.bottom < min_bottom]
        polys += [(w.rectangle(), wall_margin) for w in plan.walls]
        for p, margin in polys:
            x, y = p[:, 0], p[:, 1]
            if float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y)) < 0:
                p = p[::-1]
            e = np.roll(p, -1, axis=0) - p
            n = np.column_stack((e[:, 1], -e[:, 0]))  # outward for a counter-clockwise polygon
            n /= np.linalg.norm(n, axis=1, keepdims=True)
            c = np.einsum("ij,ij->i", n, p) + margin
            # The grown polygon's corners: where consecutive edges' shifted lines meet.
            corners = np.array([np.linalg.solve(np.array([n[i - 1], n[i]]), np.array([c[i - 1], c[i]])) for i in range(len(n))])
            lo, hi = corners.min(axis=0) - 1e-6, corners.max(axis=0) + 1e-6
            edges = [(float(a), float(b), float(cc)) for (a, b), cc in zip(n.tolist(), c.tolist())]
            self._footprints.append((float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1]), edges))
        self.count = len(self._footprints)
        self._index()

    def _index(self) -> None:
        """The grid over the footprints' boxes: for each cell, the footprints (in plan order) whose box overlaps it."""
        fps = self._footprints
        inv = self._inv = 1.0 / CELL
        if not fps:
            self._box = (1.0, 1.0, 0.0, 0.0)  # empty: holds no point
            self._ny = 0
            self._cells: list[list[Footprint]] = []
            return
        ox, oy = min(f[0] for f in fps), min(f[1] for f in fps)
        ex, ey = max(f[2] for f in fps), max(f[3] for f in fps)
        self._box = (ox, oy, ex, ey)
        nx, ny = math.floor((ex - ox) * inv) + 1, math.floor((ey - oy) * inv) + 1
        self._ny = ny
        self._cells = [[] for _ in range(nx * ny)]
        for f in fps:
            x0, y0, x1, y1, _ = f
            for i in range(math.floor((x0 - ox) * inv), math.floor((x1 - ox) * inv) + 1):
                for j in range(math.floor((y0 - oy) * inv), math.floor((y1 - oy) * inv) + 1):
                    self._cells[i * ny + j].append(f)

    def near(self, x: float, y: float) -> list[Footprint] | tuple[()]:
        """The footprints whose box may hold (x, y): those listed in its cell (none outside every box).

        :meth:`inside_points` does the same inline (it runs for every leg candidate and sonar echo)."""
        ox, oy, ex, ey = self._box
        if not (ox <= x <= ex and oy <= y <= ey):
            return ()
        return self._cells[math.floor((x - ox) * self._inv) * self._ny + math.floor((y - oy) * self._inv)]

    def inside(self, xy: np.ndarray) -> np.ndarray:
        """Which map-frame points (K, 2) lie in a (grown) raised-furniture footprint."""
        return np.array(self.inside_points(np.asarray(xy, dtype=float).reshape(-1, 2).tolist()), dtype=bool)

    def inside_points(self, points: list[tuple[float, float]] | list[list[float]]) -> list[bool]:
        """:meth:`inside` for a list of (x, y) map-frame points."""
        out = []
        ox, oy, ex, ey = self._box
        cells, ny = self._cells, self._ny
        inv = self._inv
        for x, y in points:
            hit = False
            # outside every box (also NaN): no footprint holds it; inside, the cell's floors stay in the grid
            near = cells[math.floor((x - ox) * inv) * ny + math.floor((y - oy) * inv)] if ox <= x <= ex and oy <= y <= ey else ()
            for x0, y0, x1, y1, edges in near:
                if x0 <= x <= x1 and y0 <= y <= y1:
                    for a, b, c in edges:
                        if x * a + y * b > c:  # beyond this edge's line: outside this footprint
                            break
                    else:
                        hit = True
                        break
            out.append(hit)
        return out

    def map_pose(self, odom: tuple[float, float, float]) -> tuple[float, float, float]:
        """The start pose composed with an odometry pose (odometry starts at 0, 0, 0 there)."""
        sx, sy, sth = self.start
        x, y, th = odom
        c, s = math.cos(sth), math.sin(sth)
        return sx + c * x - s * y, sy + s * x + c * y, sth + th
