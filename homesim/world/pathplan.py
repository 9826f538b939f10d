"""Paths around obstacles for scripted people: an occupancy grid and A*.

The grid covers the flat at ``cell`` metres; a cell is blocked when its
centre lies inside a wall or a piece of furniture, or closer to one than
the walker's ``clearance``. A* (8-connected, octile costs, ties broken by
insertion order so paths are deterministic) finds a cell path, which is
then shortened by line-of-sight smoothing over the grid. Doors are just
gaps in the walls, so paths go through them when they are wide enough.
"""

from __future__ import annotations

import heapq
import math

import numpy as np

from .geometry import distance_points_segments, points_in_polygon, polygon_edges

Point = tuple[float, float]

_MOVES = ((1, 0, 1.0), (-1, 0, 1.0), (0, 1, 1.0), (0, -1, 1.0), (1, 1, math.sqrt(2)), (1, -1, math.sqrt(2)), (-1, 1, math.sqrt(2)), (-1, -1, math.sqrt(2)))


class NoPathError(ValueError):
    """No free path between two points (a closed door, a walled-in goal)."""


class Grid:
    """Blocked cells of the flat for one walker size."""

    def __init__(self, polygons: list[np.ndarray], bounds: tuple[float, float, float, float], *, cell: float = 0.1, clearance: float = 0.25) -> None:
        xmin, ymin, xmax, ymax = bounds
        pad = 1.5  # room outside the flat, for people leaving through a door
        self.cell = cell
        self.x0, self.y0 = xmin - pad, ymin - pad
        self.nx = int(math.ceil((xmax - xmin + 2 * pad) / cell))
        self.ny = int(math.ceil((ymax - ymin + 2 * pad) / cell))
        xs = self.x0 + (np.arange(self.nx) + 0.5) * cell
        ys = self.y0 + (np.arange(self.ny) + 0.5) * cell
        gx, gy = np.meshgrid(xs, ys, indexing="ij")
        centres = np.stack((gx.ravel(), gy.ravel()), axis=1)
        blocked = np.zeros(centres.shape[0], dtype=bool)
        for poly in polygons:
            lo, hi = poly.min(axis=0) - clearance - cell, poly.max(axis=0) + clearance + cell
            near = np.flatnonzero(np.all((centres >= lo) & (centres <= hi), axis=1))
            if near.size == 0:
                continue
            pts = centres[near]
            a, b = polygon_edges(poly)
            hit = points_in_polygon(pts, poly) | (distance_points_segments(pts, a, b).min(axis=1) < clearance)
            blocked[near[hit]] = True
        self.blocked = blocked.reshape(self.nx, self.ny)

    def cell_of(self, p: Point) -> tuple[int, int]:
        i = int(math.floor((p[0] - self.x0) / self.cell))
        j = int(math.floor((p[1] - self.y0) / self.cell))
        return min(max(i, 0), self.nx - 1), min(max(j, 0), self.ny - 1)

    def centre(self, c: tuple[int, int]) -> Point:
        return self.x0 + (c[0] + 0.5) * self.cell, self.y0 + (c[1] + 0.5) * self.cell

    def free(self, c: tuple[int, int]) -> bool:
        return 0 <= c[0] < self.nx and 0 <= c[1] < self.ny and not self.blocked[c]

    def nearest_free(self, c: tuple[int, int], *, max_radius: int = 15) -> tuple[int, int] | None:
        """The free cell nearest to ``c`` (ring by ring, deterministic order)."""
        if self.free(c):
            return c
        for r in range(1, max_radius + 1):
            ring = [(c[0] + di, c[1] + dj) for di in range(-r, r + 1) for dj in range(-r, r + 1) if max(abs(di), abs(dj)) == r]
            ring = [q for q in ring if self.free(q)]
            if ring:
                return min(ring, key=lambda q: ((q[0] - c[0]) ** 2 + (q[1] - c[1]) ** 2, q))
        return None

    def line_free(self, a: Point, b: Point) -> bool:
        """Whether the straight walk a -> b crosses only free cells."""
        n = max(2, int(math.hypot(b[0] - a[0], b[1] - a[1]) / (self.cell * 0.5)) + 1)
        for k in range(n + 1):
            t = k / n
            if not self.free(self.cell_of((a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t))):
                return False
        return True

    def plan(self, start: Point, goal: Point) -> list[Point]:
        """Waypoints from ``start`` to ``goal`` (excluding start, ending at goal or the
        nearest free point to it). Raises NoPathError when the goal is unreachable."""
        s = self.nearest_free(self.cell_of(start))
        g = self.nearest_free(self.cell_of(goal))
        if s is None or g is None:
            raise NoPathError(f"no free space near {start if s is None else goal}")
        end = goal if self.free(self.cell_of(goal)) else self.centre(g)
        if self.line_free(start, end) and self.free(self.cell_of(start)):
            return [end]
        cells = self._astar(s, g)
        pts = [self.centre(c) for c in cells[1:-1]] + [end]
        return self._smooth(start, pts)

    def _astar(self, s: tuple[int, int], g: tuple[int, int]) -> list[tuple[int, int]]:
        def h(c: tuple[int, int]) -> float:
            dx, dy = abs(c[0] - g[0]), abs(c[1] - g[1])
            return max(dx, dy) + (math.sqrt(2) - 1) * min(dx, dy)

        counter = 0
        frontier: list[tuple[float, int, tuple[int, int]]] = [(h(s), counter, s)]
        came: dict[tuple[int, int], tuple[int, int] | None] = {s: None}
        cost = {s: 0.0}
        while frontier:
            _, _, c = heapq.heappop(frontier)
            if c == g:
                path = [c]
                while came[path[-1]] is not None:
                    path.append(came[path[-1]])  # type: ignore[arg-type]
                return path[::-1]
            for di, dj, w in _MOVES:
                n = (c[0] + di, c[1] + dj)
                if not self.free(n):
                    continue
                if di and dj and not (self.free((c[0] + di, c[1])) and self.free((c[0], c[1] + dj))):
                    continue  # no corner cutting
                nc = cost[c] + w
                if nc < cost.get(n, math.inf):
                    cost[n] = nc
                    came[n] = c
                    counter += 1
                    heapq.heappush(frontier, (nc + h(n), counter, n))
        raise NoPathError(f"no path from {self.centre(s)} to {self.centre(g)}")

    def _smooth(self, start: Point, pts: list[Point]) -> list[Point]:
        out: list[Point] = []
        here = start
        i = 0
        while i < len(pts):
            j = len(pts) - 1
            while j > i and not self.line_free(here, pts[j]):
                j -= 1
            out.append(pts[j])
            here = pts[j]
            i = j + 1
        return out
