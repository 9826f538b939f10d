"""Where to stand to see what the partner points at: sight lines over the floor plan and a viewpoint.

Pure functions, no bus and no time. The object attention knows roughly where
an object is from the pointing ray (where it comes down on a table top or the
floor) but the camera may not see that spot from where the robot stopped: the
partner stands in front of it, a sofa or a wall is in the way (the robot is
still at the door of the previous room), or it is out of the camera's range.
:func:`sight_clear` tells from the robot's own floor plan (walls, furniture
with their heights) and the people it tracks whether the camera at a point
sees a target; :func:`viewpoint` finds the nearest place, reachable on a
drive (through a door too), from which it does, so the robot moves there and looks
again, as a real robot would instead of saying it found nothing.

The plan's furniture hides a sight line only where the line, at its height
there, passes between the piece's bottom and top (the camera looks over a low
table at what is behind it, under a table top at the floor), as the camera
model's own sight lines do; people are upright cylinders taller than the
camera.
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Sequence

import numpy as np

from robot.floorplan import FloorPlan
from robot.footprint import BODY, HALF_WIDTH

Point = tuple[float, float]

CAMERA_RANGE = (0.8, 3.0)  # m: where the camera's object detector is reliable (its range is 0.3-3.5 m)
BODY_RADIUS = 0.3  # m: a person's body and arm, seen from the camera
ROBOT_CLEARANCE = 0.35  # m: the robot's half-width (0.43 m wide) and a margin, to walls and furniture
#: m: the player's social gap between its footprint and someone standing by its goal
#: (robot.navigation.player.GOTO_SOCIAL_GAP): a goal with someone standing within BODY + this + HALF_WIDTH
#: (0.765 m) of it is theirs, and the player stops short of it, "as near as it politely can"
STAND_GAP = 0.30
#: m: never stand or drive closer than this to a person's centre: where the player can stand (the radius
#: above and 5 cm of the tracker's noise on someone standing). At 0.7 m the viewpoint beside the partner was
#: a place the player would not take: it stopped 0.3 m short, where the bookcase hid the box
#: (perceive/view_round_corner seeds 1, 3)
PERSON_CLEARANCE = BODY + STAND_GAP + HALF_WIDTH + 0.05
RINGS = (1.2, 1.5, 1.9, 2.4)  # m from the target: where a viewpoint may be
DIRECTIONS = 24  # per ring
DIRECTIONS_FINE = 72  # per ring, when none of the DIRECTIONS sees the target (a narrow gap between furniture)
MAX_TRAVEL = 3.5  # m: a viewpoint farther than this drive is not worth it
ROBOT_HEIGHT = 1.45  # m: furniture whose underside is higher does not stop the base
GRID_CELL = 0.1  # m: the drive's grid
GRID_MARGIN = 0.01  # m: a grid cell keeps this more than the clearances (a straight leg between two cells dips by less)
#: m from the hand: how far out a pointing ray is followed (across a living room: she points from the
#: door at the remote on the coffee table 4 m away, fresh3 angle_long_tour; beyond the camera's range the
#: robot comes closer to look)
POINT_REACH = 5.0
OBJECT_BAND = 0.35  # m: how high above a surface an object a person points at reaches (most household objects)
DRIVE_CLEARANCE = 0.8  # of the standing clearances, kept on the way (the player's own local planner keeps the footprint clear)
ARRIVE_TOLERANCE = 0.2  # m: the tolerance of the POSE the object attention sends the player (move_to)
LEG_LEAVE = 0.3  # m: the start of a straight leg may run closer to something than the clearance (where the robot stands)
MAX_LEGS = 3  # straight legs to a viewpoint round corners (the player drives each pose it is sent straight)
#: m of travel a waypoint costs (the robot stops and turns there): of two ways about as long, the straight one
WAYPOINT_COST = 0.3
APART_TURN = math.radians(40.0)  # a view this far round the target from the first: depth there is mostly across the image
MAX_ROUTE = 5.0  # m: the longest drive, round corners, to a viewpoint (through a door into the next room)


def _clip(a: Point, b: Point, poly: Sequence[Point]) -> tuple[float, float] | None:
    """The parameter interval [t0, t1] of segment a->b inside a convex polygon (either winding)
    (Cyrus-Beck), or None if it misses it."""
    n = len(poly)
    area = sum(poly[i][0] * poly[(i + 1) % n][1] - poly[(i + 1) % n][0] * poly[i][1] for i in range(n))
    sign = 1.0 if area >= 0 else -1.0
    dx, dy = b[0] - a[0], b[1] - a[1]
    t0, t1 = 0.0, 1.0
    for i in range(n):
        (x1, y1), (x2, y2) = poly[i], poly[(i + 1) % n]
        # inward normal of edge i (left of the edge for a counter-clockwise polygon)
        nx, ny = -(y2 - y1) * sign, (x2 - x1) * sign
        num = nx * (a[0] - x1) + ny * (a[1] - y1)  # >= 0: a is inside this edge's half-plane
        den = nx * dx + ny * dy
        if abs(den) < 1e-12:
            if num < 0:
                return None
            continue
        t = -num / den
        if den > 0:
            t0 = max(t0, t)
        else:
            t1 = min(t1, t)
        if t0 > t1:
            return None
    return t0, t1


def _point_polygon(p: Point, poly: Sequence[Point]) -> float:
    """Distance from a point to a convex polygon (0 inside)."""
    inside, best = True, math.inf
    n = len(poly)
    area = sum(poly[i][0] * poly[(i + 1) % n][1] - poly[(i + 1) % n][0] * poly[i][1] for i in range(n))
    for i in range(n):
        (x1, y1), (x2, y2) = poly[i], poly[(i + 1) % n]
        cross = (x2 - x1) * (p[1] - y1) - (y2 - y1) * (p[0] - x1)
        if (cross < 0) if area >= 0 else (cross > 0):
            inside = False
        dx, dy = x2 - x1, y2 - y1
        L = dx * dx + dy * dy
        t = 0.0 if L == 0 else max(0.0, min(1.0, ((p[0] - x1) * dx + (p[1] - y1) * dy) / L))
        best = min(best, math.hypot(p[0] - x1 - t * dx, p[1] - y1 - t * dy))
    return 0.0 if inside else best


def _blocks(plan: FloorPlan) -> list[tuple[tuple[Point, ...], float, float]]:
    """Every footprint of the plan with its vertical span: walls (floor to ceiling), furniture."""
    out: list[tuple[tuple[Point, ...], float, float]] = [(tuple((float(x), float(y)) for x, y in w.rectangle()), 0.0, math.inf) for w in plan.walls]
    out += [(o.points, o.bottom, o.top) for o in plan.obstacles]
    return out


def sight_clear(plan: FloorPlan, camera: tuple[float, float, float], target: tuple[float, float, float],
                people: Sequence[Point] = (), *, body_radius: float = BODY_RADIUS) -> bool:
    """Whether the straight line from ``camera`` (x, y, z) to ``target`` (x, y, z) passes no wall,
    no piece of furniture (between its bottom and top where the line crosses it) and no person
    (a cylinder of ``body_radius`` around each of ``people``, taller than the camera)."""
    a, b = (camera[0], camera[1]), (target[0], target[1])
    za, zb = camera[2], target[2]
    for poly, bottom, top in _blocks(plan):
        span = _clip(a, b, poly)
        if span is None:
            continue
        t0, t1 = span
        t1 = min(t1, 1.0 - 1e-6)  # the target's own support (the table it stands on) does not hide it
        if t1 <= t0:
            continue
        z0, z1 = za + t0 * (zb - za), za + t1 * (zb - za)
        if min(z0, z1) < top - 1e-9 and max(z0, z1) > bottom + 1e-9:
            return False
    dx, dy = b[0] - a[0], b[1] - a[1]
    length = math.hypot(dx, dy)
    for px, py in people:
        along = 0.0 if length == 0 else ((px - a[0]) * dx + (py - a[1]) * dy) / length
        if 0.0 < along < length - 0.1 and abs((px - a[0]) * dy - (py - a[1]) * dx) / max(length, 1e-9) < body_radius:
            return False  # nearer the camera than the target, across the line
    return True


def in_range(camera: tuple[float, float, float], target: tuple[float, float, float], rng: tuple[float, float] = CAMERA_RANGE) -> bool:
    """Whether the target lies within the camera's reliable object range."""
    return rng[0] <= math.dist(camera, target) <= rng[1]


def _free(plan_blocks: list[tuple[tuple[Point, ...], float, float]], p: Point, people: Sequence[Point], clearance: float, person_clearance: float) -> bool:
    for poly, bottom, _top in plan_blocks:
        if bottom < ROBOT_HEIGHT and _point_polygon(p, poly) < clearance:
            return False
    return all(math.hypot(p[0] - q[0], p[1] - q[1]) >= person_clearance for q in people)


def _inside_room(plan: FloorPlan, p: Point) -> bool:
    for room in plan.rooms:
        poly, inside, n = room.points, False, len(room.points)
        for i in range(n):
            (x1, y1), (x2, y2) = poly[i], poly[(i + 1) % n]
            if (y1 > p[1]) != (y2 > p[1]) and p[0] < x1 + (p[1] - y1) * (x2 - x1) / (y2 - y1):
                inside = not inside
        if inside:
            return True
    return not plan.rooms


def _inside_mask(xs: np.ndarray, ys: np.ndarray, poly: Sequence[Point]) -> np.ndarray:
    """Crossing-number point-in-polygon test for grids of points."""
    inside = np.zeros(xs.shape, dtype=bool)
    n = len(poly)
    for i in range(n):
        (x1, y1), (x2, y2) = poly[i], poly[(i + 1) % n]
        if y1 == y2:
            continue
        cross = (ys > y1) != (ys > y2)
        xint = x1 + (ys - y1) * (x2 - x1) / (y2 - y1)
        inside ^= cross & (xs < xint)
    return inside


def _edges_distance(xs: np.ndarray, ys: np.ndarray, poly: Sequence[Point]) -> np.ndarray:
    """Distance from grids of points to a polygon's edges (the outline; the inside is not 0)."""
    best = np.full(xs.shape, np.inf)
    n = len(poly)
    for i in range(n):
        (x1, y1), (x2, y2) = poly[i], poly[(i + 1) % n]
        dx, dy = x2 - x1, y2 - y1
        L = dx * dx + dy * dy
        t = np.zeros(xs.shape) if L == 0 else np.clip(((xs - x1) * dx + (ys - y1) * dy) / L, 0.0, 1.0)
        best = np.minimum(best, np.hypot(xs - x1 - t * dx, ys - y1 - t * dy))
    return best


def travel_map(plan: FloorPlan, robot: Point, people: Sequence[Point], *, reach: float, clearance: float, person_clearance: float,
               cell: float = GRID_CELL) -> tuple[np.ndarray, float, float]:
    """Driving distances (m) from ``robot`` over a grid of ``cell`` m around it (``reach`` m each
    way): cells ``clearance`` from walls and furniture and ``person_clearance`` from people,
    8-connected (Dijkstra); ``inf`` where it cannot drive. Returns the grid and its origin (x0, y0).
    The robot's own cell is always a start (it may stand closer to something than ``clearance``)."""
    n = int(math.ceil(2 * reach / cell)) + 1
    x0, y0 = robot[0] - reach, robot[1] - reach
    xs, ys = np.meshgrid(x0 + cell * np.arange(n), y0 + cell * np.arange(n), indexing="xy")
    occ = np.zeros(xs.shape, dtype=bool)
    near = np.full(xs.shape, np.inf)  # each cell's exact distance to the nearest footprint's edge
    for poly, bottom, _top in _blocks(plan):
        if bottom < ROBOT_HEIGHT:
            occ |= _inside_mask(xs, ys, poly)
            near = np.minimum(near, _edges_distance(xs, ys, poly))
    # Exactly as the legs are checked (:func:`straight_leg_free`), with ``GRID_MARGIN`` for a leg between
    # two cells passing a corner a little closer than either: the grid's distance transform (to the
    # centres of occupied cells) let the path run past the bookcase's end closer than the straight legs
    # may, and no leg reached it (perceive/view_round_corner seeds 1, 3: no route at all).
    free = ~occ & (near >= clearance + GRID_MARGIN)
    for px, py in people:
        free &= np.hypot(xs - px, ys - py) >= person_clearance + GRID_MARGIN
    dist = np.full(xs.shape, np.inf)
    si, sj = int(round((robot[1] - y0) / cell)), int(round((robot[0] - x0) / cell))
    dist[si, sj] = 0.0
    heap = [(0.0, si, sj)]
    steps = [(di, dj, cell * math.hypot(di, dj)) for di in (-1, 0, 1) for dj in (-1, 0, 1) if di or dj]
    while heap:
        d, i, j = heapq.heappop(heap)
        if d > dist[i, j] or d > reach:
            continue
        for di, dj, w in steps:
            a, b = i + di, j + dj
            if 0 <= a < n and 0 <= b < n and free[a, b] and d + w < dist[a, b]:
                dist[a, b] = d + w
                heapq.heappush(heap, (d + w, a, b))
    return dist, x0, y0


def straight_leg_free(plan_blocks: list[tuple[tuple[Point, ...], float, float]], people: Sequence[Point], start: Point, goal: Point, *,
                      clearance: float, person_clearance: float, leave: float = LEG_LEAVE, step: float = 0.05) -> bool:
    """Does the straight line from ``start`` to ``goal`` keep ``clearance`` from walls and furniture
    (exactly, on the footprints: a grid's cells err by their size) and ``person_clearance`` from
    people, the first ``leave`` m excepted (the robot may stand closer to something than the
    clearance)? The player drives a viewpoint's leg straight, so a viewpoint reached only round a
    corner is not one."""
    length = math.hypot(goal[0] - start[0], goal[1] - start[1])
    k = max(1, int(math.ceil(length / step)))
    for m in range(k + 1):
        if length * m / k < leave:
            continue
        q = (start[0] + (goal[0] - start[0]) * m / k, start[1] + (goal[1] - start[1]) * m / k)
        if not _free(plan_blocks, q, people, clearance, person_clearance):
            return False
    return True


def viewpoint(plan: FloorPlan, robot: Point, target: tuple[float, float, float], people: Sequence[Point] = (), *,
              camera_height: float, camera_offset: float = 0.0, max_travel: float = MAX_TRAVEL,
              clearance: float = ROBOT_CLEARANCE, person_clearance: float = PERSON_CLEARANCE,
              arrive: float = ARRIVE_TOLERANCE, apart_from: Point | None = None, spread: float = 0.0) -> tuple[float, float, float] | None:
    """The nearest pose (x, y, heading towards the target) from which the camera sees ``target``:
    in a room of the plan, ``clearance`` from walls and furniture and ``person_clearance`` from
    every person, reached by a straight drive from ``robot`` that keeps those clearances (the
    player drives the one leg it is sent straight: through a door only when the line passes it;
    at most ``max_travel`` m, :func:`travel_map`, :func:`straight_leg_free`), with the target in the camera's range
    and a clear sight line, also from ``arrive`` m either way (the player stops within its
    tolerance of the pose: a line grazing a sofa's corner from the pose itself is hidden from
    where it stops). Of equal travel, the one nearer 1.5 m from the target. None when
    there is no such place. :func:`viewpoint_route` also finds places reached only round a corner.
    With ``apart_from`` (where the camera saw the target from), only places that see it at least
    ``APART_TURN`` from that line of sight: two things one behind the other on it stand side by side there."""
    route = viewpoint_route(plan, robot, target, people, camera_height=camera_height, camera_offset=camera_offset, max_travel=max_travel,
                            clearance=clearance, person_clearance=person_clearance, arrive=arrive, max_legs=1, apart_from=apart_from, spread=spread)
    return None if route is None else route[-1]


def viewpoint_route(plan: FloorPlan, robot: Point, target: tuple[float, float, float], people: Sequence[Point] = (), *,
                    camera_height: float, camera_offset: float = 0.0, max_travel: float = MAX_ROUTE,
                    clearance: float = ROBOT_CLEARANCE, person_clearance: float = PERSON_CLEARANCE,
                    arrive: float = ARRIVE_TOLERANCE, max_legs: int = MAX_LEGS,
                    apart_from: Point | None = None, spread: float = 0.0) -> list[tuple[float, float, float]] | None:
    """Like :func:`viewpoint`, but a place reached only round a corner (a sofa's end, a door
    frame, the partner) counts too: the way there is the grid's shortest path (:func:`travel_map`)
    cut into at most ``max_legs`` straight legs that keep the clearances (:func:`_legs`), since the
    player drives each pose it is sent on a straight leg from the previous one. Returns the poses
    to send one after the other (each waypoint heading along its next leg; the last the viewpoint,
    heading towards the target), at most ``max_travel`` m of legs in all; None when no place the
    robot can reach sees the target; ``apart_from`` as in :func:`viewpoint`.
    The grid's way hugs a corner at the legs' clearance (0.28 m), so a waypoint on it, where the robot
    turns, may lie closer to the corner than the robot stands (``_legs`` takes the farthest point a leg
    reaches when none keeps the standing clearance): the player, turning there, stood blocked 0.4 m short
    of one 0.33 m from a bookcase's end (perceive/view_round_corner seed 9). Such a route is planned again
    over a grid that keeps the standing clearance from furniture (the way round the corner a little wider),
    and that route is taken when there is one."""
    def plan_over(grid_clearance: float) -> list[tuple[float, float, float]] | None:
        return _route(plan, robot, target, people, camera_height=camera_height, camera_offset=camera_offset, max_travel=max_travel,
                      clearance=clearance, person_clearance=person_clearance, arrive=arrive, max_legs=max_legs, apart_from=apart_from,
                      spread=spread, grid_clearance=grid_clearance)

    route = plan_over(clearance * DRIVE_CLEARANCE)
    if route is None or len(route) < 2:
        return route
    every = _blocks(plan)
    drive_p = person_clearance * DRIVE_CLEARANCE
    if all(_free(every, (x, y), people, max(clearance * DRIVE_CLEARANCE, ROBOT_CLEARANCE), drive_p) for x, y, _ in route[:-1]):
        return route
    wide = plan_over(max(clearance * DRIVE_CLEARANCE, ROBOT_CLEARANCE))
    return route if wide is None else wide


def _route(plan: FloorPlan, robot: Point, target: tuple[float, float, float], people: Sequence[Point], *,
           camera_height: float, camera_offset: float, max_travel: float, clearance: float, person_clearance: float,
           arrive: float, max_legs: int, apart_from: Point | None, spread: float,
           grid_clearance: float) -> list[tuple[float, float, float]] | None:
    """:func:`viewpoint_route` over a grid keeping ``grid_clearance`` from walls and furniture."""
    every = _blocks(plan)
    seen_from = None if apart_from is None else math.atan2(apart_from[1] - target[1], apart_from[0] - target[0])
    blocks = [(poly, bottom, top) for poly, bottom, top in every
              if min(math.hypot(x - target[0], y - target[1]) for x, y in poly) < max(RINGS) + 1.0 or top == math.inf]
    drive_c, drive_p = clearance * DRIVE_CLEARANCE, person_clearance * DRIVE_CLEARANCE
    dist, gx, gy = travel_map(plan, robot, people, reach=max_travel, clearance=grid_clearance, person_clearance=drive_p)
    n = dist.shape[0]
    best: tuple[float, list[tuple[float, float, float]]] | None = None
    # Every DIRECTIONS-th direction first; only when none of those sees the target, the ones between
    # them (DIRECTIONS_FINE): the one gap between two pieces of furniture a plant behind an armchair is
    # seen through (between the armchair's and the sofa's corners, 8 degrees wide: generated tour 9100-11)
    # falls between two 15-degree directions.
    passes = ([(r, 2 * math.pi * k / DIRECTIONS) for r in RINGS for k in range(DIRECTIONS)],
              [(r, 2 * math.pi * k / DIRECTIONS_FINE) for r in RINGS for k in range(DIRECTIONS_FINE) if k % (DIRECTIONS_FINE // DIRECTIONS)])
    for pass_ in passes:
        if best is not None:
            break  # the coarse directions found a place
        for r, a in pass_:
            if seen_from is not None and abs(math.remainder(a - seen_from, 2 * math.pi)) < APART_TURN:
                continue
            q = (target[0] + r * math.cos(a), target[1] + r * math.sin(a))
            i, j = int(round((q[1] - gy) / GRID_CELL)), int(round((q[0] - gx) / GRID_CELL))
            if not (0 <= i < n and 0 <= j < n):
                continue
            if not math.isfinite(float(dist[i, j])):
                continue
            straight = math.hypot(q[0] - robot[0], q[1] - robot[1])
            if straight > max_travel or float(dist[i, j]) > max_travel + GRID_CELL or (best is not None and straight + 0.5 * abs(r - 1.5) >= best[0]):
                continue  # no way there is shorter than the straight line
            heading = math.atan2(target[1] - q[1], target[0] - q[0])
            cam = (q[0] + camera_offset * math.cos(heading), q[1] + camera_offset * math.sin(heading), camera_height)
            if not in_range(cam, target) or not _inside_room(plan, q) or not _free(blocks, q, people, clearance, person_clearance):
                continue
            if not all(sight_clear(plan, (cam[0] + dx, cam[1] + dy, camera_height), target, people)
                       for dx, dy in ((0.0, 0.0), (arrive, 0.0), (-arrive, 0.0), (0.0, arrive), (0.0, -arrive))):
                continue  # the player stops within ``arrive`` of the pose: the view must hold there too
            if spread > 0.0:
                # The spot is known only to ``spread`` (her aim over the way from her hand to it): the view must
                # hold to either side of it too, from the pose and from where the player may stop (a line that
                # just clears an armchair's corner to the estimate is hidden to the basket 4 cm beside it).
                ux, uy = -math.sin(heading) * spread, math.cos(heading) * spread
                if not all(sight_clear(plan, (cam[0] + dx, cam[1] + dy, camera_height), (target[0] + sx, target[1] + sy, target[2]), people)
                           for sx, sy in ((ux, uy), (-ux, -uy))
                           for dx, dy in ((0.0, 0.0), (arrive, 0.0), (-arrive, 0.0), (0.0, arrive), (0.0, -arrive))):
                    continue
            if straight_leg_free(every, people, robot, q, clearance=drive_c, person_clearance=drive_p):
                points = [q]
            elif max_legs > 1:
                cut = _legs(every, people, robot, q, _grid_path(dist, gx, gy, (i, j)), clearance=drive_c, person_clearance=drive_p)
                if cut is None or len(cut) > max_legs:
                    continue
                points = cut
            else:
                continue
            travel = sum(math.dist(p0, p1) for p0, p1 in zip([robot, *points[:-1]], points))
            cost = travel + 0.5 * abs(r - 1.5) + WAYPOINT_COST * (len(points) - 1)
            if travel > max_travel or (best is not None and cost >= best[0]):
                continue
            poses = [(p[0], p[1], math.atan2(nxt[1] - p[1], nxt[0] - p[0])) for p, nxt in zip(points[:-1], points[1:])]
            best = (cost, [*poses, (q[0], q[1], heading)])
    return None if best is None else best[1]


def _grid_path(dist: np.ndarray, gx: float, gy: float, cell: tuple[int, int]) -> list[Point]:
    """The grid's shortest way from the robot (distance 0) to ``cell``, as points from the robot's end
    (steepest descent over the driving distances of :func:`travel_map`)."""
    n = dist.shape[0]
    i, j = cell
    out = [(gx + j * GRID_CELL, gy + i * GRID_CELL)]
    while dist[i, j] > 0.0:
        nxt = min(((i + di, j + dj) for di in (-1, 0, 1) for dj in (-1, 0, 1) if (di or dj) and 0 <= i + di < n and 0 <= j + dj < n),
                  key=lambda c: (float(dist[c]), c))
        if not dist[nxt] < dist[i, j]:
            break
        i, j = nxt
        out.append((gx + j * GRID_CELL, gy + i * GRID_CELL))
    return out[::-1]


def _legs(plan_blocks: list[tuple[tuple[Point, ...], float, float]], people: Sequence[Point], robot: Point, goal: Point, path: list[Point], *,
          clearance: float, person_clearance: float) -> list[Point] | None:
    """The grid path cut into straight legs that keep the clearances (exactly, :func:`straight_leg_free`):
    from each end, the farthest point of the path a straight leg reaches that keeps the standing
    clearance ``ROBOT_CLEARANCE`` as a waypoint (the robot turns there: its corners sweep wider than
    its sides, and the player stopped short of a waypoint 0.29 m from a bookcase's corner,
    perceive/view_round_corner seeds 0, 5), else the farthest it reaches; the waypoints and ``goal``
    last. None when a stretch of the path cannot be driven straight at all."""
    pts = [*path[1:-1], goal] if len(path) > 1 else [goal]
    out: list[Point] = []
    here, first = robot, True
    k = 0
    while k < len(pts):
        reach = None
        loose = None
        for m in range(len(pts) - 1, k - 1, -1):
            if straight_leg_free(plan_blocks, people, here, pts[m], clearance=clearance, person_clearance=person_clearance,
                                 leave=LEG_LEAVE if first else 0.0):
                loose = m if loose is None else loose
                if m == len(pts) - 1 or _free(plan_blocks, pts[m], people, max(clearance, ROBOT_CLEARANCE), person_clearance):
                    reach = m
                    break
        reach = loose if reach is None else reach
        if reach is None:
            return None
        here, first = pts[reach], False
        out.append(here)
        k = reach + 1
        if len(out) > MAX_LEGS:
            return None
    return out


def pointed_spot(plan: FloorPlan, hand: tuple[float, float, float], direction: float, elevation: float, *,
                 band: float = OBJECT_BAND, reach: float = POINT_REACH, step: float = 0.05) -> tuple[float, float, float] | None:
    """Where on the plan a pointing ray (from ``hand``, map frame, ``direction`` and ``elevation``
    in radians) most likely shows an object: the middle of the last stretch of the ray that runs
    at most ``band`` m above what is under it (a piece of furniture's top, or the floor), before
    it meets a wall, the floor or a piece of furniture (where the ray ends: a first stretch low
    over a kitchen island she points past is not where she points); ``(x, y, z)`` with ``z`` a little above that surface. Objects have a height:
    a ray aimed at a kettle on a counter passes the kettle low over the counter and may come
    down on the floor behind it, so where it comes down is not where the object is. None when
    the ray stays higher than ``band`` over everything within ``reach`` m."""
    if elevation >= 0.0:
        return _spot_above(plan, hand, direction, elevation, band=band, reach=reach, step=step)
    walls = [tuple((float(x), float(y)) for x, y in w.rectangle()) for w in plan.walls]
    tops = [(o.points, o.top) for o in plan.obstacles if o.type != "leg" and o.top < hand[2]]
    c, s, slope = math.cos(direction), math.sin(direction), math.tan(elevation)
    runs: list[list[tuple[float, float, float]]] = []
    low = False
    d = 0.1
    while d <= reach:
        x, y, z = hand[0] + d * c, hand[1] + d * s, hand[2] + d * slope
        if any(_point_polygon((x, y), w) == 0.0 for w in walls) or z < 0.0:
            break
        under = max((top for pts, top in tops if _point_polygon((x, y), pts) == 0.0), default=0.0)
        if z < under:  # it meets a piece of furniture (its top, or its side): the ray ends there
            break
        if z - under <= band:
            if not low:
                runs.append([])
            runs[-1].append((x, y, under))
            low = True
        else:
            low = False
        d += step
    if not runs:
        return None
    run = runs[-1]
    x, y, under = run[len(run) // 2]
    return x, y, under + 0.05


def _spot_above(plan: FloorPlan, hand: tuple[float, float, float], direction: float, elevation: float, *,
                band: float, reach: float, step: float) -> tuple[float, float, float] | None:
    """:func:`pointed_spot` for a ray that rises (she points up at a book on top of a bookshelf, a
    clock on a tall cabinet): the first stretch of it over a piece of furniture taller than her hand
    that runs at most ``band`` m above its top, or the point where it meets that furniture's side no
    more than ``band`` below its top (aimed at an object's middle, the arm points a little low), before
    it meets a wall; ``(x, y, top + 0.05)``. None when the ray passes over nothing that high within
    ``reach`` m (it shows a picture on the wall, the ceiling lamp: nothing on a surface)."""
    walls = [tuple((float(x), float(y)) for x, y in w.rectangle()) for w in plan.walls]
    tall = [(o.points, o.top) for o in plan.obstacles if o.type != "leg" and o.top >= hand[2] - band]
    c, s, slope = math.cos(direction), math.sin(direction), math.tan(elevation)
    d = 0.1
    while d <= reach:
        x, y, z = hand[0] + d * c, hand[1] + d * s, hand[2] + d * slope
        if any(_point_polygon((x, y), w) == 0.0 for w in walls):
            return None
        for pts, top in tall:
            if _point_polygon((x, y), pts) == 0.0:
                if z < top - band:
                    return None  # into its side, well below the top: nothing on a surface there
                if z - top <= band:
                    return x, y, top + 0.05
        d += step
    return None


# -- bringing the whole search area into view (beside24) ---------------------------------------------------------
#: m: the search area's grid (a bag, a plant, a cup is about this big)
COVER_CELL = 0.2
#: m: how far the robot may move (a straight leg, away from no one) to bring the rest of the search area into view:
#: backing off 0.4-0.8 m puts what lies beside it, under the camera's 0.8 m minimum range, into the image
COVER_MOVES = (0.4, 0.8, 1.2)
COVER_DIRECTIONS = 24  # directions of such a move (15 deg apart, as the viewpoint rings)
COVER_BEARINGS = 24  # directions a view may look along (the base turns: the pan-tilt's reach does not limit it)
#: rad: a spot this near the image's middle counts as viewed (the image's half width is 24 deg; the camera lags its focus)
COVER_HALF = math.radians(20.0)
#: rad: the lowest sight line in the image, the pan-tilt unit tilted down as far as it goes (25 deg, the EVI-D31) and
#: the image's lower half (18.8 deg), less 2 deg: from the camera 1.41 m up the floor within about 1.3 m is never in view
LOWEST_VIEW = math.radians(25.0 + 18.8 - 2.0)
#: s: what a view costs, roughly: its look (2 s), each metre of the move there (the base's 0.3 m/s, the turns at either
#: end), each radian of a turn on the spot (45 deg/s): of views that bring alike much into view, the cheaper first
COVER_LOOK_COST, COVER_MOVE_COST, COVER_TURN_COST = 2.0, 5.0, 1.3
COVER_TOP = 1.2  # m: furniture up to this height is searched on its top (the camera sees onto it); taller hides its footprint


def search_area(plan: FloorPlan, centre: Point, radius: float, *, cell: float = COVER_CELL) -> list[tuple[float, float, float]]:
    """The spots where a thing someone shows without a gesture may lie: a grid of ``cell`` m within
    ``radius`` of ``centre``, in a room of the plan, on the floor or on a piece of furniture no taller than
    ``COVER_TOP`` (0.05 m above the surface); none inside a wall or taller furniture."""
    blocks = [(w, 0.0, math.inf) for w, _b, _t in _blocks(plan)[:len(plan.walls)]]
    out: list[tuple[float, float, float]] = []
    n = int(radius / cell)
    for i in range(-n, n + 1):
        for j in range(-n, n + 1):
            x, y = centre[0] + i * cell, centre[1] + j * cell
            if math.hypot(x - centre[0], y - centre[1]) > radius + 1e-9 or not _inside_room(plan, (x, y)):
                continue
            if any(_point_polygon((x, y), poly) <= 0.05 for poly, _b, _t in blocks):
                continue
            top, hidden = 0.0, False
            for o in plan.obstacles:
                if o.type != "leg" and _point_polygon((x, y), o.points) == 0.0:
                    if o.top > COVER_TOP:
                        hidden = True
                    else:
                        top = max(top, o.top)
            if not hidden:
                out.append((x, y, top + 0.05))
    return out


def sees(plan: FloorPlan, camera: tuple[float, float, float], bearing: float, spot: tuple[float, float, float],
         people: Sequence[Point] = (), *, half: float = COVER_HALF) -> bool:
    """Whether a camera at ``camera`` looking along ``bearing`` (map frame, rad) has ``spot`` in its image
    (within ``half`` of its middle, no lower than ``LOWEST_VIEW``), in its object range, with a clear sight line."""
    off = math.remainder(math.atan2(spot[1] - camera[1], spot[0] - camera[0]) - bearing, 2 * math.pi)
    if abs(off) > half or not in_range(camera, spot):
        return False
    if math.atan2(camera[2] - spot[2], math.hypot(spot[0] - camera[0], spot[1] - camera[1])) > LOWEST_VIEW:
        return False  # under the image's lower edge, the camera tilted down as far as it goes
    return sight_clear(plan, camera, spot, people)


def cover_places(plan: FloorPlan, robot: Point, people: Sequence[Point] = (), *, clearance: float = ROBOT_CLEARANCE,
                 person_clearance: float = PERSON_CLEARANCE) -> list[tuple[float, Point]]:
    """Where the robot may stand to bring the rest of a search area into view, with how far it moves there: where
    it stands, and ``COVER_MOVES`` m in each of ``COVER_DIRECTIONS`` on a straight leg in a room that keeps the
    clearances (:func:`straight_leg_free`) and ends no nearer to anyone than they stand now (nor within
    ``person_clearance`` + 0.5 m of anyone farther): never a drive at a person."""
    blocks = _blocks(plan)
    start = (robot[0], robot[1])
    places: list[tuple[float, Point]] = [(0.0, start)]
    for d in COVER_MOVES:
        for k in range(COVER_DIRECTIONS):
            a = 2 * math.pi * k / COVER_DIRECTIONS
            q = (robot[0] + d * math.cos(a), robot[1] + d * math.sin(a))
            if not _inside_room(plan, q):
                continue
            if any(math.hypot(q[0] - px, q[1] - py) < min(math.hypot(start[0] - px, start[1] - py), person_clearance + 0.5) - 1e-9
                   for px, py in people):
                continue  # nearer to someone than now: never a drive at a person
            if straight_leg_free(blocks, people, start, q, clearance=clearance, person_clearance=person_clearance):
                places.append((d, q))
    return places


def cover_views(plan: FloorPlan, robot: tuple[float, float, float], unseen: Sequence[tuple[float, float, float]], people: Sequence[Point] = (), *,
                camera_height: float, camera_offset: float = 0.0, clearance: float = ROBOT_CLEARANCE,
                person_clearance: float = PERSON_CLEARANCE) -> list[tuple[float, float, float, list[int]]]:
    """Views (x, y, bearing, the indices of ``unseen`` each brings into the image) that together bring every
    spot of ``unseen`` into view that any pose the robot may take sees: turned on the spot, or at one of the
    :func:`cover_places` (never a drive at a person), looking along any of ``COVER_BEARINGS``. Greedy: the view that brings most of what is left into view for
    its cost first (``COVER_LOOK_COST`` + its move and turn), until no view brings more. Pure."""
    places = cover_places(plan, (robot[0], robot[1]), people, clearance=clearance, person_clearance=person_clearance)
    options: list[tuple[float, float, float, float, frozenset[int]]] = []  # move, turn, x, y, bearing ... covered
    for d, q in places:
        for k in range(COVER_BEARINGS):
            b = math.remainder(2 * math.pi * k / COVER_BEARINGS, 2 * math.pi)
            cam = (q[0] + camera_offset * math.cos(b), q[1] + camera_offset * math.sin(b), camera_height)
            got = frozenset(i for i, s in enumerate(unseen) if sees(plan, cam, b, s, people))
            if got:
                options.append((d, abs(math.remainder(b - robot[2], 2 * math.pi)), q[0], q[1], b, got))  # type: ignore[arg-type]
    left = set(range(len(unseen)))
    out: list[tuple[float, float, float, list[int]]] = []
    while options:
        best = max(options, key=lambda o: (len(o[5] & left) / (COVER_LOOK_COST + COVER_MOVE_COST * o[0] + COVER_TURN_COST * o[1]), -o[0], -o[1]))  # type: ignore[operator]
        new = best[5] & left  # type: ignore[operator]
        if not new:
            break
        out.append((best[2], best[3], best[4], sorted(new)))
        left -= new
    return out
