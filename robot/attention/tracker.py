"""Anchoring: person tracks from leg candidates, one constant-velocity Kalman filter each.

Frame: ``odom`` (odometry's integration frame). Measurements arrive in the
robot frame and are moved into odom with the odometry pose at scan time.
Why odom and not the robot frame: the robot turns on the spot to face
people, and in the robot frame a person standing still would then sweep
sideways at the turn rate, which a constant-velocity model cannot follow;
in odom a standing person stands still and a walking one walks straight.
Odometry drifts (a few cm per metre driven), far slower than a track lives,
so the drift never matters to association.

Each track is a constant-velocity Kalman filter, state ``[x, y, vx, vy]``,
white-noise acceleration ``accel_noise``; a leg candidate measures ``[x, y]``.
The filters are kept as stacked arrays and predicted, gated and updated for
all tracks at once (numpy): ``filterpy.kalman.KalmanFilter.update`` costs
about 135 us per call, three tracks would eat the whole per-scan budget
four times over. The batched filter computes exactly what one filterpy
KalmanFilter per track would (the tests check it against filterpy); the
per-track view :meth:`Tracks.filterpy` builds that filter.

Association: Mahalanobis distance of every candidate to every track's
predicted position (batched 2x2 innovation covariances), gated at the
chi-square 99 % point, then global nearest neighbour with
``scipy.optimize.linear_sum_assignment``. Pairs and blobs can start tracks;
single legs (the other hidden, or a table leg) feed tracks but never start
or confirm one, and alone (with frontal faces, :meth:`Tracks.support`) keep one for at most
``single_support`` seconds after a pair or blob last fed it, so a track that
lost its person does not live on a table leg. Birth: a tentative track per unassigned
pair/blob, confirmed after ``confirm_hits`` pair/blob hits within
``confirm_window`` seconds (repeated evidence; a far person's legs pair only
now and then); a tentative track unseen for ``tentative_gap`` is dropped; a
confirmed track dies ``death_timeout`` seconds after its last anchored evidence
(a leg update, a frontal face, or for the partner its torso or voice: a
person standing still whose legs do not associate for a while is still
there while the camera sees them; its
prediction coasts through occlusions and crossings meanwhile, with its
velocity damped so it does not run away).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import linear_sum_assignment

from .legs import SINGLE, Detections

GATE_99 = 9.2103  # chi-square, 2 degrees of freedom, 99 %


@dataclass(frozen=True)
class TrackerSpec:
    accel_noise: float = 1.5  # m/s^2 (std of the white-noise acceleration)
    meas_std: float = 0.06  # m: a leg pair's centre (legs swing about it while walking)
    single_std: float = 0.12  # m: a single leg is up to a leg spread off the person's centre
    gate: float = GATE_99  # squared Mahalanobis distance
    single_gate: float = 4.0  # tighter for single legs (clutter)
    single_support: float = 8.0  # s: singles (or faces) alone keep a track only this long after a pair/blob fed it
    confirm_hits: int = 3
    confirm_window: float = 1.0  # s: ... within this long after birth
    tentative_gap: float = 0.35  # s: a tentative track not seen for longer is dropped
    death_timeout: float = 2.5  # s without an update: the track is gone
    coast_damping: float = 0.5  # 1/s: an unobserved track's velocity decays at this rate
    max_speed: float = 2.5  # m/s: clamp (nobody walks faster indoors)
    init_speed_std: float = 1.0  # m/s: velocity uncertainty of a new track


class Tracks:
    """All tracks as stacked arrays (see the module docstring). Row i is one track."""

    def __init__(self, spec: TrackerSpec = TrackerSpec()) -> None:
        self.spec = spec
        self.x = np.zeros((0, 4))
        self.P = np.zeros((0, 4, 4))
        self.ids = np.zeros(0, dtype=np.int64)
        self.hits = np.zeros(0, dtype=np.int64)
        self.born = np.zeros(0)
        self.last_update = np.zeros(0)
        self.last_strong = np.zeros(0)  # last update by a pair or blob
        self.last_seen = np.zeros(0)  # last anchored evidence of any kind (legs, frontal face, torso, voice)
        self.confirmed = np.zeros(0, dtype=bool)
        self._next = 1
        self._t: float | None = None

    def __len__(self) -> int:
        return int(self.ids.shape[0])

    # ------------------------------------------------------------ filter steps
    def predict(self, t: float) -> None:
        """Predict every track to time ``t`` (constant velocity, white-noise acceleration)."""
        if self._t is None or len(self) == 0:
            self._t = t
            return
        dt = t - self._t
        self._t = t
        if dt <= 0:
            return
        F, Q = cv_model(dt, self.spec.accel_noise)
        self.x = self.x @ F.T
        self.P = F @ self.P @ F.T + Q
        # Coasting tracks slow down (a person unseen for a while has probably stopped).
        idle = t - self.last_update
        damp = np.where(idle > 0.3, math.exp(-self.spec.coast_damping * dt), 1.0)
        self.x[:, 2:] *= damp[:, None]
        speed = np.hypot(self.x[:, 2], self.x[:, 3])
        over = speed > self.spec.max_speed
        if over.any():
            self.x[over, 2:] *= (self.spec.max_speed / speed[over])[:, None]

    def step(self, t: float, z: np.ndarray, kind: np.ndarray) -> np.ndarray:
        """One scan: predict to ``t``, associate candidates ``z`` (M, 2, odom) of ``kind``, update,
        give birth and bury. Returns, per candidate, the row of the track it updated (or -1)."""
        spec = self.spec
        self.predict(t)
        m = z.shape[0]
        assigned = np.full(m, -1, dtype=np.int64)
        single = kind == SINGLE
        r = np.where(single, spec.single_std, spec.meas_std) ** 2
        n = len(self)
        if n and m:
            d2 = mahalanobis2(self.x, self.P, z, r)
            gate = np.where(single, spec.single_gate, spec.gate)[None, :]
            allowed = d2 <= gate
            if allowed.any():
                cost = np.where(allowed, d2, 1e6)
                rows, cols = linear_sum_assignment(cost)
                ok = allowed[rows, cols]
                rows, cols = rows[ok], cols[ok]
                self._update(rows, z[cols], r[cols])
                assigned[cols] = rows
                self.last_update[rows] = t
                self.last_seen[rows] = np.maximum(self.last_seen[rows], t)
                strong = ~single[cols]
                self.last_strong[rows[strong]] = t
                self.hits[rows[strong]] += 1  # only pairs and blobs confirm a track
        # Confirmation on repeated evidence; a tentative track that missed this scan is dropped.
        young = ~self.confirmed
        self.confirmed |= young & (self.hits >= spec.confirm_hits) & (t - self.born <= spec.confirm_window + 1e-9)
        dead = (~self.confirmed & (t - self.last_update > spec.tentative_gap + 1e-9)) | (t - self.last_seen > spec.death_timeout)
        dead |= t - self.last_strong > spec.single_support  # a table leg must not keep a track forever
        dead |= ~self.confirmed & (t - self.born > spec.confirm_window + 1e-9)
        if dead.any():
            keep = ~dead
            remap = np.cumsum(keep) - 1
            assigned = np.where(assigned >= 0, np.where(keep[np.maximum(assigned, 0)], remap[np.maximum(assigned, 0)], -1), -1)
            self._keep(keep)
        # Birth: every unassigned pair or blob starts a tentative track.
        new = np.flatnonzero((assigned < 0) & ~single)
        if new.size:
            self._birth(t, z[new], r[new])
        return assigned

    def _update(self, rows: np.ndarray, z: np.ndarray, r: np.ndarray) -> None:
        """Kalman update of tracks ``rows`` with position measurements ``z`` (batched, H = [I 0])."""
        P = self.P[rows]
        S = P[:, :2, :2] + r[:, None, None] * np.eye(2)
        Sinv = inv2(S)
        K = P[:, :, :2] @ Sinv  # (k, 4, 2)
        y = z - self.x[rows, :2]
        self.x[rows] += np.einsum("kij,kj->ki", K, y)
        # Joseph form, as filterpy: P = (I - KH) P (I - KH)' + K R K'
        IKH = np.broadcast_to(np.eye(4), P.shape).copy()
        IKH[:, :, :2] -= K
        self.P[rows] = IKH @ P @ IKH.transpose(0, 2, 1) + r[:, None, None] * (K @ K.transpose(0, 2, 1))

    def _birth(self, t: float, z: np.ndarray, r: np.ndarray) -> None:
        k = z.shape[0]
        x = np.zeros((k, 4))
        x[:, :2] = z
        P = np.zeros((k, 4, 4))
        P[:, 0, 0] = P[:, 1, 1] = r
        P[:, 2, 2] = P[:, 3, 3] = self.spec.init_speed_std**2
        self.x = np.concatenate((self.x, x))
        self.P = np.concatenate((self.P, P))
        self.ids = np.concatenate((self.ids, np.arange(self._next, self._next + k)))
        self._next += k
        self.hits = np.concatenate((self.hits, np.ones(k, dtype=np.int64)))
        self.born = np.concatenate((self.born, np.full(k, t)))
        self.last_update = np.concatenate((self.last_update, np.full(k, t)))
        self.last_strong = np.concatenate((self.last_strong, np.full(k, t)))
        self.last_seen = np.concatenate((self.last_seen, np.full(k, t)))
        self.confirmed = np.concatenate((self.confirmed, np.zeros(k, dtype=bool)))

    def _keep(self, keep: np.ndarray) -> None:
        for name in ("x", "P", "ids", "hits", "born", "last_update", "last_strong", "last_seen", "confirmed"):
            setattr(self, name, getattr(self, name)[keep])

    def support(self, rows: list[int], t: float) -> None:
        """Other strong evidence that tracks ``rows`` are people (a frontal face, or the partner's torso,
        matched them at ``t``):
        it keeps them alive (``last_seen``) and renews the single-leg allowance (``last_strong``)."""
        if rows:
            idx = np.asarray(rows, dtype=np.int64)
            self.last_strong[idx] = np.maximum(self.last_strong[idx], t)
            self.last_seen[idx] = np.maximum(self.last_seen[idx], t)

    def seen(self, rows: list[int], t: float) -> None:
        """Weak anchored evidence for tracks ``rows`` at ``t`` (the partner's voice from its bearing):
        keeps them alive, but only within ``single_support`` of their last pair, blob
        or face, so a bearing-only cue cannot hold a track whose person has gone."""
        if rows:
            idx = np.asarray(rows, dtype=np.int64)
            self.last_seen[idx] = np.maximum(self.last_seen[idx], t)

    # ------------------------------------------------------------ views
    def row(self, track_id: int) -> int:
        """Row of a track id, or -1."""
        hit = np.flatnonzero(self.ids == track_id)
        return int(hit[0]) if hit.size else -1

    def filterpy(self, i: int):  # -> filterpy.kalman.KalmanFilter
        """Track ``i`` as a filterpy KalmanFilter (the reference the batched filter matches)."""
        from filterpy.kalman import KalmanFilter

        kf = KalmanFilter(dim_x=4, dim_z=2)
        kf.x = self.x[i].reshape(4, 1).copy()
        kf.P = self.P[i].copy()
        kf.H = np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0]])
        return kf


def cv_model(dt: float, accel_noise: float) -> tuple[np.ndarray, np.ndarray]:
    """Constant-velocity transition F and discrete white-noise-acceleration Q for ``dt``."""
    F = np.eye(4)
    F[0, 2] = F[1, 3] = dt
    q = accel_noise**2
    a, b, c = dt**4 / 4, dt**3 / 2, dt**2
    Q = q * np.array([[a, 0, b, 0], [0, a, 0, b], [b, 0, c, 0], [0, b, 0, c]])
    return F, Q


def inv2(S: np.ndarray) -> np.ndarray:
    """Inverses of a stack of 2x2 matrices (k, 2, 2), closed form."""
    a, b, c, d = S[..., 0, 0], S[..., 0, 1], S[..., 1, 0], S[..., 1, 1]
    det = a * d - b * c
    out = np.empty_like(S)
    out[..., 0, 0] = d / det
    out[..., 0, 1] = -b / det
    out[..., 1, 0] = -c / det
    out[..., 1, 1] = a / det
    return out


def mahalanobis2(x: np.ndarray, P: np.ndarray, z: np.ndarray, r: np.ndarray) -> np.ndarray:
    """Squared Mahalanobis distances (N, M) of measurements z (M, 2), variances r (M,), to tracks (N)."""
    a = P[:, None, 0, 0] + r[None, :]
    d = P[:, None, 1, 1] + r[None, :]
    b = P[:, None, 0, 1]
    dx = z[None, :, 0] - x[:, None, 0]
    dy = z[None, :, 1] - x[:, None, 1]
    det = a * d - b * b
    return (d * dx * dx - 2 * b * dx * dy + a * dy * dy) / det
