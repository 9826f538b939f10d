"""Put BIRON's modules (everything above the hardware) on a run.

The runner (the composition root) calls :func:`install` after the hardware and
the supervisor. Each subsystem package listed in :data:`SUBSYSTEMS` exposes
``install(run) -> dict[str, Module]``; ``run`` gives ``run.sim`` (the
Simulation) and ``run.config`` (the scenario's robot options as plain values),
never the world: robot modules see only the bus (docs/robot-contract.md).
Subsystems are named, not imported, so a run can leave one out.
"""

from __future__ import annotations

import importlib
from collections.abc import Sequence
from typing import Any

from homesim.module import Module

#: Subsystem packages, installed in this order.
SUBSYSTEMS: tuple[str, ...] = (
    "robot.localisation",
    "robot.attention",
    "robot.knowledge",
    "robot.objects",
    "robot.speech",
    "robot.dialog",
    "robot.watchdog",
    "robot.navigation",
    "robot.navigation.player",
)


def install(run: Any, subsystems: Sequence[str] = SUBSYSTEMS) -> dict[str, Module]:
    """Install every subsystem in ``subsystems``; refuse two modules of the same name.

    Only names of :data:`SUBSYSTEMS` are accepted (refused before anything is
    imported): the names may come from a trace header, which must never run code.
    """
    unknown = [name for name in subsystems if name not in SUBSYSTEMS]
    if unknown:
        raise ValueError(f"unknown subsystem(s) {', '.join(map(repr, unknown))}; known: {', '.join(SUBSYSTEMS)}")
    modules: dict[str, Module] = {}
    for name in subsystems:
        for key, module in importlib.import_module(name).install(run).items():
            if key in modules:
                raise ValueError(f"{name}: module {key!r} is already installed")
            modules[key] = module
    return modules
