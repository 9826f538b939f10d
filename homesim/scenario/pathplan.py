"""Paths around obstacles for scripted people: an occupancy grid and A*.

The grid covers the flat (plus a margin outside it, for people leaving
through a door) at ``cell`` metres (5 cm). A cell is blocked when its centre
lies inside a wall or a piece of furniture, or closer to one than the
walker's ``clearance`` (a person's radius, 0.25 m): a free cell is a place
where a person's body fits. A* (8-connected, no corner cutting, octile
costs, ties broken by insertion order so paths are deterministic) finds a
cell path, which is then shortened by line-of-sight smoothing.

Doors are gaps in the walls. A gap at least :data:`MIN_DOOR_WIDTH` wide
(a person's diameter plus 10 cm) always leaves a corridor of free cells
through it, however the door lies against the grid; the scenario checks
refuse narrower or obstructed doors (:meth:`Grid.passable`), and targets a
person cannot reach from where they start (:meth:`Grid.component`).

``plan(..., avoid=[(x, y, r)])`` also keeps clear of discs (the robot's
footprint), so people walk around the robot instead of into it. A goal that
is not free ends at the free cell nearest to it; ``plan(..., inside=True)``
(every person's walk but leaving) keeps that cell inside the flat (a grid
given the rooms: :meth:`Grid.for_scenario`), never beyond an outer wall.
"""

from __future__ import annotations

import heapq
import math
from collections import OrderedDict, deque
from collections.abc import Iterable, Sequence

import numpy as np
from .. import ndgrid

from .model import Door, Scenario, Wall
from ..geometry import distance_points_segments, points_in_polygon, polygon_edges, split_wall, wall_rectangle

Point = tuple[float, float]
Disc = tuple[float, float, float]

#: A scripted person's radius, which is the grid's clearance from obstacles.
WALKER_RADIUS = 0.25
#: Grid resolution (metres).
CELL = 0.05
#: The narrowest door a person can be planned through, whatever its position.
MIN_DOOR_WIDTH = 2 * WALKER_RADIUS + 0.10
#: How far outside the flat the grid reaches (people leave through exits).
PAD = 1.5

#: How many recent plans (and A* cell paths) a grid keeps.
PLAN_CACHE = 64
#: How many line-of-sight candidates smoothing tests in one numpy pass.
SMOOTH_BATCH = 24

_SQRT2 = math.sqrt(2.0)


class NoPathError(ValueError):
    """No free path between two points (a closed door, a walled-in goal)."""


def walk_polygons(sc: Scenario) -> list[np.ndarray]:
    """What people walk around: every wall piece (doors are gaps) and every piece of furniture."""
    polys = []
    for wall in sc.walls:
        for a, b in split_wall(wall.start, wall.end, [(d.at, d.width) for d in wall.doors]):
            polys.append(wall_rectangle(a, b, wall.thickness))
    polys += [np.array(f.polygon, dtype=float) for f in sc.furniture]
    return polys


def door_frame(wall: Wall, door: Door) -> tuple[Point, Point]:
    """The centre of a door gap and the unit direction of its wall."""
    (ax, ay), (bx, by) = wall.start, wall.end
    n = math.hypot(bx - ax, by - ay)
    ux, uy = (bx - ax) / n, (by - ay) / n
    return (ax + ux * door.at, ay + uy * door.at), (ux, uy)


def door_sides(wall: Wall, door: Door) -> tuple[Point, Point]:
    """Two points straight through a door, one each side, where a person stands clear of the wall."""
    (cx, cy), (ux, uy) = door_frame(wall, door)
    d = max(0.6, wall.thickness / 2 + WALKER_RADIUS + 0.1)
    return (cx - uy * d, cy + ux * d), (cx + uy * d, cy - ux * d)


def scenario_bounds(sc: Scenario) -> tuple[float, float, float, float]:
    """(xmin, ymin, xmax, ymax) of the rooms and walls."""
    pts = [p for r in sc.rooms for p in r.polygon]
    pts += [w.start for w in sc.walls] + [w.end for w in sc.walls]
    arr = np.array(pts, dtype=float)
    lo, hi = arr.min(axis=0), arr.max(axis=0)
    return float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1])


class Grid:
    """Blocked cells of the flat for one walker size."""

    def __init__(self, polygons: Sequence[np.ndarray], bounds: tuple[float, float, float, float], *, cell: float = CELL, clearance: float = WALKER_RADIUS,
                 rooms: Sequence[np.ndarray] = ()) -> None:
        xmin, ymin, xmax, ymax = bounds
        self._rooms = [np.asarray(r, dtype=float) for r in rooms]  # the flat's rooms: a goal inside ends inside
        self._inside: np.ndarray | None = None  # cells whose centre lies in a room, made when a goal first needs it
        self.cell = cell
        self.clearance = clearance
        self.x0, self.y0 = xmin - PAD, ymin - PAD
        self.nx = int(math.ceil((xmax - xmin + 2 * PAD) / cell))
        self.ny = int(math.ceil((ymax - ymin + 2 * PAD) / cell))
        xs = self.x0 + (np.arange(self.nx) + 0.5) * cell
        ys = self.y0 + (np.arange(self.ny) + 0.5) * cell
        blocked = np.zeros((self.nx, self.ny), dtype=bool)
        for poly in polygons:
            poly = np.asarray(poly, dtype=float)
            lo, hi = poly.min(axis=0) - clearance - cell, poly.max(axis=0) + clearance + cell
            i0, i1 = np.searchsorted(xs, lo[0]), np.searchsorted(xs, hi[0], side="right")
            j0, j1 = np.searchsorted(ys, lo[1]), np.searchsorted(ys, hi[1], side="right")
            if i0 >= i1 or j0 >= j1:
                continue
            gx, gy = np.meshgrid(xs[i0:i1], ys[j0:j1], indexing="ij")
            pts = np.stack((gx.ravel(), gy.ravel()), axis=1)
            a, b = polygon_edges(poly)
            hit = points_in_polygon(pts, poly) | (distance_points_segments(pts, a, b).min(axis=1) < clearance)
            blocked[i0:i1, j0:j1] |= hit.reshape(i1 - i0, j1 - j0)
        # A blocked border: the search never needs bounds checks on flat indices.
        blocked[0, :] = blocked[-1, :] = True
        blocked[:, 0] = blocked[:, -1] = True
        self.blocked = blocked
        self._components: np.ndarray | None = None
        self._free: list[bool] | None = None  # (~blocked).ravel().tolist(), made when A* first needs it
        self._free_u8: np.ndarray | None = None  # the same as bytes, for the compiled A*
        # The last plans and A* cell paths asked for (both pure functions of their keys).
        self._plans: OrderedDict[tuple[object, ...], tuple[Point, ...] | str] = OrderedDict()  # str: NoPathError's message
        self._paths: OrderedDict[tuple[object, ...], tuple[tuple[int, int], ...] | None] = OrderedDict()  # None: no path

    @classmethod
    def for_scenario(cls, sc: Scenario, *, clearance: float = WALKER_RADIUS) -> Grid:
        return cls(walk_polygons(sc), scenario_bounds(sc), clearance=clearance, rooms=[np.array(r.polygon, dtype=float) for r in sc.rooms])

    def inside(self) -> np.ndarray | None:
        """Cells whose centre lies in one of the flat's rooms (None: the grid was given no rooms)."""
        if not self._rooms:
            return None
        if self._inside is None:
            xs = self.x0 + (np.arange(self.nx) + 0.5) * self.cell
            ys = self.y0 + (np.arange(self.ny) + 0.5) * self.cell
            gx, gy = np.meshgrid(xs, ys, indexing="ij")
            pts = np.stack((gx.ravel(), gy.ravel()), axis=1)
            inside = np.zeros(len(pts), dtype=bool)
            for poly in self._rooms:
                inside |= points_in_polygon(pts, poly)
            self._inside = inside.reshape(self.nx, self.ny)
        return self._inside

    # ------------------------------------------------------------- cells
    def cell_of(self, p: Point) -> tuple[int, int]:
        i = int(math.floor((p[0] - self.x0) / self.cell))
        j = int(math.floor((p[1] - self.y0) / self.cell))
        return min(max(i, 0), self.nx - 1), min(max(j, 0), self.ny - 1)

    def centre(self, c: tuple[int, int]) -> Point:
        return self.x0 + (c[0] + 0.5) * self.cell, self.y0 + (c[1] + 0.5) * self.cell

    def free(self, c: tuple[int, int], blocked: np.ndarray | None = None) -> bool:
        b = self.blocked if blocked is None else blocked
        return 0 <= c[0] < self.nx and 0 <= c[1] < self.ny and not b[c]

    def nearest_free(self, c: tuple[int, int], *, max_distance: float = 1.5, blocked: np.ndarray | None = None,
                     allowed: np.ndarray | None = None) -> tuple[int, int] | None:
        """The free cell nearest to ``c`` within ``max_distance`` metres (deterministic ties); with ``allowed``
        (a mask of cells), only among those."""
        b = self.blocked if blocked is None else blocked
        if self.free(c, b) and (allowed is None or allowed[c]):
            return c
        r = max(1, int(math.ceil(max_distance / self.cell)))
        i0, i1 = max(c[0] - r, 0), min(c[0] + r + 1, self.nx)
        j0, j1 = max(c[1] - r, 0), min(c[1] + r + 1, self.ny)
        free = ~b[i0:i1, j0:j1]
        if allowed is not None:
            free &= allowed[i0:i1, j0:j1]
        if not free.any():
            return None
        di = np.arange(i0, i1)[:, None] - c[0]
        dj = np.arange(j0, j1)[None, :] - c[1]
        d2 = np.where(free, di * di + dj * dj, np.iinfo(np.int64).max)
        k = int(np.argmin(d2))  # row-major: ties go to the smaller (i, j)
        if d2.flat[k] > r * r:
            return None
        return i0 + k // (j1 - j0), j0 + k % (j1 - j0)

    def with_discs(self, discs: Iterable[Disc]) -> np.ndarray:
        """A copy of the blocked cells with each disc (x, y, r), grown by the clearance, blocked too."""
        blocked = self.blocked.copy()
        for x, y, r in discs:
            rr = r + self.clearance
            i0, j0 = self.cell_of((x - rr, y - rr))
            i1, j1 = self.cell_of((x + rr, y + rr))
            xs = self.x0 + (np.arange(i0, i1 + 1) + 0.5) * self.cell
            ys = self.y0 + (np.arange(j0, j1 + 1) + 0.5) * self.cell
            blocked[i0 : i1 + 1, j0 : j1 + 1] |= (xs[:, None] - x) ** 2 + (ys[None, :] - y) ** 2 < rr * rr
        return blocked

    def line_free(self, a: Point, b: Point, blocked: np.ndarray | None = None) -> bool:
        """Whether the straight walk a -> b crosses only free cells."""
        bl = self.blocked if blocked is None else blocked
        n = max(2, int(math.hypot(b[0] - a[0], b[1] - a[1]) / (self.cell * 0.5)) + 1)
        t = np.linspace(0.0, 1.0, n + 1)
        i = np.clip(np.floor((a[0] + (b[0] - a[0]) * t - self.x0) / self.cell).astype(int), 0, self.nx - 1)
        j = np.clip(np.floor((a[1] + (b[1] - a[1]) * t - self.y0) / self.cell).astype(int), 0, self.ny - 1)
        return not bool(bl[i, j].any())

    def lines_free(self, a: Point, ends: Sequence[Point], blocked: np.ndarray | None = None) -> np.ndarray:
        """:meth:`line_free` from ``a`` to each of ``ends`` at once (boolean per end).

        The same samples with the same arithmetic as :meth:`line_free` (``linspace`` is
        ``k * (1 / n)`` with the last sample exactly 1), so the answers are identical;
        one numpy pass instead of one per line.
        """
        bl = self.blocked if blocked is None else blocked
        m = len(ends)
        if m == 0:
            return np.zeros(0, dtype=bool)
        ax, ay = a
        half = self.cell * 0.5
        ns = [max(2, int(math.hypot(bx - ax, by - ay) / half) + 1) for bx, by in ends]
        counts = np.array(ns, dtype=np.int64) + 1
        total = int(counts.sum())
        first = np.zeros(m, dtype=np.int64)
        np.cumsum(counts[:-1], out=first[1:])
        k = np.arange(total, dtype=np.int64) - np.repeat(first, counts)
        t = k * np.repeat(1.0 / np.array(ns, dtype=float), counts)
        t[first + counts - 1] = 1.0
        e = np.asarray(ends, dtype=float)
        dx = np.repeat(e[:, 0] - ax, counts)
        dy = np.repeat(e[:, 1] - ay, counts)
        i = np.clip(np.floor((ax + dx * t - self.x0) / self.cell).astype(int), 0, self.nx - 1)
        j = np.clip(np.floor((ay + dy * t - self.y0) / self.cell).astype(int), 0, self.ny - 1)
        return ~np.logical_or.reduceat(bl[i, j], first)

    # ------------------------------------------------------------ planning
    def plan(self, start: Point, goal: Point, *, avoid: Iterable[Disc] = (), inside: bool = False, reachable: bool = False) -> list[Point]:
        """Waypoints from ``start`` to ``goal`` (excluding start, ending at goal or the
        nearest free point to it), keeping clear of the ``avoid`` discs.
        Raises NoPathError when the goal is unreachable.

        ``inside``: the walk must end inside the flat (at the free spot nearest the goal among the
        cells in a room; a grid given no rooms has none to keep to), as the simulated people ask for
        on every walk but leaving the flat.

        ``reachable`` (without ``avoid``): a goal whose free spot lies in a pocket that walls and
        furniture close off from the start (a gap narrower than a person between a shelf and a table)
        ends at the free spot nearest it that the start reaches, within the same 1.5 m; for a goal the
        walker does not choose (the place in front of the robot), never a scene's own walk.

        A plan is a pure function of its arguments, so the last few are kept: a person held
        back by the robot re-plans from where she stands to the same goal, and people
        pacing between two places ask for the same cell path again (``_astar``'s own cache).
        """
        avoid = [(float(x), float(y), float(r)) for x, y, r in avoid]
        key = (float(start[0]), float(start[1]), float(goal[0]), float(goal[1]), tuple(avoid), inside, reachable)
        got = self._plans.get(key)
        if got is not None:
            self._plans.move_to_end(key)
            if isinstance(got, str):  # the same question failed before: the same answer
                raise NoPathError(got)
            return list(got)
        try:
            pts = self._plan(start, goal, avoid, inside, reachable and not avoid)
        except NoPathError as exc:
            self._remember(key, str(exc))
            raise
        self._remember(key, tuple(pts))
        return pts

    def _remember(self, key: tuple[object, ...], answer: tuple[Point, ...] | str) -> None:
        """Keep a plan (or a failure's message) among the last PLAN_CACHE asked for.

        Failures are kept too: a person held back at the robot where it blocks a doorway asks
        again every half second from the same spot, and is told no (then walks up to it).
        """
        self._plans[key] = answer
        if len(self._plans) > PLAN_CACHE:
            self._plans.popitem(last=False)

    def _plan(self, start: Point, goal: Point, avoid: list[Disc], inside: bool = False, reachable: bool = False) -> list[Point]:
        blocked = self.with_discs(avoid) if avoid else self.blocked
        s = self.nearest_free(self.cell_of(start), blocked=blocked)
        # A walk inside the flat ends inside it: the free spot nearest a goal by an outer wall (the robot's
        # disc covering it, the goal in the wall) may lie beyond the wall, and the walk then went out through
        # the front door (gen12, tour-3000-03). Leaving walks to a point outside, the nearest spot anywhere.
        cells_in = self.inside() if inside else None
        gc = self.cell_of(goal)
        keep = cells_in is not None
        g = self.nearest_free(gc, blocked=blocked, allowed=cells_in if keep else None)
        if s is None or g is None:
            raise NoPathError(f"no free space near ({(start if s is None else goal)[0]:.2f}, {(start if s is None else goal)[1]:.2f})"
                              + (" inside the flat" if keep and g is None else ""))
        if reachable and s is not None and g is not None:
            if self._components is None:
                self._components = self._label()
            comp = self._components
            if comp[s] != comp[g]:  # the goal's free spot is closed off from her: the nearest one she reaches
                mask = comp == comp[s]
                g = self.nearest_free(gc, blocked=blocked, allowed=mask & cells_in if keep else mask)
                if g is None:
                    raise NoPathError(f"no free space near ({goal[0]:.2f}, {goal[1]:.2f}) reachable from ({start[0]:.2f}, {start[1]:.2f})")
        end = goal if g == gc else self.centre(g)
        if self.free(self.cell_of(start), blocked) and self.line_free(start, end, blocked):
            return [end]
        akey = (s, g, tuple(avoid))
        if akey in self._paths:
            self._paths.move_to_end(akey)
            cells = self._paths[akey]
        else:
            # A* fails only after searching everything reachable (the robot closing a doorway):
            # ask the regions first. Its moves (no corner cutting) reach exactly the 4-connected
            # region of the start, so it finds a path exactly when s and g share one.
            if avoid and not self._connected(blocked, s, g):
                cells = None
            else:
                cells = tuple(self._astar(blocked, s, g))
            self._paths[akey] = cells
            if len(self._paths) > PLAN_CACHE:
                self._paths.popitem(last=False)
        if cells is None:
            raise NoPathError(self._no_path(s, g))
        pts = [self.centre(c) for c in cells[1:-1]] + [end]
        return self._smooth(start, pts, blocked)

    def _astar(self, blocked: np.ndarray, s: tuple[int, int], g: tuple[int, int]) -> list[tuple[int, int]]:
        """A* over the flat cell indices: 8-connected, no corner cutting, octile heuristic, ties by push order.

        Written for speed (a list for costs, a bytearray for the closed set, the eight moves
        unrolled with the four orthogonal cells read once per expansion) and for sameness: the
        same pops, pushes, costs and ties as the textbook loop (moves in the order east, west,
        north, south, then the diagonals; each priority ``cost + (dx + dy + (sqrt2 - 2) *
        min(dx, dy))`` with the same operations), so the same path.
        """
        ny = self.ny
        start, goal = s[0] * ny + s[1], g[0] * ny + g[1]
        k = ndgrid._kernel()
        if k is not None:  # the same search compiled (homesim/_gridkernels.c): same pops, same path
            cells = k.astar(self._free_bytes(blocked), ny, start, goal)
            if cells is None:
                raise NoPathError(self._no_path(s, g))
            return [divmod(q, ny) for q in cells]
        return self._astar_python(blocked, s, g)

    def _astar_python(self, blocked: np.ndarray, s: tuple[int, int], g: tuple[int, int]) -> list[tuple[int, int]]:
        """:meth:`_astar` in Python: the reference, and the path when the grid kernel is not built."""
        ny = self.ny
        free = self._free_list(blocked)
        start, goal = s[0] * ny + s[1], g[0] * ny + g[1]
        gi, gj = g
        km1 = (_SQRT2 - 1.0) - 1.0
        sq2 = _SQRT2
        inf = math.inf
        cost = [inf] * len(free)
        cost[start] = 0.0
        came: dict[int, int] = {}
        counter = 0
        frontier: list[tuple[float, int, int]] = [(0.0, 0, start)]
        closed = bytearray(len(free))
        push, pop = heapq.heappush, heapq.heappop
        while frontier:
            c = pop(frontier)[2]
            if c == goal:
                path = [c]
                while path[-1] != start:
                    path.append(came[path[-1]])
                return [divmod(q, ny) for q in reversed(path)]
            if closed[c]:
                continue
            closed[c] = 1
            base = cost[c]
            ci, cj = divmod(c, ny)
            ex, ey = ci - gi, cj - gj
            fe, fw, fn, fs = free[c + ny], free[c - ny], free[c + 1], free[c - 1]
            if fe:
                n = c + ny
                nc = base + 1.0
                if nc < cost[n]:
                    cost[n] = nc
                    came[n] = c
                    dx, dy = abs(ex + 1), abs(ey)
                    counter += 1
                    push(frontier, (nc + (dx + dy + km1 * min(dx, dy)), counter, n))
            if fw:
                n = c - ny
                nc = base + 1.0
                if nc < cost[n]:
                    cost[n] = nc
                    came[n] = c
                    dx, dy = abs(ex - 1), abs(ey)
                    counter += 1
                    push(frontier, (nc + (dx + dy + km1 * min(dx, dy)), counter, n))
            if fn:
                n = c + 1
                nc = base + 1.0
                if nc < cost[n]:
                    cost[n] = nc
                    came[n] = c
                    dx, dy = abs(ex), abs(ey + 1)
                    counter += 1
                    push(frontier, (nc + (dx + dy + km1 * min(dx, dy)), counter, n))
            if fs:
                n = c - 1
                nc = base + 1.0
                if nc < cost[n]:
                    cost[n] = nc
                    came[n] = c
                    dx, dy = abs(ex), abs(ey - 1)
                    counter += 1
                    push(frontier, (nc + (dx + dy + km1 * min(dx, dy)), counter, n))
            if fe:
                if fn:
                    n = c + ny + 1
                    if free[n]:
                        nc = base + sq2
                        if nc < cost[n]:
                            cost[n] = nc
                            came[n] = c
                            dx, dy = abs(ex + 1), abs(ey + 1)
                            counter += 1
                            push(frontier, (nc + (dx + dy + km1 * min(dx, dy)), counter, n))
                if fs:
                    n = c + ny - 1
                    if free[n]:
                        nc = base + sq2
                        if nc < cost[n]:
                            cost[n] = nc
                            came[n] = c
                            dx, dy = abs(ex + 1), abs(ey - 1)
                            counter += 1
                            push(frontier, (nc + (dx + dy + km1 * min(dx, dy)), counter, n))
            if fw:
                if fn:
                    n = c - ny + 1
                    if free[n]:
                        nc = base + sq2
                        if nc < cost[n]:
                            cost[n] = nc
                            came[n] = c
                            dx, dy = abs(ex - 1), abs(ey + 1)
                            counter += 1
                            push(frontier, (nc + (dx + dy + km1 * min(dx, dy)), counter, n))
                if fs:
                    n = c - ny - 1
                    if free[n]:
                        nc = base + sq2
                        if nc < cost[n]:
                            cost[n] = nc
                            came[n] = c
                            dx, dy = abs(ex - 1), abs(ey - 1)
                            counter += 1
                            push(frontier, (nc + (dx + dy + km1 * min(dx, dy)), counter, n))
        raise NoPathError(self._no_path(s, g))

    def _free_bytes(self, blocked: np.ndarray) -> np.ndarray:
        """The free cells as flat bytes for the compiled A* (the grid's own kept, as :meth:`_free_list`)."""
        if blocked is not self.blocked:
            return np.ascontiguousarray(~blocked).view(np.uint8).ravel()
        if self._free_u8 is None:
            self._free_u8 = np.ascontiguousarray(~self.blocked).view(np.uint8).ravel()
        return self._free_u8

    def _free_list(self, blocked: np.ndarray) -> list[bool]:
        """The free cells as a flat list (the grid's own kept: plans without discs ask for it every time)."""
        if blocked is not self.blocked:
            return (~blocked).ravel().tolist()  # type: ignore[no-any-return]
        if self._free is None:
            self._free = (~self.blocked).ravel().tolist()
        return self._free

    def _no_path(self, s: tuple[int, int], g: tuple[int, int]) -> str:
        return f"no path from ({self.centre(s)[0]:.2f}, {self.centre(s)[1]:.2f}) to ({self.centre(g)[0]:.2f}, {self.centre(g)[1]:.2f})"

    def _connected(self, blocked: np.ndarray, s: tuple[int, int], g: tuple[int, int]) -> bool:
        """Whether free cells s and g lie in one 4-connected region of ``blocked``'s free space."""
        if self._components is None:
            self._components = self._label()
        base = self._components
        if base[s] != base[g]:
            return False  # apart without the discs already
        labels, _ = ndgrid.label(~blocked)  # 4-connected (the default structure)
        return bool(labels[s] == labels[g])

    def _smooth(self, start: Point, pts: list[Point], blocked: np.ndarray) -> list[Point]:
        """Line-of-sight shortening: from each kept point, on to the farthest point in plain sight.

        The farthest candidates are tested a batch at a time (:meth:`lines_free`), which
        picks the same point as testing them one by one from the farthest down.
        """
        out: list[Point] = []
        here = start
        i = 0
        while i < len(pts):
            j = len(pts) - 1
            while j > i:
                lo = max(i + 1, j - SMOOTH_BATCH + 1)
                ok = np.flatnonzero(self.lines_free(here, pts[lo : j + 1], blocked))
                if ok.size:
                    j = lo + int(ok[-1])
                    break
                j = lo - 1
            out.append(pts[j])
            here = pts[j]
            i = j + 1
        return out

    # ------------------------------------------------- reachability (checks)
    def component(self, p: Point) -> int:
        """Which connected region of free space ``p`` (or the free cell nearest to it) is in; -1: none."""
        if self._components is None:
            self._components = self._label()
        c = self.nearest_free(self.cell_of(p))
        return -1 if c is None else int(self._components[c])

    def _label(self) -> np.ndarray:
        """Connected regions of free cells, 4-connected (as A* without corner cutting).

        Numbered 1, 2, ... in the order of each region's first cell in row-major order (what
        ``scipy.ndimage.label`` does; ``tests/test_world_fast_paths.py`` checks it against
        a plain flood fill).
        """
        labels, _ = ndgrid.label(~self.blocked)  # 4-connected (the default structure)
        return labels.astype(np.int32, copy=False)

    def passable(self, wall: Wall, door: Door) -> bool:
        """Whether a person can walk through a door gap, staying near it.

        From any free cell on one side of the wall to any on the other,
        within a box around the gap (0.5 m beyond its edges along the wall,
        0.6 m beyond the clearance zone across it).
        """
        (cx, cy), (ux, uy) = door_frame(wall, door)
        nx_, ny_ = -uy, ux
        half_w = door.width / 2 + 0.5
        half_t = wall.thickness / 2
        half_d = half_t + self.clearance + 0.6
        corners = [(cx + a * half_w * ux + b * half_d * nx_, cy + a * half_w * uy + b * half_d * ny_) for a in (-1, 1) for b in (-1, 1)]
        lo = self.cell_of((min(p[0] for p in corners), min(p[1] for p in corners)))
        hi = self.cell_of((max(p[0] for p in corners), max(p[1] for p in corners)))
        # Each cell's (along, across) in the door's frame, elementwise as where() computes it in floats.
        xs = self.x0 + (np.arange(lo[0], hi[0] + 1) + 0.5) * self.cell
        ys = self.y0 + (np.arange(lo[1], hi[1] + 1) + 0.5) * self.cell
        dx, dy = (xs - cx)[:, None], (ys - cy)[None, :]
        along, across = dx * ux + dy * uy, dx * nx_ + dy * ny_
        box = ~self.blocked[lo[0] : hi[0] + 1, lo[1] : hi[1] + 1] & (np.abs(along) <= half_w) & (np.abs(across) <= half_d)
        # A walk from a cell on one side to one on the other within the box, 4-connected: the
        # breadth-first search of _passable_search, as one region shared by a source and a target.
        labels, _ = ndgrid.label(box)
        sources = np.unique(labels[box & (across > half_t)])
        targets = np.unique(labels[box & (across < -half_t)])
        return bool(np.intersect1d(sources, targets).size)

    def _passable_search(self, wall: Wall, door: Door) -> bool:
        """:meth:`passable` as the breadth-first search it stands for (the reference; tests compare them)."""
        (cx, cy), (ux, uy) = door_frame(wall, door)
        nx_, ny_ = -uy, ux
        half_w = door.width / 2 + 0.5
        half_t = wall.thickness / 2
        half_d = half_t + self.clearance + 0.6

        def where(c: tuple[int, int]) -> tuple[float, float]:
            x, y = self.centre(c)
            dx, dy = x - cx, y - cy
            return dx * ux + dy * uy, dx * nx_ + dy * ny_

        corners = [(cx + a * half_w * ux + b * half_d * nx_, cy + a * half_w * uy + b * half_d * ny_) for a in (-1, 1) for b in (-1, 1)]
        lo = self.cell_of((min(p[0] for p in corners), min(p[1] for p in corners)))
        hi = self.cell_of((max(p[0] for p in corners), max(p[1] for p in corners)))
        box = set()
        sources, targets = [], set()
        for i in range(lo[0], hi[0] + 1):
            for j in range(lo[1], hi[1] + 1):
                if self.blocked[i, j]:
                    continue
                s, t = where((i, j))
                if abs(s) > half_w or abs(t) > half_d:
                    continue
                box.add((i, j))
                if t > half_t:
                    sources.append((i, j))
                elif t < -half_t:
                    targets.add((i, j))
        seen = set(sources)
        todo = deque(sources)
        while todo:
            c = todo.popleft()
            if c in targets:
                return True
            for d in ((1, 0), (-1, 0), (0, 1), (0, -1)):
                n = (c[0] + d[0], c[1] + d[1])
                if n in box and n not in seen:
                    seen.add(n)
                    todo.append(n)
        return False

