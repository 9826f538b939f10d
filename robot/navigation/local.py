"""Local obstacle avoidance: a dynamic window approach (Fox, Burgard and Thrun 1997) on the laser scan.

Pure functions, no state, no bus: the follower and the player's ``move_to``
both call :func:`dwa` once per control step.

Every control step looks at the velocities the base can reach within one
step from its present (v, w) (the *dynamic window*, from the acceleration
limits), simulates each as an arc for ``horizon`` seconds, and measures how
close the PeopleBot's rectangular footprint comes to any laser point along
it. Arcs that would come closer than ``margin`` before the robot could
brake are inadmissible. Among the others it picks the best by

    score = - w_goal * distance from the arc's end to the goal
            - w_heading * |bearing of the goal from the arc's end|
            + w_clear * min(clearance, clear_cap)
            - w_speed * |v - v_pref|

``v_pref`` is what the caller wants (the follower's distance law, the
player's approach speed). When nothing is admissible the answer is to stop
(``ok`` False): waiting is always safe, since the base brakes within its
window.

Points: the scan as (N, 2) points in the robot frame (metres, x forward,
y left), e.g. from :func:`scan_points`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np

# The footprint and the people rule every base command keeps (robot.footprint), imported from here by
# the follower, the player and the planner.
from robot.footprint import (BODY, HALF_LENGTH, HALF_WIDTH, SOCIAL_GAP, SWEEP_STEP, SWEEP_TURN_STEP, TURN_GAP,  # noqa: F401
                             arcs, footprint_distance, people_sweep_clear, turn_clear)

from .config import Limits


@dataclass(frozen=True)
class DWAParams:
    """Tuning of :func:`dwa` (weights are per metre / radian / m/s)."""

    horizon: float = 1.6  # s of simulated motion per arc
    steps: int = 6  # poses per arc
    nv: int = 5  # speed samples in the window
    nw: int = 9  # turn-rate samples in the window
    sectors: int = 90  # the nearest echo per sector of 360/sectors degrees round the centre is kept
    window: float = 0.25  # s of acceleration the window spans (a few control steps)
    margin: float = 0.10  # m: an arc closer than this to a laser echo (or a body ring) is inadmissible
    clear_cap: float = 0.5
    w_goal: float = 1.0
    w_heading: float = 0.35
    w_clear: float = 0.6
    w_speed: float = 0.8
    reach: float = 2.5  # m: laser points further than this from the robot are ignored
    period: float = 0.1  # s: the caller's control period (the robot keeps a command that long)
    social_gap: float = 0.25  # m: air kept to people's bodies (SOCIAL_GAP; see social_mask)


@dataclass(frozen=True)
class Command:
    """The chosen velocity; ``ok`` False means no admissible motion (stop and wait)."""

    v: float
    w: float
    ok: bool
    clearance: float


def scan_points(ranges: np.ndarray, min_angle: float, resolution: float, max_range: float, offset: float, *,
                stride: int = 2, bodies: bool = True) -> np.ndarray:
    """Laser echoes as (N, 2) robot-frame points (angles in radians, ``offset`` m ahead of the centre).

    ``bodies``: a narrow isolated cluster of echoes (under :data:`NARROW` m wide,
    set off from what is behind it) is a leg or a table leg; the laser sees a
    person only at the knees, but their body is wider, so a pair of such
    clusters gets a ring of points :data:`BODY_RING` m around their middle
    (a lone one :data:`LONE_RING`), which keeps the footprint clear of the body.
    """
    r_all = np.asarray(ranges, dtype=float)
    a_all, cos_all, sin_all = _beams(min_angle, resolution, len(r_all))
    r = r_all[::stride]
    keep = r < max_range - 1e-6
    pts = np.column_stack((offset + r[keep] * cos_all[::stride][keep], r[keep] * sin_all[::stride][keep]))
    if not bodies:
        return pts
    d = leg_discs(r_all, a_all, max_range, offset, trig=(cos_all, sin_all))
    if not len(d):
        return pts
    rx = (d[:, 0:1] + d[:, 2:3] * _RING_COS[None, :]).ravel()
    ry = (d[:, 1:2] + d[:, 2:3] * _RING_SIN[None, :]).ravel()
    return np.concatenate((pts, np.column_stack((rx, ry))))


def leg_discs(r_all: np.ndarray, a_all: np.ndarray, max_range: float, offset: float, *,
              trig: tuple[np.ndarray, np.ndarray] | None = None) -> np.ndarray:
    """(K, 3) robot-frame discs (x, y, radius) the narrow clusters of a scan stand for: a pair of legs
    is a body of :data:`BODY_RING` m round their middle, a lone cluster (a leg hiding the other, a
    table leg) :data:`LONE_RING` m (``r_all``, ``a_all``: every beam's range and angle, radians)."""
    centres = narrow_clusters(r_all, a_all, max_range, trig=trig)
    if not len(centres):
        return np.zeros((0, 3))
    cx = offset + centres[:, 0] * np.cos(centres[:, 1])
    cy = centres[:, 0] * np.sin(centres[:, 1])
    discs = []  # (x, y, radius): a pair of legs is a body between them, a lone cluster a smaller disc
    used = np.zeros(len(cx), dtype=bool)
    for i in range(len(cx)):
        if used[i]:
            continue
        j = next((j for j in range(i + 1, len(cx)) if not used[j] and math.hypot(cx[j] - cx[i], cy[j] - cy[i]) < PAIR), None)
        if j is None:
            discs.append((cx[i], cy[i], LONE_RING))
        else:
            used[j] = True
            discs.append(((cx[i] + cx[j]) / 2, (cy[i] + cy[j]) / 2, BODY_RING))
    return np.array(discs)


_RING = np.linspace(0.0, 2 * math.pi, 10, endpoint=False)
_RING_COS, _RING_SIN = np.cos(_RING), np.sin(_RING)
def people_gaps(x: np.ndarray, y: np.ndarray, th: np.ndarray, people: np.ndarray) -> np.ndarray:
    """The air gap (m) between the footprint at each pose (arrays of one shape) and the nearest body.

    ``people``: (P, 2) person centres in the robot frame; bodies are :data:`BODY` m round them.
    """
    c, s = np.cos(th)[..., None], np.sin(th)[..., None]
    dx, dy = people[:, 0] - x[..., None], people[:, 1] - y[..., None]
    lx, ly = c * dx + s * dy, -s * dx + c * dy
    return (footprint_distance(lx, ly) - BODY).min(axis=-1)


@lru_cache(maxsize=8)
def _beams(min_angle: float, resolution: float, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each beam's angle, cosine and sine (the same for every scan of a laser: computed once, read-only)."""
    a = min_angle + resolution * np.arange(n)
    out = (a, np.cos(a), np.sin(a))
    for arr in out:
        arr.flags.writeable = False
    return out


def looked_empty(ranges: Any, min_angle: float, resolution: float, offset: float, x: float, y: float,
                 radius: float = 0.25) -> bool:
    """Whether a scan (``ranges`` from ``min_angle`` in steps of ``resolution``, the laser ``offset`` m
    ahead of the robot's centre) looks at the disc of ``radius`` m round (``x``, ``y``) (robot frame)
    and finds nobody there: its middle (the half of it round its centre's bearing, where her legs
    would be) lies in the laser's field of view, and every beam of the scan that crosses the disc
    reaches beyond its far side. A body stands where the scan shows nothing only when the
    scan does not look there (beside or behind the laser, behind a wall or someone nearer). A
    partner's predicted position the laser sees through is no body: she is not there (she walked
    past the robot's side; flow/follow_while_looking, libflow14)."""
    lx, ly = x - offset, y
    dist = math.hypot(lx, ly)
    if dist <= radius + 0.05:
        return False  # the laser is inside or at the disc: it cannot look across it
    r = np.asarray(ranges, dtype=float)
    half = math.asin(min(1.0, radius / dist))
    bearing = math.atan2(ly, lx)
    lo, hi = bearing - half, bearing + half
    last = min_angle + resolution * (len(r) - 1)
    if not min_angle + half / 2 <= bearing <= last - half / 2:
        return False  # its middle (where her legs are) out of the field of view
    i0 = max(0, int(math.ceil((lo - min_angle) / resolution)))
    i1 = min(len(r) - 1, int(math.floor((hi - min_angle) / resolution)))
    if i1 < i0:
        return False
    return bool(np.all(r[i0:i1 + 1] > dist + radius))


def heading_speed(v: float, bearing: float) -> float:
    """``v`` scaled down as the goal's ``bearing`` (rad, robot frame) grows: 0 beyond 60 degrees.

    A goal behind or beside the robot is turned to first (on the spot) instead
    of reached by a wide forward arc, which would sweep the footprint into
    furniture and out of the laser's 180-degree view.
    """
    off = abs(bearing) * 1.5
    return 0.0 if off >= math.pi / 2 else v * math.cos(off)


#: Within this distance (m, centre to centre) of a person the robot drives at most :data:`SOCIAL_SPEED`.
SOCIAL_NEAR = 1.2
#: Beyond this distance (m) a person does not limit the speed; in between the limit rises linearly.
SOCIAL_FAR = 2.0
#: m/s: the speed limit close to people (a slow walk: people are passed gently, never rushed at).
SOCIAL_SPEED = 0.2


def social_speed_limit(d: float, max_speed: float) -> float:
    """The speed limit (m/s) with the nearest person ``d`` metres away (no person: ``inf``)."""
    if d <= SOCIAL_NEAR:
        return min(SOCIAL_SPEED, max_speed)
    if d >= SOCIAL_FAR:
        return max_speed
    f = (d - SOCIAL_NEAR) / (SOCIAL_FAR - SOCIAL_NEAR)
    return min(max_speed, SOCIAL_SPEED + f * max(max_speed - SOCIAL_SPEED, 0.0))


def carrot(a: tuple[float, float], b: tuple[float, float], p: tuple[float, float], lookahead: float) -> tuple[float, float]:
    """The point ``lookahead`` m ahead of ``p``'s projection on the segment a-b, at most ``b`` (pure pursuit).

    Steering at it keeps the robot on the planned leg (which the planner kept clear of
    the map's obstacles) instead of cutting corners toward the leg's end.
    """
    dx, dy = b[0] - a[0], b[1] - a[1]
    n2 = dx * dx + dy * dy
    if n2 < 1e-12:
        return b
    n = math.sqrt(n2)
    t = max(0.0, min(1.0, ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / n2))
    t = min(1.0, t + lookahead / n)
    return a[0] + t * dx, a[1] + t * dy


class LatestScan:
    """The latest ``/robot/laser/scan`` message, turned into obstacle points only when asked.

    The laser publishes faster than (or as fast as) the controllers run; a scan
    is converted (:func:`scan_points`, legs inflated to bodies) at most once,
    by the first control step that needs it. Until the first scan: no points.
    """

    def __init__(self) -> None:
        self._msg: Any = None
        self._points = np.zeros((0, 2))
        self._raw: Any = None  # the latest scan message, for :meth:`bodies`

    def update(self, msg: Any) -> None:
        """Keep ``msg`` (a scan Message: XML attributes and the ``ranges`` attachment)."""
        self._msg = msg
        self._raw = msg

    @property
    def latest(self) -> Any:
        """The latest scan message (None before the first)."""
        return self._raw

    def bodies(self) -> np.ndarray:
        """(K, 2) robot-frame centres of the people (pairs of legs, :func:`leg_discs`) in the latest scan."""
        msg = self._raw
        if msg is None:
            return np.zeros((0, 2))
        x = msg.xml
        r = np.asarray(msg.attachments["ranges"], dtype=float)
        a, c, s = _beams(math.radians(float(x.get("min_angle"))), math.radians(float(x.get("resolution"))), len(r))
        d = leg_discs(r, a, float(x.get("max_range")), float(x.get("offset")), trig=(c, s))
        return d[d[:, 2] >= BODY_RING - 1e-9, :2] if len(d) else np.zeros((0, 2))

    def sees_through(self, x: float, y: float, radius: float = 0.25) -> bool:
        """Whether the latest scan looks at the disc of ``radius`` m round (``x``, ``y``) (robot frame)
        and finds it empty: :func:`looked_empty`. False before the first scan."""
        msg = self._raw
        if msg is None:
            return False
        a = msg.xml
        return looked_empty(msg.attachments["ranges"], math.radians(float(a.get("min_angle"))),
                            math.radians(float(a.get("resolution"))), float(a.get("offset")), x, y, radius)

    def points(self) -> np.ndarray:
        """The latest scan as (N, 2) robot-frame points (computed once per scan)."""
        msg = self._msg
        if msg is not None:
            x = msg.xml
            self._points = scan_points(msg.attachments["ranges"], math.radians(float(x.get("min_angle"))),
                                       math.radians(float(x.get("resolution"))), float(x.get("max_range")),
                                       float(x.get("offset")))
            self._msg = None
        return self._points


#: A cluster of echoes narrower than this (m) is a leg (or a table leg).
NARROW = 0.2
#: Radius (m) of the ring of points standing for a body between a pair of legs.
BODY_RING = 0.25
#: Radius (m) of the ring around a lone narrow cluster (one leg hiding the other, or a table leg).
LONE_RING = 0.15
#: Two narrow clusters closer than this (m) are one person's legs.
PAIR = 0.45
JUMP = 0.15  # m: a range jump between neighbouring beams separates clusters


def narrow_clusters(r: np.ndarray, a: np.ndarray, max_range: float, *, near: float = 4.0,
                    trig: tuple[np.ndarray, np.ndarray] | None = None) -> np.ndarray:
    """(K, 2) (range, angle) of a point 6 cm behind the middle of each narrow cluster within ``near`` m.

    ``trig``: cos and sin of ``a`` when the caller has them already."""
    valid = r < max_range - 1e-6
    if not valid.any():
        return np.zeros((0, 2))
    breaks = np.flatnonzero((np.abs(np.diff(r)) > JUMP) | ~valid[1:] | ~valid[:-1]) + 1
    starts = np.concatenate(([0], breaks))
    ends = np.concatenate((breaks, [len(r)]))
    ok = valid[starts]  # clusters of echoes (a run of no-echo beams is a cluster too: dropped below)
    last = ends - 1
    ca, sa = trig if trig is not None else (np.cos(a), np.sin(a))
    x, y = r * ca, r * sa
    width = np.hypot(x[last] - x[starts], y[last] - y[starts])
    sums = np.add.reduceat(np.where(valid, r, 0.0), starts)
    counts = ends - starts
    mid = sums / counts
    amid = np.add.reduceat(a, starts) / counts
    nearest = np.minimum.reduceat(np.where(valid, r, np.inf), starts)
    # set off from its neighbours: both sides further away (or nothing)
    pad = np.concatenate((np.where(valid, r, max_range), [max_range]))
    left = pad[ends]
    right = np.where(starts > 0, pad[np.maximum(starts - 1, 0)], max_range)
    keep = ok & (width < NARROW) & (nearest <= near) & (left > mid + JUMP) & (right > mid + JUMP)
    return np.column_stack((mid[keep] + 0.06, amid[keep]))


def sweep_clearance(v: float, w: float, points: np.ndarray, duration: float, *, steps: int = 5) -> float:
    """The smallest footprint distance (m) to ``points`` (robot frame) along the arc (v, w) for ``duration`` s.

    What a command the dynamic window does not choose (the follower's wait: turning to face
    the partner, backing off) is checked with: the footprint at each of ``steps`` poses,
    the start included (inf without points).
    """
    if not len(points):
        return math.inf
    t = np.linspace(0.0, duration, steps + 1)
    x, y, th = arcs(np.array([v]), np.array([w]), t)
    c, s = np.cos(th[0])[:, None], np.sin(th[0])[:, None]
    dx, dy = points[None, :, 0] - x[0][:, None], points[None, :, 1] - y[0][:, None]
    return float(footprint_distance(c * dx + s * dy, -s * dx + c * dy).min())


def nearest_per_sector(points: np.ndarray, reach: float, sectors: int) -> np.ndarray:
    """The nearest point within ``reach`` of the centre in each of ``sectors`` equal angular sectors.

    What can hit the footprint in the next second is the nearest thing in each
    direction; this keeps the dynamic window's cost bounded by ``sectors``
    whatever the scan holds (4 degrees: 7 cm apart at a metre).
    """
    if not len(points):
        return points
    r = np.hypot(points[:, 0], points[:, 1])
    keep = r < reach
    if not keep.any():
        return points[:0]
    pts, r = points[keep], r[keep]
    sector = ((np.arctan2(pts[:, 1], pts[:, 0]) + math.pi) * (sectors / (2 * math.pi))).astype(int) % sectors
    order = np.argsort(sector + r / (reach + 1.0), kind="stable")  # by sector, then by range (r < reach)
    s = sector[order]
    first = np.flatnonzero(np.concatenate(([True], s[1:] != s[:-1])))
    return pts[order[first]]


def stopping_time(v: np.ndarray, limits: Limits, params: DWAParams) -> np.ndarray:
    """Seconds at constant ``v`` that cover one more control step plus the braking distance v^2/2a."""
    return params.period + np.abs(v) / (2 * limits.max_accel)


def arcs_at(v: np.ndarray, w: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The pose of each arc at its own time ``t[k]``, each (K, 1)."""
    small = np.abs(w) < 1e-6
    safe_w = np.where(small, 1.0, w)
    th = w * t
    x = np.where(small, v * t, v / safe_w * np.sin(th))
    y = np.where(small, 0.0, v / safe_w * (1.0 - np.cos(th)))
    return x[:, None], y[:, None], th[:, None]


@lru_cache(maxsize=8)
def _index(n: int) -> np.ndarray:
    a = np.arange(n, dtype=float)
    a.flags.writeable = False
    return a


def _linspace(lo: float, hi: float, n: int) -> np.ndarray:
    """``np.linspace(lo, hi, n)``, bit for bit (the same operations), without its per-call overhead."""
    if n == 1:
        return np.array([lo])
    y = _index(n) * ((hi - lo) / (n - 1)) + lo
    y[-1] = hi
    return y


@lru_cache(maxsize=8)
def _times(horizon: float, steps: int) -> np.ndarray:
    """The arc poses' times (a constant of the tuning: computed once, read-only)."""
    t = np.linspace(horizon / steps, horizon, steps)
    t.flags.writeable = False
    return t


def dwa(v0: float, w0: float, goal: tuple[float, float], points: np.ndarray, limits: Limits, *, v_pref: float,
        params: DWAParams = DWAParams(), people: np.ndarray | None = None) -> Command:
    """The best admissible (v, w) toward ``goal`` (robot frame) given the laser ``points`` (see module docstring).

    ``people``: (P, 2) robot-frame centres of the people the attention tracks (the follower leaves
    its partner out): arcs keep :data:`SOCIAL_GAP` from their bodies (see :func:`social_mask`).
    """
    p = params
    dv, dw = limits.max_accel * p.window, limits.max_turn_accel * p.window
    vlo = max(v0 - dv, -limits.max_reverse if v_pref < 0 else 0.0)
    vhi = min(v0 + dv, limits.max_speed)
    if vlo > vhi:  # moving faster backwards/forwards than the window allows: brake
        vlo = vhi = min(max(0.0, vlo), vhi) if v0 > 0 else max(vlo, min(0.0, vhi))
    vs = _linspace(vlo, vhi, p.nv)
    if not np.any(np.abs(vs) <= 1e-8) and vlo <= 0.0 <= vhi:
        vs = np.append(vs, 0.0)
    ws = _linspace(max(w0 - dw, -limits.max_turn), min(w0 + dw, limits.max_turn), p.nw)
    V, W = np.repeat(vs, len(ws)), np.tile(ws, len(vs))  # np.meshgrid(vs, ws, indexing="ij"), raveled
    times = _times(p.horizon, p.steps)
    x, y, th = arcs(V, W, times)

    t_stop = stopping_time(V, limits, p)
    # only echoes the footprint can come within clear_cap of along any arc (or its stopping pose)
    # matter: further ones neither make an arc inadmissible nor change its capped clearance
    travel = float(np.max(np.abs(V))) * max(p.horizon, float(np.max(t_stop)))
    near = min(p.reach, travel + math.hypot(HALF_LENGTH, HALF_WIDTH) + max(p.clear_cap, p.margin) + 1e-6)
    pts = nearest_per_sector(points, near, p.sectors)
    if len(pts):
        # every echo in the frame of every pose (the K*S arc poses, then the K stopping poses) by one
        # matrix product: local = R(-th) (pt - pose) = [c, s, -(c x + s y)] . [px, py, 1]
        sx, sy, sth = (a[:, 0] for a in arcs_at(V, W, t_stop))
        px_all = np.concatenate((x.ravel(), sx))
        py_all = np.concatenate((y.ravel(), sy))
        th_all = np.concatenate((th.ravel(), sth))
        c, s = np.cos(th_all), np.sin(th_all)
        rows = len(c)
        m = np.empty((2 * rows, 3))
        m[:rows, 0], m[:rows, 1], m[:rows, 2] = c, s, -(c * px_all + s * py_all)
        m[rows:, 0], m[rows:, 1], m[rows:, 2] = -s, c, s * px_all - c * py_all
        q = np.empty((3, len(pts)))
        q[0], q[1], q[2] = pts[:, 0], pts[:, 1], 1.0
        loc = m @ q  # (2 rows, N): local x then local y
        np.abs(loc, out=loc)
        loc[:rows] -= HALF_LENGTH
        loc[rows:] -= HALF_WIDTH
        np.maximum(loc, 0.0, out=loc)
        np.square(loc, out=loc)
        d2 = loc[:rows] + loc[rows:]
        dmin = np.sqrt(d2.min(axis=1))  # footprint distance of the nearest echo, per pose
        k_arcs = len(V)
        d = dmin[: k_arcs * len(times)].reshape(k_arcs, len(times))  # (K, S)
        # hard limit: the part of the arc the robot covers if it keeps v for one more control
        # step and then brakes (its stopping distance, at constant v: t_stop), end point included
        hard = np.where(times[None, :] <= t_stop[:, None], d, np.inf).min(axis=1)
        hard = np.minimum(hard, dmin[k_arcs * len(times):])
        here = footprint_distance(pts[:, 0], pts[:, 1]).min()
        clear = d.min(axis=1)
    else:
        hard = clear = np.full(len(V), np.inf)
        here = np.inf
    social = None
    if people is not None and len(people):
        social, gaps = social_mask(x, y, th, np.asarray(people, dtype=float).reshape(-1, 2), V, gap=p.social_gap)
        clear = np.minimum(clear, gaps)
    return choose(V, W, x, y, th, hard, clear, here, d if len(pts) else None, goal, v_pref, p, social=social)


def social_mask(x: np.ndarray, y: np.ndarray, th: np.ndarray, people: np.ndarray,
                v: np.ndarray | None = None, *, gap: float = SOCIAL_GAP) -> tuple[np.ndarray, np.ndarray]:
    """Which arcs (rows of the (K, S) poses) respect people's space, and each arc's smallest gap to a body.

    An arc is fine when its footprint stays ``gap`` (:data:`SOCIAL_GAP`) from every body over its whole
    horizon, or when it never brings the robot closer than it is now (standing still always does),
    or when it turns on the spot (``v`` 0: nobody comes nearer the centre; the laser echoes guard the
    corners. The follower's own turns, outside the window, are held to :func:`turn_clear`).
    The whole horizon, not just the stopping distance as for walls: people's positions come from
    a tracker and jitter by a decimetre, and a robot that may close in until it could just stop
    creeps up to them step by step.
    """
    gaps = people_gaps(x, y, th, people).min(axis=1)
    now = float(people_gaps(np.zeros(1), np.zeros(1), np.zeros(1), people)[0])
    ok = (gaps >= gap) | (gaps >= min(now, gap) - 1e-3)
    if v is not None:
        ok |= np.abs(v) < 1e-9
    return ok, gaps


def choose(V: np.ndarray, W: np.ndarray, x: np.ndarray, y: np.ndarray, th: np.ndarray, hard: np.ndarray,
           clear: np.ndarray, here: float, d: np.ndarray | None, goal: tuple[float, float], v_pref: float,
           p: DWAParams, *, social: np.ndarray | None = None) -> Command:
    """Score the admissible arcs and pick the best: the dynamic window's decision once distances are known.

    ``d`` (arcs x steps) is the footprint distance along each arc, None without obstacles; shared by
    the fast window and the elementwise reference the tests hold it to, so they differ only in how
    they measure distances.
    """
    admissible = hard > p.margin
    # in contact already: only arcs that do not get closer
    if here <= p.margin:
        admissible = admissible | (d.min(axis=1) >= here - 1e-3) if d is not None else admissible
    if social is not None:
        admissible = admissible & social
    if not admissible.any():
        return Command(0.0, 0.0, False, float(here))
    gx, gy = goal
    ex, ey, eth = x[:, -1], y[:, -1], th[:, -1]
    dist = np.hypot(gx - ex, gy - ey)
    head = np.abs(np.remainder(np.arctan2(gy - ey, gx - ex) - eth + math.pi, 2 * math.pi) - math.pi)
    head = np.where(dist < 0.15, 0.0, head)
    score = (-p.w_goal * dist - p.w_heading * head + p.w_clear * np.minimum(clear, p.clear_cap)
             - p.w_speed * np.abs(V - v_pref))
    score = np.where(admissible, score, -np.inf)
    k = int(np.argmax(score))
    return Command(float(V[k]), float(W[k]), True, float(clear[k]))
