"""Simulation: the one owner of virtual time, the bus and the random streams.

A run is built around one :class:`Simulation`: it owns the virtual-time
loop (:mod:`homesim.vloop`), the bus (:mod:`homesim.bus`) with its network,
one seeded numpy Generator per named stream, the registered modules and
fault injection. Same seed + same construction = the same run, to the
nanosecond and the byte.
"""

from __future__ import annotations

import asyncio
import hashlib
import os
from pathlib import Path
from collections.abc import Awaitable, Callable, Coroutine
from typing import Any, TypeVar

import numpy as np
from lxml import etree

from .bus import VALIDATE_ALL, VALIDATE_EDGES, Bus
from .errors import HomesimError
from .network import Network
from .realtime import RealtimePacer
from .trace import FileTrace, MemoryTrace, TraceRecorder
from .vloop import VirtualEventLoop, to_ns

T = TypeVar("T")

FAULT_CHANNEL = "/system/faults"


def stream_key(name: str) -> tuple[int, ...]:
    """A random stream's spawn key: 128 bits of sha256(name), so names never collide in practice."""
    digest = hashlib.sha256(name.encode("utf-8")).digest()
    return tuple(int.from_bytes(digest[i : i + 4], "little") for i in range(0, 16, 4))


class Simulation:
    """Virtual time, bus and seeded randomness for one run.

    ``realtime`` (a scale factor) paces the run against the wall clock for
    live demos; the run's results are unchanged. ``strict`` makes the bus
    validate every message on a typed channel (the test suite's and
    ``--strict``'s setting); by default it trusts the elements the modules
    build and validates text from outside (see :mod:`homesim.bus`).
    """

    def __init__(self, *, seed: int = 0, scenario: str = "", realtime: float | None = None, strict: bool = False) -> None:
        if not isinstance(seed, (int, np.integer)) or seed < 0:
            raise HomesimError(f"seed must be a non-negative integer, got {seed!r}")
        self.seed = int(seed)
        self.scenario = scenario
        self._rngs: dict[str, np.random.Generator] = {}
        self.loop = VirtualEventLoop(pacer=RealtimePacer(realtime) if realtime else None)
        self.network = Network(self.rng("homesim.network"))
        self.bus = Bus(self.loop, network=self.network, validation=VALIDATE_ALL if strict else VALIDATE_EDGES)
        self.bus.on_flood = self._flooded
        self.modules: dict[str, Any] = {}
        self._system = self.bus.participant("simulator", host="simulator")
        system_xsd = Path(__file__).with_name("schemas") / "system.xsd"
        self.bus.declare_channel(FAULT_CHANNEL, system_xsd)
        # Every heartbeat channel is typed from the start: a participant cannot
        # put an untyped "heartbeat" where the monitor listens.
        self.bus.declare_channel("/system/heartbeat/**", system_xsd)
        self.bus.declare_channel("/system/health", system_xsd)
        self.traces: list[TraceRecorder] = []

    # ------------------------------------------------------------ randomness
    def rng(self, name: str) -> np.random.Generator:
        """The generator of stream ``name``: stable per (seed, name), one object per name."""
        gen = self._rngs.get(name)
        if gen is None:
            gen = np.random.Generator(np.random.PCG64(np.random.SeedSequence(self.seed, spawn_key=stream_key(name))))
            self._rngs[name] = gen
        return gen

    # ------------------------------------------------------------------ time
    @property
    def now(self) -> float:
        """Virtual time in seconds."""
        return self.loop.now

    @property
    def now_ns(self) -> int:
        """Virtual time in integer nanoseconds."""
        return self.loop.now_ns

    def spawn(self, coro: Coroutine[Any, Any, T], *, name: str) -> Any:
        """Start a top-level task; an exception in it fails the run."""
        return self.loop.spawn(coro, name=name)

    def step(self) -> bool:
        """Run one scheduling round (see :meth:`VirtualEventLoop.step`)."""
        return self.loop.step()

    def peek(self) -> float:
        """Time of the next round; ``inf`` when nothing is scheduled."""
        return self.loop.peek()

    def run(self, until: float | None = None) -> None:
        """Run until virtual time ``until`` (exclusive, as in SimPy)."""
        self.loop.run(until)

    def run_until(self, predicate: Callable[[], bool], *, timeout: float | None = None) -> bool:
        """Step until ``predicate()`` holds or ``timeout`` virtual seconds pass."""
        return self.loop.run_until(predicate, timeout=timeout)

    def run_until_complete(self, aw: Awaitable[T]) -> T:
        """Run until the awaitable is done and return its result."""
        return self.loop.run_until_complete(aw)

    def call_at(self, t: float, callback: Callable[..., Any], *args: Any) -> Any:
        """Schedule a plain callback at virtual time ``t`` (seconds)."""
        return self.loop.call_at_ns(to_ns(t), callback, *args)

    # ----------------------------------------------------------------- trace
    def record_trace(self, path: str | os.PathLike[str] | None = None) -> TraceRecorder:
        """Record the bus to a JSON Lines file, or to memory when ``path`` is None."""
        rec: TraceRecorder
        if path is None:
            rec = MemoryTrace(self.bus, scenario=self.scenario, seed=self.seed)
        else:
            rec = FileTrace(self.bus, path, scenario=self.scenario, seed=self.seed)
        self.traces.append(rec)
        return rec

    # --------------------------------------------------------------- modules
    def _register_module(self, module: Any) -> None:
        if module.name in self.modules:
            raise HomesimError(f"a module named {module.name!r} is already registered")
        self.modules[module.name] = module

    def start(self) -> None:
        """Start every registered module that is not running yet (in registration order)."""
        for module in list(self.modules.values()):
            module.start()

    # ---------------------------------------------------------------- faults
    def inject_fault(self, module: str, kind: str, *, at: float | None = None) -> None:
        """Crash or hang ``module`` now or at virtual time ``at``.

        ``crash``: its main loop is cancelled and it leaves the bus (calls to
        it fail, messages to it are dropped). ``hang``: its main loop is
        cancelled but it stays registered and swallows what it receives (a
        stuck process: calls to it time out). Both stop its heartbeats. The
        fault is announced on ``/system/faults`` so it shows in the trace.
        """
        if kind not in ("crash", "hang"):
            raise HomesimError(f"unknown fault {kind!r}: use 'crash' or 'hang'")
        if module not in self.modules:
            raise HomesimError(f"cannot inject a fault into unknown module {module!r}; known: {sorted(self.modules)}")
        if at is None:
            self._apply_fault(module, kind)
        else:
            self.call_at(at, self._apply_fault, module, kind)

    def _flooded(self, participant: Any) -> None:
        """The bus's rate guard tripped: a module sending far above any sane rate fails as a crashed one.

        Its crash is announced (``reason="flood"``), its main loop cancelled and it leaves the bus;
        the send that tripped the guard ends the module's task (``CancelledError``), as a crash does.
        Another participant (not a module) gets the bus's :class:`BusError`.
        """
        mod = self.modules.get(participant.name)
        if mod is None or mod.bus is not participant:
            return
        self._apply_fault(participant.name, "crash", reason="flood")
        raise asyncio.CancelledError(f"{participant.name} crashed: it flooded the bus")

    def _apply_fault(self, name: str, kind: str, *, reason: str | None = None) -> None:
        mod = self.modules[name]
        fault = etree.Element("fault", module=name, kind=kind)
        if reason is not None:
            fault.set("reason", reason)
        self._system.publish(FAULT_CHANNEL, fault)
        if mod.task is not None and not mod.task.done():
            mod.task.cancel()
        if kind == "crash":
            mod.bus.close()
        else:
            mod.bus.hung = True

    def remove_module(self, name: str) -> Any:
        """Take a (failed) module off the run so a fresh instance may take its name: its main loop
        is cancelled, its participant leaves the bus, and it is unregistered. Returns the old
        module. This is what a process manager does before restarting a process; raises
        :class:`HomesimError` for an unknown name."""
        mod = self.modules.get(name)
        if mod is None:
            raise HomesimError(f"cannot remove unknown module {name!r}; known: {sorted(self.modules)}")
        if mod.task is not None and not mod.task.done():
            mod.task.cancel()
        mod.bus.close()
        del self.modules[name]
        return mod

    def close(self) -> None:
        """Flush traces and close the loop (cancelling tasks still waiting)."""
        for rec in self.traces:
            rec.close()
        self.traces.clear()
        self.loop.close()

    def __enter__(self) -> Simulation:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
