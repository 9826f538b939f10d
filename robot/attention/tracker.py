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
The filters are written out in plain floats, the predict and update in
closed form for this model (``H = [I 0]``, a symmetric covariance kept as
its 10 entries): ``filterpy.kalman.KalmanFilter.update`` costs about 135 us
per call, and even one batched numpy step over all tracks costs more than
the arithmetic of the three or four tracks a home has (a numpy call on a
4x4 stack costs as much as ~30 float operations). The filter computes what
one filterpy KalmanFilter per track would (its update ``P - K H P`` equals
filterpy's Joseph form for the optimal gain, up to rounding; the tests
check it against filterpy); :meth:`Tracks.filterpy` builds that filter.

Association: Mahalanobis distance of every candidate to every track's
predicted position (2x2 innovation covariances), gated at the chi-square
99 % point, then global nearest neighbour with
``scipy.optimize.linear_sum_assignment`` on the gated cost matrix, in two
rounds: the tracks whose person is in sight first, the dormant ones among the
candidates left (:func:`_associate`). When
the gate leaves no choice (no candidate within two tracks' gates, no track
with two candidates in its gate), the optimal assignment is every gated
pair, and the solver is not called. Pairs and blobs can start tracks, and so can faces whose legs
the laser cannot see (``FACE``: a person behind a coffee table; their spread is ``face_std``);
single legs (the other hidden, or a table leg) feed tracks but never start
or confirm one, and alone (with frontal faces, :meth:`Tracks.support`) keep one for at most
``single_support`` seconds after a pair or blob last fed it, so a track that
lost its person does not live on a table leg (time in which the laser could not see the rest of the
person, a lone leg beside someone in front, does not count, up to ``hidden_timeout``). Birth: a tentative track per unassigned
pair/blob, confirmed after ``confirm_hits`` pair/blob hits within
``confirm_window`` seconds (repeated evidence; a far person's legs pair only
now and then); a tentative track unseen for ``tentative_gap`` is dropped; a
confirmed track dies ``death_timeout`` seconds after its last anchored evidence
(a leg update, a frontal face, or for the partner its torso or voice: a
person standing still whose legs do not associate for a while is still
there while the camera sees them; its
prediction coasts through occlusions and crossings meanwhile, with its
velocity damped so it does not run away). Two confirmed tracks closer than ``merge_distance``
for ``merge_time`` seconds (both measured, or one measured and the other held by torso or face where it last had
the legs the first now measures) are one person tracked twice: the younger is dropped (:meth:`Tracks._twins`).
A track slower than walking pace never takes a candidate that a walking track explains and predicts nearer
(:func:`_claimed`): someone walking past a person who stands does not carry her track off.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from homesim.lsap import linear_sum_assignment  # SciPy's solver, without importing scipy.optimize

from .legs import SINGLE

#: A candidate kind besides the leg detector's PAIR, BLOB and SINGLE: a frontal face whose legs the laser
#: cannot see (a table or a sofa between), placed at the distance its size gives (robot.attention.module)
FACE = 3

GATE_99 = 9.2103  # chi-square, 2 degrees of freedom, 99 %
_FILL = 1e6  # the cost of a pair outside the gate (far above any gate: every gated pair that can be in the assignment is)


@dataclass(frozen=True)
class TrackerSpec:
    accel_noise: float = 1.5  # m/s^2 (std of the white-noise acceleration)
    meas_std: float = 0.06  # m: a leg pair's centre (legs swing about it while walking)
    single_std: float = 0.12  # m: a single leg is up to a leg spread off the person's centre
    gate: float = GATE_99  # squared Mahalanobis distance
    single_gate: float = 4.0  # tighter for single legs (clutter)
    single_support: float = 8.0  # s: singles (or faces) alone keep a track only this long after a pair/blob fed it
    still_radius: float = 0.3  # m: a track this near where its last pair/blob/face put it has not moved (:meth:`Tracks.still`)
    confirm_hits: int = 3
    confirm_window: float = 1.0  # s: ... within this long after birth
    tentative_gap: float = 0.35  # s: a tentative track not seen for longer is dropped
    death_timeout: float = 2.5  # s without an update: the track is gone
    coast_damping: float = 0.5  # 1/s: an unobserved track's velocity decays at this rate ...
    coast_hold: float = 0.8  # s: ... once it has been unobserved this long (a crossing hides a walker ~0.5-1 s: keep its pace)
    birth_clearance: float = 0.5  # m: no new person within this of a confirmed track (two bodies' centres are never closer)
    stop_after: float = 0.25  # s unobserved: a track is also gated as stopped where last measured ...
    stop_spread: float = 0.5  # m/s: ... within a radius (1 sigma) growing this fast (a turn, a stop while hidden)
    max_speed: float = 2.5  # m/s: clamp (nobody walks faster indoors)
    init_speed_std: float = 1.0  # m/s: velocity uncertainty of a new track
    contact: float = 0.6  # m: two confirmed tracks predicted this close: their legs mix (pairs of one leg each, merged blobs) ...
    contact_std: float = 0.6  # m: ... so a candidate there may be the other person's: off this one's centre by up to a contact
    merge_distance: float = 0.25  # m: two confirmed tracks closer than this (no two bodies' centres are) ...
    merge_time: float = 1.5  # s: ... for this long (longer than a crossing lasts) are one person: the younger goes
    max_gate_std: float = 1.0  # m: a coasting track's position spread (and the stopped spread) is gated at most this wide
    # s: a confirmed track whose person the laser could not see (hidden behind a wall's edge or someone
    # else, outside its half circle: ``step``'s ``hidden``) does not count that time towards
    # ``death_timeout``; it is dropped at the latest this long after its last evidence
    hidden_timeout: float = 30.0
    # m: a dormant track (unseen longer than ``death_timeout``, kept because hidden) is gated at most this
    # wide around where it coasted to and where it was last measured: long unseen, the person is found
    # again near there or not at all (ines' track, hidden behind a wall, took a bookshelf's corner 2.5 m
    # off at the 1 m cap, then the partner: cross_u_pair seed 7; at 0.5 m another's track 1.5 m off took
    # hugo: seed 4)
    dormant_gate_std: float = 0.3
    # m: a lone leg (the other hidden, or a table leg, a door jamb's end) feeds a track only if it lies
    # within this spread of the prediction, however long the track coasted: the person's leg is within a
    # leg spread of their centre, and a coasting partner's track took a jamb 1.8 m off (cross_u_pair seed 2)
    single_gate_std: float = 0.5
    # m: a face candidate's position spread (FACE): its distance comes from the face's size, some
    # tenths of a metre off at conversation distance; it starts and confirms a track as a pair does
    face_std: float = 0.25

    def __post_init__(self) -> None:
        for name in ("gate", "single_gate"):
            g = getattr(self, name)
            if not 0 < g < _FILL / 10:
                raise ValueError(f"TrackerSpec.{name} = {g}: a squared Mahalanobis distance in (0, {_FILL / 10:g})")


class Track:
    """One person track: state ``x`` = [x, y, vx, vy] (odom frame), covariance ``P`` as the 10
    entries of the symmetric 4x4 matrix row by row (00 01 02 03 11 12 13 22 23 33), its id,
    the pair/blob hits that confirm it and the times of its evidence."""

    __slots__ = ("id", "x", "P", "hits", "born", "last_update", "last_strong", "last_seen", "confirmed", "last_z", "origin",
                 "blind_seen", "blind_strong", "dormant", "last_legs", "strong_xy")

    def __init__(self, track_id: int, x: list[float], P: list[float], t: float) -> None:
        self.id = track_id
        self.x = x
        self.P = P
        self.hits = 1
        self.born = self.last_update = t
        self.last_legs = -math.inf  # last update by a leg candidate (not a FACE): are the person's legs in the laser's view?
        self.last_strong = t  # last update by a pair or blob
        self.strong_xy = (x[0], x[1])  # where the track stood then (a person standing still since: :meth:`Tracks._still`)
        self.last_seen = t  # last anchored evidence of any kind (legs, frontal face, torso, voice)
        self.confirmed = False
        self.last_z = (x[0], x[1])  # where the last measurement put the person (the "stopped" hypothesis)
        self.origin = (x[0], x[1])  # where the person was first seen (did they come from where someone vanished?)
        # seconds since ``last_seen`` / ``last_strong`` in which the laser could not have seen the person
        # (:mod:`.visibility`): no evidence of absence, so not counted towards the timeouts
        self.blind_seen = 0.0
        self.blind_strong = 0.0
        # alive only because the person was hidden (unseen longer than ``death_timeout``): kept to be
        # found again under the same id, but not reported as a person seen (:meth:`Tracks.step`)
        self.dormant = False

    def cov(self) -> np.ndarray:
        """The full 4x4 covariance."""
        p00, p01, p02, p03, p11, p12, p13, p22, p23, p33 = self.P
        return np.array([[p00, p01, p02, p03], [p01, p11, p12, p13], [p02, p12, p22, p23], [p03, p13, p23, p33]])

    def predict(self, dt: float, qa: float, qb: float, qc: float) -> None:
        """x = F x, P = F P F' + Q for the constant-velocity model over ``dt`` (Q = q [a b c] pattern)."""
        x = self.x
        x[0] += dt * x[2]
        x[1] += dt * x[3]
        p00, p01, p02, p03, p11, p12, p13, p22, p23, p33 = self.P
        m02 = p02 + dt * p22
        m03 = p03 + dt * p23
        m12 = p12 + dt * p23
        m13 = p13 + dt * p33
        self.P = [
            p00 + dt * p02 + dt * m02 + qa, p01 + dt * p12 + dt * m03, m02 + qb, m03,
            p11 + dt * p13 + dt * m13 + qa, m12, m13 + qb,
            p22 + qc, p23, p33 + qc,
        ]

    def update(self, zx: float, zy: float, r: float) -> None:
        """Kalman update with a position measurement (``H = [I 0]``, ``R = r I``)."""
        x = self.x
        p00, p01, p02, p03, p11, p12, p13, p22, p23, p33 = self.P
        s00, s11 = p00 + r, p11 + r
        det = s00 * s11 - p01 * p01
        a, b, d = s11 / det, -p01 / det, s00 / det  # S^-1 = [[a b] [b d]]
        # K = P H' S^-1: rows i of P's first two columns times S^-1.
        k00, k01 = p00 * a + p01 * b, p00 * b + p01 * d
        k10, k11 = p01 * a + p11 * b, p01 * b + p11 * d
        k20, k21 = p02 * a + p12 * b, p02 * b + p12 * d
        k30, k31 = p03 * a + p13 * b, p03 * b + p13 * d
        y0, y1 = zx - x[0], zy - x[1]
        x[0] += k00 * y0 + k01 * y1
        x[1] += k10 * y0 + k11 * y1
        x[2] += k20 * y0 + k21 * y1
        x[3] += k30 * y0 + k31 * y1
        # P - K H P (H P: P's first two rows), upper triangle.
        self.P = [
            p00 - (k00 * p00 + k01 * p01), p01 - (k00 * p01 + k01 * p11), p02 - (k00 * p02 + k01 * p12), p03 - (k00 * p03 + k01 * p13),
            p11 - (k10 * p01 + k11 * p11), p12 - (k10 * p02 + k11 * p12), p13 - (k10 * p03 + k11 * p13),
            p22 - (k20 * p02 + k21 * p12), p23 - (k20 * p03 + k21 * p13),
            p33 - (k30 * p03 + k31 * p13),
        ]


class Tracks:
    """All tracks, oldest first (see the module docstring): :attr:`tracks`, and numpy views of them."""

    def __init__(self, spec: TrackerSpec = TrackerSpec()) -> None:
        self.spec = spec
        self.tracks: list[Track] = []
        self._next = 1
        self._t: float | None = None
        self._model: tuple[float, float, float, float] | None = None  # dt, q a, q b, q c of the last predict
        self._together: dict[tuple[int, int], float] = {}  # (older id, younger id) of confirmed tracks this close, since
        self._heir_of: dict[int, int] = {}  # the last step's twins: younger id -> the older id that keeps the person
        self.confirmed_now: list[int] = []  # ids of the tracks the last step confirmed
        self.restarted: list[int] = []  # ids of the tracks the last step took a candidate for under the "stopped" hypothesis

    def __len__(self) -> int:
        return len(self.tracks)

    # ------------------------------------------------------------ filter steps
    def predict(self, t: float) -> None:
        """Predict every track to time ``t`` (constant velocity, white-noise acceleration)."""
        if self._t is None or not self.tracks:
            self._t = t
            return
        dt = t - self._t
        self._t = t
        if dt <= 0:
            return
        model = self._model
        if model is None or model[0] != dt:
            q = self.spec.accel_noise**2
            model = self._model = (dt, q * (dt**4 / 4), q * (dt**3 / 2), q * dt**2)
        _, qa, qb, qc = model
        spec = self.spec
        damp = math.exp(-spec.coast_damping * dt)
        vmax = spec.max_speed
        for tk in self.tracks:
            tk.predict(dt, qa, qb, qc)
            x = tk.x
            # Coasting tracks slow down (a person unseen for a while has probably stopped).
            if t - tk.last_update > spec.coast_hold:
                x[2] *= damp
                x[3] *= damp
            if x[2] * x[2] + x[3] * x[3] > vmax * vmax * 0.99:
                speed = float(np.hypot(x[2], x[3]))
                if speed > vmax:
                    x[2] *= vmax / speed
                    x[3] *= vmax / speed

    def step(
        self, t: float, z: Sequence[Sequence[float]] | np.ndarray, kind: Sequence[int] | np.ndarray,
        hidden: Callable[[list[tuple[float, float]]], list[bool]] | None = None,
        blocked: Callable[[list[tuple[float, float]]], list[bool]] | None = None,
    ) -> list[int]:
        """One scan: predict to ``t``, associate candidates ``z`` (M, 2, odom) of ``kind``, update,
        give birth and bury. Returns, per candidate, the row of the track it updated (or -1).

        ``hidden`` (optional) tells, for the tracks' predicted odom positions, which the laser could
        not have seen on this scan (:func:`.visibility.hidden_points`): a track that gets no
        candidate there is not counted unseen for ``death_timeout`` and the single-leg allowance
        (up to ``hidden_timeout``). Without it every track is taken as in view.

        ``blocked`` (optional) tells which odom positions nobody can stand at (inside a wall or raised
        furniture, from the floor plan): a track no candidate fed that coasted into one stops where it
        was before this scan's prediction. Nobody walks through a wall; a track that coasted on through
        one (she turned along it, unseen) was metres from her when she came back into view."""
        if isinstance(z, np.ndarray):
            z = z.tolist()
        if isinstance(kind, np.ndarray):
            kind = kind.tolist()
        spec = self.spec
        self.confirmed_now = []
        self.restarted = []
        before = self._t
        was = [(tk.x[0], tk.x[1]) for tk in self.tracks] if blocked is not None else None
        self.predict(t)
        dt = t - before if before is not None and t > before else 0.0
        m = len(z)
        assigned = [-1] * m
        single = [k == SINGLE for k in kind]
        tracks = self.tracks
        if tracks and m:
            var = [spec.single_std**2 if s else spec.face_std**2 if k == FACE else spec.meas_std**2 for s, k in zip(single, kind)]
            gates = [spec.single_gate if s else spec.gate for s in single]
            extra = _contact_variance(tracks, spec)
            pairs, stopped = _gated(tracks, z, var, gates, t, spec, single, extra)
            if pairs:
                pairs = _associate(pairs, tracks, m)
                for i, j, _ in pairs:
                    tk = tracks[i]
                    zj = z[j]
                    if (i, j) in stopped:  # the person stopped or turned while unseen: start the motion afresh
                        v = spec.init_speed_std**2
                        self.restarted.append(tk.id)
                        tk.x = [zj[0], zj[1], 0.0, 0.0]
                        tk.P = [var[j], 0.0, 0.0, 0.0, var[j], 0.0, 0.0, v, 0.0, v]
                    else:
                        tk.update(zj[0], zj[1], var[j] + extra[i])
                    tk.last_z = (zj[0], zj[1])
                    assigned[j] = i
                    tk.last_update = t
                    if kind[j] != FACE:
                        tk.last_legs = t
                    if t > tk.last_seen:
                        tk.last_seen = t
                        tk.blind_seen = 0.0
                    if not single[j]:  # only pairs and blobs confirm a track
                        tk.last_strong = t
                        tk.strong_xy = (tk.x[0], tk.x[1])
                        tk.blind_strong = 0.0
                        tk.hits += 1
        fed = set(assigned)
        if was is not None and dt > 0 and tracks:
            for i, stop in enumerate(blocked([(tk.x[0], tk.x[1]) for tk in tracks])):  # type: ignore[misc]
                if stop and i not in fed:
                    tk = tracks[i]
                    tk.x = [was[i][0], was[i][1], 0.0, 0.0]
        if hidden is not None and dt > 0 and tracks:
            for i, h in enumerate(hidden([(tk.x[0], tk.x[1]) for tk in tracks])):
                if h and i not in fed:
                    tk = tracks[i]
                    tk.blind_seen += dt
                    tk.blind_strong += dt
                elif h and tracks[i].last_strong < t:
                    # half hidden: only a lone leg showed beside whatever hides the rest (a person in
                    # front): the other leg is no more missing than a hidden person is, so the
                    # single-leg allowance does not run (up to ``hidden_timeout``). A bystander standing
                    # half behind the partner lost his track after ``single_support``; no track may be
                    # born within ``birth_clearance`` of hers, so he stayed untracked when she walked off,
                    # and pairs of one leg of each pulled her track onto him (she was not heard again).
                    tracks[i].blind_strong += dt
        # Confirmation on repeated evidence; a tentative track that missed this scan is dropped, and
        # so is one that came within ``birth_clearance`` of a confirmed track (the same person twice).
        window = spec.confirm_window + 1e-9
        clear2 = spec.birth_clearance**2
        anchors = [(tk.x[0], tk.x[1]) for tk in tracks if tk.confirmed]
        keep: list[Track] = []
        row_of: list[int] = []
        twins = self._twins(t)
        heirs: dict[int, int] = {}  # row of a twin dropped -> row of the older track that took over its legs
        if twins:
            rows = {tk.id: i for i, tk in enumerate(tracks)}
            for young, old in self._heir_of.items():
                ty, to = tracks[rows[young]], tracks[rows[old]]
                if t - to.last_update > spec.tentative_gap + 1e-9 >= t - ty.last_update:
                    # the older had lost the legs to the younger: it takes them over where they are now
                    heirs[rows[young]] = rows[old]
                    to.x, to.P, to.last_z = list(ty.x), list(ty.P), ty.last_z
                    to.last_update, to.last_legs = ty.last_update, max(to.last_legs, ty.last_legs)
                    if ty.last_strong > to.last_strong:
                        to.last_strong, to.blind_strong, to.strong_xy = ty.last_strong, ty.blind_strong, ty.strong_xy
        for tk in tracks:
            crowded = tk.id in twins or not tk.confirmed and any((tk.x[0] - ax) ** 2 + (tk.x[1] - ay) ** 2 < clear2 for ax, ay in anchors)
            if not tk.confirmed and not crowded and tk.hits >= spec.confirm_hits and t - tk.born <= window:
                tk.confirmed = True
                self.confirmed_now.append(tk.id)
            unseen = t - tk.last_seen
            dead = crowded or (
                (not tk.confirmed and (t - tk.last_update > spec.tentative_gap + 1e-9 or t - tk.born > window))
                or unseen - tk.blind_seen > spec.death_timeout  # the laser looked and saw no legs
                or unseen > spec.hidden_timeout
                # a table leg must not keep a track forever
                or t - tk.last_strong - tk.blind_strong > spec.single_support
                or t - tk.last_strong > spec.hidden_timeout
            )
            tk.dormant = unseen > spec.death_timeout
            row_of.append(-1 if dead else len(keep))
            if not dead:
                keep.append(tk)
        if len(keep) < len(tracks):
            assigned = [row_of[heirs.get(a, a)] if a >= 0 else -1 for a in assigned]
            self.tracks = tracks = keep
        # Birth: every unassigned pair or blob starts a tentative track, unless it lies within
        # ``birth_clearance`` of a confirmed track: two people close together give pairs made of
        # one leg of each, and such a pair confirmed as a third person stole the evidence of both.
        anchors = [(tk.x[0], tk.x[1]) for tk in tracks if tk.confirmed]
        for j in range(m):
            if assigned[j] < 0 and not single[j]:
                zx, zy = z[j][0], z[j][1]
                if any((zx - ax) ** 2 + (zy - ay) ** 2 < clear2 for ax, ay in anchors):
                    continue
                face = kind[j] == FACE
                self._birth_one(t, zx, zy, spec.face_std**2 if face else spec.meas_std**2, legs=not face)
        return assigned

    def adopt(self, new_id: int, old_id: int) -> int:
        """Re-identification: the track ``new_id`` (just confirmed) is the person of the dormant track
        ``old_id`` found again; it takes that id and the dormant track is dropped. Returns the row
        that was dropped (rows after it move up by one), or -1 when either id is unknown or they are one."""
        new, old = self.row(new_id), self.row(old_id)
        if new < 0 or old < 0 or new == old:
            return -1
        self.tracks[new].id = old_id
        del self.tracks[old]
        self.confirmed_now = [old_id if i == new_id else i for i in self.confirmed_now]
        return old

    @staticmethod
    def copy(tk: Track) -> Track:
        """A copy of ``tk`` as it is now (its own state lists), for :meth:`give_back`."""
        c = Track.__new__(Track)
        for k in Track.__slots__:
            setattr(c, k, getattr(tk, k))
        c.x, c.P = list(tk.x), list(tk.P)
        return c

    def give_back(self, track_id: int, old: Track, since: float, t: float) -> tuple[int, int]:
        """Undo a re-identification (:meth:`adopt` at ``since``) that later evidence contradicts: the track
        now holding ``track_id`` is someone else, so it gets a new id of its own, and ``old`` (the track
        :meth:`adopt` dropped, kept as it was then) is the person again, coasted on from ``since`` to ``t``
        as the steps would have coasted it (unseen: damped). Returns (the new id given to the wrong track, or
        -1 when no track holds ``track_id``; the row ``old`` was put in, or -1 when by now it would have
        died of ``hidden_timeout`` and is not put back). Rows at and after that row move down by one."""
        spec = self.spec
        row = self.row(track_id)
        fresh = -1
        if row >= 0:
            fresh = self._next
            self._next += 1
            self.tracks[row].id = fresh
            self.confirmed_now = [fresh if i == track_id else i for i in self.confirmed_now]
        if t - old.last_seen > spec.hidden_timeout:
            return fresh, -1
        dt = t - since
        if dt > 0.0:
            q = spec.accel_noise**2
            old.predict(dt, q * (dt**4 / 4), q * (dt**3 / 2), q * dt**2)
            damp = math.exp(-spec.coast_damping * dt)
            old.x[2] *= damp
            old.x[3] *= damp
        old.id = track_id
        old.dormant = True
        at = next((i for i, tk in enumerate(self.tracks) if tk.born > old.born), len(self.tracks))
        self.tracks.insert(at, old)
        return fresh, at

    def renew(self, track_id: int) -> int:
        """The track holding ``track_id`` is someone else than the person the id stands for (the camera saw
        other clothes on it): it gets a new id of its own, and ``track_id`` has no track until the person is
        found again. Returns the new id, or -1 when no track holds ``track_id``."""
        row = self.row(track_id)
        if row < 0:
            return -1
        fresh = self._next
        self._next += 1
        self.tracks[row].id = fresh
        self.confirmed_now = [fresh if i == track_id else i for i in self.confirmed_now]
        return fresh

    def _twins(self, t: float) -> set[int]:
        """Ids of confirmed tracks that have followed an older confirmed track closer than
        ``merge_distance`` for ``merge_time`` s: one person tracked twice (a second track born on
        her legs while the first coasted elsewhere, then converged). No two people's centres come
        that close (their bodies are in the way), and a crossing lets them part within a second;
        the older track keeps the person (it is the one the attention knows; :attr:`_heir_of` maps
        each younger id to it).

        Both must be there all the while: measured just now (a track coasting unseen over someone
        else's position is not a twin), or one measured and the other :meth:`_held_there`: kept by
        anchored evidence (her torso, face) without legs, last measured where the other now
        measures someone. That is a person whose legs another track took: fresh3/open_cross_child
        seed 4, the running child's track, coasting, came out on Mia and took her legs; her partner
        track, still held by her torso and face 0.1 m off, never got a leg again and never merged
        (counted a false positive for the rest of the run)."""
        spec = self.spec
        gap = spec.tentative_gap + 1e-9
        d2 = spec.merge_distance**2
        conf = [tk for tk in self.tracks if tk.confirmed]
        measured = [t - tk.last_update <= gap for tk in conf]
        together: dict[tuple[int, int], float] = {}
        heir: dict[int, int] = {}
        for a, ta in enumerate(conf):
            for b in range(a + 1, len(conf)):
                tb = conf[b]
                if (ta.x[0] - tb.x[0]) ** 2 + (ta.x[1] - tb.x[1]) ** 2 >= d2:
                    continue
                if not (measured[a] and measured[b] or measured[a] and self._held_there(tb, ta, t)
                        or measured[b] and self._held_there(ta, tb, t)):
                    continue
                key = (ta.id, tb.id) if ta.id < tb.id else (tb.id, ta.id)
                together[key] = self._together.get(key, t)
                if t - together[key] >= spec.merge_time - 1e-9:
                    heir[key[1]] = key[0]
        self._together = together  # only pairs close now: bounded by the tracks alive
        self._heir_of = heir
        return set(heir)

    def _held_there(self, tk: Track, other: Track, t: float) -> bool:
        """Whether ``tk``, not measured now, is held by anchored evidence (:meth:`support`, :meth:`seen`)
        just now and was last measured within ``merge_distance`` of where ``other`` is measured now."""
        spec = self.spec
        lx, ly = tk.last_z
        return (not tk.dormant and t - tk.last_seen <= spec.tentative_gap + 1e-9
                and (lx - other.x[0]) ** 2 + (ly - other.x[1]) ** 2 < spec.merge_distance**2)

    def _birth_one(self, t: float, zx: float, zy: float, r: float, legs: bool = True) -> None:
        v = self.spec.init_speed_std**2
        tk = Track(self._next, [zx, zy, 0.0, 0.0], [r, 0.0, 0.0, 0.0, r, 0.0, 0.0, v, 0.0, v], t)
        if legs:
            tk.last_legs = t
        self.tracks.append(tk)
        self._next += 1

    def _birth(self, t: float, z: np.ndarray, r: np.ndarray) -> None:
        """Tentative tracks at positions ``z`` (K, 2) with measurement variances ``r`` (K,)."""
        for (zx, zy), rr in zip(np.asarray(z, dtype=float).tolist(), np.asarray(r, dtype=float).tolist()):
            self._birth_one(t, zx, zy, rr)

    def still(self, row: int) -> bool:
        """Whether track ``row`` stands within ``still_radius`` of where its last pair, blob or face put it
        (a person who has not moved since; a person standing side-on to the laser shows one leg, the
        near one hiding the other). Used by the person attention for its partner while the camera looks
        away from her on the ES's order (:meth:`robot.attention.module.PersonAttention._keep_still_partner`)."""
        tk = self.tracks[row]
        sx, sy = tk.strong_xy
        return math.hypot(tk.x[0] - sx, tk.x[1] - sy) <= self.spec.still_radius

    def hold(self, row: int, t: float) -> None:
        """Renew track ``row``'s single-leg allowance without moving where its last strong evidence put it
        (``strong_xy``): a partner kept by :meth:`still` stays kept only while she stays near that place."""
        tk = self.tracks[row]
        if t >= tk.last_strong:
            tk.last_strong, tk.blind_strong = t, 0.0

    def support(self, rows: list[int], t: float) -> None:
        """Other strong evidence that tracks ``rows`` are people (a frontal face, or the partner's torso,
        matched them at ``t``):
        it keeps them alive (``last_seen``) and renews the single-leg allowance (``last_strong``)."""
        for i in rows:
            tk = self.tracks[i]
            if t >= tk.last_strong:
                tk.last_strong, tk.blind_strong, tk.strong_xy = t, 0.0, (tk.x[0], tk.x[1])
            if t >= tk.last_seen:
                tk.last_seen, tk.blind_seen = t, 0.0
                tk.dormant = False

    def seen(self, rows: list[int], t: float) -> None:
        """Weak anchored evidence for tracks ``rows`` at ``t`` (the partner's voice from its bearing):
        keeps them alive, but only within ``single_support`` of their last pair, blob
        or face, so a bearing-only cue cannot hold a track whose person has gone."""
        for i in rows:
            tk = self.tracks[i]
            if t >= tk.last_seen:
                tk.last_seen, tk.blind_seen = t, 0.0
                tk.dormant = False

    # ------------------------------------------------------------ views
    def row(self, track_id: int) -> int:
        """Row of a track id, or -1."""
        for i, tk in enumerate(self.tracks):
            if tk.id == track_id:
                return i
        return -1

    @property
    def ids(self) -> np.ndarray:
        return np.array([tk.id for tk in self.tracks], dtype=np.int64)

    @property
    def x(self) -> np.ndarray:
        """States (N, 4) (a copy)."""
        return np.array([tk.x for tk in self.tracks], dtype=float).reshape(-1, 4)

    @property
    def P(self) -> np.ndarray:
        """Covariances (N, 4, 4) (a copy)."""
        return np.array([tk.cov() for tk in self.tracks]).reshape(-1, 4, 4)

    @property
    def confirmed(self) -> np.ndarray:
        return np.array([tk.confirmed for tk in self.tracks], dtype=bool)

    @property
    def last_seen(self) -> np.ndarray:
        return np.array([tk.last_seen for tk in self.tracks], dtype=float)

    @property
    def last_update(self) -> np.ndarray:
        return np.array([tk.last_update for tk in self.tracks], dtype=float)

    def filterpy(self, i: int):  # -> filterpy.kalman.KalmanFilter
        """Track ``i`` as a filterpy KalmanFilter (the reference the filter matches)."""
        from filterpy.kalman import KalmanFilter

        kf = KalmanFilter(dim_x=4, dim_z=2)
        kf.x = np.array(self.tracks[i].x, dtype=float).reshape(4, 1)
        kf.P = self.tracks[i].cov()
        kf.H = np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0]])
        return kf


def _contact_variance(tracks: list[Track], spec: TrackerSpec) -> list[float]:
    """Extra measurement variance per track: ``contact_std**2`` for a confirmed track whose predicted
    centre is within ``spec.contact`` of another confirmed track's, else 0.

    Why: while two people cross, the laser sees a merged blob, or pairs made of one leg of each, or
    one person half hidden behind the other; any candidate then lies somewhere between the two
    centres. Taken at face value (a pair's 6 cm), these mixed candidates bend both tracks' velocities
    toward each other within a few scans, and when the people part, each track predicts the other's
    path: the identities swap. With the measurement as loose as the contact really is, the updates
    still hold both tracks on the pair, but their velocities (what the people were doing before they
    met) carry them through, and each track comes out on its own person.
    """
    out = [0.0] * len(tracks)
    c2 = spec.contact**2
    extra = spec.contact_std**2
    conf = [i for i, tk in enumerate(tracks) if tk.confirmed]
    for a, i in enumerate(conf):
        xi = tracks[i].x
        for k in conf[a + 1 :]:
            xk = tracks[k].x
            if (xi[0] - xk[0]) ** 2 + (xi[1] - xk[1]) ** 2 < c2:
                out[i] = out[k] = extra
    return out


#: m/s: walking pace in a track: a track slower than this never takes a candidate that a track at least this fast
#: explains and predicts nearer (:func:`_claimed`). A walker at 0.5 m/s whose legs show apart, one at a time, near
#: someone reads down to 0.35 m/s in his track; a standing person's track, coasting on a noisy leg, up to 0.28 m/s
WALK_SPEED = 0.3

#: m: the early stopped hypothesis (unobserved less than ``stop_after``) gates within its spread plus this 1-sigma floor
#: (a leg pair's own measurement noise) ...
EARLY_STOP_FLOOR = 0.05
#: m: ... and never wider than this: half the gap of two people passing close (0.28 m), so it never spans both
EARLY_STOP_RADIUS = 0.14


def _gated(
    tracks: list[Track], z: Sequence[Sequence[float]], var: list[float], gates: list[float], t: float, spec: TrackerSpec,
    single: list[bool] | None = None, extra: list[float] | None = None,
) -> tuple[list[tuple[int, int, float]], set[tuple[int, int]]]:
    """(track row, candidate, cost) of every pair within the candidate's gate, and the pairs gated
    under the "stopped" hypothesis.

    The gate is on the squared Mahalanobis distance; the cost is the negative log-likelihood
    up to a constant, ``d2 + ln det S``, so a wide (long unseen) track or a loose single leg
    does not take a candidate from a track that predicts it tightly.

    A track unobserved for ``spec.stop_after`` has two hypotheses: it walked on (the constant-velocity
    prediction) or it stopped or turned where it was last measured (radius ``stop_spread`` per second
    unobserved); only pairs and blobs are taken under the second (a lone leg there is as likely a
    chair's). Unobserved for less, the second only takes what the first's gate misses (someone who
    stopped dead between two scans), never a pair the walk-on prediction explains, and only within its
    spread plus ``EARLY_STOP_FLOOR`` (not the measurement's variance), never farther than
    ``EARLY_STOP_RADIUS`` (0.14 m) from where it was last measured. The likelier of the two counts: a person who turns back while hidden behind another is
    found where they were instead of being searched for where they would have walked to.

    ``extra`` (per track) is added to every candidate's variance for that track (see :func:`_contact_variance`).

    Both spreads are gated at most ``spec.max_gate_std`` wide (the filter's own covariance is untouched).
    """
    out = []
    stopped: set[tuple[int, int]] = set()
    wide, narrow = spec.max_gate_std**2, spec.dormant_gate_std**2
    claimed = _claimed(tracks, z, var, gates, t, spec)
    for i, tk in enumerate(tracks):
        cap2 = narrow if tk.dormant else wide
        x0, x1 = tk.x[0], tk.x[1]
        P = tk.P
        p00, b, p11 = P[0], P[1], P[4]
        bb = b * b
        hidden = t - tk.last_update
        spread = (spec.stop_spread * hidden) ** 2 if hidden > 0 else 0.0
        # Before ``stop_after`` the stopped hypothesis only catches what the walk-on one misses: a
        # runner who stops dead between two scans (fresh5/row_child_runs_across seed 0: the child's
        # track lost him, 0.25 m behind its prediction, and a walker's track unseen for 1 s took him).
        early = hidden < spec.stop_after
        # A long-coasting track (kept alive by her voice or torso) has a spread of metres: gated
        # at that width it took someone 5 m away, across the room, as its person (four_people
        # seed 6: the partner's track jumped out of the kitchen onto a man in the living room).
        # Beyond ``max_gate_std`` a candidate is likelier someone else; a person who went that far
        # unseen is found again by the attention's reacquisition, not by the gate.
        if p00 > cap2 or p11 > cap2:
            k = cap2 / (p00 if p00 > p11 else p11)
            p00, p11, bb = p00 * k, p11 * k, bb * k * k
            b *= k
        if spread > cap2:
            spread = cap2
        lx, ly = tk.last_z
        ex = extra[i] if extra else 0.0
        dormant = tk.dormant and single is not None
        # the spread a lone leg is gated with (capped at single_gate_std)
        k1 = min(1.0, spec.single_gate_std**2 / max(p00, p11, 1e-12))
        s00, s01, s11 = p00 * k1, b * k1, p11 * k1
        stands = claimed and tk.x[2] * tk.x[2] + tk.x[3] * tk.x[3] < WALK_SPEED**2
        for j, zj in enumerate(z):
            lone = single is not None and single[j]
            if dormant and lone:
                continue  # a lone leg where someone was long unseen is as likely a chair's: pairs and blobs only
            if stands and j in claimed:
                kx, ky, k = claimed[j]
                if k != i and (zj[0] - x0) ** 2 + (zj[1] - x1) ** 2 > (zj[0] - kx) ** 2 + (zj[1] - ky) ** 2:
                    continue  # someone walking past her, where his own track predicts him: never hers
            r = var[j] + ex
            a = p00 + r
            d = p11 + r
            det = a * d - bb
            dx = zj[0] - x0
            dy = zj[1] - x1
            d2 = (d * dx * dx - 2 * b * dx * dy + a * dy * dy) / det
            ok = d2 <= gates[j]
            if ok and lone and k1 < 1.0:  # gated at the capped spread, scored as before
                a1, d1 = s00 + r, s11 + r
                ok = (d1 * dx * dx - 2 * s01 * dx * dy + a1 * dy * dy) / (a1 * d1 - s01 * s01) <= gates[j]
            cost = d2 + math.log(det)
            if spread and not (single and single[j]):
                s2 = r + spread
                dz2 = (zj[0] - lx) ** 2 + (zj[1] - ly) ** 2
                ds = dz2 / s2
                cs = ds + 2 * math.log(s2)
                if early and not ok:
                    # early: gated by how far someone gets from where they were last measured (the spread, a
                    # floor for the measurement's own noise), never wider than EARLY_STOP_RADIUS: in a close crossing the
                    # other person's pair is not offered as this one's "stopped" (review17 F8: it had gated pairs
                    # 0.28 m apart, two_people_radio seed 6). (Not "only a pair no walk-on gate takes": the runner's
                    # pair was taken by another walker's wide walk-on gate, the very case the rule is for)
                    if dz2 <= min(gates[j] * (spread + EARLY_STOP_FLOOR**2), EARLY_STOP_RADIUS**2):
                        ok, cost = True, cs
                        stopped.add((i, j))
                elif not early and ds <= gates[j] and (not ok or cs < cost):
                    ok, cost = True, cs
                    stopped.add((i, j))
            if ok:
                out.append((i, j, cost))
    return out, stopped


def _claimed(
    tracks: list[Track], z: Sequence[Sequence[float]], var: list[float], gates: list[float], t: float, spec: TrackerSpec,
) -> dict[int, tuple[float, float, int]]:
    """Candidates a walking track explains: candidate -> (the predicted position, row) of a confirmed track
    measured within ``tentative_gap``, walking at ``WALK_SPEED`` or more, in whose own gate (its covariance
    and the candidate's variance, without the contact allowance) the candidate lies; of several, the nearest.

    Why: while someone walks past a person who stands (in front of her, in a doorway), the contact
    allowance (:func:`_contact_variance`) and her track's "stopped" hypothesis gate his legs for her
    track nearly as well as for his own, and a hundredth of a cost decided: her track took his pair
    (restarted on it), his coasted, and a few scans later her track walked off with him (the swap
    fresh11/rail_fast_crossing showed in a dining-room door on session 13's integ). A standing person does not move at
    walking speed from one scan to the next; a candidate where a walker's own track predicts him,
    nearer to that prediction than to where she stands, is his (:func:`_gated` skips it for every
    track slower than ``WALK_SPEED``). Mixed candidates nearer to her stay hers to take; two people
    walking past each other are left to the contact allowance as before."""
    if len(tracks) < 2:
        return {}
    gap = spec.tentative_gap + 1e-9
    walk2 = WALK_SPEED**2
    out: dict[int, tuple[float, float, int]] = {}
    best: dict[int, float] = {}
    for k, tk in enumerate(tracks):
        x = tk.x
        if not tk.confirmed or tk.dormant or t - tk.last_update > gap or x[2] * x[2] + x[3] * x[3] < walk2:
            continue
        p00, b, p11 = tk.P[0], tk.P[1], tk.P[4]
        for j, zj in enumerate(z):
            a, d = p00 + var[j], p11 + var[j]
            dx, dy = zj[0] - x[0], zj[1] - x[1]
            d2 = (d * dx * dx - 2 * b * dx * dy + a * dy * dy) / (a * d - b * b)
            if d2 <= gates[j] and d2 < best.get(j, math.inf):
                best[j] = d2
                out[j] = (x[0], x[1], k)
    return out


def _associate(pairs: list[tuple[int, int, float]], tracks: list[Track], m: int) -> list[tuple[int, int, float]]:
    """The gated pairs kept: first among the tracks whose person is in sight, then the dormant tracks
    (unseen longer than ``death_timeout``) among the candidates those left.

    Why two rounds: the assignment makes as many gated pairs as it can before it weighs their costs,
    so in one round a dormant track that gates a seen person's pair took it, and pushed that
    person's own, tightly predicting track onto a lone leg of someone else beside her
    (bystander_at_door: the partner's track slid onto the bystander she walked past, and her voice,
    no longer from her track's bearing, was taken for his: she was never heard again). A dormant
    track is for a person coming back into view, never one the robot sees now."""
    dormant = {i for i, _, _ in pairs if tracks[i].dormant}
    if dormant and len(dormant) < len({i for i, _, _ in pairs}):
        seen = _choose([p for p in pairs if p[0] not in dormant], len(tracks), m)
        taken = {j for _, j, _ in seen}
        return seen + _choose([p for p in pairs if p[0] in dormant and p[1] not in taken], len(tracks), m)
    return _choose(pairs, len(tracks), m)


def _choose(pairs: list[tuple[int, int, float]], n: int, m: int) -> list[tuple[int, int, float]]:
    """Every gated pair when that leaves no choice, else the global nearest neighbour (:func:`_assign`)."""
    rows = {i for i, _, _ in pairs}
    cols = {j for _, j, _ in pairs}
    if len(rows) < len(pairs) or len(cols) < len(pairs):  # a choice to make
        return _assign(pairs, n, m)
    return pairs


def _assign(pairs: list[tuple[int, int, float]], n: int, m: int) -> list[tuple[int, int, float]]:
    """Global nearest neighbour among the gated pairs: ``linear_sum_assignment`` on the cost matrix."""
    cost = np.full((n, m), _FILL)
    gated = {}
    for i, j, d2 in pairs:
        cost[i, j] = d2
        gated[i, j] = d2
    rows, cols = linear_sum_assignment(cost)
    return [(i, j, gated[i, j]) for i, j in zip(rows.tolist(), cols.tolist()) if (i, j) in gated]


def cv_model(dt: float, accel_noise: float) -> tuple[np.ndarray, np.ndarray]:
    """Constant-velocity transition F and discrete white-noise-acceleration Q for ``dt``."""
    F = np.eye(4)
    F[0, 2] = F[1, 3] = dt
    q = accel_noise**2
    a, b, c = dt**4 / 4, dt**3 / 2, dt**2
    Q = q * np.array([[a, 0, b, 0], [0, a, 0, b], [b, 0, c, 0], [0, b, 0, c]])
    return F, Q
