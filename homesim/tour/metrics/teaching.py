"""Teaching accuracy: precision and recall of the objects the robot learned, and of their attributes.

A streaming :class:`~homesim.tour.metrics.Observer` (``metrics["teaching"]``).

Ground truth of what was taught: every pointing gesture of a scripted
person (sampled every ``step_every`` world steps) is a teaching *episode*;
its intended objects are the object pointed at (``<point object=...>``), or,
for a point or piece of furniture, every scenario object within
``NEAR`` metres of the pointed spot (the robot has to ask which one; either
answer is right).

What was learned: each ``store_object`` order the supervisor sends the
scene model (``/robot/es/orders/scene_model``; ``source="events"`` takes the
object attention's ``object_recognized`` events instead, for runs without a
supervisor). A learned object is matched to the nearest scenario object
within ``MATCH`` metres of its ``x y``; it is *correct* when that object is
intended by the episode it answers: the latest gesture that began before the
request it answers (the last ``object_teaching`` event the dialog sent the
supervisor before the store: the supervisor runs one search at a time, a new
request replaces the old; without a supervisor, the store itself), and at
most ``WINDOW`` seconds before it. Pointing at the red cup, then at the green
one, and storing the red one scores 0.

Summary: ``learned``, ``correct``, ``episodes``, ``precision`` (correct /
learned), ``recall`` (episodes with a correct object learned / episodes),
``attributes``: for the correct objects, ``type`` and ``colour`` compared
with the scenario's (``precision``: right / stated; ``recall``: right / two
per taught episode), and ``position_error_m`` (mean, max). Constant memory
apart from the episodes (one per scripted gesture, at most ``MAX_EPISODES``).
"""

from __future__ import annotations

import math
from typing import Any

from . import Observer
from .stats import Running

NEAR = 0.5  # metres: objects this close to a pointed spot are all meant
MATCH = 0.3  # metres: a learned position this close to an object is that object
# seconds from the gesture's start to the object's arrival: a robot that asks her to step aside
# (10 s for her to do so) and then drives to see the object (slowly, near her) learns it 30-40 s
# after she pointed, and it is still the object she meant
WINDOW = 60.0
MAX_EPISODES = 1000


class TeachingMetric(Observer):
    """Precision/recall of learned objects and their type and colour (see the module docstring)."""

    channels: tuple[str, ...] = ("/robot/es/orders/scene_model", "/robot/es/events")
    step_every = 5

    def __init__(self, run: Any = None, *, source: str = "orders", world: Any = None) -> None:
        super().__init__(run)
        if source not in ("orders", "events"):
            raise ValueError(f"teaching metric: source must be 'orders' or 'events', not {source!r}")
        self.source = source
        self.world = world if world is not None else getattr(run, "world", None)
        self.episodes: list[tuple[float, frozenset[str]]] = []  # (start, intended object names)
        self._request: float | None = None  # when the last object_teaching request reached the supervisor
        self._current: dict[str, tuple[str, tuple[float, float, float]]] = {}
        self.learned = 0
        self.correct = 0
        self._hit_episodes: set[int] = set()
        self.attr_stated = 0
        self.attr_right = 0
        self.position = Running()
        self.unmatched = 0

    # ------------------------------------------------------------ truth
    def on_step(self, world: Any) -> None:
        """Open an episode for every gesture that started since the last look."""
        self.world = world
        for name, h in world.humans.items():
            p = h.pointing if h.present else None
            key = None if p is None else (p.target_name, p.target)
            if key is None:
                self._current.pop(name, None)
                continue
            if self._current.get(name) == key:
                continue
            self._current[name] = key
            if len(self.episodes) < MAX_EPISODES:
                self.episodes.append((world.time, self._intended(world, p.target_name, p.target)))

    def _intended(self, world: Any, target_name: str, target: tuple[float, float, float]) -> frozenset[str]:
        if target_name in world.objects:
            return frozenset([target_name])
        return frozenset(n for n, o in world.objects.items() if math.hypot(o.x - target[0], o.y - target[1]) <= NEAR)

    # ------------------------------------------------------------ learned
    def on_message(self, msg: Any) -> None:
        xml = msg.xml
        if xml.tag == "event" and xml.get("name") == "object_teaching":
            self._request = float(msg.created)
            return
        if self.source == "orders":
            if xml.tag != "order" or xml.get("name") != "store_object":
                return
            obj = next((p.find("OBJECT") for p in xml.iterfind("param") if p.find("OBJECT") is not None), None)
        else:
            if xml.tag != "event" or xml.get("name") != "object_recognized":
                return
            obj = xml.find("OBJECT")
        if obj is None or obj.get("x") is None or obj.get("y") is None or self.world is None:
            return
        t = float(msg.created)
        self.score(obj, t, self._request if self._request is not None and self._request <= t else t)

    def _answered(self, asked: float) -> int | None:
        """The episode a request made at ``asked`` answers: the latest gesture begun before it."""
        for i in range(len(self.episodes) - 1, -1, -1):
            start = self.episodes[i][0]
            if start <= asked + 1e-9:
                return i if asked - start <= WINDOW else None
        return None

    def score(self, obj: Any, t: float, asked: float | None = None) -> None:
        """Score one learned ``<OBJECT>`` that arrived at virtual time ``t`` in answer to a request
        made at ``asked`` (default ``t``)."""
        self.learned += 1
        x, y = float(obj.get("x")), float(obj.get("y"))
        near = sorted((math.hypot(o.x - x, o.y - y), n) for n, o in self.world.objects.items())
        if not near or near[0][0] > MATCH:
            self.unmatched += 1
            return
        dist, name = near[0]
        ep = self._answered(t if asked is None else asked)
        if ep is None or name not in self.episodes[ep][1]:
            return
        self.correct += 1
        self._hit_episodes.add(ep)
        self.position.add(dist)
        truth = self.world.objects[name]
        for key, want in (("type", truth.type), ("colour", truth.colour_name)):
            said = (obj.get(key) or "").strip().lower()
            if said:
                self.attr_stated += 1
                self.attr_right += said == want.lower()

    def summary(self) -> dict[str, Any]:
        n_ep = len(self.episodes)
        return {
            "learned": self.learned,
            "correct": self.correct,
            "episodes": n_ep,
            "unmatched": self.unmatched,
            "precision": round(self.correct / self.learned, 4) if self.learned else None,
            "recall": round(len(self._hit_episodes) / n_ep, 4) if n_ep else None,
            "attributes": {
                "stated": self.attr_stated,
                "right": self.attr_right,
                "precision": round(self.attr_right / self.attr_stated, 4) if self.attr_stated else None,
                "recall": round(self.attr_right / (2 * n_ep), 4) if n_ep else None,
            },
            "position_error_m": {"mean": round(self.position.mean, 4), "max": round(self.position.hi, 4)} if self.position.n else None,
        }


OBSERVERS = {"teaching": TeachingMetric}
