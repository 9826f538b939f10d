"""The dynamic window as it was before it was vectorised (one elementwise pass per pose), kept as the
reference that :func:`robot.navigation.local.dwa` must agree with (tests/test_nav_dwa.py)."""

from __future__ import annotations

import math

import numpy as np

from robot.navigation.config import Limits
from robot.navigation.local import Command, DWAParams, arcs, arcs_at, choose, footprint_distance, stopping_time


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
    order = np.lexsort((r, sector))
    _, first = np.unique(sector[order], return_index=True)
    return pts[order[first]]


def reference_dwa(v0: float, w0: float, goal: tuple[float, float], points: np.ndarray, limits: Limits, *, v_pref: float,
        params: DWAParams = DWAParams()) -> Command:
    """The best admissible (v, w) toward ``goal`` (robot frame) given the laser ``points`` (see module docstring)."""
    p = params
    dv, dw = limits.max_accel * p.window, limits.max_turn_accel * p.window
    vlo = max(v0 - dv, -limits.max_reverse if v_pref < 0 else 0.0)
    vhi = min(v0 + dv, limits.max_speed)
    if vlo > vhi:  # moving faster backwards/forwards than the window allows: brake
        vlo = vhi = min(max(0.0, vlo), vhi) if v0 > 0 else max(vlo, min(0.0, vhi))
    vs = np.linspace(vlo, vhi, p.nv)
    if not np.any(np.isclose(vs, 0.0)) and vlo <= 0.0 <= vhi:
        vs = np.append(vs, 0.0)
    ws = np.linspace(max(w0 - dw, -limits.max_turn), min(w0 + dw, limits.max_turn), p.nw)
    V, W = (a.ravel() for a in np.meshgrid(vs, ws, indexing="ij"))
    times = np.linspace(p.horizon / p.steps, p.horizon, p.steps)
    x, y, th = arcs(V, W, times)

    pts = nearest_per_sector(points, p.reach, p.sectors)
    if len(pts):
        # each obstacle point in each pose's frame: (K, S, N)
        dxw = pts[None, None, :, 0] - x[:, :, None]
        dyw = pts[None, None, :, 1] - y[:, :, None]
        c, s = np.cos(th)[:, :, None], np.sin(th)[:, :, None]
        lx = c * dxw + s * dyw
        ly = -s * dxw + c * dyw
        d = footprint_distance(lx, ly).min(axis=2)  # (K, S)
        # hard limit: the part of the arc the robot covers if it keeps v for one more control
        # step and then brakes (its stopping distance, at constant v: t_stop), end point included
        t_stop = stopping_time(V, limits, p)
        hard = np.where(times[None, :] <= t_stop[:, None], d, np.inf).min(axis=1)
        sx, sy, sth = (a[:, 0] for a in arcs_at(V, W, t_stop))
        dxs, dys = pts[None, :, 0] - sx[:, None], pts[None, :, 1] - sy[:, None]
        cs, ss = np.cos(sth)[:, None], np.sin(sth)[:, None]
        hard = np.minimum(hard, footprint_distance(cs * dxs + ss * dys, -ss * dxs + cs * dys).min(axis=1))
        here = footprint_distance(pts[:, 0], pts[:, 1]).min()
        clear = d.min(axis=1)
    else:
        hard = clear = np.full(len(V), np.inf)
        here = np.inf
    return choose(V, W, x, y, th, hard, clear, here, d if len(pts) else None, goal, v_pref, p)
