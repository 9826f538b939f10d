"""BIRON's dialog control: XML-defined sub-dialogs, speech output, events to the execution supervisor."""

from __future__ import annotations

from typing import Any

from homesim.module import Module

from .module import Dialog


def install(run: Any) -> dict[str, Module]:
    """The ``dialog`` module on ``run.sim``; options from ``run.config["dialog"]`` (plain values)."""
    config = getattr(run, "config", None) or {}
    options = dict(config.get("dialog", {})) if isinstance(config, dict) else {}
    return {"dialog": Dialog(run.sim, **options)}
