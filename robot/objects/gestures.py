"""Gesture detection: deictic pointing from the camera's percepts, as a ray in the map frame.

The camera reports a pointing arm only while the hand is in its image
(which is why the person attention looks at the partner's hands in
Interaction and Object): ``<pointing bearing distance direction elevation
hand_height/>`` in the robot frame, each direction with ~5 degrees of noise.
:class:`GestureTracker` turns each detection into a :class:`Pointing` in the
map frame with the localised pose of the robot at the image's capture time,
keeps the last ``window`` seconds (a bounded deque), and :meth:`pointing`
averages the largest group of consistent detections (hands within 0.5 m)
into one ray: averaging n detections divides the direction noise by sqrt(n).
A single detection is not a gesture (``min_count``).

The camera's mount (height, offset ahead of the base's centre) is the
robot's own geometry, not knowledge of the world.
"""

from __future__ import annotations

import math
from collections import deque

from .resolve import Pointing

CAMERA_HEIGHT = 1.41  # metres, the EVI-D31 on the PeopleBot
CAMERA_OFFSET = 0.05  # metres ahead of the base's centre
DIRECTION_NOISE = math.radians(5.0)  # the gesture detector's per-frame error in the arm's direction (its data sheet)


def camera_to_map(pose: tuple[float, float, float], bearing: float, distance: float, height: float) -> tuple[float, float]:
    """Map (x, y) of a point seen at ``bearing`` (rad, robot frame) and 3D ``distance`` from the
    camera, at ``height`` metres above the floor."""
    x, y, th = pose
    cx, cy = x + CAMERA_OFFSET * math.cos(th), y + CAMERA_OFFSET * math.sin(th)
    dz = CAMERA_HEIGHT - height
    horiz = math.sqrt(max(distance * distance - dz * dz, 0.0))
    return cx + horiz * math.cos(th + bearing), cy + horiz * math.sin(th + bearing)


class GestureTracker:
    """Recent pointing detections (map frame) and their consensus ray."""

    def __init__(self, *, window: float = 4.0, memory: float = 15.0, min_count: int = 2, maxlen: int = 200) -> None:
        self.window = window
        self.memory = max(memory, window)  # s: how long detections are kept for :meth:`pointing` with ``start``
        self.min_count = min_count
        self._seen: deque[tuple[float, Pointing]] = deque(maxlen=maxlen)

    def add(self, t: float, pose: tuple[float, float, float], bearing_deg: float, distance: float, direction_deg: float, elevation_deg: float, hand_height: float) -> Pointing:
        """One camera detection taken at ``t`` from ``pose`` (map frame) -> its ray (kept)."""
        hx, hy = camera_to_map(pose, math.radians(bearing_deg), distance, hand_height)
        p = Pointing(hx, hy, hand_height, math.remainder(pose[2] + math.radians(direction_deg), 2 * math.pi), math.radians(elevation_deg))
        self._seen.append((t, p))
        return p

    def recent(self, now: float, since: float = -math.inf, start: float | None = None) -> list[Pointing]:
        """Detections of the last ``window`` s (from ``start`` instead, if given, at most ``memory``
        s back) taken at ``since`` or later."""
        while self._seen and self._seen[0][0] < now - self.memory:
            self._seen.popleft()
        lo = max(since, now - self.window if start is None else max(start, now - self.memory))
        return [p for t, p in self._seen if t >= lo]

    def bouts(self, now: float, since: float, gap: float = 1.0) -> list[Pointing]:
        """The pointing gestures made since ``since`` (at most ``memory`` s back), each its own ray:
        detections apart by more than ``gap`` s are two gestures (her arm came down between them),
        and each gesture is averaged as :meth:`pointing` averages (the largest consistent group).
        Each gesture aims with its own error, so each is its own evidence (she pointed again)."""
        seen = [(t, p) for t, p in self._seen if t >= max(since, now - self.memory)]
        runs: list[list[tuple[float, Pointing]]] = []
        for t, p in seen:
            if runs and t - runs[-1][-1][0] <= gap:
                runs[-1].append((t, p))
            else:
                runs.append([(t, p)])
        out = []
        for run in runs:
            ray = _consensus([p for _, p in run], self.min_count, latest=False)
            if ray is not None:
                out.append(ray)
        return out

    def pointing(self, now: float, since: float = -math.inf, start: float | None = None) -> Pointing | None:
        """The averaged ray of the largest group of consistent recent detections (taken at
        ``since`` or later; ``start``: look back to then instead of ``window`` s, e.g. to the
        beginning of the sentence the gesture went with), or None. Of groups equally large, the
        earliest (with ``start``: the latest)."""
        return _consensus(self.recent(now, since, start), self.min_count, latest=start is not None)

    def target(self, now: float, floor_heights: tuple[float, ...] = (0.75, 0.0)) -> tuple[float, float, float] | None:
        """Where the ray comes down to the first of ``floor_heights`` (a table top, then the
        floor) within 3 m of the hand: the region to look at. None without a gesture."""
        p = self.pointing(now)
        if p is None:
            return None
        for h in floor_heights:
            drop = p.z - h
            if drop > 0 and p.elevation < -math.radians(3):
                reach = drop / math.tan(-p.elevation)
                if reach <= 3.0:
                    return p.x + reach * math.cos(p.direction), p.y + reach * math.sin(p.direction), h
        return p.x + 1.0 * math.cos(p.direction), p.y + 1.0 * math.sin(p.direction), max(p.z - 0.3, 0.0)


def _consensus(seen: list[Pointing], min_count: int, *, latest: bool) -> Pointing | None:
    """The averaged ray of the largest group of consistent detections (hands within 0.5 m, directions
    within 30 degrees), or None under ``min_count``. Of groups equally large, the earliest (``latest``:
    the latest; groups are in order of first detection)."""
    if len(seen) < min_count:
        return None
    groups: list[list[Pointing]] = []
    for p in seen:
        for g in groups:
            if math.hypot(g[0].x - p.x, g[0].y - p.y) < 0.5 and abs(math.remainder(g[0].direction - p.direction, 2 * math.pi)) < math.radians(30):
                g.append(p)
                break
        else:
            groups.append([p])
    best = max(reversed(groups), key=len) if latest else max(groups, key=len)
    if len(best) < min_count:
        return None
    n = len(best)
    sx = sum(math.sin(p.direction) for p in best)
    cx = sum(math.cos(p.direction) for p in best)
    mean = math.atan2(sx, cx)
    # The standard error of the mean direction: the detections' spread over sqrt(n) (at least
    # the camera's own noise over sqrt(n): a few detections can agree by chance).
    var = sum(math.remainder(p.direction - mean, 2 * math.pi) ** 2 for p in best) / max(1, n - 1)
    sigma = math.sqrt(max(var, DIRECTION_NOISE**2) / n)
    return Pointing(
        sum(p.x for p in best) / n, sum(p.y for p in best) / n, sum(p.z for p in best) / n,
        mean, sum(p.elevation for p in best) / n, sigma,
    )
