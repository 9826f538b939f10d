"""Giving way: where a robot standing in a door frame or a passage goes when the partner wants through.

A partner who turns back (she taught a room behind a narrow door, and asks the
robot to follow her back out) walks towards the robot; when the robot stands in
the door she came through, it blocks the only way, and backing off the way it
came (the follower's answer to a partner who comes too close) takes it deeper
into the door, ahead of her (issue 26: follow_corridor, a robot that waited in
a 0.9 m door while its partner stood in front of it for the rest of the run).

What a person does there, the robot does: it steps aside, out of the passage
and out of her way, to the side she comes from, then lets her pass and follows.
:func:`give_way_spot` picks that place on the planner's occupancy grid (map
frame), among the cells within :data:`REACH` m of the robot:

* roomy: the centre at least :data:`ROOM` m from every wall and piece of
  furniture (out of the door frame, turnable);
* out of her way: at least :data:`LATERAL` m to the side of the line from her
  through the robot (the way she presumably wants to go), and not further
  down that way than the robot stands now;
* not at her: at least ``keep`` m from her, and reached on the grid's shortest
  path (no longer than twice :data:`REACH`; out of a door frame it may lead
  round the jamb) that passes her no closer than :data:`PASS` m and starts off
  no more than :data:`FACE` from the direction to her (she stays in the view of
  the forward-looking laser and camera; backing is for when nothing lies ahead, below);

and of those the nearest to the robot: the answer is the path there. None when
there is no such place (then the robot waits where it is, as before).

When there is none ahead (a storeroom behind a door: she stands in the little
room and wants out through the door the robot stands in), it backs out the way
it came: :func:`back_out_spot` picks, by the same rule but further down her way,
a roomy spot behind the robot (through the door, round the jamb), :data:`BACK_GAIN` m
further from her than the robot stands and to the side of the door's or passage's
mouth (:data:`BACK_SIDE`; she walks on along it next),
whose path starts straight away from her (within :data:`BACK_FACE`), so the robot
reverses along it facing her; the floor plan checks the ground behind it, where
the laser does not look (:func:`reverse_command` steers the rear along the path).

Out of a door into a passage no roomier than 1.0 m (a corridor: issue 26, galley_follow_bend and
galley_long_tour, where a robot in a dead-end room's 0.9 m door stood in the way of its partner for the
rest of the run), no cell has :data:`ROOM`. Then a spot in the passage will do where the robot can
still turn (:data:`PASSAGE_ROOM`), but she cannot walk round it there: it must stand at least
(:data:`LATERAL` m along the passage from the mouth's axis, where she walks out; its first leg
need only lead away from her, :data:`PASSAGE_FACE`). Of the two ways
along the passage it prefers the one it did not come by (``came``: where it drove from): the way
it came is the way to the rest of the flat, where she leads it next; the other is the dead end.
"""

from __future__ import annotations

import math

import numpy as np

from .grid import NoPathError, OccupancyGrid, path_length

Point = tuple[float, float]

#: m: a give-way spot's centre is this far from the floor plan's obstacles (out of the door frame).
ROOM = 0.5
#: m: ... this far to the side of the partner's way (her body 0.25 m, the footprint's half width 0.22 m, air).
LATERAL = 0.75
#: m: ... and within this distance of the robot.
REACH = 1.8
#: m: the way there (the grid's shortest path: round a door jamb, through the door) passes the
#: partner's centre no closer than this (or than she stands now, if nearer).
PASS = 0.7
#: the nearest this many candidate spots are planned to, at most (one Dijkstra each).
CANDIDATES = 8
#: rad: the way's first leg lies at most this far off the direction to her (she stays in view as it drives).
FACE = math.radians(100)
#: m: ... each at least this far from the ones before it (nearer ones first).
SPREAD = 0.4
#: rad: backing out, the way's first leg lies at most this far off straight away from her.
BACK_FACE = math.radians(60)
#: m: a centre closer than this to the floor plan's walls and furniture stands in a door frame or a
#: passage (the middle of a 1.1 m door is 0.55 m from its jambs): a partner walking at it there is backed away from.
NARROW = 0.6
#: m: backing out, the spot is at least this much further from her than the robot stands now.
BACK_GAIN = 0.5
#: rad: backing out, the spot lies at least this far off the direction of the door or passage it leaves.
BACK_SIDE = math.radians(45)
#: m: with no :data:`ROOM` anywhere near (a 1.0 m corridor's middle is 0.47 m from its walls on the
#: grid), a back-out spot's centre this far from walls and furniture: the footprint (half diagonal
#: 0.34 m) still turns on the spot there (the follower's own turning room)
PASSAGE_ROOM = 0.40
#: rad: ... and its path's first leg at most this far off straight away from her: out of a door into a
#: corridor it backs out along the door's axis whichever side of it she stands (standing diagonally in
#: the room, :data:`BACK_FACE` left only the side it came by, and she then walked into it there)
PASSAGE_FACE = math.radians(90)


def give_way_spot(grid: OccupancyGrid, robot: Point, partner: Point, *, keep: float = 1.0, room: float = ROOM,
                  lateral: float = LATERAL, reach: float = REACH, way: Point | None = None) -> list[Point] | None:
    """The path (map frame, from ``robot``; its last point the spot) by which the robot steps aside
    for the partner at ``partner``, or None.

    See the module docstring for the rule; ``keep``: the least distance to her (the follower's
    near band). ``way``: where she walks to (the way out of the room she is leaving, as far as the
    robot can tell): her way is then the segment from her to that point, not the line from her
    through the robot, and the spot lies at least ``lateral`` off that segment, no further down it
    than the robot stands (beside the door's mouth on the room side, not in the door).
    """
    return _spot(grid, robot, partner, keep=keep, room=room, lateral=lateral, reach=reach, backing=False, way=way)


def back_out_spot(grid: OccupancyGrid, robot: Point, partner: Point, *, keep: float = 1.0, room: float = ROOM,
                  lateral: float = LATERAL, reach: float = REACH, came: Point | None = None) -> list[Point] | None:
    """The path (map frame, from ``robot``) by which the robot backs out of her way when no spot
    lies ahead (see the module docstring): a roomy spot beside her way, further down it than the
    robot stands (behind the robot, through the door it came in by), reached by a path whose first
    leg points away from her (it reverses, facing her); with no roomy spot (a corridor), one in the
    passage at least ``lateral`` m along it from the mouth (:data:`PASSAGE_ROOM`); None when there is
    none. ``came``: where it drove from (map frame); the spot on the other side of her way is preferred.
    """
    path = _spot(grid, robot, partner, keep=keep, room=room, lateral=lateral, reach=reach, backing=True, came=came)
    if path is None and room > PASSAGE_ROOM:
        path = _spot(grid, robot, partner, keep=keep, room=PASSAGE_ROOM, lateral=lateral, reach=reach, backing=True,
                     came=came, passage=True)
    return path


def reverse_command(goal: Point, *, speed: float, max_turn: float, gain: float = 1.8) -> tuple[float, float]:
    """(v, w) that backs the robot toward ``goal`` (robot frame, behind it): the rear is steered at the
    goal, and the speed falls with the cosine of how far off it points (0 from a right angle on: it
    turns on the spot). The caller checks the sweep (and may keep only v or only w)."""
    off = math.atan2(-goal[1], -goal[0])  # the goal's bearing from the rear (0: straight behind)
    w = max(-max_turn, min(max_turn, gain * off))
    return -speed * max(math.cos(off), 0.0), w


def _spot(grid: OccupancyGrid, robot: Point, partner: Point, *, keep: float, room: float, lateral: float,
          reach: float, backing: bool, came: Point | None = None, passage: bool = False,
          way: Point | None = None) -> list[Point] | None:
    """:func:`give_way_spot` (ahead, ``backing`` False) and :func:`back_out_spot` (behind; ``passage``:
    its spot at least ``lateral`` off the line of the path's first leg, out of the door; ``came``: the
    side of her way it came from is taken only when the other side has no spot)."""
    ux, uy = robot[0] - partner[0], robot[1] - partner[1]
    d = math.hypot(ux, uy)
    if d < 1e-6:
        return None
    ux, uy = ux / d, uy / d
    ci, cj = grid.cell_of(robot)
    r = int(math.ceil(reach / grid.cell))
    i0, i1 = max(ci - r, 0), min(ci + r + 1, grid.nx)
    j0, j1 = max(cj - r, 0), min(cj + r + 1, grid.ny)
    if i0 >= i1 or j0 >= j1:
        return None
    ii, jj = np.nonzero(grid.clearance[i0:i1, j0:j1] >= room)
    if not len(ii):
        return None
    x = grid.origin[0] + (ii + i0 + 0.5) * grid.cell
    y = grid.origin[1] + (jj + j0 + 0.5) * grid.cell
    dx, dy = x - partner[0], y - partner[1]
    along = dx * ux + dy * uy
    side = np.abs(dx * uy - dy * ux)
    travel = np.hypot(x - robot[0], y - robot[1])
    if backing:  # further from her than it stands, off the door or passage it backs out of (checked below)
        ok = (travel <= reach) & (travel >= lateral) & (np.hypot(dx, dy) >= max(keep, d + BACK_GAIN))
    elif way is not None:  # off her way to where she walks (the segment), no further down it than the robot
        ok = (travel <= reach) & (np.hypot(dx, dy) >= keep) & (way_distance(x, y, partner, way) >= lateral)
        wx, wy = way[0] - partner[0], way[1] - partner[1]
        n = math.hypot(wx, wy)
        if n > 1e-6:
            ok &= (dx * wx + dy * wy) / n <= ((robot[0] - partner[0]) * wx + (robot[1] - partner[1]) * wy) / n
    else:
        ok = (travel <= reach) & (np.hypot(dx, dy) >= keep) & (side >= lateral) & (along <= d)
    if not ok.any():
        return None
    pts = np.column_stack((x[ok], y[ok]))
    order = np.argsort(travel[ok], kind="stable")
    keep_off = min(PASS, d) - 0.01
    tried: list[Point] = []
    fallback: list[Point] | None = None  # a valid spot on the side it came from
    for k in order:
        spot = (float(pts[k, 0]), float(pts[k, 1]))
        if any(math.hypot(spot[0] - a, spot[1] - b) < SPREAD for a, b in tried):
            continue  # a neighbour of a spot already tried: the same way there
        if len(tried) >= (2 * CANDIDATES if backing else CANDIDATES):
            break
        tried.append(spot)
        try:
            path = grid.plan(robot, spot)
        except NoPathError:
            continue
        if path_length(path) > 2 * reach or _passes(path, partner) < keep_off:
            continue
        if len(path) > 1:
            lx, ly = path[1][0] - robot[0], path[1][1] - robot[1]
            if backing and (ux * lx + uy * ly) < math.cos(PASSAGE_FACE if passage else BACK_FACE) * math.hypot(lx, ly):
                continue  # not straight back from her: it would reverse across her way
            if backing and not passage and not _off_the_way(grid, path, room, (ux, uy)):
                continue  # by the door or passage it backs out of: where she walks next
            if passage and abs((path[-1][0] - robot[0]) * ly - (path[-1][1] - robot[1]) * lx) < lateral * math.hypot(lx, ly):
                continue  # in the passage, on the line it backs out along (out of the door): where she walks out
            if not backing and (-ux * lx - uy * ly) < math.cos(FACE) * math.hypot(lx, ly):
                continue  # it would drive off with her behind it, out of the laser's and camera's view
        if came is not None and passage:
            # which side of her way (the line from her through the robot) the spot and where it came from lie on
            side = (path[-1][0] - robot[0]) * -uy + (path[-1][1] - robot[1]) * ux
            back = (came[0] - robot[0]) * -uy + (came[1] - robot[1]) * ux
            if side * back > 0.0:
                fallback = fallback or path  # toward the rest of the flat: where she leads it next
                continue
        return path
    return fallback


def way_distance(x: np.ndarray, y: np.ndarray, partner: Point, way: Point) -> np.ndarray:
    """How far (m) the points ``x, y`` lie from the segment from ``partner`` to ``way`` (her way out)."""
    wx, wy = way[0] - partner[0], way[1] - partner[1]
    n2 = wx * wx + wy * wy
    dx, dy = np.asarray(x, dtype=float) - partner[0], np.asarray(y, dtype=float) - partner[1]
    t = np.clip((dx * wx + dy * wy) / n2, 0.0, 1.0) if n2 > 1e-12 else np.zeros_like(dx)
    return np.hypot(dx - t * wx, dy - t * wy)


def _off_the_way(grid: OccupancyGrid, path: list[Point], room: float, away: Point) -> bool:
    """Whether the end of ``path`` lies off the way out of the door frame or passage the path starts
    in (the first run of points, every quarter cell, whose clearance is under ``room``; she walks
    along it next): at least ``room`` m from the run's end and at least :data:`BACK_SIDE` off its
    direction (to the side of the door's mouth, not on along it). Where the path starts roomy (a
    1.0 m door's middle is 0.5 m from its jambs), the way out is ``away`` (the direction from her)."""
    pts = []
    for a, b in zip(path, path[1:]):
        n = max(int(math.hypot(b[0] - a[0], b[1] - a[1]) / (grid.cell / 4)) + 2, 2)
        t = np.linspace(0.0, 1.0, n)[:, None]
        pts.append(np.asarray(a, dtype=float) + t * (np.asarray(b, dtype=float) - np.asarray(a, dtype=float)))
    q = np.concatenate(pts)
    i = np.clip(((q[:, 0] - grid.origin[0]) / grid.cell).astype(int), 0, grid.nx - 1)
    j = np.clip(((q[:, 1] - grid.origin[1]) / grid.cell).astype(int), 0, grid.ny - 1)
    roomy = np.flatnonzero(grid.clearance[i, j] >= room)
    if not len(roomy):
        return False  # it never leaves the door's mouth
    mouth = q[max(roomy[0] - 1, 0)]
    rx, ry = mouth[0] - q[0, 0], mouth[1] - q[0, 1]
    ex, ey = path[-1][0] - mouth[0], path[-1][1] - mouth[1]
    e, r = math.hypot(ex, ey), math.hypot(rx, ry)
    if e < room:
        return False
    if r < 0.1:
        rx, ry, r = away[0], away[1], 1.0
    return (ex * rx + ey * ry) <= math.cos(BACK_SIDE) * e * r


def _passes(path: list[Point], p: Point) -> float:
    """How close (m) the polyline ``path`` comes to ``p``."""
    a = np.array(path[:-1], dtype=float)
    b = np.array(path[1:], dtype=float)
    if not len(a):
        return math.hypot(path[0][0] - p[0], path[0][1] - p[1])
    ab = b - a
    ap = np.array(p)[None, :] - a
    t = np.clip((ap * ab).sum(axis=1) / np.maximum((ab * ab).sum(axis=1), 1e-12), 0.0, 1.0)
    q = a + ab * t[:, None]
    return float(np.hypot(q[:, 0] - p[0], q[:, 1] - p[1]).min())



#: m: a passage's sides are looked for within this distance of the robot's centre
AXIS_REACH = 1.2


def passage_axis(grid: OccupancyGrid, p: Point) -> float | None:
    """The axis (map frame, radians in [0, pi): either way along it) of the door frame or passage whose
    floor point ``p`` (map frame) lies within :data:`NARROW` of the floor plan, else None (a room's floor).

    Its two sides: the floor plan's nearest point to ``p`` (a jamb's end, a hallway's wall) and the nearest on the
    other side of ``p`` (the half-plane facing away from the first: the other jamb's end, the opposite wall), both
    within :data:`AXIS_REACH`; the axis runs square to the line joining them (through a door, its normal, also
    from the room side of its mouth or a little off its middle; along a hallway, the hallway). None without a
    second side (a wall's face in a room)."""
    cell = grid.cell
    i, j = int((p[0] - grid.origin[0]) / cell), int((p[1] - grid.origin[1]) / cell)
    if not (0 <= i < grid.nx and 0 <= j < grid.ny) or grid.clearance[i, j] >= NARROW:
        return None
    k = int(AXIS_REACH / cell) + 1
    i0, j0 = max(i - k, 0), max(j - k, 0)
    ii, jj = np.nonzero(grid.occupied[i0:i + k + 1, j0:j + k + 1])
    if not len(ii):
        return None
    dx = grid.origin[0] + (ii + i0 + 0.5) * cell - p[0]
    dy = grid.origin[1] + (jj + j0 + 0.5) * cell - p[1]
    d = np.hypot(dx, dy)
    a = int(np.argmin(d))
    other = (dx * dx[a] + dy * dy[a] < 0.0) & (d <= AXIS_REACH)
    if not other.any():
        return None
    b = int(np.flatnonzero(other)[np.argmin(d[other])])
    return (math.atan2(dy[b] - dy[a], dx[b] - dx[a]) + math.pi / 2) % math.pi


def axis_offset(heading: float, axis: float) -> float:
    """How far (radians, signed, within +-pi/2) ``heading`` lies off a passage's ``axis`` (either way along it)."""
    return (heading - axis + math.pi / 2) % math.pi - math.pi / 2
