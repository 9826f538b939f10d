"""A stage: one scenario's world, people and robot hardware on a Simulation.

:class:`Stage` builds the :class:`~homesim.world.world.World`, steps it in
virtual time as a top-level task (``world``), records ground truth, and
installs the actors: by default the scripted people and sound sources
(``humans.install``) and the PeopleBot hardware models
(``robot.hardware.install``). Actor modules are named, not imported, here:
the kernel never imports ``robot`` or ``humans`` (the same pattern as the
CLI's list of subcommand modules); each exposes ``install(stage)``.

The stage also keeps every message published under ``/robot/`` (through a
bus interceptor, which observes and never modifies) so expectations can be
checked on what the sensors really reported. Robot modules get the bus
only; the stage, the world and the ground truth stay out of their reach.
"""

from __future__ import annotations

import asyncio
import importlib
from collections.abc import Sequence
from typing import Any

from ..bus import SEND, Observation
from ..message import PUBLISH, Message
from ..scenario.expect import Verdict, evaluate
from ..scenario.model import Scenario
from ..sim import Simulation
from .truth import GroundTruth
from .world import World

#: Modules whose ``install(stage)`` puts actors on the stage, in this order.
DEFAULT_ACTORS: tuple[str, ...] = ("humans.install", "robot.hardware.install")


class Stage:
    """The world of ``scenario`` running on ``sim`` (see the module docstring)."""

    def __init__(
        self,
        sim: Simulation,
        scenario: Scenario,
        *,
        actors: Sequence[str] = DEFAULT_ACTORS,
        truth_every: int = 5,
        record_prefix: str = "/robot/",
    ) -> None:
        self.sim = sim
        self.scenario = scenario
        self.world = World(scenario)
        self.truth = GroundTruth(self.world, every=truth_every)
        self.actors: dict[str, Any] = {}
        self.hardware: dict[str, Any] = {}
        self.messages: list[Message] = []
        self._prefix = record_prefix
        sim.bus.add_interceptor(self._observe)
        sim.spawn(self._step_world(), name="world")
        for name in actors:
            importlib.import_module(name).install(self)

    def _observe(self, obs: Observation) -> None:
        m = obs.message
        if obs.event == SEND and m.kind == PUBLISH and m.channel.startswith(self._prefix):
            self.messages.append(m)

    async def _step_world(self) -> None:
        """Step physics every ``dt`` of virtual time, aligned to the step count."""
        loop = asyncio.get_running_loop()
        world = self.world
        start = loop.time()
        while True:
            await asyncio.sleep(max(start + (world.steps + 1) * world.dt - loop.time(), 0.0))
            world.step()

    def run(self, until: float | None = None) -> None:
        """Run the simulation to ``until`` (default: the scenario's duration)."""
        self.sim.run(until=self.scenario.duration if until is None else until)

    def verdicts(self) -> list[Verdict]:
        """Check the scenario's expectations against truth and recorded sensor messages."""
        return evaluate(self.scenario, self.world, self.truth, self.messages)
