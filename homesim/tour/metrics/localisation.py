"""Localisation error: the robot's published pose estimate against the true pose.

A streaming :class:`~homesim.tour.metrics.Observer` (``metrics["localisation"]`` of
the run summary). It
records the true robot pose every world step in a short ring buffer (two
seconds) and, for each ``<pose time x y ...>`` sent on
``/robot/localisation/pose``, interpolates the truth at the estimate's
``time`` (the odometry's capture time, not the moment of sending) and adds
the position and heading errors to running sums. A pose whose time the
world has not reached yet waits (at most ``MAX_PENDING`` of them) until it
has. Nothing grows with the length of the run.

Summary: ``samples``, ``mean_m``, ``max_m``, ``rms_m``, ``final_m``,
``heading_mean_deg``, ``heading_max_deg``, ``worst_at`` (virtual s), and
``unmatched`` (estimates whose time fell outside the truth buffer).
"""

from __future__ import annotations

import math
from collections import deque
from typing import Any

from robot.contract import POSE

from . import Observer

MAX_PENDING = 64


class LocalisationMetric(Observer):
    """Mean, max and RMS position error (metres) and heading error of the published poses."""

    channels: tuple[str, ...] = (POSE,)
    step_every: int = 1

    def __init__(self, run: Any = None, *, history: float = 2.0) -> None:
        super().__init__(run)
        self._truth: deque[tuple[float, float, float, float]] = deque()
        self._history = history
        self._pending: deque[tuple[float, float, float, float]] = deque()
        self.n = 0
        self.sum = 0.0
        self.sum_sq = 0.0
        self.max = 0.0
        self.worst_at = 0.0
        self.final = 0.0
        self.h_sum = 0.0
        self.h_max = 0.0
        self.unmatched = 0

    # ------------------------------------------------------------ inputs
    def on_step(self, world: Any) -> None:
        """Record the true pose at the world's time; resolve estimates that were waiting for it."""
        x, y, th = world.robot.pose
        t = world.time
        self._truth.append((t, x, y, th))
        while self._truth and self._truth[0][0] < t - self._history:
            self._truth.popleft()
        while self._pending and self._pending[0][0] <= t + 1e-9:
            self._score(*self._pending.popleft())

    def on_message(self, msg: Any) -> None:
        """Take one ``<pose>`` estimate (other messages are ignored)."""
        xml = msg.xml
        if xml.tag != "pose":
            return
        est = (float(xml.get("time")), float(xml.get("x")), float(xml.get("y")), float(xml.get("theta")))
        if self._truth and est[0] <= self._truth[-1][0] + 1e-9:
            self._score(*est)
        elif len(self._pending) < MAX_PENDING:
            self._pending.append(est)
        else:
            self.unmatched += 1

    # ------------------------------------------------------------ scoring
    def truth_at(self, t: float) -> tuple[float, float, float] | None:
        """The true pose at ``t``, interpolated between recorded steps (None: outside the buffer)."""
        tr = self._truth
        if not tr or t < tr[0][0] - 1e-9 or t > tr[-1][0] + 1e-9:
            return None
        nxt = tr[-1]
        for cur in reversed(tr):  # estimates are recent: search from the newest
            if cur[0] <= t + 1e-12:
                if nxt[0] - cur[0] < 1e-12:
                    return cur[1:]
                f = (t - cur[0]) / (nxt[0] - cur[0])
                dth = math.remainder(nxt[3] - cur[3], 2 * math.pi)
                return cur[1] + f * (nxt[1] - cur[1]), cur[2] + f * (nxt[2] - cur[2]), cur[3] + f * dth
            nxt = cur
        return tr[0][1:]

    def _score(self, t: float, x: float, y: float, th: float) -> None:
        truth = self.truth_at(t)
        if truth is None:
            self.unmatched += 1
            return
        e = math.hypot(x - truth[0], y - truth[1])
        h = abs(math.remainder(th - truth[2], 2 * math.pi))
        self.n += 1
        self.sum += e
        self.sum_sq += e * e
        self.final = e
        if e > self.max:
            self.max, self.worst_at = e, t
        self.h_sum += h
        self.h_max = max(self.h_max, h)

    def summary(self) -> dict[str, Any]:
        n = self.n
        return {
            "samples": n,
            "mean_m": round(self.sum / n, 4) if n else None,
            "max_m": round(self.max, 4) if n else None,
            "rms_m": round(math.sqrt(self.sum_sq / n), 4) if n else None,
            "final_m": round(self.final, 4) if n else None,
            "heading_mean_deg": round(math.degrees(self.h_sum / n), 3) if n else None,
            "heading_max_deg": round(math.degrees(self.h_max), 3) if n else None,
            "worst_at": round(self.worst_at, 3) if n else None,
            "unmatched": self.unmatched,
        }


OBSERVERS = {"localisation": LocalisationMetric}
