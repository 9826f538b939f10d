"""BIRON's dialog control: XML-defined sub-dialogs, speech output, events to the execution supervisor."""

from __future__ import annotations

from typing import Any

from homesim.module import Module

from .module import Dialog


def install(run: Any) -> dict[str, Module]:
    """The ``dialog`` module on ``run.sim``; numeric options ``dialog.<name>`` from the robot options."""
    return {"dialog": Dialog(run.sim, **options_for(run, "dialog"))}


def options_for(run: Any, module: str) -> dict[str, float]:
    """Numeric options ``<module>.<name>`` from the scenario's robot options (``run.config.options``)."""
    config = getattr(run, "config", None)
    raw = getattr(config, "options", None) or (config if isinstance(config, dict) else {})
    prefix = module + "."
    return {k[len(prefix):]: float(v) for k, v in raw.items() if isinstance(k, str) and k.startswith(prefix)}
