"""Module: a named bus participant with a main loop and heartbeats.

Every simulated component (a sensor, the supervisor, the dialog) is a
:class:`Module`. It sees only its bus participant, its own seeded random
generator and asyncio time: modules never import or call each other. The
main loop is :meth:`Module.run`; call :meth:`Module.beat` in it so that a
hung loop stops beating and the heartbeat monitor notices.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .bus import Participant
from .heartbeat import Heartbeat

if TYPE_CHECKING:
    from .sim import Simulation


class Module:
    """Base class of simulated modules; subclasses implement :meth:`run`."""

    def __init__(self, sim: Simulation, name: str, *, host: str = "robot", heartbeat: float | None = 0.5) -> None:
        self.sim = sim
        self.name = name
        self.bus: Participant = sim.bus.participant(name, host=host)
        self.rng: np.random.Generator = sim.rng(name)
        self.heartbeat = Heartbeat(self.bus, heartbeat) if heartbeat else None
        self.task = None
        sim._register_module(self)

    async def run(self) -> None:
        """The module's main loop (subclasses override)."""
        raise NotImplementedError(f"{type(self).__name__} must implement run()")

    def beat(self) -> None:
        """Send a heartbeat if one is due (call this from the main loop)."""
        if self.heartbeat is not None:
            self.heartbeat.beat()

    def start(self) -> None:
        """Start the main loop as a top-level task (its failure fails the run)."""
        if self.task is None:
            self.task = self.sim.spawn(self.run(), name=self.name)

    @property
    def now(self) -> float:
        """Virtual time in seconds."""
        return self.sim.now
