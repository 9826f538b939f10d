"""BIRON's person attention system (participant ``person_attention``).

Modules: :mod:`.legs` (leg detector on the raw scan), :mod:`.tracker`
(anchoring: Kalman tracks, gating, GNN, birth and death), :mod:`.cues`
(speaking/facing from sound directions and frontal faces, with hysteresis),
:mod:`.selection` (categories, ties, inhibition of return), :mod:`.fsm`
(the attention state machine), :mod:`.module` (the bus module).
"""

from __future__ import annotations

from typing import Any

from homesim.module import Module

from robot.partner_search import robot_top_speed

from .module import AttentionParams, PersonAttention


def install(run: Any) -> dict[str, Module]:
    """Create and start ``person_attention`` on ``run.sim`` (its channels typed first), its leaving rule
    told the robot's top speed from the run's configuration (``run.config``: what the robot knows of
    itself), as the follower's search is (:mod:`robot.partner_search`)."""
    top = robot_top_speed(getattr(run, "config", {}) or {})
    module = PersonAttention(run.sim, params=AttentionParams(robot_top_speed=top))
    module.start()
    return {"person_attention": module}
