"""Anchoring faces and sound directions to tracks: the "speaking" and "facing" attributes.

A sound direction from the microphone pair lies in the front half-plane and
stands for two bearings, ``b`` and ``180 - b`` (front/back ambiguity). It is
anchored to the track whose bearing (seen from the microphones) is nearest
either of them, within ``sound_tolerance``; one direction speaks for one
track (two people in nearly the same direction are one direction, and the
nearer-in-bearing track gets it). A frontal face (the camera detects only
frontal faces) is anchored to the track nearest its bearing and distance.

Hysteresis (:class:`Hysteresis`): an attribute turns on after ``on_frames``
matching frames in a row and off after ``off_after`` seconds without one,
so a pause between words or a missed face does not flip the category.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class CueSpec:
    sound_tolerance: float = math.radians(9.0)
    face_bearing_tolerance: float = math.radians(7.0)
    torso_bearing_tolerance: float = math.radians(8.0)  # a torso blob at the partner's bearing
    face_distance_tolerance: float = 0.35  # relative (face size -> distance is noisy)
    speaking_on: int = 2  # frames
    speaking_off: float = 0.7  # s: longer than a pause between words
    facing_on: int = 2
    facing_off: float = 0.3  # s: a face missing where the camera looks means the person looked away
    mic_offset: float = 0.10  # m ahead of the robot centre
    camera_offset: float = 0.05


@dataclass
class Hysteresis:
    """An on/off attribute per track id with an onset count and an offset time."""

    on_frames: int
    off_after: float
    _count: dict[int, int] = field(default_factory=dict)
    _last: dict[int, float] = field(default_factory=dict)
    _on: dict[int, bool] = field(default_factory=dict)

    def feed(self, now: float, ids: np.ndarray, matched: set[int]) -> None:
        """One frame: which of ``ids`` matched the cue."""
        for i in ids.tolist():
            if i in matched:
                self._count[i] = self._count.get(i, 0) + 1
                self._last[i] = now
                if self._count[i] >= self.on_frames:
                    self._on[i] = True
            else:
                self._count[i] = 0
                if self._on.get(i) and now - self._last.get(i, -math.inf) > self.off_after:
                    self._on[i] = False

    def on(self, i: int) -> bool:
        return self._on.get(i, False)

    def forget(self, alive: set[int]) -> None:
        for d in (self._count, self._last, self._on):
            for k in [k for k in d if k not in alive]:
                del d[k]


def bearings_from(xy_robot: np.ndarray, offset: float) -> np.ndarray:
    """Bearings (rad) of robot-frame points (N, 2) seen from a sensor ``offset`` ahead of the centre."""
    return np.arctan2(xy_robot[:, 1], xy_robot[:, 0] - offset)


def match_sounds(track_bearings: np.ndarray, sound_bearings: np.ndarray, tolerance: float) -> list[int]:
    """Rows of the tracks that the front-half-plane sound directions speak for (one track per direction)."""
    out: list[int] = []
    if track_bearings.size == 0:
        return out
    for b in sound_bearings.tolist():
        d_front = np.abs(np.remainder(track_bearings - b + math.pi, 2 * math.pi) - math.pi)
        d_back = np.abs(np.remainder(track_bearings - (math.pi - b) + math.pi, 2 * math.pi) - math.pi)
        d = np.minimum(d_front, d_back)
        k = int(np.argmin(d))
        if d[k] <= tolerance:
            out.append(k)
    return out


def match_faces(track_xy: np.ndarray, faces: np.ndarray, spec: CueSpec) -> list[int]:
    """Rows of the tracks that frontal faces (F, 2: bearing rad, distance m; robot frame) belong to."""
    out: list[int] = []
    if track_xy.shape[0] == 0:
        return out
    tb = bearings_from(track_xy, spec.camera_offset)
    td = np.hypot(track_xy[:, 0] - spec.camera_offset, track_xy[:, 1])
    for b, dist in faces.tolist():
        db = np.abs(np.remainder(tb - b + math.pi, 2 * math.pi) - math.pi)
        ok = (db <= spec.face_bearing_tolerance) & (np.abs(td - dist) <= spec.face_distance_tolerance * dist)
        if ok.any():
            out.append(int(np.flatnonzero(ok)[np.argmin(db[ok])]))
    return out
