"""The watchdog: BIRON's heartbeat monitor and the corrective action, a restart policy per module.

Every module's main loop beats (``/system/heartbeat/<name>``). The watchdog
runs the kernel's :class:`~homesim.heartbeat.HeartbeatMonitor`: a module that
missed ``misses`` beats has *failed perceptibly*, and ``module_failed`` goes
out on ``/system/health``, where the execution supervisor turns it into an
event (TechnicalFailure: the robot stops; the dialog gets ``technical_failure``).

The corrective action is the watchdog's: it is the robot's process manager.
A module may be restarted when it can be rebuilt from its configuration
(it has ``respawn() -> Module``, as the navigation modules and the player
do) and it has restarts left (``max_restarts`` per module per run, default
:data:`MAX_RESTARTS`; ``policy`` overrides it by name, 0 = never). Then
``module_failed`` says ``restarting="true"``, and ``restart_delay`` later
the old instance is taken off the run (its participant leaves the bus) and a
fresh one is started; its first beat makes the monitor publish
``module_recovered``, and the supervisor goes back to LookingAround: the
tour goes on. Otherwise ``restarting="false"``: the module stays down, the
supervisor stays in TechnicalFailure and the dialog asks the user to call
technical support. Hardware (laser, base, ...) is never restarted this way.

The watchdog sees the run's modules through ``run.sim`` (as a process
manager sees processes), never the world.
"""

from __future__ import annotations

import asyncio
from typing import Any

from lxml import etree

from homesim.heartbeat import HeartbeatMonitor
from homesim.module import Module

#: Restarts allowed per module per run unless the policy says otherwise.
MAX_RESTARTS = 2


class RestartingMonitor(HeartbeatMonitor):
    """A heartbeat monitor that asks ``decide(name)`` whether a silent module will be restarted."""

    def __init__(self, participant: Any, decide: Any, **kw: Any) -> None:
        super().__init__(participant, **kw)
        self.decide = decide

    def failure(self, name: str) -> etree._Element:
        """The kernel's ``module_failed``, with ``restarting`` as ``decide(name)`` says."""
        el = super().failure(name)
        el.set("restarting", "true" if self.decide(name) else "false")
        return el


class Watchdog(Module):
    """Monitors heartbeats and restarts failed modules by policy (see the module docstring)."""

    #: The runner starts no heartbeat monitor of its own when a module says this.
    monitors_heartbeats = True

    def __init__(self, sim: Any, *, name: str = "watchdog", misses: int = 3, period: float = 0.1,
                 restart_delay: float = 1.0, max_restarts: int = MAX_RESTARTS,
                 policy: dict[str, int] | None = None) -> None:
        super().__init__(sim, name)
        self.restart_delay = restart_delay
        self.max_restarts = max_restarts
        self.policy = dict(policy or {})
        self.restarts: dict[str, int] = {}
        self.period = period
        self.monitor = RestartingMonitor(self.bus, self._decide, misses=misses, period=period)

    def restartable(self, name: str) -> bool:
        """Whether ``name`` can and may be restarted now."""
        mod = self.sim.modules.get(name)
        limit = self.policy.get(name, self.max_restarts)
        return mod is not None and hasattr(mod, "respawn") and self.restarts.get(name, 0) < limit

    def _decide(self, name: str) -> bool:
        if name == self.name or not self.restartable(name):
            return False
        self.restarts[name] = self.restarts.get(name, 0) + 1
        self.sim.call_at(self.now + self.restart_delay, self._restart, name)
        return True

    def _restart(self, name: str) -> None:
        if self.bus.closed or self.bus.hung:
            return  # the watchdog itself is down: nobody restarts anything
        old = self.sim.remove_module(name)
        fresh = old.respawn()
        fresh.start()

    async def run(self) -> None:
        while True:
            self.beat()
            self.monitor.check()
            await asyncio.sleep(self.period)


def install(run: Any) -> dict[str, Module]:
    """The watchdog with the default policy (every module with ``respawn``: up to 2 restarts)."""
    dog = Watchdog(run.sim)
    dog.start()
    return {"watchdog": dog}
