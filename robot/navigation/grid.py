"""The planner's world model: an occupancy grid from the floor plan, and shortest paths on it.

The map server's reply (``<map frame="map">`` with wall pieces, furniture
footprints and the start pose, docs/robot-contract.md) is rasterised at
``cell`` metres: a cell is occupied when its centre lies in a wall piece or
a footprint that stands below the robot's top (everything on a floor plan
does: the robot cannot drive under a table top). The free space is then
eroded by the robot's radius with an exact distance transform (``homesim.ndgrid``, as SciPy's ``distance_transform_edt``)
(the distance of every cell to the nearest occupied one), so a free cell is a
place where the robot's centre may be. Cells a little further from obstacles
than that cost a little more, so paths keep to the middle of doorways.

Paths: Dijkstra (``scipy.sparse.csgraph.dijkstra``, C code, imported at the first plan) on the
8-connected free cells, with octile step lengths times the clearance cost,
diagonal moves only when both side cells are free (no corner cutting). The
cell path is shortened by line-of-sight smoothing on the free cells. A grid keeps its latest
shortest-path trees (one search answers every goal from a start cell) and paths (:data:`TREES`,
:data:`PATHS`): the same answers as searching afresh, at a bounded cost in memory.

How it fails: :class:`MapError` for a map reply it cannot read (naming what
is wrong), :class:`NoPathError` when start or goal is not free (after a
search for the nearest free cell within 0.5 m) or when they are not
connected.
"""

from __future__ import annotations

import copy
import math
from collections import OrderedDict
from dataclasses import dataclass
from typing import Any

import numpy as np
from lxml import etree
from homesim import ndgrid

from homesim.errors import HomesimError
from robot import floorplan
from robot.floorplan import MapFormatError

Point = tuple[float, float]

#: Grid resolution (metres).
CELL = 0.05
#: Extra cost weight for cells within ``soft`` metres of the inflated obstacles.
SOFT_WEIGHT = 2.0
#: Shortest-path trees kept per grid (one per start cell, the latest): a search for a place to give
#: way plans from where the robot stands to up to 16 candidate spots, and again every second while
#: it stands wedged (fresh11 twin_long_tour_elderly: 20 whole-grid Dijkstras a second). Each holds
#: two arrays of the grid's size (about 1.5 MB for a 20 x 15 m flat).
TREES = 2
#: Smoothed paths kept per grid (the latest; a path is a few points).
PATHS = 64


class MapError(HomesimError):
    """A floor plan the planner cannot read."""


class NoPathError(HomesimError):
    """No free path between start and goal (the ``reason`` says which end or that they are apart)."""

    def __init__(self, message: str, reason: str) -> None:
        super().__init__(message)
        self.reason = reason


@dataclass(frozen=True)
class Plan2D:
    """What the planner knows of the flat: occupied polygons (map frame) and the start pose."""

    polygons: tuple[np.ndarray, ...]
    start: tuple[float, float, float]


def parse_map(el: etree._Element, *, robot_height: float = 1.4) -> Plan2D:
    """The contract's ``<map>`` reply (parsed by :func:`robot.floorplan.parse_map`) as the polygons
    the robot cannot cross: every wall piece and every obstacle that starts below the robot's top."""
    try:
        plan = floorplan.parse_map(el)
    except MapFormatError as e:
        raise MapError(str(e)) from e
    polys = [w.rectangle() for w in plan.walls] + [o.polygon() for o in plan.obstacles if o.bottom < robot_height]
    if not polys:
        raise MapError("map: no walls or obstacles: not a floor plan")
    return Plan2D(tuple(polys), plan.start)


def _inside(px: np.ndarray, py: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """Even-odd point-in-polygon test for arrays of points (vectorised over the points)."""
    inside = np.zeros(px.shape, dtype=bool)
    n = len(poly)
    for i in range(n):
        x1, y1 = poly[i]
        x2, y2 = poly[(i + 1) % n]
        cond = (y1 > py) != (y2 > py)
        with np.errstate(divide="ignore", invalid="ignore"):
            xint = (x2 - x1) * (py - y1) / (y2 - y1) + x1
        inside ^= cond & (px < xint)
    return inside


class OccupancyGrid:
    """The floor plan rasterised at ``cell`` m and inflated by ``radius`` (see the module docstring)."""

    def __init__(self, plan: Plan2D, *, radius: float, cell: float = CELL, soft: float = 0.3, margin: float = 0.08, pad: float = 0.5) -> None:
        self.cell = cell
        self.radius = radius
        allp = np.concatenate(plan.polygons)
        xmin, ymin = allp.min(axis=0) - pad
        xmax, ymax = allp.max(axis=0) + pad
        self.origin = (float(xmin), float(ymin))
        self.nx = int(math.ceil((xmax - xmin) / cell))
        self.ny = int(math.ceil((ymax - ymin) / cell))
        xs = xmin + (np.arange(self.nx) + 0.5) * cell
        ys = ymin + (np.arange(self.ny) + 0.5) * cell
        gx, gy = np.meshgrid(xs, ys, indexing="ij")
        occ = np.zeros((self.nx, self.ny), dtype=bool)
        for poly in plan.polygons:
            lo, hi = poly.min(axis=0), poly.max(axis=0)
            i0, i1 = max(int((lo[0] - xmin) / cell) - 1, 0), min(int((hi[0] - xmin) / cell) + 2, self.nx)
            j0, j1 = max(int((lo[1] - ymin) / cell) - 1, 0), min(int((hi[1] - ymin) / cell) + 2, self.ny)
            if i0 >= i1 or j0 >= j1:
                continue
            sub = _inside(gx[i0:i1, j0:j1], gy[i0:i1, j0:j1], poly)
            # thin walls: also mark every cell a polygon's outline passes through
            occ[i0:i1, j0:j1] |= sub
            for k in range(len(poly)):
                a, b = poly[k], poly[(k + 1) % len(poly)]
                m = max(int(np.hypot(*(b - a)) / (cell / 2)) + 2, 2)
                t = np.linspace(0.0, 1.0, m)
                ii = ((a[0] + (b[0] - a[0]) * t - xmin) / cell).astype(int)
                jj = ((a[1] + (b[1] - a[1]) * t - ymin) / cell).astype(int)
                ok = (ii >= 0) & (ii < self.nx) & (jj >= 0) & (jj < self.ny)
                occ[ii[ok], jj[ok]] = True
        self.soft, self.margin = soft, margin
        self._derive(occ)

    def _derive(self, occ: np.ndarray) -> None:
        """Clearance, free and roomy cells, costs from the occupied cells ``occ``."""
        cell, radius = self.cell, self.radius
        self.occupied = occ
        #: metres from each cell centre to the nearest occupied cell (0 inside obstacles)
        # (centre to centre, less half a cell: an occupied cell's centre lies inside the obstacle)
        self.clearance = np.maximum(ndgrid.distance_transform_edt(~occ) * cell - cell / 2, 0.0)
        self.free = self.clearance > radius
        #: where smoothed shortcuts may run: ``margin`` more than the radius from anything
        self.roomy = self.clearance > radius + self.margin
        extra = np.clip((radius + self.soft - self.clearance) / self.soft, 0.0, 1.0)
        self.cost = 1.0 + SOFT_WEIGHT * extra
        self._graph: Any = None  # scipy.sparse.csr_matrix, built at the first plan
        self._forget()

    def _forget(self) -> None:
        """Drop the kept shortest-path trees and paths (the grid's cells or costs changed; a copy's own)."""
        #: start cell index -> (dist, pred) of the single-source Dijkstra from it (the latest TREES)
        self._trees: OrderedDict[int, tuple[np.ndarray, np.ndarray]] = OrderedDict()
        #: (start, goal) -> the smoothed path or the NoPathError's (message, reason) (the latest PATHS)
        self._paths: OrderedDict[tuple[float, float, float, float], tuple[Point, ...] | tuple[str, str]] = OrderedDict()

    def with_obstacles(self, points: np.ndarray) -> OccupancyGrid:
        """A copy in which the cells holding ``points`` ((N, 2), map frame) are occupied too.

        The local costmap of a replan: what the laser sees that is not on the
        floor plan (a person in a doorway, a box) is inflated like the map's own
        obstacles, so the new path keeps the robot's radius clear of it. Points
        outside the grid are ignored. The original grid is not changed.
        """
        new = copy.copy(self)
        occ = self.occupied.copy()
        pts = np.asarray(points, dtype=float).reshape(-1, 2)
        i = np.floor((pts[:, 0] - self.origin[0]) / self.cell).astype(int)
        j = np.floor((pts[:, 1] - self.origin[1]) / self.cell).astype(int)
        ok = (i >= 0) & (i < self.nx) & (j >= 0) & (j < self.ny)
        occ[i[ok], j[ok]] = True
        new._derive(occ)
        return new

    def with_cost(self, centres: list[Point], *, radius: float, cost: float) -> OccupancyGrid:
        """A copy in which the cells within ``radius`` m of each of ``centres`` (map frame) cost ``cost``
        more per metre: a path avoids them where another way costs less, and still goes through them
        where there is none (nothing becomes occupied). The original grid is not changed."""
        if not centres:
            return self
        new = copy.copy(self)
        xs = self.origin[0] + (np.arange(self.nx) + 0.5) * self.cell
        ys = self.origin[1] + (np.arange(self.ny) + 0.5) * self.cell
        extra = np.zeros((self.nx, self.ny))
        for cx, cy in centres:
            near = (xs[:, None] - cx) ** 2 + (ys[None, :] - cy) ** 2 <= radius * radius
            extra[near] = cost
        new.cost = self.cost + extra
        new._graph = None
        new._forget()
        return new

    # ------------------------------------------------------------- cells
    def cell_of(self, p: Point) -> tuple[int, int]:
        return int((p[0] - self.origin[0]) / self.cell), int((p[1] - self.origin[1]) / self.cell)

    def centre(self, c: tuple[int, int]) -> Point:
        return self.origin[0] + (c[0] + 0.5) * self.cell, self.origin[1] + (c[1] + 0.5) * self.cell

    def inside(self, c: tuple[int, int]) -> bool:
        return 0 <= c[0] < self.nx and 0 <= c[1] < self.ny

    def is_free(self, p: Point) -> bool:
        c = self.cell_of(p)
        return self.inside(c) and bool(self.free[c])

    def nearest_free(self, p: Point, *, within: float = 0.5) -> tuple[int, int] | None:
        """The free cell nearest to ``p`` within ``within`` metres (ties: lowest index), or None."""
        ci, cj = self.cell_of(p)
        r = int(math.ceil(within / self.cell))
        i0, i1 = max(ci - r, 0), min(ci + r + 1, self.nx)
        j0, j1 = max(cj - r, 0), min(cj + r + 1, self.ny)
        if i0 >= i1 or j0 >= j1:
            return None
        sub = self.free[i0:i1, j0:j1]
        ii, jj = np.nonzero(sub)
        if len(ii) == 0:
            return None
        d2 = (ii + i0 - ci) ** 2 + (jj + j0 - cj) ** 2
        k = int(np.argmin(d2))
        if d2[k] > r * r:
            return None
        return int(ii[k] + i0), int(jj[k] + j0)

    # ------------------------------------------------------------- graph
    def _build_graph(self) -> Any:
        """The 8-connected graph of free cells: edge weight = step length x mean cell cost.

        SciPy's sparse package is imported here, at the first plan, not at start-up (~0.2 s of
        CPU with ``scipy.linalg``, which ``scipy.sparse.csgraph`` pulls in)."""
        from scipy.sparse import csr_matrix

        nx, ny = self.nx, self.ny
        idx = np.arange(nx * ny).reshape(nx, ny)
        free, cost = self.free, self.cost
        rows, cols, vals = [], [], []
        for di, dj in ((1, 0), (0, 1), (1, 1), (1, -1)):
            j0, j1 = max(0, -dj), ny - max(0, dj)
            a = (slice(0, nx - di), slice(j0, j1))
            b = (slice(di, nx), slice(j0 + dj, j1 + dj))
            ok = free[a] & free[b]
            if di and dj:  # no corner cutting: both side cells free too
                ok &= free[(slice(di, nx), slice(j0, j1))] & free[(slice(0, nx - di), slice(j0 + dj, j1 + dj))]
            w = math.hypot(di, dj) * self.cell * 0.5 * (cost[a] + cost[b])
            ai, bi, wk = idx[a][ok], idx[b][ok], w[ok]
            rows += [ai, bi]
            cols += [bi, ai]
            vals += [wk, wk]
        n = nx * ny
        return csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n))

    def plan(self, start: Point, goal: Point) -> list[Point]:
        """A smoothed free path start -> goal (map frame), first point ``start``, last ``goal``.

        Raises :class:`NoPathError` (reason ``start_blocked``, ``goal_blocked`` or
        ``no_path``).

        A plan is a pure function of the grid and its two points: the last :data:`PATHS` answers
        are kept, and the last :data:`TREES` shortest-path trees (a tree answers every goal from its
        start cell), so candidate spots planned from one place, and the same question asked again
        while the robot stands, cost one search. The same paths as searching afresh every time.
        """
        key = (float(start[0]), float(start[1]), float(goal[0]), float(goal[1]))
        got = self._paths.get(key)
        if got is not None:
            self._paths.move_to_end(key)
            if len(got) == 2 and isinstance(got[0], str):
                raise NoPathError(got[0], got[1])  # type: ignore[arg-type]
            return [_own(p) for p in got]  # type: ignore[union-attr]
        try:
            path = self._plan(start, goal)
        except NoPathError as e:
            self._keep(key, (str(e), e.reason))
            raise
        self._keep(key, tuple(_own(p) for p in path))
        return path

    def _keep(self, key: tuple[float, float, float, float], answer: tuple[Point, ...] | tuple[str, str]) -> None:
        self._paths[key] = answer
        if len(self._paths) > PATHS:
            self._paths.popitem(last=False)

    def _tree(self, si: int) -> tuple[np.ndarray, np.ndarray]:
        """The shortest-path tree (distances, predecessors) from cell index ``si`` (kept: :data:`TREES`)."""
        got = self._trees.get(si)
        if got is not None:
            self._trees.move_to_end(si)
            return got
        if self._graph is None:
            self._graph = self._build_graph()
        from scipy.sparse.csgraph import dijkstra

        dist, pred = dijkstra(self._graph, directed=False, indices=si, return_predecessors=True)
        self._trees[si] = (dist, pred)
        if len(self._trees) > TREES:
            self._trees.popitem(last=False)
        return dist, pred

    def _plan(self, start: Point, goal: Point) -> list[Point]:
        s = self.cell_of(start) if self.is_free(start) else self.nearest_free(start)
        if s is None:
            raise NoPathError(f"the robot's position ({start[0]:.2f}, {start[1]:.2f}) is not free on the map", "start_blocked")
        g = self.cell_of(goal) if self.is_free(goal) else self.nearest_free(goal)
        if g is None:
            raise NoPathError(f"the goal ({goal[0]:.2f}, {goal[1]:.2f}) is not reachable by the robot's body", "goal_blocked")
        si, gi = s[0] * self.ny + s[1], g[0] * self.ny + g[1]
        dist, pred = self._tree(si)
        if not np.isfinite(dist[gi]):
            raise NoPathError(f"no free path from ({start[0]:.2f}, {start[1]:.2f}) to ({goal[0]:.2f}, {goal[1]:.2f})", "no_path")
        cells = [gi]
        while cells[-1] != si:
            cells.append(int(pred[cells[-1]]))
        cells.reverse()
        pts = [self.centre((k // self.ny, k % self.ny)) for k in cells]
        goal_pt = goal if self.is_free(goal) else pts[-1]
        return self._smooth([start, *pts[1:-1], goal_pt])

    def line_free(self, a: Point, b: Point, *, roomy: bool = True) -> bool:
        """Every cell the segment a-b passes (sampled at a quarter cell) is free (``roomy``: radius + margin clear)."""
        n = max(int(math.hypot(b[0] - a[0], b[1] - a[1]) / (self.cell / 4)) + 2, 2)
        t = np.linspace(0.0, 1.0, n)
        i = ((a[0] + (b[0] - a[0]) * t - self.origin[0]) / self.cell).astype(int)
        j = ((a[1] + (b[1] - a[1]) * t - self.origin[1]) / self.cell).astype(int)
        if (i < 0).any() or (i >= self.nx).any() or (j < 0).any() or (j >= self.ny).any():
            return False
        grid = self.roomy if roomy else self.free
        return bool(grid[i, j][1:-1].all())

    def _smooth(self, pts: list[Point]) -> list[Point]:
        """Greedy line-of-sight shortening: from each kept point jump to the furthest visible one."""
        if len(pts) <= 2:
            return pts
        out = [pts[0]]
        i = 0
        while i < len(pts) - 1:
            j = len(pts) - 1
            while j > i + 1 and not self.line_free(pts[i], pts[j]):
                j -= 1
            if j == i + 1:  # a tight passage: shortcuts only on free cells
                j = len(pts) - 1
                while j > i + 1 and not self.line_free(pts[i], pts[j], roomy=False):
                    j -= 1
            out.append(pts[j])
            i = j
        return out


def _own(p: Any) -> Any:
    """A point as kept or handed out by :meth:`OccupancyGrid.plan`: a tuple as it is, anything else (the
    caller's start, an array) copied, so neither side's later changes reach the other."""
    return p if type(p) is tuple else copy.copy(p)


def without_end_corner(points: list[Point], grid: OccupancyGrid, near: float) -> list[Point]:
    """``points`` without their last corner when it is nearer the goal than ``near`` and the straight leg
    from the corner before it to the goal keeps the robot's body clear on ``grid`` (free cells, inflated
    by the robot's radius).

    The grid's path often ends a few centimetres past its last free corner (the goal cell's centre, then
    the goal): such a corner is no step of its own. But a corner the path turns at to get round a door
    jamb or a furniture corner stays, however near the goal (review9 item 2: a leg cut straight through
    the jamb, with only the player's window between the footprint and the wall)."""
    if len(points) >= 3 and math.hypot(points[-1][0] - points[-2][0], points[-1][1] - points[-2][1]) < near \
            and grid.line_free(points[-3], points[-1], roomy=False):
        return [*points[:-2], points[-1]]
    return points


def path_length(points: list[Point]) -> float:
    """Length of a polyline (metres)."""
    return float(sum(math.hypot(b[0] - a[0], b[1] - a[1]) for a, b in zip(points, points[1:])))
