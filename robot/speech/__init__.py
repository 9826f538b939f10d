"""BIRON's speech understanding: recognised words -> frame XML (semantic grammar, lark LALR)."""

from __future__ import annotations

from typing import Any

from homesim.module import Module

from .module import SpeechUnderstanding


def install(run: Any) -> dict[str, Module]:
    """The ``understanding`` module on ``run.sim``; options from ``run.config["understanding"]``."""
    config = getattr(run, "config", None) or {}
    options = dict(config.get("understanding", {})) if isinstance(config, dict) else {}
    return {"understanding": SpeechUnderstanding(run.sim, **options)}
