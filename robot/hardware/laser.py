"""SICK LMS200 laser range finder: the scan kernel and the module.

The scan is a raycast at the laser's height (0.30 m) against the world's
geometry: walls, furniture that reaches that height (a sofa, a cupboard),
table legs but not table tops, and people's legs. 180 degrees in 0.5 degree
steps (361 beams), 8.19 m range, about 1 cm Gaussian noise; beams that hit
nothing read ``max_range``. Noise comes from the generator handed in.

Leg detectors: the robot's is person attention's (``robot/attention/legs.py``);
:func:`homesim.world.reference_legs.detect_leg_pairs` is the evaluation's
reference (scenario expectations and tests check with it that people appear
in the scan), not part of the robot.
"""

from __future__ import annotations

import asyncio
import copy
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from lxml import etree

if TYPE_CHECKING:
    from homesim.sim import Simulation
    from homesim.world.world import World

from homesim.module import Module
from homesim.world.raycast import add_range_noise
from robot.contract import SCAN

__all__ = ["LaserSpec", "Laser", "laser_origin", "simulate_scan", "SCAN"]



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
        add_range_noise(ranges, rng.normal(0.0, spec.noise, ranges.shape[0]), spec.max_range)
    return ranges


def scan_element(t: float, spec: LaserSpec, seq: int, *, template: etree._Element | None = None) -> etree._Element:
    """The XML part of a scan message (the ranges travel as an attachment).

    ``template``: an earlier element for the same ``spec``; copying it and setting ``seq`` and
    ``time`` (which keep their places) gives the same element at a third of the cost of
    formatting every attribute again.
    """
    if template is not None:
        el = copy.copy(template)  # lxml: a deep copy, its own document, no parent
        el.set("seq", str(seq))
        el.set("time", f"{t:.6f}")
        return el
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
        self._template = scan_element(0.0, self.spec, 0)
        self.seq = 0

    async def run(self) -> None:
        period = 1.0 / self.spec.rate
        while True:
            self.beat()
            ranges = simulate_scan(self.world, self.world.robot.pose, self.spec, self.rng, bearings=self._bearings)
            self.bus.publish(SCAN, scan_element(self.now, self.spec, self.seq, template=self._template), attachments={"ranges": ranges}, transfer=True)
            self.seq += 1
            await asyncio.sleep(period)
