"""Monte Carlo localisation on a likelihood field: the filter, without the bus.

Why a particle filter and not scan matching. The robot is given its start
pose, so both would track; but the flat is full of things the floor plan
does not hold (people's legs, right in front of the robot during the whole
interaction) and of repeating geometry (parallel walls, a row of table
legs), where an ICP-style matcher locks onto a wrong correspondence and
never recovers, and its single estimate carries no honest uncertainty. A
particle filter keeps several hypotheses, absorbs unexplained beams in the
likelihood field's random term, and its spread is the covariance the
contract publishes. With a likelihood field (Thrun et al., Probabilistic
Robotics §6.4: a precomputed distance-to-nearest-obstacle grid from
:func:`homesim.ndgrid.distance_transform_edt`, SciPy's EDT bit for bit) a beam costs one table look-up,
so 120 particles x 30 beams is one vectorised gather of 3600 cells.

Cost control: the filter corrects only after the robot moved ``update_dist``
metres or turned ``update_angle`` radians (as AMCL), uses every
``len(ranges) // beams``-th beam, and resamples (low-variance) only when the
effective sample size falls under half the particles. Between corrections
the published pose is the last estimate composed with the odometry since.

Frames: odometry poses are in ``odom``; particles and estimates in ``map``.
Everything is numpy; randomness only from the generator handed in.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from homesim.ndgrid import dilate3x3, distance_transform_edt, label

from robot.floorplan import FloorPlan

Pose = tuple[float, float, float]


def wrap(a: float | np.ndarray) -> float | np.ndarray:
    """Angle(s) wrapped to [-pi, pi)."""
    return (a + math.pi) % (2 * math.pi) - math.pi


def relative(a: Pose, b: Pose) -> Pose:
    """Pose b expressed in the frame of pose a (b ominus a)."""
    dx, dy = b[0] - a[0], b[1] - a[1]
    c, s = math.cos(a[2]), math.sin(a[2])
    return c * dx + s * dy, -s * dx + c * dy, float(wrap(b[2] - a[2]))


def compose(a: Pose, d: Pose) -> Pose:
    """Pose a moved by d given in a's frame (a oplus d)."""
    c, s = math.cos(a[2]), math.sin(a[2])
    return a[0] + c * d[0] - s * d[1], a[1] + s * d[0] + c * d[1], float(wrap(a[2] + d[2]))


@dataclass(frozen=True)
class MCLParams:
    """Filter settings (defaults: a PeopleBot in a flat, SICK at 10 Hz)."""

    particles: int = 120
    beams: int = 30  # beams used per correction (subsampled evenly)
    resolution: float = 0.02  # likelihood-field cell, metres (quantisation is +-res/2 of error)
    sigma_hit: float = 0.08  # metres: beam end point to nearest obstacle (noise + plan error + cells)
    z_hit: float = 0.85
    z_rand: float = 0.15  # people, unmapped things
    effective_beams: float = 36  # the scan counts as this many independent beams (tempering)
    update_dist: float = 0.10  # metres moved before a correction
    update_angle: float = 0.10  # radians turned before a correction
    # odometry motion model (Probabilistic Robotics Table 5.6), std factors
    a_rot_rot: float = 0.05
    a_rot_trans: float = 0.15  # rad per metre
    a_trans_trans: float = 0.15
    a_trans_rot: float = 0.02  # metres per rad
    init_xy: float = 0.10  # metres, the operator's start pose uncertainty
    init_theta: float = 0.05  # radians
    laser_height: float = 0.30
    through_min_depth: float = 0.03  # metres inside a solid that count (a grazing beam nicks a corner)
    through_depth: float = 0.05  # metres before a beam's end checked for lying inside a solid (half a 10 cm wall)


class LikelihoodField:
    """Distance to the nearest mapped obstacle at the laser's height, on a grid."""

    def __init__(self, plan: FloorPlan, *, resolution: float = 0.05, height: float = 0.30, margin: float = 1.0) -> None:
        xmin, ymin, xmax, ymax = plan.bounds()
        self.res = resolution
        self.x0, self.y0 = xmin - margin, ymin - margin
        self.nx = int(math.ceil((xmax + margin - self.x0) / resolution)) + 1
        self.ny = int(math.ceil((ymax + margin - self.y0) / resolution)) + 1
        occ = np.zeros((self.ny, self.nx), dtype=bool)
        a, b = plan.segments_at(height)
        for (ax, ay), (bx, by) in zip(a, b):
            n = max(2, int(math.ceil(math.hypot(bx - ax, by - ay) / (resolution * 0.25))) + 1)
            t = np.linspace(0.0, 1.0, n)
            ix = np.floor((ax + t * (bx - ax) - self.x0) / resolution).astype(int)
            iy = np.floor((ay + t * (by - ay) - self.y0) / resolution).astype(int)
            occ[iy, ix] = True
        if not occ.any():
            raise ValueError("the floor plan has nothing at the laser's height to localise against")
        self.solid = np.zeros_like(occ)  # inside a wall or closed furniture (set by _visible_faces)
        occ = self._visible_faces(occ, plan, (xmin, ymin, xmax, ymax))
        # Distance from each cell centre to the nearest occupied cell centre; a half cell is
        # the worst-case offset of a surface inside its cell, removed so the field is unbiased.
        self.dist = np.maximum(distance_transform_edt(~occ) * resolution - resolution / 2, 0.0)
        self.far = float(self.dist.max())

    def _visible_faces(self, occ: np.ndarray, plan: FloorPlan, bounds: tuple[float, float, float, float]) -> np.ndarray:
        """Keep only the obstacle faces the laser can see from the rooms.

        The plan's outlines give both faces of every wall and closed piece of furniture; with
        both in the field, a pose shifted by a wall's thickness (10 cm) towards it matches the
        far face as well as the truth matches the near one, and the cloud drifts into the wall.
        The rooms are the free cells connected (4-neighbours, inside the plan's bounds) to the
        operator's start pose; a face counts if it touches them. If the start is not in free
        space (a plan that does not close), every face is kept, as before.
        """
        xmin, ymin, xmax, ymax = bounds
        ix, iy = int((plan.start[0] - self.x0) / self.res), int((plan.start[1] - self.y0) / self.res)
        free = ~occ
        inside = np.zeros_like(occ)
        i0, j0 = int((xmin - self.x0) / self.res), int((ymin - self.y0) / self.res)
        i1, j1 = int((xmax - self.x0) / self.res), int((ymax - self.y0) / self.res)
        inside[j0 : j1 + 1, i0 : i1 + 1] = True
        labels, _ = label(free & inside)
        if not (0 <= iy < self.ny and 0 <= ix < self.nx) or labels[iy, ix] == 0:
            return occ
        rooms = labels == labels[iy, ix]
        # the inside of walls and closed furniture: free cells of the plan not in the rooms
        self.solid = free & inside & ~rooms
        faces = occ & dilate3x3(rooms)
        return faces if faces.any() else occ

    def lookup(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """Distance at world points (any shape); points off the grid read the field's maximum."""
        return self._gather(self.dist, x, y, self.far)

    def log_table(self, sigma: float, z_hit: float, rand: float) -> np.ndarray:
        """Per cell, the log-likelihood of a beam ending there (z_hit Gaussian on the distance
        plus a uniform ``rand`` for unmapped things), with a border row/column of the
        off-grid value: :meth:`gather_log` then needs no exp, log or mask per beam."""
        d = np.pad(self.dist, 1, constant_values=self.far)
        return np.log(z_hit * np.exp(-0.5 * (d / sigma) ** 2) + rand).astype(np.float32)

    def through_table(self, penalty: float, depth: float) -> np.ndarray:
        """Per cell, ``penalty`` inside a wall or closed furniture and 0 elsewhere, padded as
        :meth:`log_table`: a beam whose last few centimetres lie inside a solid went through it.
        Only cells ``depth`` or more inside count: a beam grazing a face at a shallow angle,
        from a pose a few centimetres off, nicks the solid's edge without going through.

        Why: a wall between two rooms shows both its faces to the rooms, so the distance field
        alone scores a pose shifted by the wall's thickness (its beams ending on the far face)
        as well as the truth; a real beam stops at the near face."""
        deep = distance_transform_edt(self.solid) * self.res >= depth
        return np.pad(np.where(deep, penalty, 0.0), 1, constant_values=0.0).astype(np.float32)

    def gather_log(self, table: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """Look up ``table`` (from :meth:`log_table`) at world points; off-grid points read its border."""
        ix = np.clip(((x - self.x0) * (1.0 / self.res)).astype(np.intp) + 1, 0, self.nx + 1)
        iy = np.clip(((y - self.y0) * (1.0 / self.res)).astype(np.intp) + 1, 0, self.ny + 1)
        return table.ravel()[iy * (self.nx + 2) + ix]

    def _gather(self, grid: np.ndarray, x: np.ndarray, y: np.ndarray, off: float) -> np.ndarray:
        ix = np.floor((x - self.x0) / self.res).astype(np.intp)
        iy = np.floor((y - self.y0) / self.res).astype(np.intp)
        inside = (ix >= 0) & (ix < self.nx) & (iy >= 0) & (iy < self.ny)
        out = np.full(x.shape, off)
        out[inside] = grid[iy[inside], ix[inside]]
        return out


class MCL:
    """The particle set and its three steps: predict (odometry), correct (a scan), resample."""

    def __init__(self, plan: FloorPlan, rng: np.random.Generator, params: MCLParams | None = None, *, start: Pose | None = None) -> None:
        self.p = params or MCLParams()
        self.rng = rng
        self.field = LikelihoodField(plan, resolution=self.p.resolution, height=self.p.laser_height)
        x, y, th = plan.start if start is None else start
        n = self.p.particles
        self.x = x + rng.normal(0.0, self.p.init_xy, n)
        self.y = y + rng.normal(0.0, self.p.init_xy, n)
        self.th = wrap(th + rng.normal(0.0, self.p.init_theta, n))
        self.logw = np.zeros(n)
        self.updates = 0
        self.resamples = 0
        self._table = self.field.log_table(self.p.sigma_hit, self.p.z_hit, self.p.z_rand / 8.19)
        # a beam through a solid scores as a miss instead of a hit
        rand = self.p.z_rand / 8.19
        self._through = self.field.through_table(math.log(rand) - math.log(self.p.z_hit + rand), self.p.through_min_depth)

    # ------------------------------------------------------------ predict
    def predict(self, d: Pose) -> None:
        """Move every particle by the odometry increment ``d`` (in the robot's frame), with noise."""
        dx, dy, dth = d
        trans = math.hypot(dx, dy)
        if trans < 1e-6 and abs(dth) < 1e-9:
            return
        # Decompose into rot1, trans, rot2; driving backwards keeps rot1 small.
        if trans < 1e-4:
            rot1 = 0.0
        else:
            rot1 = math.atan2(dy, dx)
            if abs(rot1) > math.pi / 2:  # reversing
                rot1 = float(wrap(rot1 - math.pi))
                trans = -trans
        rot2 = float(wrap(dth - rot1))
        p, n, r = self.p, self.x.shape[0], self.rng
        sr1 = p.a_rot_rot * abs(rot1) + p.a_rot_trans * abs(trans)
        st = p.a_trans_trans * abs(trans) + p.a_trans_rot * (abs(rot1) + abs(rot2))
        sr2 = p.a_rot_rot * abs(rot2) + p.a_rot_trans * abs(trans)
        noise = r.standard_normal((3, n))
        r1 = rot1 + sr1 * noise[0]
        tr = trans + st * noise[1]
        r2 = rot2 + sr2 * noise[2]
        h = self.th + r1
        self.x += tr * np.cos(h)
        self.y += tr * np.sin(h)
        self.th = wrap(h + r2)

    # ------------------------------------------------------------ correct
    def correct(self, ranges: np.ndarray, bearings: np.ndarray, offset: float, max_range: float) -> None:
        """Weight the particles by how well the scan's end points fall on the plan's obstacles.

        ``bearings`` are the beams' angles in the laser frame, ``offset`` the laser's distance
        ahead of the robot's centre. Beams reading ``max_range`` (no echo) are skipped.
        """
        step = max(1, ranges.shape[0] // self.p.beams)
        r = ranges[::step]
        b = bearings[::step]
        ok = (r < max_range - 1e-6) & (r > 0.05)
        r, b = r[ok], b[ok]
        if r.shape[0] < 5:
            return
        # End points in the robot's frame once (laser offset included), then rotated and moved
        # per particle: two products per beam instead of a cos and a sin.
        px = offset + r * np.cos(b)
        py = r * np.sin(b)
        c, s = np.cos(self.th)[:, None], np.sin(self.th)[:, None]
        ex = self.x[:, None] + c * px - s * py
        ey = self.y[:, None] + s * px + c * py
        loglike = self.field.gather_log(self._table, ex, ey).sum(axis=1, dtype=np.float64)
        # the point ``through_depth`` before each end point: inside a solid, the beam went through it
        qx, qy = px - self.p.through_depth * np.cos(b), py - self.p.through_depth * np.sin(b)
        loglike += self.field.gather_log(self._through, self.x[:, None] + c * qx - s * qy,
                                         self.y[:, None] + s * qx + c * qy).sum(axis=1, dtype=np.float64)
        # Beams are not independent (neighbouring beams hit the same wall): temper the product
        # so one scan cannot collapse the cloud to a single particle.
        self.logw += loglike * (self.p.effective_beams / r.shape[0])
        self.logw -= self.logw.max()
        self.updates += 1
        if self.neff() < 0.5 * self.x.shape[0]:
            self.resample()

    def weights(self) -> np.ndarray:
        w = np.exp(self.logw - self.logw.max())
        return w / w.sum()

    def neff(self) -> float:
        w = self.weights()
        return float(1.0 / np.dot(w, w))

    def resample(self) -> None:
        """Low-variance (systematic) resampling: one random number, the particles in order."""
        w = self.weights()
        n = w.shape[0]
        pos = (self.rng.random() + np.arange(n)) / n
        idx = np.minimum(np.searchsorted(np.cumsum(w), pos), n - 1)
        self.x, self.y, self.th = self.x[idx], self.y[idx], self.th[idx]
        self.logw = np.zeros(n)
        self.resamples += 1

    # ------------------------------------------------------------ estimate
    def estimate(self) -> tuple[Pose, tuple[float, float, float]]:
        """The weighted mean pose (circular mean heading) and the variances (xx, yy, theta)."""
        w = self.weights()
        mx, my = float(w @ self.x), float(w @ self.y)
        mth = math.atan2(float(w @ np.sin(self.th)), float(w @ np.cos(self.th)))
        dth = wrap(self.th - mth)
        cxx = float(w @ (self.x - mx) ** 2)
        cyy = float(w @ (self.y - my) ** 2)
        ctt = float(w @ dth**2)
        return (mx, my, mth), (cxx, cyy, ctt)
