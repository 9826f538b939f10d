"""Streaming metrics: the observer base class and the registry a run package fills.

A metric is an :class:`Observer`: constructed with the run, it sees the bus
messages sent on the channels it names (``channels``: prefixes, through the
run's one :class:`~homesim.observe.Dispatcher`) and, every ``step_every``
world steps, the world itself (ground truth); at the end ``summary()``
becomes ``metrics[<name>]`` of the run summary. Observers keep running
sums, never every message: a run's memory must not grow with its length.
The run package registers its metrics (:func:`register`); :func:`install`
wires the named ones to a run (``run.dispatcher``, ``run.world``).
"""

from __future__ import annotations

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


_REGISTRY: dict[str, type[Observer]] = {}


def register(name: str, cls: type[Observer]) -> None:
    """Add a metric; a name registered twice by two different classes is an error."""
    known = _REGISTRY.get(name)
    if known is not None and known is not cls:
        raise ValueError(f"metric {name!r} is defined twice ({known.__module__} and {cls.__module__})")
    _REGISTRY[name] = cls


def registry() -> dict[str, type[Observer]]:
    """Every registered metric, by name."""
    return dict(_REGISTRY)


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
