"""Localisation: where the robot is on the floor plan (``localiser``).

:mod:`robot.localisation.mcl` is the filter (Monte Carlo localisation on a
likelihood field), :mod:`robot.localisation.localiser` the bus module.
``install(run)`` types ``/robot/localisation/pose`` and starts the localiser
(the scenario's ``<robot><option name="localisation-particles" value="N"/>``
sets the particle count).
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Any

from homesim.module import Module

from .localiser import POSE, Localiser
from .mcl import MCLParams

POSE_SCHEMA = Path(__file__).resolve().parent.parent / "schemas" / "localisation-pose.xsd"


def install(run: Any) -> dict[str, Module]:
    """Type the pose channel and start the localiser (it asks map_server for the plan)."""
    sim = run.sim
    sim.bus.declare_channel(POSE, POSE_SCHEMA)
    options = getattr(getattr(run, "config", None), "options", None) or {}
    params = MCLParams()
    n = options.get("localisation-particles")
    if n:
        try:
            params = replace(params, particles=int(n))
        except ValueError:
            raise ValueError(f"robot option localisation-particles={n!r}: not a whole number") from None
    loc = Localiser(sim, params)
    loc.start()
    return {"localiser": loc}
