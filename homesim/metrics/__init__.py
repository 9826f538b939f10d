"""Streaming metrics: scores of a run against ground truth, computed as it goes.

A metric is an :class:`Observer`. The runner (:mod:`homesim.runner`)
constructs every registered observer with the run, routes to it the bus
messages sent on the channels it names (``channels``: prefixes, through the
run's one :class:`~homesim.observe.Dispatcher`) and, every ``step_every``
world steps, the world itself (ground truth); at the end ``summary()``
becomes ``metrics[<name>]`` of the run summary (JSON: numbers, strings,
lists, dicts). Observers keep running sums, never every message: a run's
memory must not grow with its length.

Registering a metric: put a module in this package that defines
``OBSERVERS = {"name": ObserverClass}``. :func:`registry` finds every such
module (in name order), so adding a metric touches no shared file. Metrics
are the only robot-related code that may read ground truth (the world, the
scenario); they never publish on the bus.

What an observer may use of ``run`` (see :class:`homesim.runner.Run`):
``run.sim`` (time: ``run.sim.now``), ``run.world`` (ground truth: people,
robot pose, sound field, contacts), ``run.scenario``, ``run.config`` and
``run.es_state`` (the supervisor's current state as seen on its log).
"""

from __future__ import annotations

import importlib
import pkgutil
from typing import Any


class Observer:
    """Base class of a streaming metric (see the module docstring)."""

    #: Channel prefixes whose sent messages :meth:`on_message` sees.
    channels: tuple[str, ...] = ()
    #: Call :meth:`on_step` every this many world steps (0: never).
    step_every: int = 0

    def __init__(self, run: Any) -> None:
        self.run = run

    def on_message(self, msg: Any) -> None:
        """A message was sent on one of ``channels`` (observe only)."""

    def on_step(self, world: Any) -> None:
        """The world has stepped (ground truth); called every ``step_every`` steps."""

    def summary(self) -> dict[str, Any]:
        """The metric's values at the end of the run (JSON-serialisable)."""
        return {}


def registry() -> dict[str, type[Observer]]:
    """Every metric defined by a module of this package (``OBSERVERS``), by name."""
    found: dict[str, type[Observer]] = {}
    for info in sorted(pkgutil.iter_modules(__path__), key=lambda i: i.name):
        module = importlib.import_module(f"{__name__}.{info.name}")
        for name, cls in getattr(module, "OBSERVERS", {}).items():
            if name in found:
                raise ValueError(f"metric {name!r} is defined twice ({found[name].__module__} and {module.__name__})")
            found[name] = cls
    return found


def install(run: Any, names: list[str] | tuple[str, ...] | None = None) -> dict[str, Observer]:
    """Construct the named metrics (default: all) on ``run``, wired to its dispatcher and world."""
    known = registry()
    wanted = sorted(known) if names is None else list(names)
    unknown = [n for n in wanted if n not in known]
    if unknown:
        raise ValueError(f"unknown metric(s) {', '.join(unknown)}; known: {', '.join(sorted(known))}")
    observers = {name: known[name](run) for name in wanted}
    for obs in observers.values():
        if obs.channels:
            run.dispatcher.add(obs.channels, obs.on_message)
    stepped = [(o.step_every, o.on_step) for o in observers.values() if o.step_every > 0]
    if stepped:
        def step(world: Any) -> None:
            n = world.steps
            for every, fn in stepped:
                if n % every == 0:
                    fn(world)

        run.world.add_listener(step)
    return observers
