"""People among people, measured on ground truth (metric ``crowd``).

How close the simulated people come to one another (the user simulation's realism, not the
robot's doing): for every pair of people present in the flat at the same step,

* ``min_people_distance_m``: the smallest distance between two people's centres over the run
  (None with fewer than two people present at once); two bodies (the world's 0.25 m circles)
  overlap below :data:`OVERLAP` (0.5 m, one body width);
* ``overlap_s``: time with at least one pair of bodies overlapping (people standing inside each
  other: the tracker sees one blob where there are two; gen22, tour 8800-04);
* ``overlaps``: how many times a pair began to overlap;
* ``pair_closest``: the closest distance per pair (``"ann/bob"``, names in sorted order).

Constant memory: one running minimum per pair of the scenario's people.
"""

from __future__ import annotations

import math
from typing import Any

from . import Observer

#: m between centres: two people's bodies (0.25 m circles) overlap when closer than this.
OVERLAP = 0.5


class Crowd(Observer):
    """Streaming closest distances between people (see the module docstring)."""

    step_every = 1

    def __init__(self, run: Any) -> None:
        super().__init__(run)
        self.dt = run.world.dt
        self.closest: dict[str, float] = {}
        self.touching: set[str] = set()
        self.overlaps = 0
        self.overlap_s = 0.0

    def on_step(self, world: Any) -> None:
        people = sorted((n, h.position) for n, h in world.humans.items() if h.present)
        any_overlap = False
        for i in range(len(people)):
            a, (ax, ay) = people[i]
            for j in range(i + 1, len(people)):
                b, (bx, by) = people[j]
                d = math.hypot(ax - bx, ay - by)
                key = f"{a}/{b}"
                if d < self.closest.get(key, math.inf):
                    self.closest[key] = d
                if d < OVERLAP:
                    any_overlap = True
                    if key not in self.touching:
                        self.touching.add(key)
                        self.overlaps += 1
                else:
                    self.touching.discard(key)
        if any_overlap:
            self.overlap_s += self.dt

    def summary(self) -> dict[str, Any]:
        return {
            "min_people_distance_m": round(min(self.closest.values()), 4) if self.closest else None,
            "overlap_s": round(self.overlap_s, 3),
            "overlaps": self.overlaps,
            "pair_closest": {k: round(v, 4) for k, v in sorted(self.closest.items())},
        }


OBSERVERS = {"crowd": Crowd}
