"""A stage: one scenario's world, people and robot hardware on a Simulation.

:class:`Stage` builds the :class:`~homesim.world.world.World`, steps it in
virtual time as a top-level task (``world``), and installs the actors: by
default the scripted people and sound sources (``humans.install``) and the
PeopleBot hardware models (``robot.hardware.install``). Actor modules are
named, not imported, here: the kernel never imports ``robot`` or ``humans``
(the same pattern as the CLI's list of subcommand modules); each exposes
``install(stage)``. A whole robot run is put together by
:mod:`homesim.tour.runner`, which builds a stage first.

The scenario's expectations are checked as the run goes
(:class:`~homesim.tour.expect.Expectations`, through one bus
:class:`~homesim.observe.Dispatcher`): nothing is kept for the end, so a
run's memory does not grow with its length. For tests and notebooks,
``keep_messages=True`` keeps every ``/robot/`` message in ``stage.messages``
and ``truth_every=n`` records a ground-truth frame every n steps
(``stage.truth``); a run made by the runner does neither. Robot modules get
the bus only; the stage, the world and the ground truth stay out of their
reach.
"""

from __future__ import annotations

import asyncio
import importlib
from collections.abc import Mapping, Sequence
from typing import Any

from ..message import Message
from ..observe import Dispatcher
from .expect import Expectations, Verdict
from ..scenario.model import Scenario
from ..sim import Simulation
from ..world.truth import GroundTruth
from ..world.world import World

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
        truth_every: int | None = 5,
        keep_messages: bool = False,
        record_prefix: str = "/robot/",
    ) -> None:
        self.sim = sim
        self.scenario = scenario
        self.world = World(scenario)
        self.truth: GroundTruth | None = GroundTruth(self.world, every=truth_every) if truth_every else None
        self.actors: dict[str, Any] = {}
        self.hardware: dict[str, Any] = {}
        self.dispatcher = Dispatcher(sim.bus)
        self.messages: list[Message] = []
        if keep_messages:
            self.dispatcher.add(record_prefix, self.messages.append)
        self.expectations = Expectations(scenario, self.world, self.dispatcher)
        sim.spawn(self._step_world(), name="world")
        for name in actors:
            importlib.import_module(name).install(self)

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

    def verdicts(self, context: Mapping[str, Any] | None = None) -> list[Verdict]:
        """The scenario's expectations as checked so far (``context``: ``metrics``, ``knowledge``)."""
        return self.expectations.verdicts(self.sim.now, context)
