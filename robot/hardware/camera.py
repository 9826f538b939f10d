"""Sony EVI-D31 pan-tilt camera: pure detection kernels on the world's geometry.

The camera sits at 1.41 m on the robot's top. Pan +-100 deg (up to 80
deg/s), tilt +-25 deg (up to 50 deg/s), horizontal field of view 48.8 deg
(vertical 37.6 deg, 4:3). What it reports, each a pure function here:

- faces: frontal only (the person looks at the camera within about
  +-30 deg), in the field of view, not occluded (3D sight lines against
  walls, furniture and other people, each with its height), 0.5-4 m away; bearing, distance from
  the face's size (noise grows with distance) and height;
- torsos: colour (RGB with noise) and bearing, any facing direction;
- pointing gestures: when the pointing hand is in view; the arm's
  direction in the robot frame;
- objects: type through a confusion model, colour, bearing, distance, and the
  object's extent across and up the image (its detection box, whole pixels).

Bearings are in the robot frame (0 ahead, + left). The module wrapper is
in :mod:`robot.hardware.camera_module`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from homesim.geometry import TWO_PI, wrap_angle
from homesim.world.raycast import sight_lines_clear
from homesim.world.world import World

Occluders = tuple[np.ndarray, np.ndarray, np.ndarray, list[str]]
# numpy's hypot on floats is libm's (math.hypot rounds differently in the last bit).
_hypot = np.hypot


@dataclass(frozen=True)
class CameraSpec:
    height: float = 1.41
    offset: float = 0.05  # metres ahead of the robot's centre
    hfov: float = math.radians(48.8)
    vfov: float = math.radians(37.6)
    pan_limit: float = math.radians(100)
    tilt_limit: float = math.radians(25)
    pan_speed: float = math.radians(80)
    tilt_speed: float = math.radians(50)
    face_range: tuple[float, float] = (0.5, 4.0)
    frontal: float = math.radians(30)
    torso_range: tuple[float, float] = (0.5, 5.0)
    gesture_range: float = 3.5
    object_range: tuple[float, float] = (0.3, 3.5)
    bearing_noise: float = math.radians(1.0)
    distance_noise: float = 0.06  # relative (face size -> distance)
    height_noise: float = 0.03
    colour_noise: float = 0.04
    direction_noise: float = math.radians(5.0)
    rate: float = 10.0
    image_width: int = 640  # pixels across hfov: an object's image extent is measured to a pixel


@dataclass
class PanTilt:
    """The pan-tilt unit's state and target (radians)."""

    pan: float = 0.0
    tilt: float = 0.0
    target_pan: float = 0.0
    target_tilt: float = 0.0


def ptu_step(ptu: PanTilt, dt: float, spec: CameraSpec) -> PanTilt:
    """Move towards the (clamped) target at most at the unit's speeds; returns a new state."""
    tp = _clip(ptu.target_pan, -spec.pan_limit, spec.pan_limit)
    tt = _clip(ptu.target_tilt, -spec.tilt_limit, spec.tilt_limit)
    pan = ptu.pan + _clip(tp - ptu.pan, -spec.pan_speed * dt, spec.pan_speed * dt)
    tilt = ptu.tilt + _clip(tt - ptu.tilt, -spec.tilt_speed * dt, spec.tilt_speed * dt)
    return PanTilt(pan, tilt, tp, tt)


def _clip(x: float, lo: float, hi: float) -> float:
    """``float(np.clip(x, lo, hi))`` for one float, without numpy's per-call cost."""
    return float(lo if x < lo else hi if x > hi else x)


def camera_point(pose: tuple[float, float, float], spec: CameraSpec) -> tuple[float, float, float]:
    x, y, th = pose
    return x + spec.offset * math.cos(th), y + spec.offset * math.sin(th), spec.height


def view_angles(cam: tuple[float, float, float], robot_heading: float, points: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Robot-frame bearing, elevation and 3D distance from the camera to points (N, 3)."""
    p = np.atleast_2d(np.asarray(points, dtype=float))
    d = p - np.asarray(cam)
    horiz = np.hypot(d[:, 0], d[:, 1])
    bearing = wrap_angle(np.arctan2(d[:, 1], d[:, 0]) - robot_heading)
    elev = np.arctan2(d[:, 2], horiz)
    return bearing, elev, np.hypot(horiz, d[:, 2])


def _look(cam: tuple[float, float, float], heading: float, p: tuple[float, float, float]) -> tuple[float, float, float]:
    """:func:`view_angles` for one point in plain floats (bit-identical: same operations, same libm)."""
    dx, dy, dz = p[0] - cam[0], p[1] - cam[1], p[2] - cam[2]
    horiz = float(_hypot(dx, dy))
    return (math.atan2(dy, dx) - heading + math.pi) % TWO_PI - math.pi, math.atan2(dz, horiz), float(_hypot(horiz, dz))


def _in_view(bearing: float, elev: float, ptu: PanTilt, spec: CameraSpec) -> bool:
    """:func:`in_field_of_view` for one direction in plain floats."""
    return abs((bearing - ptu.pan + math.pi) % TWO_PI - math.pi) <= spec.hfov / 2 and abs(elev - ptu.tilt) <= spec.vfov / 2


def in_field_of_view(bearing: np.ndarray, elev: np.ndarray, ptu: PanTilt, spec: CameraSpec) -> np.ndarray:
    """Whether robot-frame directions fall inside the image at the current pan and tilt."""
    return (np.abs(wrap_angle(bearing - ptu.pan)) <= spec.hfov / 2) & (np.abs(elev - ptu.tilt) <= spec.vfov / 2)


def visible(world: World, cam: tuple[float, float, float], points: np.ndarray, *, exclude: list[str | None], occluders: Occluders | None = None) -> np.ndarray:
    """Line of sight from the camera to each point (N, 3), in 3D.

    Walls, furniture (from its underside to its top) and people (upright
    cylinders as tall as they are) block a sight line only where the line,
    at its height there, passes through them: the camera looks over a
    child or a sofa at a face behind, and under a table top. ``exclude[i]``
    names the person point i belongs to (their own body does not hide it).
    ``occluders`` is ``world.person_cylinders()`` when the caller has it (once per frame).
    """
    p = np.atleast_2d(np.asarray(points, dtype=float))
    c, r, top, names = world.person_cylinders() if occluders is None else occluders
    skip = np.array([[n == ex for n in names] for ex in exclude], dtype=bool).reshape(p.shape[0], len(names))
    return sight_lines_clear(cam, p, world.prisms, c, r, top, skip=skip)


@dataclass(frozen=True)
class FaceDetection:
    bearing: float  # robot frame, radians
    distance: float
    height: float
    truth: str  # who it was (ground truth; kept out of bus messages)


@dataclass(frozen=True)
class TorsoDetection:
    bearing: float
    colour: tuple[float, float, float]
    truth: str


@dataclass(frozen=True)
class GestureDetection:
    """A pointing gesture: where the hand is and which way the arm points (robot frame)."""

    bearing: float  # of the hand
    distance: float
    direction: float  # of the arm, robot frame
    elevation: float  # of the arm (negative: pointing down)
    hand_height: float
    truth: str
    target: str


@dataclass(frozen=True)
class ObjectDetection:
    type: str
    colour: tuple[float, float, float]
    bearing: float
    distance: float
    truth: str
    width: float = 0.0  # rad: the object's extent across the image (whole pixels)
    height: float = 0.0  # rad: its extent up the image, from its bottom to its top (whole pixels)


@dataclass(frozen=True)
class Frame:
    """Everything one image shows, per percept kind (each in the order of the world's people or objects)."""

    faces: list[FaceDetection]
    torsos: list[TorsoDetection]
    gestures: list[GestureDetection]
    objects: list[ObjectDetection]


# --- candidates: in view and in range, in plain floats (a few people and objects, where numpy's
# per-call cost would dominate). Each is (who or what, the 3D point the sight line ends at,
# bearing, distance); who the line may pass through is the candidate's own person.
Candidate = tuple[Any, tuple[float, float, float], float, float]
Point = tuple[Any, tuple[float, float, float]]


def _face_points(world: World) -> list[Point]:
    return [(h, h.face_point()) for h in world.humans.values() if h.present]


def _torso_points(world: World) -> list[Point]:
    return [(h, (*h.position, h.torso_z)) for h in world.humans.values() if h.present]


def _hand_points(world: World) -> list[Point]:
    out = []
    for h in world.humans.values():
        hand = h.hand_point() if h.present else None
        if hand is not None and h.pointing is not None:
            out.append((h, hand))
    return out


def _object_points(world: World) -> list[Point]:
    return [(o, world.object_point(n)) for n, o in world.objects.items()]


def _looks(cam: tuple[float, float, float], heading: float, points: list[tuple[float, float, float]]) -> list[tuple[float, float, float]]:
    """:func:`_look` for many points, its two hypotenuses in one numpy call each (the same libm
    function per element, so the same floats)."""
    if not points:
        return []
    cx, cy, cz = cam
    dx = [p[0] - cx for p in points]
    dy = [p[1] - cy for p in points]
    dz = [p[2] - cz for p in points]
    horiz = _hypot(dx, dy)
    dist = _hypot(horiz, dz).tolist()
    return [((math.atan2(y, x) - heading + math.pi) % TWO_PI - math.pi, math.atan2(z, hz), d)
            for x, y, z, hz, d in zip(dx, dy, dz, horiz.tolist(), dist)]


def _face_ok(h: Any, f: tuple[float, float, float], b: float, e: float, d: float, cam: tuple[float, float, float], ptu: PanTilt, spec: CameraSpec) -> bool:
    lo, hi = spec.face_range
    to_cam = math.atan2(cam[1] - f[1], cam[0] - f[0])  # from the face to the camera vs where it looks
    return abs((h.gaze - to_cam + math.pi) % TWO_PI - math.pi) <= spec.frontal and _in_view(b, e, ptu, spec) and lo <= d <= hi


def _candidates(world: World, cam: tuple[float, float, float], heading: float, ptu: PanTilt, spec: CameraSpec, kinds: str) -> list[list[Candidate]]:
    """Per kind (letters of ``kinds``: f faces, t torsos, g gestures, o objects) the candidates,
    every point's direction computed in one batch."""
    sources = [{"f": _face_points, "t": _torso_points, "g": _hand_points, "o": _object_points}[k](world) for k in kinds]
    looks = iter(_looks(cam, heading, [p for src in sources for _, p in src]))
    out: list[list[Candidate]] = []
    for kind, src in zip(kinds, sources):
        cand: list[Candidate] = []
        for (who, p), (b, e, d) in zip(src, looks):
            if kind == "f":
                ok = _face_ok(who, p, b, e, d, cam, ptu, spec)
            elif kind == "t":
                ok = _in_view(b, e, ptu, spec) and spec.torso_range[0] <= d <= spec.torso_range[1]
            elif kind == "g":
                ok = _in_view(b, e, ptu, spec) and d <= spec.gesture_range
            else:
                ok = _in_view(b, e, ptu, spec) and spec.object_range[0] <= d <= spec.object_range[1]
                p = (p[0], p[1], p[2] + who.height / 2)  # its top: its own furniture does not hide it
            if ok:
                cand.append((who, p, b, d))
        out.append(cand)
    return out


def _seen(world: World, cam: tuple[float, float, float], groups: list[list[Candidate]], owners: list[bool], occluders: Occluders | None) -> list[list[Candidate]]:
    """The candidates of every group whose sight line is clear, in one pass of 3D sight lines
    (each line's answer does not depend on the others asked with it). ``owners[g]``: group g's
    candidates are people, whose own bodies do not hide their points."""
    points = [c[1] for g in groups for c in g]
    if not points:
        return groups
    exclude = [c[0].name if own else None for g, own in zip(groups, owners) for c in g]
    sight = visible(world, cam, np.array(points, dtype=float), exclude=exclude, occluders=occluders).tolist()
    out, k = [], 0
    for g in groups:
        out.append([c for c, ok in zip(g, sight[k : k + len(g)]) if ok])
        k += len(g)
    return out


# --- noise: drawn in the order of the candidates, per kind.
def _faces(cand: list[Candidate], spec: CameraSpec, rng: np.random.Generator | None) -> list[FaceDetection]:
    out = []
    for h, f, b, d in cand:
        z = float(f[2])
        if rng is not None:
            b += float(rng.normal(0.0, spec.bearing_noise))
            d *= float(1.0 + rng.normal(0.0, spec.distance_noise))
            z += float(rng.normal(0.0, spec.height_noise))
        out.append(FaceDetection(float(wrap_angle(b)), max(0.1, d), z, h.name))
    return out


def _torsos(cand: list[Candidate], spec: CameraSpec, rng: np.random.Generator | None) -> list[TorsoDetection]:
    out = []
    for h, _, b, _ in cand:
        rgb = h.torso
        if rng is not None:
            b += float(rng.normal(0.0, spec.bearing_noise * 2))
            rgb = _noisy_colour(rgb, rng.normal(0.0, spec.colour_noise, 3).tolist())
        out.append(TorsoDetection(float(wrap_angle(b)), (float(rgb[0]), float(rgb[1]), float(rgb[2])), h.name))
    return out


def _gestures(cand: list[Candidate], pose: tuple[float, float, float], spec: CameraSpec, rng: np.random.Generator | None) -> list[GestureDetection]:
    out = []
    for h, hand, b, d in cand:
        x, y = h.position
        arm = np.array(hand) - np.array([x, y, h.shoulder_z])
        direction = math.atan2(arm[1], arm[0]) - pose[2]
        arm_elev = math.atan2(arm[2], math.hypot(arm[0], arm[1]))
        if rng is not None:
            direction += float(rng.normal(0.0, spec.direction_noise))
            arm_elev += float(rng.normal(0.0, spec.direction_noise))
            b += float(rng.normal(0.0, spec.bearing_noise))
        out.append(GestureDetection(float(wrap_angle(b)), d, float(wrap_angle(direction)), arm_elev, float(hand[2]), h.name, h.pointing.target_name))
    return out


def _objects(cand: list[Candidate], types: list[str], confusion: float, spec: CameraSpec, rng: np.random.Generator | None,
             cam: tuple[float, float, float] | None = None) -> list[ObjectDetection]:
    out = []
    for o, top, b, d in cand:
        rgb = o.colour
        true_d = d
        if rng is not None:
            b += float(rng.normal(0.0, spec.bearing_noise))
            d *= float(1.0 + rng.normal(0.0, spec.distance_noise))
            rgb = _noisy_colour(rgb, rng.normal(0.0, spec.colour_noise, 3).tolist())
        out.append(ObjectDetection(confuse(o.type, types, confusion, rng), (float(rgb[0]), float(rgb[1]), float(rgb[2])), float(wrap_angle(b)), max(0.05, d), o.name,
                                   image_extent(o.size, true_d, spec), 0.0 if cam is None else image_rise(cam, top, o.height, spec)))
    return out


def image_rise(cam: tuple[float, float, float], top: tuple[float, float, float], height: float, spec: CameraSpec) -> float:
    """The angle (rad) an upright object ``height`` metres tall with its top at ``top`` spans up the
    image seen from ``cam``, in whole pixels (at least one): a detector's box is as tall as it is wide."""
    pixel = spec.vfov / (spec.image_width * 3 // 4)
    horiz = max(math.hypot(top[0] - cam[0], top[1] - cam[1]), 1e-3)
    rise = math.atan2(top[2] - cam[2], horiz) - math.atan2(top[2] - height - cam[2], horiz)
    return max(1, round(rise / pixel)) * pixel


def image_extent(size: float, distance: float, spec: CameraSpec) -> float:
    """The angle (rad) an object ``size`` metres across spans at ``distance``, in whole pixels (at
    least one): the image measures extents to a pixel, so the size the robot computes from it
    carries the distance's noise (and a pixel's, far away), as a real camera's does."""
    pixel = spec.hfov / spec.image_width
    return max(1, round(2 * math.atan2(size / 2, max(distance, 1e-3)) / pixel)) * pixel


def _noisy_colour(rgb: tuple[float, float, float], noise: list[float]) -> tuple[float, float, float]:
    """``np.clip(rgb + noise, 0, 1)`` in plain floats (the same sums, the same clipped values)."""
    return tuple(min(max(float(c) + n, 0.0), 1.0) for c, n in zip(rgb, noise))  # type: ignore[return-value]


def _object_types(world: World) -> list[str]:
    return sorted({o.type for o in world.objects.values()})


def detect_frame(world: World, pose: tuple[float, float, float], ptu: PanTilt, spec: CameraSpec, rng: np.random.Generator | None, *,
                 confusion: float = 0.05, occluders: Occluders | None = None) -> Frame:
    """Every percept kind of one image: the candidates of all kinds first, their sight lines in
    one pass, then each kind's noise in turn. The same detections, and the same random numbers
    in the same order, as :func:`detect_faces`, :func:`detect_torsos`, :func:`detect_gestures`
    and :func:`detect_objects` called one after the other."""
    cam = camera_point(pose, spec)
    groups = _candidates(world, cam, pose[2], ptu, spec, "ftgo")
    faces, torsos, gestures, objects = _seen(world, cam, groups, [True, True, True, False], occluders)
    return Frame(_faces(faces, spec, rng), _torsos(torsos, spec, rng), _gestures(gestures, pose, spec, rng),
                 _objects(objects, _object_types(world), confusion, spec, rng, cam))


def detect_faces(world: World, pose: tuple[float, float, float], ptu: PanTilt, spec: CameraSpec, rng: np.random.Generator | None,
                 *, occluders: Occluders | None = None) -> list[FaceDetection]:
    """Faces in frontal view, in the image, unoccluded and 0.5-4 m away."""
    cam = camera_point(pose, spec)
    (cand,) = _seen(world, cam, _candidates(world, cam, pose[2], ptu, spec, "f"), [True], occluders)
    return _faces(cand, spec, rng)


def detect_torsos(world: World, pose: tuple[float, float, float], ptu: PanTilt, spec: CameraSpec, rng: np.random.Generator | None,
                  *, occluders: Occluders | None = None) -> list[TorsoDetection]:
    """Torsos (clothing colour and bearing) of people in view, whichever way they face."""
    cam = camera_point(pose, spec)
    (cand,) = _seen(world, cam, _candidates(world, cam, pose[2], ptu, spec, "t"), [True], occluders)
    return _torsos(cand, spec, rng)


def detect_gestures(world: World, pose: tuple[float, float, float], ptu: PanTilt, spec: CameraSpec, rng: np.random.Generator | None,
                    *, occluders: Occluders | None = None) -> list[GestureDetection]:
    """Pointing gestures whose hand is in the image, unoccluded and near enough."""
    cam = camera_point(pose, spec)
    (cand,) = _seen(world, cam, _candidates(world, cam, pose[2], ptu, spec, "g"), [True], occluders)
    return _gestures(cand, pose, spec, rng)


def confuse(true_type: str, types: list[str], p: float, rng: np.random.Generator | None) -> str:
    """The confusion model: with probability ``p`` report another known type."""
    others = [t for t in types if t != true_type]
    if rng is None or not others or p <= 0 or rng.random() >= p:
        return true_type
    return others[int(rng.integers(len(others)))]


def detect_objects(world: World, pose: tuple[float, float, float], ptu: PanTilt, spec: CameraSpec, rng: np.random.Generator | None, *,
                   confusion: float = 0.05, occluders: Occluders | None = None) -> list[ObjectDetection]:
    """Objects in the image, unoccluded, 0.3-3.5 m away; types through :func:`confuse`."""
    cam = camera_point(pose, spec)
    (cand,) = _seen(world, cam, _candidates(world, cam, pose[2], ptu, spec, "o"), [False], occluders)
    return _objects(cand, _object_types(world), confusion, spec, rng, cam)
