"""Ground the laser has seen free: what a robot without a rear sensor may back over.

The PeopleBot's laser looks forwards (180 degrees); backing off, the robot
cannot see where it goes. :class:`SeenGround` keeps, in the odometry frame, a
small grid (10 cm cells, a 10 x 10 m window that follows the robot) of the
cells that laser beams passed through (free) and ended in (an echo), the
latest scan winning. A pose may be backed into when every sample of the
footprint (with a margin) lies in a cell seen free and none in an echo's cell;
unknown ground (never in view) is never backed into.

Memory is constant (one ``int8`` array); an update marks a few thousand cells
with numpy. What moved into seen ground since it was seen (a person walking
behind) is not known: the back-off is slow and short for that reason.
"""

from __future__ import annotations

import math

import numpy as np

UNKNOWN, FREE, ECHO = 0, 1, 2


class SeenGround:
    """Free and echo cells from laser scans in the odometry frame (see the module docstring)."""

    def __init__(self, *, cell: float = 0.1, size: int = 100, reach: float = 3.0) -> None:
        self.cell, self.size, self.reach = cell, size, reach
        self.grid = np.zeros((size, size), dtype=np.int8)
        self.origin: tuple[int, int] | None = None  # the window's lower-left cell (odom cell indices)
        self._ts = np.arange(0.05, reach, cell * 0.7)

    def _recentre(self, x: float, y: float) -> None:
        ci, cj = int(math.floor(x / self.cell)), int(math.floor(y / self.cell))
        half = self.size // 2
        if self.origin is not None:
            oi, oj = self.origin
            if abs(ci - (oi + half)) < half // 2 and abs(cj - (oj + half)) < half // 2:
                return
        new = (ci - half, cj - half)
        grid = np.zeros_like(self.grid)
        if self.origin is not None:
            di, dj = new[0] - self.origin[0], new[1] - self.origin[1]
            src = self.grid[max(di, 0):self.size + min(di, 0), max(dj, 0):self.size + min(dj, 0)]
            grid[max(-di, 0):max(-di, 0) + src.shape[0], max(-dj, 0):max(-dj, 0) + src.shape[1]] = src
        self.grid, self.origin = grid, new

    def _mark(self, xs: np.ndarray, ys: np.ndarray, value: int) -> None:
        oi, oj = self.origin  # type: ignore[misc]
        i = np.floor(xs / self.cell).astype(np.int64) - oi
        j = np.floor(ys / self.cell).astype(np.int64) - oj
        ok = (i >= 0) & (i < self.size) & (j >= 0) & (j < self.size)
        self.grid[i[ok], j[ok]] = value

    def add(self, ranges: np.ndarray, min_angle: float, resolution: float, max_range: float,
            sensor: tuple[float, float, float], *, stride: int = 4) -> None:
        """One scan (angles in radians) taken from ``sensor`` (x, y, heading in odom): beams free, echoes marked."""
        sx, sy, sth = sensor
        self._recentre(sx, sy)
        r = np.asarray(ranges, dtype=float)[::stride]
        a = sth + min_angle + resolution * stride * np.arange(len(r))
        c, s = np.cos(a), np.sin(a)
        ts = self._ts[:, None]
        free = ts < np.minimum(r, self.reach)[None, :] - 0.5 * self.cell
        self._mark((sx + ts * c)[free], (sy + ts * s)[free], FREE)
        hit = r < max_range - 1e-6
        self._mark(sx + r[hit] * c[hit], sy + r[hit] * s[hit], ECHO)

    def clear(self, xs: np.ndarray, ys: np.ndarray) -> bool:
        """Whether every point (odom frame) lies in a cell seen free (False for any unknown or echo cell)."""
        if self.origin is None:
            return False
        oi, oj = self.origin
        i = np.floor(np.asarray(xs) / self.cell).astype(np.int64) - oi
        j = np.floor(np.asarray(ys) / self.cell).astype(np.int64) - oj
        if ((i < 0) | (i >= self.size) | (j < 0) | (j >= self.size)).any():
            return False
        return bool((self.grid[i, j] == FREE).all())


def footprint_samples(x: float, y: float, theta: float, *, length: float, width: float,
                      margin: float) -> tuple[np.ndarray, np.ndarray]:
    """Points on and inside a ``length`` x ``width`` rectangle (grown by ``margin``) at the pose (odom)."""
    hl, hw = length / 2 + margin, width / 2 + margin
    u = np.array([-hl, -hl, -hl, 0.0, 0.0, hl, hl, hl, -hl / 2, hl / 2, -hl / 2, hl / 2, 0.0])
    v = np.array([-hw, 0.0, hw, -hw, hw, -hw, 0.0, hw, -hw, -hw, hw, hw, 0.0])
    c, s = math.cos(theta), math.sin(theta)
    return x + c * u - s * v, y + s * u + c * v
