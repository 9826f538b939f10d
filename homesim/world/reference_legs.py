"""A reference leg-pair finder for laser scans (evaluation, not perception).

Scenario expectations ("the laser saw legs at a bearing") and tests need to
find people in a scan without ground truth. This is the classic method:
split the scan into clusters at range jumps, keep clusters as wide as a leg
that stand out in front of their background, pair candidates that are
close together. It lives in the kernel so the scenario checker can use it;
the robot's person attention system is free to run its own detector.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class LegPair:
    """A pair of legs seen in a scan: bearing (rad, laser frame) and distance (m) of the midpoint."""

    bearing: float
    distance: float
    x: float  # laser frame
    y: float
    single: bool = False  # only one leg visible (the other occluded)


def detect_leg_pairs(
    ranges: np.ndarray,
    bearings: np.ndarray,
    *,
    max_range: float = 8.19,
    jump: float = 0.08,
    min_width: float = 0.04,
    max_width: float = 0.22,
    max_gap: float = 0.5,
    with_singles: bool = True,
) -> list[LegPair]:
    """Find legs in a scan: short clusters of beams, paired when close together.

    A cluster is a run of neighbouring beams whose ranges differ by less than
    ``jump``; a leg candidate is a cluster 4-22 cm wide standing in front of
    both its neighbours. Candidates closer than ``max_gap`` pair up (nearest
    first); with ``with_singles`` an unpaired candidate is reported as a
    single leg (its partner occluded). Returns pairs ordered by bearing.
    """
    valid = ranges < max_range - 1e-6
    xs = ranges * np.cos(bearings)
    ys = ranges * np.sin(bearings)
    breaks = np.flatnonzero((np.abs(np.diff(ranges)) > jump) | ~valid[1:] | ~valid[:-1]) + 1
    starts = np.concatenate(([0], breaks))
    ends = np.concatenate((breaks, [len(ranges)]))
    cands: list[tuple[float, float]] = []
    for s, e in zip(starts, ends):
        if not valid[s]:
            continue
        width = math.hypot(xs[e - 1] - xs[s], ys[e - 1] - ys[s])
        if not (min_width <= width <= max_width) and not (e - s <= 2 and width < max_width):
            continue
        r = float(ranges[s:e].mean())
        before = ranges[s - 1] if s > 0 else max_range
        after = ranges[e] if e < len(ranges) else max_range
        if before < r + 0.1 or after < r + 0.1:
            continue  # not standing out in front of its background
        # Centre of the leg: the cluster's mean point pushed back by about a radius.
        mx, my = float(xs[s:e].mean()), float(ys[s:e].mean())
        n = math.hypot(mx, my)
        cands.append((mx + 0.05 * mx / n, my + 0.05 * my / n))
    pairs: list[LegPair] = []
    used = [False] * len(cands)
    options = sorted(
        (math.hypot(a[0] - b[0], a[1] - b[1]), i, j)
        for i, a in enumerate(cands)
        for j, b in enumerate(cands)
        if i < j
    )
    for d, i, j in options:
        if d > max_gap or used[i] or used[j]:
            continue
        used[i] = used[j] = True
        x = (cands[i][0] + cands[j][0]) / 2
        y = (cands[i][1] + cands[j][1]) / 2
        pairs.append(LegPair(math.atan2(y, x), math.hypot(x, y), x, y))
    if with_singles:
        for k, c in enumerate(cands):
            if not used[k]:
                pairs.append(LegPair(math.atan2(c[1], c[0]), math.hypot(*c), c[0], c[1], single=True))
    pairs.sort(key=lambda p: p.bearing)
    return pairs
