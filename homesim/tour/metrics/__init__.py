"""Streaming metrics: scores of a run against ground truth, computed as it goes.

A metric is an :class:`Observer`. The runner (:mod:`homesim.tour.runner`)
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

What an observer may use of ``run`` (see :class:`homesim.tour.runner.Run`):
``run.sim`` (time: ``run.sim.now``), ``run.world`` (ground truth: people,
robot pose, sound field, contacts), ``run.scenario``, ``run.config`` and
``run.es_state`` (the supervisor's current state as seen on its log).
"""

from __future__ import annotations

import importlib
import pkgutil

from ...scoring import Observer, install, register


def registry() -> dict[str, type[Observer]]:
    """Every metric defined by a module of this package (``OBSERVERS``), by name."""
    found: dict[str, type[Observer]] = {}
    for info in sorted(pkgutil.iter_modules(__path__), key=lambda i: i.name):
        module = importlib.import_module(f"{__name__}.{info.name}")
        for name, cls in getattr(module, "OBSERVERS", {}).items():
            if name in found:
                raise ValueError(f"metric {name!r} is defined twice ({found[name].__module__} and {module.__name__})")
            found[name] = cls
    for name, cls in found.items():
        register(name, cls)
    return found


registry()

__all__ = ["Observer", "install", "registry"]
