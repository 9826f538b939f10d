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

from .module import PersonAttention


def install(run: Any) -> dict[str, Module]:
    """Create and start ``person_attention`` on ``run.sim`` (its channels typed first)."""
    module = PersonAttention(run.sim)
    module.start()
    return {"person_attention": module}
