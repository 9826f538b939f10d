"""BIRON's knowledge: the scene model (KB-manager) over the object and place bases.

``install(run)`` puts the ``scene_model`` participant on the run. The store
directory comes from ``run.config["memory_dir"]`` (the runner's ``--memory DIR``);
None or absent keeps the knowledge in memory only, so runs stay reproducible
and write nothing.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from homesim.module import Module

from .scene_model import SceneModel

__all__ = ["SceneModel", "install", "memory_dir"]


def memory_dir(run: Any) -> Any:
    """The store directory a run asks for (``memory_dir`` in ``run.config``), or None."""
    config = getattr(run, "config", None)
    if isinstance(config, Mapping):
        return config.get("memory_dir")
    return getattr(config, "memory_dir", None)


def install(run: Any) -> dict[str, Module]:
    """The scene model, with its store from the run's configuration."""
    return {"scene_model": SceneModel(run.sim, store_dir=memory_dir(run))}
