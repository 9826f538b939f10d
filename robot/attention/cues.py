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
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class CueSpec:
    sound_tolerance: float = math.radians(9.0)
    face_bearing_tolerance: float = math.radians(7.0)
    torso_bearing_tolerance: float = math.radians(8.0)  # a torso blob at the partner's bearing
    face_distance_tolerance: float = 0.35  # relative (face size -> distance is noisy)
    # m: how far a track kept by one leg may lie beside the face of its person (a face matches a near track
    # within the angle this spans, when wider than ``face_bearing_tolerance``: nearer than ~1.2 m)
    leg_reach: float = 0.15
    speaking_on: int = 2  # frames
    speaking_off: float = 0.7  # s: longer than a pause between words
    facing_on: int = 2
    facing_off: float = 0.3  # s: a face missing where the camera looks means the person looked away
    mic_offset: float = 0.10  # m ahead of the robot centre
    mic_height: float = 1.06  # m: the microphone pair's height on the robot (its own geometry)
    mic_spacing: float = 0.281  # m between the two microphones
    mouth_height: float = 1.6  # m: where an adult standing person's voice comes from (typical)
    # m: the mouth heights a voice may come from (a child or a seated adult .. a tall adult): the
    # robot does not know a person's height, and near the robot it moves the pair's bearing a lot
    # (0.55 m away, 50 deg to the side: 56 deg from 1.15 m, 35 deg from 1.6 m, 27 deg from 1.85 m)
    mouth_heights: tuple[float, float] = (1.15, 1.85)
    camera_offset: float = 0.05


@dataclass
class Hysteresis:
    """An on/off attribute per track id with an onset count and an offset time."""

    on_frames: int
    off_after: float
    _count: dict[int, int] = field(default_factory=dict)
    _last: dict[int, float] = field(default_factory=dict)
    _on: dict[int, bool] = field(default_factory=dict)
    _since: dict[int, float] = field(default_factory=dict)  # when each track's attribute last came on

    def feed(self, now: float, ids: Iterable[int], matched: set[int]) -> None:
        """One frame: which of ``ids`` matched the cue."""
        count, last, on = self._count, self._last, self._on
        for i in ids.tolist() if isinstance(ids, np.ndarray) else ids:
            if i in matched:
                c = count[i] = count.get(i, 0) + 1
                last[i] = now
                if c >= self.on_frames:
                    if not on.get(i):
                        self._since[i] = now
                    on[i] = True
            else:
                count[i] = 0
                if on.get(i) and now - last.get(i, -math.inf) > self.off_after:
                    on[i] = False

    def on(self, i: int) -> bool:
        return self._on.get(i, False)

    def since(self, i: int) -> float:
        """When the attribute of track ``i`` came on (it has been on since); -inf when not known."""
        return self._since.get(i, -math.inf) if self.on(i) else math.inf

    def last(self, i: int) -> float:
        """When track ``i`` last matched the cue (a frame, whether or not the attribute is on); -inf never."""
        return self._last.get(i, -math.inf)

    def forget(self, alive: set[int]) -> None:
        for d in (self._count, self._last, self._on, self._since):
            for k in [k for k in d if k not in alive]:
                del d[k]


def _as_list(values: Sequence[float] | np.ndarray) -> list[float]:
    return values.tolist() if isinstance(values, np.ndarray) else list(values)


def _angle(a: float) -> float:
    """|a| wrapped into [0, pi] (as ``abs(np.remainder(a + pi, 2 pi) - pi)``)."""
    return abs((a + math.pi) % _TWO_PI - math.pi)


_TWO_PI = 2 * math.pi


def bearings_from(xy_robot: np.ndarray | Sequence[Sequence[float]], offset: float) -> list[float]:
    """Bearings (rad) of robot-frame points (N, 2) seen from a sensor ``offset`` ahead of the centre."""
    pts = xy_robot.tolist() if isinstance(xy_robot, np.ndarray) else xy_robot
    return [math.atan2(y, x - offset) for x, y in pts]


def sound_bearings_from(xy_robot: np.ndarray | Sequence[Sequence[float]], spec: CueSpec) -> list[float]:
    """The front-half-plane bearing (rad) the microphone pair reports for a voice from each
    robot-frame point (N, 2): the pair measures a path difference in 3D, and a mouth above the
    microphones shortens it by the cosine of its elevation (a person 1.7 m away 76 deg to the side
    is heard at about 66 deg), so a track's voice is matched where the pair hears it, not at the
    track's own bearing. Near-field (exact distances to both microphones), far-field inverted."""
    pts = xy_robot.tolist() if isinstance(xy_robot, np.ndarray) else xy_robot
    h, dz, off = spec.mic_spacing / 2, spec.mouth_height - spec.mic_height, spec.mic_offset
    out = []
    for x, y in pts:
        ax = x - off
        dl = math.sqrt(ax * ax + (y - h) ** 2 + dz * dz)
        dr = math.sqrt(ax * ax + (y + h) ** 2 + dz * dz)
        out.append(math.asin(max(-1.0, min(1.0, (dr - dl) / spec.mic_spacing))))
    return out


def sound_bearing_span(x: float, y: float, spec: CueSpec) -> tuple[float, float]:
    """(lowest, highest) front-half-plane bearing (rad) the microphone pair can report for a voice
    from the robot-frame point (x, y), over the mouth heights ``spec.mouth_heights``: the person's
    height is unknown, and the elevation it gives shortens the path difference (:func:`sound_bearings_from`).
    Far off the span is narrow (a degree); at half a metre it is tens of degrees wide."""
    lo, hi = spec.mouth_heights
    heights = [lo, hi] + ([spec.mic_height] if lo < spec.mic_height < hi else [])
    bs = [sound_bearings_from([(x, y)], CueSpec(mic_offset=spec.mic_offset, mic_height=spec.mic_height, mic_spacing=spec.mic_spacing, mouth_height=z))[0] for z in heights]
    return min(bs), max(bs)


#: m: the nearest a person's centre stands to the robot's (its half width and a body): :func:`voice_reach`
NEAREST_SPEAKER = 0.45


def voice_reach(b: float, spec: CueSpec) -> float:
    """The furthest bearing (rad, 0 .. pi/2) off the axis a voice read at front bearing ``b`` (rad, its size is
    used) may come from: the pair's reading of the tallest mouth (``spec.mouth_heights``) standing
    :data:`NEAREST_SPEAKER` m from the robot's centre shrinks toward the axis the most
    (:func:`sound_bearings_from`), so the true direction lies between ``|b|`` and this. Bisection over the
    direction (the reading grows with it); pi/2 when even a voice from there reads nearer the axis than ``b``."""
    b = min(abs(b), math.pi / 2)
    near = CueSpec(mic_offset=spec.mic_offset, mic_height=spec.mic_height, mic_spacing=spec.mic_spacing, mouth_height=spec.mouth_heights[1])

    def reading(a: float) -> float:
        return sound_bearings_from([(NEAREST_SPEAKER * math.cos(a), NEAREST_SPEAKER * math.sin(a))], near)[0]

    lo, hi = b, math.pi / 2
    if reading(hi) <= b:
        return hi
    for _ in range(24):
        mid = (lo + hi) / 2
        if reading(mid) < b:
            lo = mid
        else:
            hi = mid
    return lo


def span_offset(span: tuple[float, float], b: float) -> float:
    """How far (rad) the front-half-plane sound direction ``b`` lies outside ``span`` (0 inside);
    the pair cannot tell ``b`` from ``180 - b``, so the nearer of the two counts."""
    lo, hi = span
    out = math.inf
    for v in (b, math.pi - b):
        v = math.remainder(v, 2 * math.pi)
        out = min(out, max(0.0, lo - v, v - hi))
    return out


def match_sounds(track_bearings: Sequence[float] | np.ndarray, sound_bearings: Sequence[float] | np.ndarray, tolerance: float) -> list[int]:
    """Rows of the tracks that the front-half-plane sound directions speak for (one track per direction)."""
    out: list[int] = []
    tracks = _as_list(track_bearings)
    if not tracks:
        return out
    for b in _as_list(sound_bearings):
        back = math.pi - b
        best, k = math.inf, -1
        for i, tb in enumerate(tracks):
            d = min(_angle(tb - b), _angle(tb - back))
            if d < best:
                best, k = d, i
        if best <= tolerance:
            out.append(k)
    return out


def match_faces(track_xy: np.ndarray | Sequence[Sequence[float]], faces: np.ndarray | Sequence[Sequence[float]], spec: CueSpec) -> list[int]:
    """Rows of the tracks that frontal faces (F, 2: bearing rad, distance m; robot frame) belong to: within
    ``face_bearing_tolerance`` of the face's bearing, or nearer the robot the angle ``leg_reach`` m spans there."""
    out: list[int] = []
    pts = track_xy.tolist() if isinstance(track_xy, np.ndarray) else list(track_xy)
    face_list = faces.tolist() if isinstance(faces, np.ndarray) else list(faces)
    if not pts or not face_list:
        return out
    off = spec.camera_offset
    tb = [math.atan2(y, x - off) for x, y in pts]
    td = np.hypot([x - off for x, _ in pts], [y for _, y in pts]).tolist()
    for b, dist in face_list:
        best, k = math.inf, -1
        # near the robot a person's track may sit on one leg, up to ``leg_reach`` m from her face's line (she
        # stands side-on to the laser at its elbow): the angle that offset spans there, if wider
        tol = max(spec.face_bearing_tolerance, math.atan2(spec.leg_reach, max(dist, 1e-3)))
        for i in range(len(pts)):
            db = _angle(tb[i] - b)
            if db <= tol and abs(td[i] - dist) <= spec.face_distance_tolerance * dist and db < best:
                best, k = db, i
        if k >= 0:
            out.append(k)
    return out
