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
  the forward-looking laser and camera; backing out of her way is not done);

and of those the nearest to the robot: the answer is the path there. None when
there is no such place (then the robot waits where it is, as before).
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


def give_way_spot(grid: OccupancyGrid, robot: Point, partner: Point, *, keep: float = 1.0, room: float = ROOM,
                  lateral: float = LATERAL, reach: float = REACH) -> list[Point] | None:
    """The path (map frame, from ``robot``; its last point the spot) by which the robot steps aside
    for the partner at ``partner``, or None.

    See the module docstring for the rule; ``keep``: the least distance to her (the follower's
    near band).
    """
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
    ok = (travel <= reach) & (np.hypot(dx, dy) >= keep) & (side >= lateral) & (along <= d)
    if not ok.any():
        return None
    pts = np.column_stack((x[ok], y[ok]))
    order = np.argsort(travel[ok], kind="stable")
    keep_off = min(PASS, d) - 0.01
    tried: list[Point] = []
    for k in order:
        spot = (float(pts[k, 0]), float(pts[k, 1]))
        if any(math.hypot(spot[0] - a, spot[1] - b) < SPREAD for a, b in tried):
            continue  # a neighbour of a spot already tried: the same way there
        if len(tried) >= CANDIDATES:
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
            if (-ux * lx - uy * ly) < math.cos(FACE) * math.hypot(lx, ly):
                continue  # it would drive off with her behind it, out of the laser's and camera's view
        return path
    return None


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
