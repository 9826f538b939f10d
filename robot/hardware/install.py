"""Put the PeopleBot's hardware models on a stage.

``install(stage)`` is what :class:`homesim.tour.stage.Stage` calls: the run
package (:mod:`homesim.tour.runner`'s ``ACTORS``) imports it and hands it to
the stage, which names no actor; the kernel never imports ``robot``. Rates and the object
confusion come from the scenario's ``<robot>`` element. Every channel the
hardware publishes on or takes commands from is typed first
(:func:`robot.hardware.channels.declare_channels`), so the bus validates each
message against its XSD in ``robot/schemas/hardware/`` when it is sent.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

from homesim.module import Module

from .microphones_module import Microphones
from .base import Base, OdometrySpec
from .camera import CameraSpec
from .camera_module import Camera
from .channels import declare_channels
from .laser import Laser, LaserSpec
from .map_server import MapServer
from .sonar import Sonar, SonarSpec
from .microphones import MicSpec
from .speaker import Display, Speaker


def install(stage: Any) -> dict[str, Module]:
    """Type the hardware channels, then create the laser, sonar rings, camera, microphones, base, speaker, display and map server modules."""
    r = stage.scenario.robot
    sim, world = stage.sim, stage.world
    declare_channels(sim.bus)
    modules: dict[str, Module] = {
        "laser": Laser(sim, world, replace(LaserSpec(), rate=r.laser_rate)),
        "sonar": Sonar(sim, world, SonarSpec()),
        "camera": Camera(sim, world, replace(CameraSpec(), rate=r.camera_rate), confusion=r.object_confusion),
        "microphones": Microphones(sim, world, replace(MicSpec(), rate=r.audio_rate)),
        "base": Base(sim, world, replace(OdometrySpec(), rate=r.odometry_rate)),
        "speaker": Speaker(sim, world),
        "display": Display(sim, world),
        "map_server": MapServer(sim, stage.scenario),
    }
    for m in modules.values():
        m.start()
    stage.hardware.update(modules)
    return modules
