"""The localiser: drifting odometry corrected by the laser against the floor plan.

Bus (docs/robot-contract.md): asks ``map_server/map`` for the plan and the
operator's start pose once at start, listens to ``/robot/odometry`` and
``/robot/laser/scan`` (ranges attachment), and publishes
``<pose time x y theta cxx cyy ctt frame="map"/>`` on
``/robot/localisation/pose`` for every odometry message (the odometry rate),
``time`` being the odometry's capture time.

The filter (:mod:`robot.localisation.mcl`, Monte Carlo localisation on a
likelihood field; the module docstring there says why) corrects only when a
scan arrives after the robot moved a threshold since the last correction
(and for the first few scans at the start, to settle the operator's pose);
between corrections the pose is the last estimate composed with the
odometry increment since, so publishing costs a few microseconds.

Failure: no map within ``map_timeout`` virtual seconds (the map server is
missing) fails the run with a message saying so; a map with nothing at the
laser's height raises ValueError from the likelihood field.
"""

from __future__ import annotations

import asyncio
import math
from collections import deque
from typing import TYPE_CHECKING

import numpy as np
from lxml import etree

from homesim.message import Message
from homesim.module import Module
from robot.floorplan import FloorPlan, parse_map

from robot.contract import ODOMETRY, POSE, SCAN

from .mcl import MCL, MCLParams, Pose, compose, relative

if TYPE_CHECKING:
    from homesim.sim import Simulation



class LocalisationError(RuntimeError):
    """The localiser cannot start (no floor plan)."""


class Localiser(Module):
    """MCL on the bus: odometry + laser + the map server's plan -> pose in ``map``."""

    def __init__(self, sim: Simulation, params: MCLParams | None = None, *, name: str = "localiser", map_timeout: float = 5.0, settle_scans: int = 3) -> None:
        super().__init__(sim, name, host="robot")
        self.params = params or MCLParams()
        self.map_timeout = map_timeout
        self.settle_scans = settle_scans
        self.plan: FloorPlan | None = None
        self.mcl: MCL | None = None
        self._odo: deque[tuple[float, Pose]] = deque(maxlen=8)  # (capture time, odom pose)
        self._odo_at_fix: Pose | None = None  # odometry pose at the last correction
        self._est_at_fix: Pose = (0.0, 0.0, 0.0)  # map pose at the last correction
        self._cov: tuple[float, float, float] = (0.0, 0.0, 0.0)
        self._cov_of_text: tuple[float, float, float] | None = None  # the covariance _cov_text was formatted from
        self._cov_text = ("", "", "")
        self._bearings: dict[tuple[int, str, str], np.ndarray] = {}
        self._scan_waiting: Message | None = None  # a scan newer than every odometry reading
        self.pose: Pose | None = None  # the latest published estimate
        self.bus.subscribe(ODOMETRY, self._on_odometry)
        self.bus.subscribe(SCAN, self._on_scan)

    async def run(self) -> None:
        self.plan = await self._fetch_map()
        self.mcl = MCL(self.plan, self.rng, self.params)
        # The operator's start pose is where odometry's frame begins (it starts at 0, 0, 0 where
        # the robot stands), whenever the map arrives: pair the two exactly.
        self._odo_at_fix = (0.0, 0.0, 0.0)
        self._est_at_fix = self.plan.start
        self._cov = (self.params.init_xy**2, self.params.init_xy**2, self.params.init_theta**2)
        while True:
            self.beat()
            await asyncio.sleep(0.5)

    async def _fetch_map(self) -> FloorPlan:
        waited = 0.0
        while waited < self.map_timeout:
            try:
                reply = await self.bus.call("map_server", "map", etree.Element("map_request"), timeout=1.0)
            except Exception:  # no server yet (or it failed): ask again
                self.beat()
                await asyncio.sleep(0.5)
                waited += 1.5
                continue
            return parse_map(reply.xml)
        raise LocalisationError(f"{self.name}: no floor plan from map_server/map within {self.map_timeout} s; is the map server installed?")

    # ------------------------------------------------------------ odometry
    def _on_odometry(self, msg: Message) -> None:
        x = msg.xml
        odo = (float(x.get("x")), float(x.get("y")), float(x.get("theta")))  # type: ignore[arg-type]
        t = msg.created
        self._odo.append((t, odo))
        if self.mcl is None:
            return
        waiting = self._scan_waiting
        if waiting is not None and float(waiting.xml.get("time", waiting.created)) <= t + 1e-6:  # type: ignore[arg-type]
            self._scan_waiting = None
            self._on_scan(waiting)
        pose = compose(self._est_at_fix, relative(self._odo_at_fix, odo))
        self.pose = pose
        cov = self._cov
        if cov is not self._cov_of_text:  # the covariance changes only at a correction: formatted once per fix
            self._cov_of_text = cov
            self._cov_text = (f"{cov[0]:.6f}", f"{cov[1]:.6f}", f"{cov[2]:.6f}")
        cxx, cyy, ctt = self._cov_text
        self.bus.publish(
            POSE,
            etree.Element(
                "pose", time=f"{t:.6f}", x=f"{pose[0]:.4f}", y=f"{pose[1]:.4f}", theta=f"{pose[2]:.5f}",
                cxx=cxx, cyy=cyy, ctt=ctt, frame="map",
            ),
            causes=(msg.id,),
            created=t,
            transfer=True,  # built here, never touched again: sent without a copy
        )

    def _odometry_at(self, t: float) -> Pose | None:
        """The odometry pose at time ``t``, interpolated between the readings around it."""
        if not self._odo:
            return None
        prev = None
        for tt, p in self._odo:
            if tt >= t:
                if prev is None or tt - prev[0] < 1e-9:
                    return p
                f = (t - prev[0]) / (tt - prev[0])
                d = relative(prev[1], p)
                return compose(prev[1], (d[0] * f, d[1] * f, d[2] * f))
            prev = (tt, p)
        return self._odo[-1][1]  # the scan is newer than every reading: the latest

    # ------------------------------------------------------------ scans
    def _on_scan(self, msg: Message) -> None:
        mcl = self.mcl
        if mcl is None or self._odo_at_fix is None:
            return
        x = msg.xml
        t = float(x.get("time", msg.created))  # type: ignore[arg-type]
        if not self._odo or self._odo[-1][0] < t - 1e-6:
            # The odometry of the scan's moment is still on its way (sensors tick together,
            # deliveries come in any order): pairing the scan with an older reading would put
            # the estimate a tick behind the odometry it is composed with.
            self._scan_waiting = msg
            return
        odo = self._odometry_at(t)
        if odo is None:
            return
        d = relative(self._odo_at_fix, odo)
        p = self.params
        moved = math.hypot(d[0], d[1]) >= p.update_dist or abs(d[2]) >= p.update_angle
        if not moved and mcl.updates >= self.settle_scans:
            return
        mcl.predict(d)
        mcl.correct(np.asarray(msg.attachments["ranges"]), self._beam_bearings(x), float(x.get("offset", "0")), float(x.get("max_range", "8.19")))
        self._odo_at_fix = odo
        self._est_at_fix, self._cov = mcl.estimate()

    def _beam_bearings(self, x: etree._Element) -> np.ndarray:
        key = (int(x.get("beams")), x.get("min_angle", "0"), x.get("resolution", "0"))  # type: ignore[arg-type]
        b = self._bearings.get(key)
        if b is None:
            b = self._bearings[key] = np.radians(float(key[1]) + float(key[2]) * np.arange(key[0]))
        return b
