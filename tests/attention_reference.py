"""The leg detector as first written: every rule one vectorised numpy expression over all segments.

``robot.attention.legs`` computes the same in plain floats where that is cheaper;
``tests/test_attention_units.py`` checks the two agree bit for bit on random scenes. Kept here
(not in the package) as the readable statement of the rules that the fast code must match.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from robot.attention.legs import BLOB, PAIR, SINGLE, LegSpec

__all__ = ["BLOB", "PAIR", "SINGLE", "RefDetections", "reference_detect"]


@dataclass(frozen=True)
class RefDetections:
    xy: np.ndarray
    kind: np.ndarray
    legs: np.ndarray

    def __len__(self) -> int:
        return int(self.xy.shape[0])


@lru_cache(maxsize=64)
def _pairs(k: int) -> tuple[np.ndarray, np.ndarray]:
    """``np.triu_indices(k, 1)``, kept per ``k``: numpy 2.4 builds it in ~70 us, a sixth of a scan's detection."""
    iu, ju = np.triu_indices(k, 1)
    iu.flags.writeable = False
    ju.flags.writeable = False
    return iu, ju


EMPTY = RefDetections(np.zeros((0, 2)), np.zeros(0, dtype=np.int8), np.zeros((0, 2)))


def segment_features(ranges: np.ndarray, bearings: np.ndarray, spec: LegSpec) -> dict[str, np.ndarray]:
    """Split the scan at range jumps and compute each segment's features (arrays, one entry per segment)."""
    r = np.asarray(ranges, dtype=float)
    valid = r < spec.max_range
    xs = r * np.cos(bearings)
    ys = r * np.sin(bearings)
    d = np.abs(np.diff(r))
    brk = np.flatnonzero((d > spec.jump) | ~valid[1:] | ~valid[:-1]) + 1
    starts = np.concatenate(([0], brk))
    ends = np.concatenate((brk, [r.shape[0]]))
    if r.shape[0] == 0:
        z = np.zeros(0)
        return {"start": starts[:0], "end": ends[:0], "n": z, "mx": z, "my": z, "width": z, "lin": z, "range": z, "front": z.astype(bool), "before": z, "after": z}
    keep = valid[starts]  # (segments are all valid or all no-echo)
    cols = np.stack((xs, ys, xs * xs, ys * ys, xs * ys, r), axis=1)
    sums = np.add.reduceat(cols, starts, axis=0)[keep]  # one pass for every segment sum
    sx, sy, sxx, syy, sxy, sr = sums.T
    starts, ends = starts[keep], ends[keep]
    n = (ends - starts).astype(float)
    mx, my = sx / n, sy / n
    cxx, cyy, cxy = sxx / n - mx * mx, syy / n - my * my, sxy / n - mx * my
    tr, det = cxx + cyy, cxx * cyy - cxy * cxy
    small = np.maximum(tr / 2 - np.sqrt(np.maximum(tr * tr / 4 - det, 0.0)), 0.0)
    last = ends - 1
    width = np.hypot(xs[last] - xs[starts], ys[last] - ys[starts])
    mean_r = sr / n
    before = np.where(starts > 0, r[np.maximum(starts - 1, 0)], np.inf)
    after = np.where(ends < r.shape[0], r[np.minimum(ends, r.shape[0] - 1)], np.inf)
    before = np.where(before >= spec.max_range, np.inf, before)
    after = np.where(after >= spec.max_range, np.inf, after)
    front = (before > mean_r + spec.background) & (after > mean_r + spec.background)
    return {"start": starts, "end": ends, "n": n, "mx": mx, "my": my, "width": width, "lin": np.sqrt(small), "range": mean_r, "front": front,
            "before": before, "after": after}


def reference_detect(ranges: np.ndarray, bearings: np.ndarray, spec: LegSpec = LegSpec(), reject: Callable[[np.ndarray], np.ndarray] | None = None) -> RefDetections:
    """Person candidates (robot frame) from one scan; see the module docstring.

    ``reject`` (optional) marks leg-like segments that are known not to be
    people (robot-frame points (K, 2) -> bool (K,), e.g. inside a table's
    footprint); they are dropped before pairing, so a table leg never pairs
    with a person's leg.
    """
    f = segment_features(ranges, bearings, spec)
    if len(f["n"]) == 0:
        return EMPTY
    spacing = f["range"] * abs(float(bearings[1] - bearings[0]))
    width = f["width"] + spacing  # the segment's beams cover half a spacing beyond each end point
    # Straightness tells only for wide segments: across a leg's visible arc the 1 cm range noise
    # is as large as the curvature, but two legs side by side are far from a straight wall piece.
    round_ = (f["lin"] > spec.max_linearity) & (f["n"] >= 4)
    few_ok = (f["n"] >= 2) | (f["range"] > 3.0)
    front = f["front"]
    # Far away a leg spans one or two beams: its width cannot be measured, only bounded.
    sparse = (f["n"] <= 2) & (f["range"] > spec.sparse_range)
    leg = front & few_ok & ((width >= spec.min_width) | sparse) & (width <= spec.max_width)
    blob = front & (f["n"] >= 3) & (width > spec.blob_width[0]) & (width <= spec.blob_width[1]) & round_
    # A leg half hidden behind the other (a person standing sideways): right next to a leg in the
    # scan, a little behind it, and standing out of the background on its other side.
    rng_, cont = f["range"], f["end"][:-1] == f["start"][1:]
    gap_prev = rng_[1:] - rng_[:-1]
    gap_next = rng_[:-1] - rng_[1:]
    hidden = ~leg & ~blob & (width <= spec.max_width)
    lo, hi = spec.hidden_behind
    behind_prev = cont & leg[:-1] & hidden[1:] & (gap_prev > lo) & (gap_prev < hi) & (f["after"][1:] > rng_[1:] + spec.background)
    behind_next = cont & leg[1:] & hidden[:-1] & (gap_next > lo) & (gap_next < hi) & (f["before"][:-1] > rng_[:-1] + spec.background)
    leg = leg.copy()
    leg[1:] |= behind_prev
    leg[:-1] |= behind_next
    # A leg partly hidden behind something well in front of it (more than ``hidden_behind[1]`` nearer on
    # one side: not its own other leg), standing out of the background on its other side, a leg wide.
    rest = ~leg & ~blob & (f["n"] >= 2) & (width >= spec.min_width) & (width <= spec.max_width)
    occluded = ((f["before"] < rng_ - hi) & (f["after"] > rng_ + spec.background)) | ((f["after"] < rng_ - hi) & (f["before"] > rng_ + spec.background))
    leg |= rest & occluded
    # A segment's points lie on the near surface: push the centre back by about a leg radius.
    norm = np.maximum(np.hypot(f["mx"], f["my"]), 1e-9)
    cx = f["mx"] + 0.05 * f["mx"] / norm + spec.offset
    cy = f["my"] + 0.05 * f["my"] / norm
    if reject is not None:
        pts = np.column_stack((cx, cy))
        bad = np.zeros(cx.shape[0], dtype=bool)
        cand = leg | blob
        if cand.any():
            bad[cand] = reject(pts[cand])
        leg &= ~bad
        blob &= ~bad
    legs = np.column_stack((cx[leg], cy[leg]))
    out_xy: list[np.ndarray] = []
    kinds: list[int] = []
    k = legs.shape[0]
    used = np.zeros(k, dtype=bool)
    if k > 1:
        dist = np.hypot(legs[:, None, 0] - legs[None, :, 0], legs[:, None, 1] - legs[None, :, 1])
        iu, ju = _pairs(k)
        dd = dist[iu, ju]
        for m in np.argsort(dd, kind="stable"):
            if dd[m] > spec.pair_distance:
                break
            i, j = int(iu[m]), int(ju[m])
            if used[i] or used[j]:
                continue
            used[i] = used[j] = True
            out_xy.append((legs[i] + legs[j]) / 2)
            kinds.append(PAIR)
    for x, y in zip(cx[blob], cy[blob]):
        out_xy.append(np.array([x, y]))
        kinds.append(BLOB)
    for i in np.flatnonzero(~used):
        out_xy.append(legs[i])
        kinds.append(SINGLE)
    if not out_xy:
        return RefDetections(np.zeros((0, 2)), np.zeros(0, dtype=np.int8), legs)
    return RefDetections(np.array(out_xy), np.array(kinds, dtype=np.int8), legs)

