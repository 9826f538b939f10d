"""Pictures of runs: the only package that imports matplotlib.

:mod:`.moment` draws the flat at one moment (truth and the robot's
percepts), :mod:`.timeline` the papers' Fig. 6 (module lanes, messages,
processing spans, phases); :mod:`.percepts` holds the plain data the moment
plot draws of the robot's view (the run package fills it from bus messages
and has ``homesim plot``). Names are
loaded on first use, so ``homesim`` commands that draw nothing never import
matplotlib.
"""

from __future__ import annotations

import importlib
from typing import Any

_WHERE = {
    **{n: "moment" for n in ("Legend", "covariance_ellipse", "draw_flat", "draw_objects", "draw_people", "draw_percepts",
                             "draw_robot", "draw_scan", "draw_sound_directions", "place_labels", "plot_moment", "view_polygon")},
    **{n: "percepts" for n in ("Percepts", "Track", "odom_to_world")},
    **{n: "timeline" for n in ("plot_timeline",)},
}
__all__ = sorted(_WHERE)


def __getattr__(name: str) -> Any:
    if name in _WHERE:
        return getattr(importlib.import_module(f".{_WHERE[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
