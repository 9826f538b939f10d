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


def point_in_polygon(point: Sequence[float], polygon: FloatArray | Sequence[Sequence[float]]) -> bool:
    """Even-odd test for one point.

    Plain floats, not numpy: for one point against a room's few corners numpy's per-call
    overhead is most of the cost (``room_of`` runs every physics step). The arithmetic is
    the same expression, in the same order, as :func:`points_in_polygon`'s, so the answers
    are identical, points on an edge included.
    """
    px, py = float(point[0]), float(point[1])
    pts = polygon.tolist() if isinstance(polygon, np.ndarray) else polygon
    n = len(pts)
    inside = False
    for i in range(n):
        ax, ay = pts[i]
        bx, by = pts[(i + 1) % n]
        ax, ay, bx, by = float(ax), float(ay), float(bx), float(by)
        if (ay > py) != (by > py) and px < ax + (py - ay) * (bx - ax) / (by - ay):
            inside = not inside
    return inside


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


def _on_segment(p: Point, a: Point, b: Point, eps: float = 1e-9) -> bool:
    """Whether p lies on the closed segment a-b (within ``eps``)."""
    cross = (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])
    if abs(cross) > eps * max(1.0, math.hypot(b[0] - a[0], b[1] - a[1])):
        return False
    return min(a[0], b[0]) - eps <= p[0] <= max(a[0], b[0]) + eps and min(a[1], b[1]) - eps <= p[1] <= max(a[1], b[1]) + eps


def _segments_touch(p: Point, q: Point, a: Point, b: Point) -> bool:
    """Whether closed segments p-q and a-b share any point (crossing, touching or overlapping)."""
    if bool(segments_intersect(np.array([p]), np.array([q]), np.array([a]), np.array([b]))[0, 0]):
        return True
    return _on_segment(p, a, b) or _on_segment(q, a, b) or _on_segment(a, p, q) or _on_segment(b, p, q)


def polygon_problem(points: FloatArray) -> str | None:
    """Why ``points`` is not a simple polygon (None when it is).

    Simple: at least three vertices, no repeated vertex, no edge that
    touches or crosses a non-adjacent edge, no edge that folds back on the
    previous one.
    """
    p = [(float(x), float(y)) for x, y in np.asarray(points, dtype=float)]
    n = len(p)
    if n < 3:
        return "a polygon needs at least three vertices"
    for i in range(n):
        for j in range(i + 1, n):
            if math.hypot(p[i][0] - p[j][0], p[i][1] - p[j][1]) < 1e-9:
                return f"vertices {i + 1} and {j + 1} are the same point {p[i]}"
    edges = [(p[i], p[(i + 1) % n]) for i in range(n)]
    for i in range(n):
        (a, b), (_, c) = edges[i], edges[(i + 1) % n]
        # Adjacent edges share b; they overlap only if c lies back on a-b (or a on b-c).
        if _on_segment(c, a, b) or _on_segment(a, b, c):
            return f"edges {i + 1} and {(i + 1) % n + 1} fold back on each other at {b}"
    for i in range(n):
        for j in range(i + 2, n):
            if i == 0 and j == n - 1:
                continue  # adjacent through the closing vertex
            if _segments_touch(*edges[i], *edges[j]):
                return f"edges {i + 1} ({edges[i][0]}-{edges[i][1]}) and {j + 1} ({edges[j][0]}-{edges[j][1]}) cross or touch"
    return None


def _strictly_inside(q: Point, polygon: FloatArray, eps: float = 1e-6) -> bool:
    a, b = polygon_edges(polygon)
    return point_in_polygon(q, polygon) and float(distance_points_segments(np.array([q]), a, b).min()) > eps


def _probe_points(polygon: FloatArray) -> list[Point]:
    """Points of a simple polygon to test for overlap: vertices, edge midpoints, interior points."""
    p = np.asarray(polygon, dtype=float)
    n = len(p)
    pts: list[Point] = [(float(x), float(y)) for x, y in p]
    pts += [(float((p[i, 0] + p[(i + 1) % n, 0]) / 2), float((p[i, 1] + p[(i + 1) % n, 1]) / 2)) for i in range(n)]
    cands = [polygon_centroid(p)] + [tuple((p[i - 1] + p[i] + p[(i + 1) % n]) / 3) for i in range(n)]
    pts += [(float(c[0]), float(c[1])) for c in cands if _strictly_inside((float(c[0]), float(c[1])), p)]
    return pts


def polygons_overlap(p: FloatArray, q: FloatArray) -> bool:
    """Whether two simple polygons share area (touching along edges or at vertices is no overlap)."""
    p = np.asarray(p, dtype=float)
    q = np.asarray(q, dtype=float)
    pa, pb = polygon_edges(p)
    qa, qb = polygon_edges(q)
    # Proper crossings: interior points of both edges.
    r = (pb - pa)[:, None, :]
    s = (qb - qa)[None, :, :]
    den = r[..., 0] * s[..., 1] - r[..., 1] * s[..., 0]
    ap = qa[None, :, :] - pa[:, None, :]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (ap[..., 0] * s[..., 1] - ap[..., 1] * s[..., 0]) / den
        u = (ap[..., 0] * r[..., 1] - ap[..., 1] * r[..., 0]) / den
    eps = 1e-9
    if bool(np.any((np.abs(den) > 1e-12) & (t > eps) & (t < 1 - eps) & (u > eps) & (u < 1 - eps))):
        return True
    return any(_strictly_inside(x, q) for x in _probe_points(p)) or any(_strictly_inside(x, p) for x in _probe_points(q))
