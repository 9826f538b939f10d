"""Go-to and failure metrics (ground truth): how the robot drove, and how failures were handled.

:class:`Navigation` (metric ``navigation``): a go-to episode starts with each plan on
``/robot/navigation/plan`` and ends with the sequencer's ``goal_reached`` or
``navigation_failed`` (or a ``cancel`` order); a ``replan="true"`` plan (a way round an
obstacle) continues it and is counted. Per episode, from the world:
the path driven (the true robot position after every step), its ratio to
the shortest collision-free path for the robot's radius (the world's own
planner, :class:`homesim.scenario.pathplan.Grid`, from where the robot stood to
the plan's last waypoint), the time, the closest distance from the robot's
centre to any person's centre, the fastest it drove while someone was within
:data:`SOCIAL_NEAR` m (the social speed limit), the replans, and the robot's
contacts (none allowed). ``replans`` counts every replan answered (the sequencer asked: the
way was blocked), ``replans_found`` those that found a way round.

:class:`Failures` (metric ``failures``): faults injected (``/system/faults``), failures
detected (``module_failed`` on ``/system/health``; time to detect = from the
fault to the report), recovered (``module_recovered``).

Both are registered streaming observers (:mod:`homesim.tour.metrics`); they keep running
totals (and one small record per go-to, the first :data:`MAX_GOTOS` of them: a tour has a
handful; a longer run's ``goto_dropped`` says how many more were counted in the totals but
not listed); ``summary()`` reports them.
"""

from __future__ import annotations

import math
from typing import Any

from ...scenario.pathplan import Grid, NoPathError
from . import Observer

ROBOT_RADIUS = 0.30
#: m: the robot's speed is reported while a person is this close (centre to centre): the social limit's range.
SOCIAL_NEAR = 1.2
#: How many go-to records the summary lists (the totals count every go-to).
MAX_GOTOS = 1000


class Navigation(Observer):
    """Streaming go-to figures (see the module docstring)."""

    channels = ("/robot/navigation/plan", "/robot/es/events", "/robot/es/orders/sequencer")
    step_every = 1

    def __init__(self, run: Any) -> None:
        super().__init__(run)
        self.world = run.world
        self.active = False
        self.started = 0.0
        self.goal: tuple[float, float] | None = None
        self.length = 0.0
        self.shortest = 0.0
        self.last: tuple[float, float] | None = None
        self.episodes: list[dict[str, Any]] = []  # one small dict per go-to, the first MAX_GOTOS
        self._totals = _Totals()  # over every go-to
        self.closest_person = math.inf
        self.replans = 0
        self.replans_found = 0
        self.speed_near = 0.0
        self._contacts_before = 0
        self._grid: Grid | None = None

    def _shortest(self, start: tuple[float, float], goal: tuple[float, float]) -> float | None:
        if self._grid is None:
            self._grid = self.world.walk_grid(clearance=ROBOT_RADIUS)
        try:
            pts = self._grid.plan(start, goal)
        except (NoPathError, ValueError):
            return None
        return float(sum(math.hypot(b[0] - a[0], b[1] - a[1]) for a, b in zip([start, *pts], pts)))

    def on_message(self, m: Any) -> None:
        if m.channel == "/robot/navigation/plan":
            wps = m.xml.findall("waypoint")
            if m.xml.get("replan") == "true":
                # the answer to a replan (a way round an obstacle, or none): the same go-to goes on
                if self.active:
                    self.replans += 1
                    self.replans_found += bool(wps) and not m.xml.get("failed")
                return
            if self.active:
                self._end("replanned", m.created)
            if m.xml.get("failed") or not wps:
                return
            self.active = True
            self.started = m.created
            self.goal = (float(wps[-1].get("x")), float(wps[-1].get("y")))
            x, y, _ = self.world.robot.pose
            self.last = (x, y)
            self.length = 0.0
            self.replans = 0
            self.replans_found = 0
            self.speed_near = 0.0
            self.closest_person = math.inf
            self._contacts_before = self.world.contact_count
            self.shortest = self._shortest((x, y), self.goal) or 0.0
        elif m.channel == "/robot/es/events" and self.active:
            name = m.xml.get("name")
            if name == "goal_reached":
                self._end("reached", m.created)
            elif name == "navigation_failed":
                self._end(f"failed: {m.xml.get('reason')}", m.created)
        elif m.channel == "/robot/es/orders/sequencer" and self.active and m.xml.get("name") == "cancel":
            self._end("cancelled", m.created)

    def on_step(self, world: Any) -> None:
        if not self.active:
            return
        x, y, _ = world.robot.pose
        if self.last is not None:
            self.length += math.hypot(x - self.last[0], y - self.last[1])
        self.last = (x, y)
        near = math.inf
        for h in world.humans.values():
            if h.present:
                hx, hy = h.position
                near = min(near, math.hypot(hx - x, hy - y))
        self.closest_person = min(self.closest_person, near)
        if near <= SOCIAL_NEAR:
            self.speed_near = max(self.speed_near, abs(world.robot.v))

    def _end(self, outcome: str, t: float) -> None:
        self.active = False
        x, y, _ = self.world.robot.pose
        episode = {
            "outcome": outcome,
            "time": round(t - self.started, 3),
            "path_length": round(self.length, 3),
            "shortest": round(self.shortest, 3),
            "ratio": round(self.length / self.shortest, 3) if self.shortest > 0 else None,
            "goal_error": round(math.hypot(x - self.goal[0], y - self.goal[1]), 3) if self.goal else None,
            "closest_person": round(self.closest_person, 3) if math.isfinite(self.closest_person) else None,
            "collisions": self.world.contact_count - self._contacts_before,
            "replans": self.replans,
            "replans_found": self.replans_found,
            "speed_near_person_max": round(self.speed_near, 3),
        }
        self._record(episode)

    def _record(self, episode: dict[str, Any]) -> None:
        """Count a finished go-to in the totals; list it if fewer than MAX_GOTOS are listed."""
        self._totals.add(episode)
        if len(self.episodes) < MAX_GOTOS:
            self.episodes.append(episode)

    def summary(self) -> dict[str, Any]:
        """Every go-to (the first MAX_GOTOS), and over all of them the figures a scenario's ``<metric>`` can bound."""
        t = self._totals
        out: dict[str, Any] = {
            "goto": list(self.episodes),
            "episodes": t.n,
            "reached": t.reached,
            "failed": t.failed,
            "time_s": round(t.time, 3),
            "path_length_m": round(t.path_length, 3),
            "ratio_max": t.worst["ratio"],
            "goal_error_max_m": t.worst["goal_error"],
            "closest_person_m": t.worst["closest_person"],
            "speed_near_person_max": t.worst["speed_near_person_max"],
            "replans": t.replans,
            "replans_found": t.replans_found,
            "collisions": t.collisions,
        }
        if t.n > len(self.episodes):
            out["goto_dropped"] = t.n - len(self.episodes)
        return out


#: The worst value of each figure over the go-tos: the largest, or the smallest (closest person).
_WORST = {"ratio": max, "goal_error": max, "closest_person": min, "speed_near_person_max": max}


class _Totals:
    """Running totals over every go-to record, added in order: the same numbers as summing,
    and taking the max or min of, the whole list (``sum`` starts at 0 and adds in order too)."""

    def __init__(self) -> None:
        self.n = self.reached = self.failed = self.replans = self.replans_found = self.collisions = 0
        self.time: float = 0
        self.path_length: float = 0
        self.worst: dict[str, float | None] = dict.fromkeys(_WORST)

    def add(self, e: dict[str, Any]) -> None:
        self.n += 1
        self.reached += e["outcome"] == "reached"
        self.failed += e["outcome"].startswith("failed")
        self.time += e["time"]
        self.path_length += e["path_length"]
        self.replans += e["replans"]
        self.replans_found += e["replans_found"]
        self.collisions += e["collisions"]
        for key, pick in _WORST.items():
            v = e[key]
            if v is not None:
                w = self.worst[key]
                self.worst[key] = v if w is None else pick(w, v)


class Failures(Observer):
    """Faults injected, failures detected and recovered, time to detect (bus only)."""

    channels = ("/system/faults", "/system/health")

    def __init__(self, run: Any) -> None:
        super().__init__(run)
        self.injected: dict[str, float] = {}
        self.faults = 0
        self.detected = 0
        self.recovered = 0
        self.restarting = 0
        self.detect_sum = 0.0
        self.detect_max = 0.0

    def on_message(self, m: Any) -> None:
        if m.channel == "/system/faults":
            self.faults += 1
            self.injected[str(m.xml.get("module"))] = m.created
        elif m.channel == "/system/health":
            module = str(m.xml.get("module"))
            if m.xml.tag == "module_failed":
                self.detected += 1
                self.restarting += m.xml.get("restarting") == "true"
                t0 = self.injected.pop(module, None)
                if t0 is not None:
                    dt = m.created - t0
                    self.detect_sum += dt
                    self.detect_max = max(self.detect_max, dt)
            elif m.xml.tag == "module_recovered":
                self.recovered += 1

    def summary(self) -> dict[str, Any]:
        n = self.detected
        return {"faults": self.faults, "detected": n, "restarting": self.restarting, "recovered": self.recovered,
                "time_to_detect_mean": round(self.detect_sum / n, 3) if n else None,
                "time_to_detect_max": round(self.detect_max, 3) if n else None}


OBSERVERS = {"navigation": Navigation, "failures": Failures}
