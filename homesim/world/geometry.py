"""Plain 2D geometry for the flat: angles, frames, polygons, segments.

Pure functions on numpy arrays (no pymunk, no state), shared by the world,
the scenario checks, the path planner, the sensor kernels and the plots.
Conventions: metres, radians, world frame x right / y up, headings
counter-clockwise from +x; a bearing in a body frame is 0 straight ahead,
positive to the left.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

Point = tuple[float, float]
FloatArray = np.ndarray

TWO_PI = 2.0 * math.pi


def wrap_angle(a: float | FloatArray) -> float | FloatArray:
    """Wrap an angle (or array of angles) to [-pi, pi), so differences compare."""
    return (a + math.pi) % TWO_PI - math.pi


def to_local(pose: Sequence[float], points: FloatArray) -> FloatArray:
    """Express world points (N, 2) in the frame of ``pose`` = (x, y, heading)."""
    x, y, th = pose
    c, s = math.cos(th), math.sin(th)
    d = np.asarray(points, dtype=float) - (x, y)
    return np.stack((c * d[..., 0] + s * d[..., 1], -s * d[..., 0] + c * d[..., 1]), axis=-1)


def to_world(pose: Sequence[float], points: FloatArray) -> FloatArray:
    """Express body-frame points (N, 2) of ``pose`` = (x, y, heading) in the world."""
    x, y, th = pose
    c, s = math.cos(th), math.sin(th)
    p = np.asarray(points, dtype=float)
    return np.stack((x + c * p[..., 0] - s * p[..., 1], y + s * p[..., 0] + c * p[..., 1]), axis=-1)


def bearing_to(pose: Sequence[float], points: FloatArray) -> FloatArray:
    """Bearings (radians, 0 ahead, + left) from ``pose`` to world points (N, 2)."""
    local = to_local(pose, points)
    return np.arctan2(local[..., 1], local[..., 0])


def polygon_area(points: FloatArray) -> float:
    """Signed area (positive when counter-clockwise)."""
    p = np.asarray(points, dtype=float)
    x, y = p[:, 0], p[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def polygon_centroid(points: FloatArray) -> Point:
    """Area centroid of a simple polygon (vertex mean when degenerate)."""
    p = np.asarray(points, dtype=float)
    a = polygon_area(p)
    if abs(a) < 1e-12:
        m = p.mean(axis=0)
        return float(m[0]), float(m[1])
    x, y = p[:, 0], p[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cr = x * yn - xn * y
    return float(((x + xn) * cr).sum() / (6 * a)), float(((y + yn) * cr).sum() / (6 * a))


def is_convex(points: FloatArray) -> bool:
    """True for a convex polygon without repeated vertices (pymunk needs convex shapes)."""
    p = np.asarray(points, dtype=float)
    if len(p) < 3:
        return False
    e = np.roll(p, -1, axis=0) - p
    if np.any(np.hypot(e[:, 0], e[:, 1]) < 1e-9):
        return False
    cr = e[:, 0] * np.roll(e[:, 1], -1) - e[:, 1] * np.roll(e[:, 0], -1)
    return bool(np.all(cr > 1e-12) or np.all(cr < -1e-12))


def polygon_edges(points: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Edges of a closed polygon as (start (N, 2), end (N, 2)) arrays."""
    p = np.asarray(points, dtype=float)
    return p, np.roll(p, -1, axis=0)


def points_in_polygon(points: FloatArray, polygon: FloatArray) -> FloatArray:
    """Even-odd test for many points (N, 2) against one polygon; boolean (N,)."""
    q = np.atleast_2d(np.asarray(points, dtype=float))
    a, b = polygon_edges(polygon)
    px, py = q[:, 0:1], q[:, 1:2]
    ax, ay, bx, by = a[:, 0], a[:, 1], b[:, 0], b[:, 1]
    straddle = (ay > py) != (by > py)
    with np.errstate(divide="ignore", invalid="ignore"):
        xcross = ax + (py - ay) * (bx - ax) / (by - ay)
    hits = straddle & (px < xcross)
    return (hits.sum(axis=1) % 2) == 1


def point_in_polygon(point: Sequence[float], polygon: FloatArray) -> bool:
    """Even-odd test for one point."""
    return bool(points_in_polygon(np.asarray([point], dtype=float), polygon)[0])


def distance_points_segments(points: FloatArray, a: FloatArray, b: FloatArray) -> FloatArray:
    """Distances (N, M) from points (N, 2) to segments a->b (M, 2)."""
    p = np.atleast_2d(np.asarray(points, dtype=float))[:, None, :]
    a = np.asarray(a, dtype=float)[None, :, :]
    b = np.asarray(b, dtype=float)[None, :, :]
    ab = b - a
    denom = (ab * ab).sum(-1)
    denom = np.where(denom < 1e-18, 1.0, denom)
    t = np.clip(((p - a) * ab).sum(-1) / denom, 0.0, 1.0)
    closest = a + t[..., None] * ab
    return np.hypot(*(p - closest).transpose(2, 0, 1))


def segments_intersect(p: FloatArray, q: FloatArray, a: FloatArray, b: FloatArray) -> FloatArray:
    """Whether segments p->q (N, 2) cross segments a->b (M, 2) properly; boolean (N, M)."""
    p = np.atleast_2d(np.asarray(p, dtype=float))[:, None, :]
    q = np.atleast_2d(np.asarray(q, dtype=float))[:, None, :]
    a = np.asarray(a, dtype=float)[None, :, :]
    b = np.asarray(b, dtype=float)[None, :, :]
    r = q - p
    s = b - a
    den = r[..., 0] * s[..., 1] - r[..., 1] * s[..., 0]
    ap = a - p
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (ap[..., 0] * s[..., 1] - ap[..., 1] * s[..., 0]) / den
        u = (ap[..., 0] * r[..., 1] - ap[..., 1] * r[..., 0]) / den
    return (np.abs(den) > 1e-12) & (t >= 0) & (t <= 1) & (u >= 0) & (u <= 1)


def wall_rectangle(a: Point, b: Point, thickness: float) -> FloatArray:
    """The counter-clockwise rectangle (4, 2) of a wall piece from a to b."""
    ax, ay = a
    bx, by = b
    dx, dy = bx - ax, by - ay
    n = math.hypot(dx, dy)
    if n < 1e-12:
        raise ValueError("a wall piece needs two distinct end points")
    ox, oy = -dy / n * thickness / 2.0, dx / n * thickness / 2.0
    rect = np.array([[ax - ox, ay - oy], [bx - ox, by - oy], [bx + ox, by + oy], [ax + ox, ay + oy]])
    return rect if polygon_area(rect) > 0 else rect[::-1].copy()


def split_wall(a: Point, b: Point, gaps: Sequence[tuple[float, float]]) -> list[tuple[Point, Point]]:
    """Cut the wall a->b at door gaps given as (centre distance from a, width).

    Returns the solid pieces in order from a; pieces shorter than 1 mm vanish.
    Raises ValueError when a gap leaves the wall or two gaps overlap.
    """
    ax, ay = a
    bx, by = b
    length = math.hypot(bx - ax, by - ay)
    ux, uy = (bx - ax) / length, (by - ay) / length
    spans = sorted((c - w / 2.0, c + w / 2.0) for c, w in gaps)
    pieces: list[tuple[Point, Point]] = []
    pos = 0.0
    for lo, hi in spans:
        if lo < -1e-9 or hi > length + 1e-9:
            raise ValueError(f"door gap {lo:.2f}..{hi:.2f} m lies outside the wall (length {length:.2f} m)")
        if lo < pos - 1e-9:
            raise ValueError(f"door gaps overlap near {lo:.2f} m")
        if lo - pos > 1e-3:
            pieces.append(((ax + ux * pos, ay + uy * pos), (ax + ux * lo, ay + uy * lo)))
        pos = hi
    if length - pos > 1e-3:
        pieces.append(((ax + ux * pos, ay + uy * pos), (bx, by)))
    return pieces
