"""Put a scenario's people and sound sources on a stage.

``install(stage)`` is what :class:`homesim.tour.stage.Stage` calls: the run
package (:mod:`homesim.tour.runner`'s ``ACTORS``) imports it and hands it to
the stage, which names no actor; the kernel never imports ``humans``. Each person
and each radio runs its script as one top-level task, named
``human:<name>`` or ``<kind>:<name>``, so a failing script fails the run.

A person's traits are drawn from her profile with the run's generator for
her, ``sim.rng("human:<name>")`` (same seed, same person; another person's
draws do not shift hers); what she chooses as she goes (phrasings, looking
away, pointing errors) comes from one generator per act of hers,
``sim.rng("human:<name>:say:<line>")`` (``look:``, ``point:``), so a reaction
that fires or a say added to her script does not shift her other acts' draws.
"""

from __future__ import annotations

from typing import Any

from .person import Person
from .profiles import traits_for
from .script import Actor, Radio


def _streams(sim: Any, name: str):  # type: ignore[no-untyped-def]
    return lambda key: sim.rng(f"human:{name}:{key}")


def install(stage: Any) -> dict[str, Actor]:
    """Create and start an actor for every human and sound source of the stage's scenario."""
    actors: dict[str, Actor] = {}
    for spec in stage.scenario.humans:
        traits = traits_for(spec, stage.sim.rng(f"human:{spec.name}") if spec.profile is not None else None)
        actors[spec.name] = Person(stage.world, spec, traits, stage.sim.rng(f"human:{spec.name}:acts"), streams=_streams(stage.sim, spec.name))
        stage.sim.spawn(actors[spec.name].run(), name=f"human:{spec.name}")
        # making way when the robot asks to pass: a task of its own, so her script's timing is untouched
        stage.sim.spawn(actors[spec.name].courtesy(), name=f"human:{spec.name}:courtesy")
    for src in stage.scenario.sources:
        actors[src.name] = Radio(stage.world, src)
        stage.sim.spawn(actors[src.name].run(), name=f"{src.kind}:{src.name}")
    stage.actors.update(actors)
    return actors
