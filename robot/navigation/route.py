"""The way to a moving person on the floor plan: what the follower steers along through doors and round corners.

Steering along the partner's own trail works in an open room. Through a door frame it
does not: a person cuts the corner close to the jamb (a walker is 0.4 m wide, the
PeopleBot 0.43 x 0.51 m and turns on its centre), the trail hugs the jamb, the dynamic
window finds no arc that reaches it without touching the frame, and the robot stalls on
this side of the wall until the wall hides the partner (issue 26: "the robot never
entered the room it was led to"). A real follower with a map does what the player does
for a go-to: it plans.

:class:`Route` keeps the planner's occupancy grid (the map server's floor plan, inflated
by the robot's radius: :class:`~robot.navigation.grid.OccupancyGrid`) and the localised
pose, and whenever the straight line from the robot to the partner is not roomy on the
grid (a door, a corner, furniture between them) it plans the shortest free path to the
partner (at most every :data:`REPLAN` s, or sooner when the partner has moved
:data:`MOVED` m from the planned end) and answers the pure-pursuit point
:data:`LOOKAHEAD` m ahead on it, in the odometry frame. The path keeps to the middle of
doorways (the grid's clearance cost), so the robot passes a 0.9 m door or a 1.0 m
corridor with a hand's width either side. With a clear line (most of an open room) it
answers None and the follower steers along the trail as before. The laser's dynamic
window still has the last word on every command: the grid knows only the floor plan.

The laser looks forwards only (180 degrees). Turning on the spot or backing off beside a
door frame, the robot's rear corners sweep ground it does not see, and a wall corner
behind it was touched (issue 26). :meth:`Route.obstacles_near` gives the floor plan's
walls and furniture round the robot (the outline cells of the grid's occupied cells within
:data:`NEAR` m) as robot-frame points, which the follower hands to the dynamic window
with the laser's echoes: every arc, turning on the spot and backing off included, keeps
the footprint off what the map holds all round, not just in front.

People standing in the way (issue 26: a bystander standing in front of a door while the partner
walks through it) are not on the floor plan, and the dynamic window alone, steering at the
door, stops in front of them for good. :meth:`Route.goal` takes the odom-frame centres of
the people standing round the robot (the attention's confirmed tracks, partner left out) and
plans on a copy of the grid with a disc of :data:`BODY` m round each
(:meth:`~robot.navigation.grid.OccupancyGrid.with_obstacles`, inflated by the robot's radius
like a wall): the path goes round them (the other half of the door), or through no gap too
narrow to pass with a body's clearance. The copy is made again only when they moved
:data:`MOVED` m.

Frames: the partner's track and the odometry are in ``odom``; the plan is in ``map``.
Each localised pose (``/robot/localisation/pose``, map frame) is paired with the
odometry pose current when it arrived (what the player does), which gives the
odom -> map transform until the next one.
"""

from __future__ import annotations

import math

import numpy as np

from .grid import NoPathError, OccupancyGrid
from .local import carrot

Point = tuple[float, float]
Pose = tuple[float, float, float]

#: m: how far ahead on the path the follower steers (the player's pure pursuit uses 0.7 m).
LOOKAHEAD = 0.35
#: s: the path to a walking partner is planned again at most this often.
REPLAN = 0.5
#: m: ... or sooner, when the partner is this far from the planned path's end.
MOVED = 0.4
#: m: a path vertex this close to the robot is reached (the next leg is steered along).
REACHED = 0.2
#: m: the floor plan's obstacle outlines within this distance of the robot's centre are handed to the dynamic window.
NEAR = 1.2
#: m: a standing person's body on the plan (a person is about 0.4-0.5 m across; the robot's radius is added by the grid)
BODY = 0.3
#: m: only standing people this close to the robot are put on the plan (the local problem; the plan is replanned as it goes)
PEOPLE_REACH = 3.0


def body_points(centres: np.ndarray, radius: float = BODY, cell: float = 0.05) -> np.ndarray:
    """Points filling a disc of ``radius`` round each centre ((N, 2) in, (M, 2) out, same frame), a
    cell or less apart, so that marking their cells occupies the whole disc."""
    c = np.asarray(centres, dtype=float).reshape(-1, 2)
    if not len(c):
        return np.zeros((0, 2))
    r = np.arange(0.0, radius + 1e-9, cell / 2)
    out = [c]
    for rr in r[1:]:
        n = max(int(math.ceil(2 * math.pi * rr / (cell / 2))), 6)
        a = np.arange(n) * (2 * math.pi / n)
        ring = np.column_stack((np.cos(a), np.sin(a))) * rr
        out.append((c[:, None, :] + ring[None, :, :]).reshape(-1, 2))
    return np.concatenate(out)


class Route:
    """Path to the partner on the floor plan (see the module docstring)."""

    def __init__(self) -> None:
        self.grid: OccupancyGrid | None = None
        self._map_pose: Pose | None = None
        self._odom_at: Pose | None = None
        # odom -> map as (odom pose, map pose, sx, sy, dx, dy, cos, sin), worked out once per pose pair (to_map runs
        # hundreds of times a control step in the follower's walk-on search); the same arithmetic as _rebase
        self._tf: tuple[object, object, float, float, float, float, float, float] | None = None
        self._occ: tuple[np.ndarray, bytes] | None = None  # the grid's occupied cells as bytes (in_sight's look-ups)
        self.path: list[Point] | None = None  # map frame, first point where the robot was when planned
        self._planned_at = -math.inf
        self.plans = 0  # how many paths were planned (for tests and the run's curiosity)
        self._outline = np.zeros((0, 2))  # map-frame centres of the occupied cells next to free ones
        self._people: np.ndarray = np.zeros((0, 2))  # map-frame centres of the standing people on the plan
        self._with_people: OccupancyGrid | None = None  # the grid with them (None: nobody standing near)
        self.rooms: tuple[np.ndarray, ...] = ()  # map-frame outlines of the flat's rooms (the map's <room>s)
        self._room_edges: tuple[list[tuple[float, float, float, float]], ...] = ()  # each room's edges (x1, y1, x2, y2)
        self._clear: tuple[np.ndarray, list[float]] | None = None  # the grid's clearance as a flat list (clearance's look-ups)

    def set_grid(self, grid: OccupancyGrid) -> None:
        self.grid = grid
        occ = grid.occupied
        edge = occ & ~_eroded(occ)
        ii, jj = np.nonzero(edge)
        self._outline = np.column_stack((grid.origin[0] + (ii + 0.5) * grid.cell, grid.origin[1] + (jj + 0.5) * grid.cell))

    def set_rooms(self, rooms: tuple[np.ndarray, ...]) -> None:
        """The flat's rooms (map frame, as the map server's ``<room>`` outlines): the flat's inside."""
        self.rooms = tuple(np.asarray(r, dtype=float) for r in rooms if len(r) >= 3)
        self._room_edges = tuple([(float(r[i][0]), float(r[i][1]), float(r[(i + 1) % len(r)][0]), float(r[(i + 1) % len(r)][1]))
                                  for i in range(len(r))] for r in self.rooms)

    def room_at(self, p: Point) -> np.ndarray | None:
        """The outline (map frame) of the room holding ``p`` (odom), None outside the flat or
        without a plan or rooms (see :meth:`inside`)."""
        if not self.ready or not self.rooms:
            return None
        x, y = self.to_map(p)
        for r, edges in zip(self.rooms, self._room_edges):
            # _inside's even-odd test for one point, in plain floats (the same operations; an edge whose ends
            # lie on one side of y is skipped there as here, where its division would be by zero)
            inside = False
            for x1, y1, x2, y2 in edges:
                if (y1 > y) != (y2 > y) and x < (x2 - x1) * (y - y1) / (y2 - y1) + x1:
                    inside = not inside
            if inside:
                return r
        return None

    def inside(self, p: Point) -> bool:
        """Whether ``p`` (odom) lies inside the flat: in one of its rooms. True without a plan or
        without rooms (nothing says where the flat ends: the laser is the only judge)."""
        if not self.ready or not self.rooms:
            return True
        return self.room_at(p) is not None

    def on_pose(self, map_pose: Pose, odom_pose: Pose | None) -> None:
        """A localised pose and the odometry pose current when it arrived."""
        if odom_pose is not None:
            self._map_pose, self._odom_at = map_pose, odom_pose

    def clear(self) -> None:
        """Forget the path (a new following begins); the grid and the transform stay."""
        self.path = None
        self._planned_at = -math.inf

    @property
    def ready(self) -> bool:
        return self.grid is not None and self._map_pose is not None

    def to_map(self, p: Point) -> Point:
        """An odom-frame point in the map frame (needs :attr:`ready`): ``_rebase(p, odom pose, map pose)``, with
        the pose pair's cosine and sine kept while the pair stays (the same operations, so the same floats)."""
        tf = self._tf
        if tf is None or tf[0] is not self._odom_at or tf[1] is not self._map_pose:
            sx, sy, sth = self._odom_at  # type: ignore[misc]
            dx_, dy_, dth = self._map_pose  # type: ignore[misc]
            a = dth - sth
            tf = self._tf = (self._odom_at, self._map_pose, sx, sy, dx_, dy_, math.cos(a), math.sin(a))
        _, _, sx, sy, dx_, dy_, c, s = tf
        dx, dy = p[0] - sx, p[1] - sy
        return dx_ + c * dx - s * dy, dy_ + s * dx + c * dy

    def to_odom(self, p: Point) -> Point:
        """A map-frame point in the odometry frame (needs :attr:`ready`)."""
        return _rebase(p, self._map_pose, self._odom_at)  # type: ignore[arg-type]

    def clearance(self, robot: Point) -> float:
        """Metres from ``robot`` (odom) to the floor plan's nearest wall or furniture (inf without a plan)."""
        if not self.ready:
            return math.inf
        g = self.grid
        assert g is not None
        mx, my = self.to_map(robot)
        i, j = int((mx - g.origin[0]) / g.cell), int((my - g.origin[1]) / g.cell)  # g.cell_of
        if not (0 <= i < g.nx and 0 <= j < g.ny):
            return 0.0
        cl = self._clear
        if cl is None or cl[0] is not g.clearance:
            cl = self._clear = (g.clearance, g.clearance.ravel().tolist())
        return cl[1][i * g.ny + j]  # type: ignore[no-any-return]

    def in_sight(self, robot: Point, target: Point) -> bool:
        """Whether the segment robot-target (odom) crosses no wall or furniture of the floor plan
        (True without a plan: the laser then is the only judge)."""
        if not self.ready:
            return True
        g = self.grid
        assert g is not None
        a, b = self.to_map(robot), self.to_map(target)
        n = max(int(math.hypot(b[0] - a[0], b[1] - a[1]) / (g.cell / 2)) + 2, 2)
        occ = self._occ
        if occ is None or occ[0] is not g.occupied:
            occ = self._occ = (g.occupied, np.ascontiguousarray(g.occupied, dtype=bool).tobytes())
        cells = occ[1]
        # n samples t = k / (n - 1) along a -> b (np.linspace's: k * (1 / (n - 1)), the last exactly 1), each cell
        # by truncation (astype(int)), cells off the grid skipped: the answer of the vectorised form
        # (_in_sight_reference), in plain floats, as most segments here are a few cells long
        ax, ay, ox, oy, cell, nx, ny = a[0], a[1], g.origin[0], g.origin[1], g.cell, g.nx, g.ny
        ddx, ddy = b[0] - ax, b[1] - ay
        step = 1.0 / (n - 1)
        last = n - 1
        for k in range(n):
            t = 1.0 if k == last else k * step
            i = int((ax + ddx * t - ox) / cell)
            j = int((ay + ddy * t - oy) / cell)
            if 0 <= i < nx and 0 <= j < ny and cells[i * ny + j]:
                return False
        return True

    def obstacles_near(self, robot: Pose) -> np.ndarray:
        """The floor plan's obstacle outlines within :data:`NEAR` m of ``robot`` (odom pose), robot frame, (N, 2)."""
        if not self.ready or not len(self._outline):
            return np.zeros((0, 2))
        mx, my, mth = self._map_pose  # type: ignore[misc]
        oth = self._odom_at[2]  # type: ignore[index]
        x, y = self.to_map(robot[:2])
        th = robot[2] + mth - oth
        o = self._outline
        dx, dy = o[:, 0] - x, o[:, 1] - y
        keep = (np.abs(dx) < NEAR) & (np.abs(dy) < NEAR)
        dx, dy = dx[keep], dy[keep]
        c, s = math.cos(th), math.sin(th)
        return np.column_stack((c * dx + s * dy, -s * dx + c * dy))

    def _grid_with(self, standing: np.ndarray | None, robot: Point) -> OccupancyGrid:
        """The grid with the standing people near ``robot`` (map) on it; the floor plan's grid without any."""
        grid = self.grid
        assert grid is not None
        if standing is None or not len(standing):
            self._people, self._with_people = np.zeros((0, 2)), None
            return grid
        pts = np.array([self.to_map((float(x), float(y))) for x, y in standing])
        pts = pts[np.hypot(pts[:, 0] - robot[0], pts[:, 1] - robot[1]) <= PEOPLE_REACH]
        if not len(pts):
            self._people, self._with_people = np.zeros((0, 2)), None
            return grid
        old = self._people
        same = (self._with_people is not None and len(old) == len(pts)
                and bool((np.hypot(*(old - pts).T) < MOVED).all()))
        if not same:
            self._people, self._with_people = pts, grid.with_obstacles(body_points(pts, cell=grid.cell))
            self._planned_at = -math.inf  # the way may have changed
        assert self._with_people is not None
        return self._with_people

    def goal(self, now: float, robot: Point, target: Point, standing: np.ndarray | None = None) -> Point | None:
        """The odom-frame point to steer at on the way from ``robot`` to ``target`` (both odom), or
        None when the straight line is roomy (steer as before) or the plan does not help.
        ``standing``: (N, 2) odom-frame centres of people standing about (not the partner), planned round."""
        if not self.ready:
            return None
        r, q = self.to_map(robot), self.to_map(target)
        grid = self._grid_with(standing, r)
        if grid.line_free(r, q):
            self.path = None
            return None
        path = self.path
        if path is None or now - self._planned_at >= REPLAN or math.hypot(q[0] - path[-1][0], q[1] - path[-1][1]) > MOVED:
            try:
                path = grid.plan(r, q)
            except NoPathError:
                self.path = None
                return None
            self.path, self._planned_at = path, now
            self.plans += 1
        while len(path) > 2 and math.hypot(r[0] - path[1][0], r[1] - path[1][1]) < REACHED:
            path.pop(0)
        if len(path) < 2:
            return None
        return self.to_odom(carrot(path[0], path[1], r, LOOKAHEAD))


def _eroded(occ: np.ndarray) -> np.ndarray:
    """``scipy.ndimage.binary_erosion(occ, border_value=1)`` (the 4-neighbour cross), in numpy: SciPy's
    ndimage costs start-up time (tests/test_startup_imports.py) and a cell with all four neighbours
    occupied is all this needs."""
    p = np.pad(occ.astype(bool), 1, constant_values=True)
    return p[1:-1, 1:-1] & p[:-2, 1:-1] & p[2:, 1:-1] & p[1:-1, :-2] & p[1:-1, 2:]


def _in_sight_reference(g: OccupancyGrid, a: Point, b: Point) -> bool:
    """:meth:`Route.in_sight`'s test on map-frame points, vectorised (the reference its loop is checked against)."""
    n = max(int(math.hypot(b[0] - a[0], b[1] - a[1]) / (g.cell / 2)) + 2, 2)
    t = np.linspace(0.0, 1.0, n)
    i = ((a[0] + (b[0] - a[0]) * t - g.origin[0]) / g.cell).astype(int)
    j = ((a[1] + (b[1] - a[1]) * t - g.origin[1]) / g.cell).astype(int)
    ok = (i >= 0) & (i < g.nx) & (j >= 0) & (j < g.ny)
    return not bool(g.occupied[i[ok], j[ok]].any())


def _rebase(p: Point, src: tuple[float, float, float], dst: tuple[float, float, float]) -> Point:
    """``p`` given in the frame where the robot's pose is ``src``, in the frame where the same pose is ``dst``
    (the odom -> map pairing and back)."""
    sx, sy, sth = src
    dx_, dy_, dth = dst
    a = dth - sth
    c, s = math.cos(a), math.sin(a)
    dx, dy = p[0] - sx, p[1] - sy
    return dx_ + c * dx - s * dy, dy_ + s * dx + c * dy
