"""SICK LMS200 laser range finder: the scan kernel, a reference leg detector, the module.

The scan is a raycast at the laser's height (0.30 m) against the world's
geometry: walls, furniture that reaches that height (a sofa, a cupboard),
table legs but not table tops, and people's legs. 180 degrees in 0.5 degree
steps (361 beams), 8.19 m range, about 1 cm Gaussian noise; beams that hit
nothing read ``max_range``. Noise comes from the generator handed in.

:func:`detect_leg_pairs` is a small reference detector (the classic
cluster-width-and-pairing method): tests and scenario expectations use it to
check that people appear in the scan. The person attention system is free
to run its own.
"""

from __future__ import annotations

import asyncio
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from lxml import etree

if TYPE_CHECKING:
    from homesim.sim import Simulation
    from homesim.world.world import World

from homesim.module import Module

SCAN_CHANNEL = "/robot/laser/scan"


@dataclass(frozen=True)
class LaserSpec:
    """Geometry and noise of the scanner (defaults: the PeopleBot's SICK LMS200)."""

    fov: float = math.pi
    resolution: float = math.radians(0.5)
    max_range: float = 8.19
    noise: float = 0.01
    offset: float = 0.13  # metres ahead of the robot's centre
    height: float = 0.30
    rate: float = 10.0

    @property
    def n_beams(self) -> int:
        return int(round(self.fov / self.resolution)) + 1

    def bearings(self) -> np.ndarray:
        """Beam bearings in the laser frame, right to left (-90 .. +90 degrees)."""
        return -self.fov / 2 + self.resolution * np.arange(self.n_beams)


def laser_origin(pose: tuple[float, float, float], spec: LaserSpec) -> tuple[float, float]:
    """World position of the laser for a robot pose."""
    x, y, th = pose
    return x + spec.offset * math.cos(th), y + spec.offset * math.sin(th)


def simulate_scan(
    world: World,
    pose: tuple[float, float, float],
    spec: LaserSpec,
    rng: np.random.Generator | None,
    *,
    bearings: np.ndarray | None = None,
    out: np.ndarray | None = None,
) -> np.ndarray:
    """One scan (ranges, metres) from a robot pose; noise from ``rng`` (None: exact).

    Noisy ranges are clipped to [0, max_range]; a beam that hit nothing
    stays exactly ``max_range`` (the SICK's "no echo" reading).
    """
    b = spec.bearings() if bearings is None else bearings
    ranges = world.laser_ranges(laser_origin(pose, spec), b + pose[2], spec.max_range, out=out)
    if rng is not None and spec.noise > 0:
        miss = ranges >= spec.max_range
        ranges += rng.normal(0.0, spec.noise, ranges.shape[0])
        np.clip(ranges, 0.0, spec.max_range, out=ranges)
        ranges[miss] = spec.max_range
    return ranges


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


def scan_element(t: float, spec: LaserSpec, seq: int) -> etree._Element:
    """The XML part of a scan message (the ranges travel as an attachment)."""
    return etree.Element(
        "scan",
        seq=str(seq),
        time=f"{t:.6f}",
        beams=str(spec.n_beams),
        min_angle=f"{math.degrees(-spec.fov / 2):.3f}",
        resolution=f"{math.degrees(spec.resolution):.3f}",
        max_range=f"{spec.max_range:.3f}",
        height=f"{spec.height:.3f}",
        offset=f"{spec.offset:.3f}",
        unit="m",
    )


class Laser(Module):
    """Publishes a scan on ``/robot/laser/scan`` at ``spec.rate`` Hz.

    Message: ``<scan seq time beams min_angle resolution max_range .../>`` with
    the ranges as a float64 attachment ``ranges`` (a fresh array per scan,
    so receivers may keep it).
    """

    def __init__(self, sim: Simulation, world: World, spec: LaserSpec | None = None, *, name: str = "laser") -> None:
        super().__init__(sim, name, host="robot")
        self.world = world
        self.spec = spec or LaserSpec()
        self._bearings = self.spec.bearings()
        self.seq = 0

    async def run(self) -> None:
        period = 1.0 / self.spec.rate
        while True:
            self.beat()
            ranges = simulate_scan(self.world, self.world.robot.pose, self.spec, self.rng, bearings=self._bearings)
            self.bus.publish(SCAN_CHANNEL, scan_element(self.now, self.spec, self.seq), attachments={"ranges": ranges})
            self.seq += 1
            await asyncio.sleep(period)
