"""Following: how far the robot stayed from the person it followed (ground truth).

While the supervisor is in ``Following`` the partner is, in ground truth,
the person who was nearest to the robot when it entered the state. Every
world step the true distance robot-partner goes into a running statistic,
with the share of time inside a socially acceptable band (``band_m``,
default 0.8-2.0 m; scenario option ``follow-band="lo hi"``), the time spent
following and the ``partner_too_fast`` warnings the robot raised.
"""

from __future__ import annotations

import math
from typing import Any

from . import Observer
from .stats import Running


class Following(Observer):
    channels = ("/robot/es/events",)
    step_every = 1

    def __init__(self, run: Any) -> None:
        super().__init__(run)
        lo, hi = (float(v) for v in run.config.options.get("follow-band", "0.8 2.0").split())
        self.band = (lo, hi)
        self.distance = Running()
        self.inside = 0
        self.partner: str | None = None
        self.warnings = 0
        self.episodes = 0

    def on_message(self, m: Any) -> None:
        if m.xml.get("name") == "partner_too_fast":
            self.warnings += 1

    def on_step(self, world: Any) -> None:
        if self.run.es_state != "Following":
            self.partner = None
            return
        rx, ry, _ = world.robot.pose
        if self.partner is None:
            near = [(math.hypot(h.position[0] - rx, h.position[1] - ry), n) for n, h in world.humans.items() if h.present]
            if not near:
                return
            self.partner = min(near)[1]
            self.episodes += 1
        h = world.humans[self.partner]
        if not h.present:
            return
        d = math.hypot(h.position[0] - rx, h.position[1] - ry)
        self.distance.add(d)
        self.inside += self.band[0] <= d <= self.band[1]

    def summary(self) -> dict[str, Any]:
        n = self.distance.n
        return {
            "episodes": self.episodes,
            "time_s": round(n * self.run.world.dt, 3),
            "distance_m": self.distance.as_dict(3),
            "mean_distance_m": round(self.distance.mean, 3) if n else None,
            "band_m": list(self.band),
            "share_in_band": round(self.inside / n, 4) if n else None,
            "too_fast_warnings": self.warnings,
        }


OBSERVERS = {"following": Following}
