"""Moving with the user: the follower, the planner and the sequencer (docs/robot-contract.md).

``install(run)`` creates and starts the three modules with the run's speed
limits (``run.config``: ``max_speed``, ``max_turn``). The local controller
(:mod:`robot.navigation.local`) and the grid planner (:mod:`robot.navigation.grid`)
are pure code the modules and the player share.
"""

from __future__ import annotations

from typing import Any

from homesim.module import Module

from .config import limits_from_config
from .follow import Follower
from .planner import Planner
from .sequencer import Sequencer


def install(run: Any) -> dict[str, Module]:
    """Follower, planner and sequencer on ``run.sim``, started."""
    limits = limits_from_config(getattr(run, "config", {}) or {})
    mods: dict[str, Module] = {
        "follower": Follower(run.sim, limits=limits),
        "planner": Planner(run.sim, limits=limits),
        "sequencer": Sequencer(run.sim),
    }
    for m in mods.values():
        m.start()
    return mods
