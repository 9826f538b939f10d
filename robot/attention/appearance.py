"""Torso colour per person track, from the camera's torso blobs: what tells the partner from others.

Issue 26 item 1: when people cross between the robot and the partner it follows, the partner's
track can die (hidden behind someone, round a door frame) and the leaving rule takes a confirmed
track near where she was last seen as hers again (``PersonAttention._reacquire``). Near her may
stand someone else, the person who crossed. Position alone cannot tell them apart; their clothes
can. The camera (on the partner in the top-down states, 48.8 deg wide) reports every torso in the
image with its bearing and colour, whichever way the person faces (``/robot/camera/torsos``).

A blob is anchored to a track by bearing only when that is unambiguous (:func:`anchor_torsos`):
the nearest track within ``tolerance`` of the blob, no second track within twice the tolerance of
it (one person half behind another: whose torso is it?), and no second blob within the tolerance
of that track. Each track keeps a running mean of its anchored colours (:class:`Colours`); it
counts after ``min_obs`` blobs. Two colours further apart than ``differ`` (RGB distance; the
camera's colour noise is 0.04 per channel) are different clothes (:func:`same_clothes`); an
unknown colour is never evidence either way.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

RGB = tuple[float, float, float]


@dataclass(frozen=True)
class AppearanceSpec:
    alpha: float = 0.25  # weight of a new blob in a track's running mean colour
    min_obs: int = 3  # blobs before a track's colour counts
    differ: float = 0.25  # RGB distance: clothes this far apart are different clothes
    fresh: float = 2.0  # s: a colour not seen again for longer is no evidence (the track may have
    # passed to another person since: a crossing, a track coasting onto someone else)


def _off(a: float, b: float) -> float:
    return abs((a - b + math.pi) % (2 * math.pi) - math.pi)


def anchor_torsos(track_bearings: Sequence[float], blob_bearings: Sequence[float], tolerance: float) -> list[tuple[int, int]]:
    """(blob index, track row) for every blob whose track is unambiguous (see the module docstring)."""
    out: list[tuple[int, int]] = []
    for j, b in enumerate(blob_bearings):
        offs = sorted((_off(tb, b), i) for i, tb in enumerate(track_bearings))
        if not offs or offs[0][0] > tolerance:
            continue
        if len(offs) > 1 and offs[1][0] <= 2 * tolerance:
            continue  # two people nearly in line: whose torso is it?
        i = offs[0][1]
        tb = track_bearings[i]
        if any(k != j and _off(tb, other) <= tolerance for k, other in enumerate(blob_bearings)):
            continue  # two blobs at this track: neither is surely its own
        out.append((j, i))
    return out


def same_clothes(a: RGB | None, b: RGB | None, spec: AppearanceSpec = AppearanceSpec()) -> bool:
    """Could ``a`` and ``b`` be the same clothes? (True when either is unknown.)"""
    if a is None or b is None:
        return True
    return math.dist(a, b) <= spec.differ


class Colours:
    """Each track's running mean torso colour (bounded: :meth:`forget` drops dead tracks)."""

    def __init__(self, spec: AppearanceSpec = AppearanceSpec()) -> None:
        self.spec = spec
        self._mean: dict[int, tuple[float, float, float, int]] = {}
        self._seen: dict[int, float] = {}  # when each track's colour was last observed

    def observe(self, track_id: int, rgb: RGB, t: float = 0.0) -> None:
        """One anchored blob of colour ``rgb`` for ``track_id`` at time ``t``."""
        self._seen[track_id] = t
        old = self._mean.get(track_id)
        if old is None:
            self._mean[track_id] = (rgb[0], rgb[1], rgb[2], 1)
            return
        a = self.spec.alpha if old[3] >= self.spec.min_obs else 1.0 / (old[3] + 1)  # a plain mean at first
        self._mean[track_id] = (old[0] + a * (rgb[0] - old[0]), old[1] + a * (rgb[1] - old[1]),
                                old[2] + a * (rgb[2] - old[2]), old[3] + 1)

    def colour(self, track_id: int, t: float | None = None) -> RGB | None:
        """The track's colour once it has ``min_obs`` blobs, else None; with ``t``, also None when
        it was last seen more than ``fresh`` s before ``t``."""
        m = self._mean.get(track_id)
        if m is None or m[3] < self.spec.min_obs:
            return None
        if t is not None and t - self._seen.get(track_id, -math.inf) > self.spec.fresh:
            return None
        return (m[0], m[1], m[2])

    def take(self, track_id: int) -> tuple[tuple[float, float, float, int], float] | None:
        """Remove and return the track's record (running mean and count, when last observed), or None."""
        m = self._mean.pop(track_id, None)
        seen = self._seen.pop(track_id, -math.inf)
        return None if m is None else (m, seen)

    def put(self, track_id: int, record: tuple[tuple[float, float, float, int], float] | None) -> None:
        """Give ``track_id`` the record :meth:`take` returned (None: no colour known for it)."""
        self._mean.pop(track_id, None)
        self._seen.pop(track_id, None)
        if record is not None:
            self._mean[track_id], self._seen[track_id] = record

    def forget(self, alive: set[int]) -> None:
        for d in (self._mean, self._seen):
            for k in [k for k in d if k not in alive]:
                del d[k]
