"""Leg detection on the raw laser scan: segments, features, rules, pairs.

The classic pipeline (Arras et al. 2007 features, rules instead of a trained
classifier, which the simulator's clean geometry does not need):

1. Segment the scan where neighbouring ranges jump by more than ``jump`` or
   a beam has no echo.
2. Per segment: the number of points, the width (first to last point), the
   linearity (the spread across the best line, smallest eigenvalue of the
   point covariance), the mean range, and whether it stands in front of both
   neighbours.
3. Rules: a leg is 2+ points (1 far away), as wide as a leg seen at that
   range (the segment covers whole beams, so a beam spacing is added to its
   measured width), in front of its background. Width between ``blob_width``
   bounds and not straight: both legs seen as one blob (standing with the
   legs together; a flat piece of furniture is straight). Straightness does
   not separate one leg from a square table leg under 1 cm range noise; the
   width (a 5 cm table leg) and the pairing do. A leg half hidden behind
   the other (a person standing sideways) shows as a sliver just behind a
   leg, next to it in the scan: it counts as a leg, so the pair is found.
   A leg a whole leg wide that something well in front hides on one side (a
   person standing behind another) counts if it stands out on the other.
4. Pairing: leg candidates at most ``pair_distance`` apart, nearest first,
   make a person candidate at their midpoint; a leftover single leg is a weak
   candidate (its partner hidden), which the tracker uses only to keep an
   existing track alive, never to start one. Table and chair legs stand 0.7 m
   or more apart, so they do not pair.

Input: ranges (metres) and beam bearings of the laser frame; output in the
robot frame (the laser's ``offset`` ahead of the centre added).

How it is computed (the cost aim is a small part of 0.1 ms per scan): numpy
only where it touches every beam (the segmentation, the per-segment sums
with one ``np.add.reduceat``, the first and last point of every segment),
plain Python floats for the few dozen segments and the handful of leg
candidates, where a numpy call costs more than the arithmetic. The beam
directions' cosines and sines are computed once per scan geometry
(:class:`LegDetector`). The arithmetic is the vectorised formulation's,
operation for operation (``tests/test_attention_units.py`` checks the
detections bit for bit against that reference on random scenes); hypotenuses
stay numpy's (``math.hypot`` rounds differently in the last bit).

When the optional extension ``robot/attention/_legkernel.c`` is built (``pip
install -e .`` with a C compiler), steps 1-3 up to the candidates' centres run
there (about 6 us a scan instead of about 100): the same floats, numpy's
pairwise sums and the C library's ``hypot`` (what ``np.hypot`` calls), no fused
multiply-adds (``tests/test_attention_kernel.py`` compares the two paths bit for
bit). The furniture filter and the pairing stay in Python. ``LegDetector(...,
compiled=False)`` or ``HOMESIM_PURE_PYTHON=1`` runs the Python path.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

PAIR, BLOB, SINGLE = 0, 1, 2
_INF = math.inf


def _load_kernel():  # -> the extension module or None
    try:
        from homesim.kernels import load
    except ImportError:  # a checkout without the compiled-kernel loader: the Python path
        return None
    return load("robot.attention._legkernel", 2)


#: The per-scan pass compiled (robot/attention/_legkernel.c), or None: the Python path below.
_KERNEL = _load_kernel()
_KERNEL_MAX_BEAMS = 4096  # the kernel's fixed scratch sizes (MAX_BEAMS there; 256 legs in pair)
_KERNEL_MAX_LEGS = 256


@dataclass(frozen=True)
class LegSpec:
    jump: float = 0.10  # m: a range jump larger than this splits segments
    min_width: float = 0.07  # m: a leg seen at any angle (with a beam spacing added)
    max_width: float = 0.22
    blob_width: tuple[float, float] = (0.22, 0.40)  # both legs merged into one segment
    max_linearity: float = 0.015  # m: a blob must spread more than this across its best line (not a flat piece)
    background: float = 0.15  # m: a leg stands this much in front of its neighbours
    pair_distance: float = 0.55  # m: two legs of one person
    max_range: float = 6.5  # m: beyond it legs are too sparse to trust
    sparse_range: float = 4.0  # m: beyond it a 1-2 beam segment may be a leg whatever its width
    hidden_behind: tuple[float, float] = (0.05, 0.45)  # m: a half-hidden leg this far behind its neighbour leg
    offset: float = 0.13  # laser ahead of the robot centre


class Detections:
    """Person candidates in the robot frame: positions (K, 2), kinds (K,) PAIR/BLOB/SINGLE; legs (L, 2).

    Held as plain tuples (``points``, ``kinds``, ``leg_points``: what the tracker reads); the
    numpy views ``xy``, ``kind`` and ``legs`` are built on first use.
    """

    __slots__ = ("points", "kinds", "leg_points", "_xy", "_kind", "_legs")

    def __init__(self, points: list[tuple[float, float]], kinds: list[int], leg_points: list[tuple[float, float]]) -> None:
        self.points, self.kinds, self.leg_points = points, kinds, leg_points
        self._xy: np.ndarray | None = None
        self._kind: np.ndarray | None = None
        self._legs: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.points)

    @property
    def xy(self) -> np.ndarray:
        if self._xy is None:
            self._xy = np.array(self.points, dtype=float).reshape(-1, 2)
        return self._xy

    @property
    def kind(self) -> np.ndarray:
        if self._kind is None:
            self._kind = np.array(self.kinds, dtype=np.int8)
        return self._kind

    @property
    def legs(self) -> np.ndarray:
        if self._legs is None:
            self._legs = np.array(self.leg_points, dtype=float).reshape(-1, 2)
        return self._legs


class LegDetector:
    """The leg detector for one scan geometry (beam ``bearings``, rad); call it with a scan's ranges.

    Raises ValueError for fewer than two beams (no beam spacing, no width).
    """

    def __init__(self, bearings: np.ndarray, spec: LegSpec = LegSpec(), *, compiled: bool = True) -> None:
        b = np.array(bearings, dtype=float)
        if b.ndim != 1 or b.shape[0] < 2:
            raise ValueError(f"leg detector: need a 1-D array of at least two beam bearings, got shape {b.shape}")
        self.spec = spec
        self.beams = int(b.shape[0])
        self._cos, self._sin = np.cos(b), np.sin(b)
        self._spacing = abs(float(b[1] - b[0]))
        n = self.beams
        # Scratch arrays, reused every scan (1-D: numpy's fancy indexing and sums are cheaper there).
        self._starts = np.empty(n, dtype=bool)  # beam i starts a segment
        self._starts[0] = True
        self._ends = np.empty(n, dtype=bool)  # beam i ends a segment
        self._ends[-1] = True
        self._jump = np.empty(n - 1)
        self._x = np.zeros(n + 1)  # x, y of every beam's point; one spare so a segment may end at n
        self._y = np.zeros(n + 1)
        self._r = np.full(n + 2, _INF)  # inf, the ranges, inf: the range before beam i is _r[i]
        self._bounds = np.empty(2 * n, dtype=np.intp)  # start, end (exclusive) of every segment
        # The compiled pass when it is built (and not turned off: ``compiled=False`` or
        # HOMESIM_PURE_PYTHON), for at most its number of beams; it computes the same floats.
        self.kernel = _KERNEL if compiled and n <= _KERNEL_MAX_BEAMS else None
        self._params = (
            spec.max_range, spec.jump, self._spacing, spec.min_width, spec.max_width, spec.blob_width[0], spec.blob_width[1],
            spec.max_linearity, spec.background, spec.sparse_range, spec.hidden_behind[0], spec.hidden_behind[1], spec.offset,
        )

    def __call__(
        self,
        ranges: np.ndarray,
        reject: Callable[[np.ndarray], np.ndarray] | None = None,
        *,
        reject_points: Callable[[list[tuple[float, float]]], list[bool]] | None = None,
    ) -> Detections:
        """Person candidates (robot frame) from one scan; see the module docstring.

        ``reject`` (optional) marks leg-like segments that are known not to be
        people (robot-frame points (K, 2) -> bool (K,), e.g. inside a table's
        footprint); they are dropped before pairing, so a table leg never pairs
        with a person's leg. ``reject_points`` is the same test on a list of
        (x, y) tuples (no arrays built: what a module that sees every scan
        passes); give one or neither. Raises ValueError if ``ranges`` does not
        hold one range per beam.
        """
        if reject is not None:
            if reject_points is not None:
                raise ValueError("leg detector: give reject or reject_points, not both")
            reject_points = _on_arrays(reject)
        spec = self.spec
        r = np.asarray(ranges, dtype=float)
        n = self.beams
        if r.shape != (n,):
            raise ValueError(f"leg detector: a scan of shape {r.shape}, expected ({n},) ranges")
        if self.kernel is not None:
            cx, cy, flags = self.kernel.candidates(np.ascontiguousarray(r), self._cos, self._sin, self._params)
            return _finish(cx, cy, flags, reject_points, spec.pair_distance, self.kernel) if flags else Detections([], [], [])
        # 1. Segments (numpy, every beam): a break after beam i where the range jumps or either beam
        # has no echo. Beams without echo are segments of their own, dropped here.
        valid = r < spec.max_range
        invalid = ~valid
        jump = self._jump
        np.subtract(r[1:], r[:-1], out=jump)
        np.abs(jump, out=jump)
        head, ends = self._starts[1:], self._ends
        np.greater(jump, spec.jump, out=head)
        head |= invalid[1:]
        head |= invalid[:-1]
        ends[:-1] = head
        head = self._starts
        head &= valid
        ends &= valid
        first = head.nonzero()[0]
        last = ends.nonzero()[0]
        head[0] = ends[-1] = True  # the scratch again: the first beam starts a segment, the last ends one
        count = first.shape[0]
        if count == 0:
            return Detections([], [], [])
        x, y, rr = self._x, self._y, self._r
        np.multiply(r, self._cos, out=x[:n])
        np.multiply(r, self._sin, out=y[:n])
        rr[1:-1] = r
        bounds = self._bounds[: 2 * count]
        bounds[0::2] = first
        np.add(last, 1, out=bounds[1::2])
        # Per segment: the sums of x, y and range (pairwise, as numpy sums), the chord from its first
        # to its last point, the ranges just before and after it (inf past either end of the scan).
        sx = np.add.reduceat(x, bounds)[0::2].tolist()
        sy = np.add.reduceat(y, bounds)[0::2].tolist()
        sr = np.add.reduceat(rr[1:], bounds)[0::2].tolist()
        chord = np.hypot(x[last] - x[first], y[last] - y[first]).tolist()
        before = rr[first].tolist()
        after = rr[2:][last].tolist()
        return self._rules(first.tolist(), last.tolist(), sx, sy, sr, chord, before, after, reject_points)

    def _rules(
        self,
        starts: list[int],
        lasts: list[int],
        sx: list[float],
        sy: list[float],
        sr: list[float],
        chord: list[float],
        before: list[float],
        after: list[float],
        reject: Callable[[list[tuple[float, float]]], list[bool]] | None,
    ) -> Detections:
        """2.-4. Features, rules and pairing on the segments (plain floats: a few dozen segments)."""
        spec = self.spec
        max_range, background, spacing = spec.max_range, spec.background, self._spacing
        min_width, max_width, sparse_range = spec.min_width, spec.max_width, spec.sparse_range
        blob_lo, blob_hi = spec.blob_width
        count = len(starts)
        size = [0] * count
        rng = [0.0] * count
        wid = [0.0] * count
        leg = [False] * count
        blob = [False] * count
        legs0 = []
        widest = max(max_width, blob_hi)  # a wider segment is no leg, no blob, no hidden leg
        for k, (s, e, sum_r, ch, b, a) in enumerate(zip(starts, lasts, sr, chord, before, after)):
            if ch > widest:
                wid[k] = ch
                continue
            n = size[k] = e + 1 - s
            mean_r = rng[k] = sum_r / n
            width = wid[k] = ch + mean_r * spacing  # the beams cover half a spacing beyond each end point
            if b >= max_range:
                b = before[k] = _INF
            if a >= max_range:
                a = after[k] = _INF
            if b > mean_r + background and a > mean_r + background:  # in front of both neighbours
                # Far away a leg spans one or two beams: its width cannot be measured, only bounded.
                if (n >= 2 or mean_r > 3.0) and (width >= min_width or (n <= 2 and mean_r > sparse_range)) and width <= max_width:
                    leg[k] = True
                    legs0.append(k)
                if n >= 4 and blob_lo < width <= blob_hi:
                    # Straightness tells only for wide segments: across a leg's visible arc the 1 cm
                    # range noise is as large as the curvature, but two legs side by side are far
                    # from a straight wall piece.
                    blob[k] = self._linearity(s, e + 1) > spec.max_linearity
        # A leg half hidden behind the other (a person standing sideways): right next to a leg in the
        # scan (contiguous: no beam without echo between them), a little behind it, and standing out
        # of the background on its other side.
        lo, hi = spec.hidden_behind
        hidden: list[int] = []
        for k in legs0:
            j = k + 1
            if j < count and lasts[k] + 1 == starts[j] and not leg[j] and not blob[j] and wid[j] <= max_width:
                if lo < rng[j] - rng[k] < hi and after[j] > rng[j] + background:
                    hidden.append(j)
            j = k - 1
            if j >= 0 and lasts[j] + 1 == starts[k] and not leg[j] and not blob[j] and wid[j] <= max_width:
                if lo < rng[j] - rng[k] < hi and before[j] > rng[j] + background:
                    hidden.append(j)
        for k in hidden:
            leg[k] = True
        # A leg partly hidden behind something well in front of it (someone standing or passing nearer,
        # a chair's edge): on one side the scan jumps nearer by more than ``hidden_behind[1]`` (so not
        # its own other leg, the rule above), on the other it stands out of the background, and what
        # shows is 2+ points a whole leg wide. Without it a person standing just behind another is
        # one lone leg for as long as both stand, which never starts a track (tour-3000-03: Paul,
        # beside and behind two others, untracked for 61 s).
        for k in range(count):
            if leg[k] or blob[k] or size[k] < 2 or not min_width <= wid[k] <= max_width:
                continue
            m = rng[k]
            if (before[k] < m - hi and after[k] > m + background) or (after[k] < m - hi and before[k] > m + background):
                leg[k] = True
        cand = [k for k in range(count) if leg[k] or blob[k]]
        if not cand:
            return Detections([], [], [])
        # A segment's points lie on the near surface: push the centre back by about a leg radius.
        mx = [sx[k] / size[k] for k in cand]
        my = [sy[k] / size[k] for k in cand]
        norms = np.hypot(mx, my).tolist()
        offset = spec.offset
        cx, cy = [], []
        for x, y, norm in zip(mx, my, norms):
            norm = max(norm, 1e-9)
            cx.append(x + 0.05 * x / norm + offset)
            cy.append(y + 0.05 * y / norm)
        flags = [(1 if leg[k] else 0) | (2 if blob[k] else 0) for k in cand]
        return _finish(cx, cy, flags, reject, spec.pair_distance)

    def _linearity(self, s: int, e: int) -> float:
        """The spread (m) of segment ``s:e``'s points across their best line: sqrt of the smaller covariance eigenvalue."""
        xs, ys = self._x[s:e], self._y[s:e]
        n = e - s
        cols = np.concatenate((xs, ys, xs * xs, ys * ys, xs * ys))  # the five sums in one reduceat
        sx, sy, sxx, syy, sxy = np.add.reduceat(cols, range(0, 5 * n, n)).tolist()
        mx, my = sx / n, sy / n
        cxx, cyy, cxy = sxx / n - mx * mx, syy / n - my * my, sxy / n - mx * my
        tr, det = cxx + cyy, cxx * cyy - cxy * cxy
        return math.sqrt(max(tr / 2 - math.sqrt(max(tr * tr / 4 - det, 0.0)), 0.0))



def _finish(
    cx: list[float],
    cy: list[float],
    flags: list[int],
    reject: Callable[[list[tuple[float, float]]], list[bool]] | None,
    pair_distance: float,
    kernel: Any = None,
) -> Detections:
    """The furniture filter and the pairing on the leg-like segments' centres (``flags``: 1 a leg, 2 a blob, 3 both);
    the pairing compiled when ``kernel`` is given (the same candidates as :func:`_pair`)."""
    points = list(zip(cx, cy))
    bad = reject(points) if reject is not None else None
    legs: list[tuple[float, float]] = []
    blobs: list[tuple[float, float]] = []
    for i, f in enumerate(flags):
        if bad is not None and bad[i]:
            continue
        if f & 1:
            legs.append(points[i])
        if f & 2:
            blobs.append(points[i])
    if kernel is not None and len(legs) <= _KERNEL_MAX_LEGS:
        pts, kinds = kernel.pair(legs, blobs, pair_distance, (pair_distance * 1.01) ** 2)
        return Detections(pts, kinds, legs)
    return _pair(legs, blobs, pair_distance)


def _on_arrays(reject: Callable[[np.ndarray], np.ndarray]) -> Callable[[list[tuple[float, float]]], list[bool]]:
    """An array test (points (K, 2) -> bool (K,)) as a test on a list of points."""

    def on_list(points: list[tuple[float, float]]) -> list[bool]:
        return np.asarray(reject(np.array(points, dtype=float).reshape(-1, 2)), dtype=bool).tolist()

    return on_list


def _pair(legs: list[tuple[float, float]], blobs: list[tuple[float, float]], pair_distance: float) -> Detections:
    """4. Pairing: nearest legs first, at most ``pair_distance`` apart; then blobs; then the leftover singles."""
    points: list[tuple[float, float]] = []
    kinds: list[int] = []
    k = len(legs)
    used = [False] * k
    if k > 1:
        # Only pairs that may be close enough (a margin over pair_distance) get the exact distance.
        near = (pair_distance * 1.01) ** 2
        ii, jj, dx, dy = [], [], [], []
        for i in range(k):
            xi, yi = legs[i]
            for j in range(i + 1, k):
                ex, ey = xi - legs[j][0], yi - legs[j][1]
                if ex * ex + ey * ey <= near:
                    ii.append(i)
                    jj.append(j)
                    dx.append(ex)
                    dy.append(ey)
        dd = np.hypot(dx, dy).tolist() if dx else []
        for m in sorted(range(len(dd)), key=dd.__getitem__):  # stable: ties keep the row-major order
            if dd[m] > pair_distance:
                break
            i, j = ii[m], jj[m]
            if used[i] or used[j]:
                continue
            used[i] = used[j] = True
            points.append(((legs[i][0] + legs[j][0]) / 2, (legs[i][1] + legs[j][1]) / 2))
            kinds.append(PAIR)
    for p in blobs:
        points.append(p)
        kinds.append(BLOB)
    for i in range(k):
        if not used[i]:
            points.append(legs[i])
            kinds.append(SINGLE)
    return Detections(points, kinds, legs)


def detect(ranges: np.ndarray, bearings: np.ndarray, spec: LegSpec = LegSpec(), reject: Callable[[np.ndarray], np.ndarray] | None = None) -> Detections:
    """Person candidates (robot frame) from one scan: :class:`LegDetector` for ``bearings`` and ``spec``.

    A convenience for one-off calls and tests; a module that sees many scans keeps its
    :class:`LegDetector` (it caches the beam directions). Raises ValueError as the detector does.
    """
    return LegDetector(bearings, spec)(ranges, reject)
