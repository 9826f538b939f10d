"""Object attention (``object_attention``): gestures, reference resolution, object events.

:mod:`robot.objects.gestures` (pointing rays from the camera's percepts),
:mod:`robot.objects.resolve` (candidates and the reference, pure),
:mod:`robot.objects.attention` (the bus module), :mod:`robot.objects.verbal` (the
biron-2005 profile's: objects from what was said only). ``install(run)`` types
``/robot/objects/focus`` and starts the module.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from homesim.module import Module

from robot.profiles import verbal_only

from .attention import FOCUS, ObjectAttention
from .verbal import VerbalObjectAttention

FOCUS_SCHEMA = Path(__file__).resolve().parent.parent / "schemas" / "objects-focus.xsd"


def install(run: Any) -> dict[str, Module]:
    """Type the focus channel and start the object attention (the profile's: verbal only for biron-2005)."""
    run.sim.bus.declare_channel(FOCUS, FOCUS_SCHEMA)
    oa: Module = VerbalObjectAttention(run.sim) if verbal_only(run) else ObjectAttention(run.sim)
    oa.start()
    return {"object_attention": oa}
