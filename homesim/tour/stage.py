"""A stage: one scenario's world, people and robot hardware on a Simulation.

:class:`Stage` builds the :class:`~homesim.world.world.World`, steps it in
virtual time as a top-level task (``world``), and installs the actors it is
given: functions ``install(stage)`` called in order, each putting its actors
on the stage. The stage knows none of them, has no default and loads nothing
by name: whoever composes a run hands them in. :mod:`homesim.tour.runner`,
the composition root, imports the people's and the PeopleBot hardware's and
passes them (its ``ACTORS``); a test hands in only the ones it needs (an
empty tuple: the world alone).

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
from collections.abc import Callable, Mapping, Sequence
from typing import Any

from ..message import Message
from ..observe import Dispatcher
from .expect import Expectations, Verdict
from ..scenario.model import Scenario
from ..sim import Simulation
from ..world.truth import GroundTruth
from ..world.world import World

#: What puts actors on a stage: ``install(stage)`` (it may also return what it made).
Install = Callable[["Stage"], Any]


class Stage:
    """The world of ``scenario`` running on ``sim`` (see the module docstring)."""

    def __init__(
        self,
        sim: Simulation,
        scenario: Scenario,
        *,
        actors: Sequence[Install],
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
        for install in actors:
            if not callable(install):
                raise TypeError(f"Stage: an actor is an install(stage) function, not {install!r}")
            install(self)

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
