"""The PeopleBot base: velocity commands in, odometry with drift and the bumper switches out.

Commands arrive on ``/robot/base/cmd`` as ``<velocity v="m/s" w="rad/s"/>``;
the base holds the last one and stops when none came for ``watchdog``
seconds (a crashed controller must not drive the robot into a wall). The
world's contact solver stops the robot at walls, furniture and people.

Odometry integrates the base's real motion with noise on each distance
and turn increment plus a slow heading drift, each a random walk (variance
proportional to the distance or angle travelled, so the error does not
depend on the publishing rate), so the pose it reports wanders away from
the truth as a real base's does. It is published
on ``/robot/odometry`` as ``<odometry x y theta v w/>`` at its rate; ``v`` and
``w`` are measured from the odometry increments (:func:`measured_velocities`),
noisy as the encoders are, never the base's true velocities. The bumper rings are read with
each odometry packet, as the PeopleBot's microcontroller reports them in the same packet, and
published on ``/robot/bumpers`` when a segment closes or opens, and with every packet while one
stays closed (:mod:`robot.hardware.bumpers`).
"""

from __future__ import annotations

import asyncio
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from lxml import etree

from homesim.message import Message
from homesim.module import Module
from homesim.geometry import wrap_angle
from robot.contract import BASE_CMD, BUMPERS, ODOMETRY

from .bumpers import BumperSensor, bumper_element

if TYPE_CHECKING:
    from homesim.sim import Simulation
    from homesim.world.world import World



@dataclass(frozen=True)
class OdometrySpec:
    """Odometry noise as random walks: each standard deviation grows with the square root
    of the distance (or angle) travelled, so the error after a drive does not depend on
    how often the base publishes."""

    distance_noise: float = 0.02  # m per sqrt(m) driven: 2 cm after 1 m, 6 cm after 10 m (std)
    turn_noise: float = 0.03  # rad per sqrt(rad) turned: 4 deg after a full turn (std)
    drift: float = 0.01  # rad of heading drift per sqrt(m) driven (std)
    rate: float = 10.0
    watchdog: float = 0.5


def odometry_step(
    odo: tuple[float, float, float],
    before: tuple[float, float, float],
    after: tuple[float, float, float],
    spec: OdometrySpec,
    rng: np.random.Generator | None,
) -> tuple[float, float, float]:
    """Advance an odometry pose by the true motion before -> after, with noise.

    The increment is taken in the robot's own frame (distance along its
    heading and turn), disturbed, and applied to the odometry pose, so
    errors accumulate exactly as dead reckoning does. The noise of an
    increment has a variance proportional to its size (a standard deviation
    proportional to its square root): split a drive into more, smaller
    increments and the total error stays the same.
    """
    dx, dy = after[0] - before[0], after[1] - before[1]
    c, s = math.cos(before[2]), math.sin(before[2])
    forward = c * dx + s * dy
    side = -s * dx + c * dy
    turn = float(wrap_angle(after[2] - before[2]))
    if rng is not None:
        dist, ang = abs(forward), abs(turn)
        forward += float(rng.normal(0.0, spec.distance_noise * math.sqrt(dist)))
        turn += float(rng.normal(0.0, spec.turn_noise * math.sqrt(ang))) + float(rng.normal(0.0, spec.drift * math.sqrt(dist)))
    ox, oy, oth = odo
    co, so = math.cos(oth), math.sin(oth)
    return ox + co * forward - so * side, oy + so * forward + co * side, float(wrap_angle(oth + turn))


def measured_velocities(before: tuple[float, float, float], after: tuple[float, float, float], dt: float) -> tuple[float, float]:
    """Forward speed and turn rate as the encoders measure them: the odometry increment over ``dt``.

    A real base knows its velocities only from its (noisy) wheel encoders,
    so these carry the same errors as the odometry pose, never the truth.
    """
    dx, dy = after[0] - before[0], after[1] - before[1]
    forward = math.cos(before[2]) * dx + math.sin(before[2]) * dy
    return forward / dt, float(wrap_angle(after[2] - before[2])) / dt


class Base(Module):
    """Drives the world's robot from bus commands and publishes odometry."""

    def __init__(self, sim: Simulation, world: World, spec: OdometrySpec | None = None, *, name: str = "base") -> None:
        super().__init__(sim, name, host="robot")
        self.world = world
        self.spec = spec or OdometrySpec()
        self.last_cmd = -math.inf
        self.odometry = (0.0, 0.0, 0.0)  # starts at the origin, as a real base does
        self._last_true = world.robot.pose
        self.bumpers = BumperSensor(world)  # the bumper rings, read with the odometry (robot.hardware.bumpers)
        self.bus.subscribe(BASE_CMD, self._on_cmd)

    def _on_cmd(self, msg: Message) -> None:
        v = float(msg.xml.get("v", "0"))
        w = float(msg.xml.get("w", "0"))
        if not (math.isfinite(v) and math.isfinite(w)):
            return
        self.world.robot.command(v, w)
        self.last_cmd = self.now

    async def run(self) -> None:
        period = 1.0 / self.spec.rate
        while True:
            self.beat()
            if self.now - self.last_cmd > self.spec.watchdog:
                self.world.robot.command(0.0, 0.0)
            true = self.world.robot.pose
            before = self.odometry
            self.odometry = odometry_step(self.odometry, self._last_true, true, self.spec, self.rng)
            self._last_true = true
            x, y, th = self.odometry
            v, w = measured_velocities(before, self.odometry, period)
            rb = self.world.robot
            self.bus.publish(
                ODOMETRY,
                etree.Element("odometry", x=f"{x:.5f}", y=f"{y:.5f}", theta=f"{th:.5f}", v=f"{v:.4f}", w=f"{w:.4f}", stalled="true" if rb.cmd_v and abs(v) < 1e-3 else "false"),
                transfer=True,  # a fresh element, not kept: no copy
            )
            before_bump = self.bumpers.pressed
            if self.bumpers.read() != before_bump or self.bumpers.pressed:
                # on every change, and with every odometry packet while a ring stays pressed (as the PeopleBot's
                # SIP does): a module restarted or subscribed late, or a message dropped, still hears the press
                self.bus.publish(BUMPERS, bumper_element(self.now, self.bumpers.pressed), transfer=True)
            await asyncio.sleep(period)
