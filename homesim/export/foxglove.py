"""The Foxglove message shapes homesim writes, as JSON Schemas, and builders for them.

Foxglove recognises a channel by its schema *name* (``foxglove.LaserScan``,
``foxglove.FrameTransforms``, ``foxglove.SceneUpdate``) and reads JSON
messages with those fields. The schemas here describe the fields homesim
fills (a subset of Foxglove's published ones, same names and meanings), so
a generic JSON-Schema validator can check every message we write. Times are
``{"sec", "nsec"}`` of virtual time.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from typing import Any

NUMBER = {"type": "number"}
TIME = {"type": "object", "title": "time", "properties": {"sec": {"type": "integer", "minimum": 0},
                                                          "nsec": {"type": "integer", "minimum": 0, "maximum": 999999999}},
        "required": ["sec", "nsec"]}
VECTOR3 = {"type": "object", "title": "foxglove.Vector3", "properties": {k: NUMBER for k in "xyz"}, "required": list("xyz")}
QUATERNION = {"type": "object", "title": "foxglove.Quaternion", "properties": {k: NUMBER for k in "xyzw"}, "required": list("xyzw")}
POSE = {"type": "object", "title": "foxglove.Pose", "properties": {"position": VECTOR3, "orientation": QUATERNION},
        "required": ["position", "orientation"]}
COLOR = {"type": "object", "title": "foxglove.Color", "properties": {k: NUMBER for k in "rgba"}, "required": list("rgba")}


def _obj(title: str, props: dict[str, Any], required: Sequence[str] = ()) -> dict[str, Any]:
    return {"title": title, "type": "object", "properties": props, "required": list(required)}


def _array(items: dict[str, Any]) -> dict[str, Any]:
    return {"type": "array", "items": items}


LASER_SCAN = _obj("foxglove.LaserScan", {
    "timestamp": TIME, "frame_id": {"type": "string"}, "pose": POSE, "start_angle": NUMBER, "end_angle": NUMBER,
    "ranges": _array(NUMBER), "intensities": _array(NUMBER)}, ["timestamp", "frame_id", "pose", "start_angle", "end_angle", "ranges"])
FRAME_TRANSFORMS = _obj("foxglove.FrameTransforms", {"transforms": _array(_obj("foxglove.FrameTransform", {
    "timestamp": TIME, "parent_frame_id": {"type": "string"}, "child_frame_id": {"type": "string"},
    "translation": VECTOR3, "rotation": QUATERNION}, ["timestamp", "parent_frame_id", "child_frame_id", "translation", "rotation"]))},
    ["transforms"])
_PRIMS = {
    "cubes": _obj("foxglove.CubePrimitive", {"pose": POSE, "size": VECTOR3, "color": COLOR}),
    "spheres": _obj("foxglove.SpherePrimitive", {"pose": POSE, "size": VECTOR3, "color": COLOR}),
    "cylinders": _obj("foxglove.CylinderPrimitive", {"pose": POSE, "size": VECTOR3, "bottom_scale": NUMBER, "top_scale": NUMBER, "color": COLOR}),
    "lines": _obj("foxglove.LinePrimitive", {"type": {"type": "integer", "enum": [0, 1, 2]}, "pose": POSE, "thickness": NUMBER,
                                             "scale_invariant": {"type": "boolean"}, "points": _array(VECTOR3), "color": COLOR}),
    "arrows": _obj("foxglove.ArrowPrimitive", {"pose": POSE, "shaft_length": NUMBER, "shaft_diameter": NUMBER, "head_length": NUMBER,
                                               "head_diameter": NUMBER, "color": COLOR}),
    "texts": _obj("foxglove.TextPrimitive", {"pose": POSE, "billboard": {"type": "boolean"}, "font_size": NUMBER,
                                             "scale_invariant": {"type": "boolean"}, "color": COLOR, "text": {"type": "string"}}),
}
SCENE_UPDATE = _obj("foxglove.SceneUpdate", {
    "deletions": _array(_obj("foxglove.SceneEntityDeletion", {"timestamp": TIME, "type": {"type": "integer", "enum": [0, 1]}, "id": {"type": "string"}})),
    "entities": _array(_obj("foxglove.SceneEntity", {"timestamp": TIME, "frame_id": {"type": "string"}, "id": {"type": "string"},
                                                    "frame_locked": {"type": "boolean"}, **{k: _array(v) for k, v in _PRIMS.items()}},
                            ["timestamp", "frame_id", "id"])),
}, ["entities"])
#: A bus message as homesim writes it on its own channel (one MCAP channel per bus channel).
BUS_MESSAGE = _obj("homesim.BusMessage", {
    "kind": {"type": "string", "enum": ["publish", "request", "reply", "error"]}, "sender": {"type": "string"},
    "id": {"type": "string"}, "receivers": _array({"type": "string"}), "causes": _array({"type": "string"}),
    "created": NUMBER, "xml": {"type": "string"},
    "attachments": {"type": "object", "additionalProperties": _obj("homesim.Attachment", {"sha256": {"type": "string"}, "dtype": {"type": "string"},
                                                                                          "shape": _array({"type": "integer"})})},
}, ["kind", "sender", "id", "receivers", "causes", "created", "xml"])

SCHEMAS: dict[str, dict[str, Any]] = {s["title"]: s for s in (LASER_SCAN, FRAME_TRANSFORMS, SCENE_UPDATE, BUS_MESSAGE)}


def dumps(obj: Any) -> bytes:
    """Canonical JSON bytes (sorted keys, no spaces): the same object gives the same bytes."""
    return json.dumps(obj, sort_keys=True, separators=(",", ":"), allow_nan=False, ensure_ascii=False).encode("utf-8")


def stamp(t_ns: int) -> dict[str, int]:
    return {"sec": t_ns // 1_000_000_000, "nsec": t_ns % 1_000_000_000}


def vec(x: float, y: float, z: float = 0.0) -> dict[str, float]:
    return {"x": float(x), "y": float(y), "z": float(z)}


def yaw(theta: float) -> dict[str, float]:
    """The quaternion of a rotation by ``theta`` about z."""
    return {"x": 0.0, "y": 0.0, "z": math.sin(theta / 2), "w": math.cos(theta / 2)}


def pose(x: float, y: float, z: float = 0.0, theta: float = 0.0) -> dict[str, Any]:
    return {"position": vec(x, y, z), "orientation": yaw(theta)}


def color(r: float, g: float, b: float, a: float = 1.0) -> dict[str, float]:
    return {"r": float(r), "g": float(g), "b": float(b), "a": float(a)}


def hex_color(h: str, a: float = 1.0) -> dict[str, float]:
    """``#rrggbb`` (or a few names) as a Foxglove colour; unknown names are grey."""
    h = h.strip()
    if h.startswith("#") and len(h) == 7:
        return color(int(h[1:3], 16) / 255, int(h[3:5], 16) / 255, int(h[5:7], 16) / 255, a)
    named = {"red": (0.85, 0.1, 0.1), "green": (0.1, 0.6, 0.2), "blue": (0.1, 0.3, 0.85), "yellow": (0.9, 0.8, 0.1),
             "white": (0.95, 0.95, 0.95), "black": (0.05, 0.05, 0.05)}
    return color(*named.get(h.lower(), (0.5, 0.5, 0.5)), a)


def transform(t_ns: int, parent: str, child: str, x: float, y: float, theta: float, z: float = 0.0) -> dict[str, Any]:
    return {"timestamp": stamp(t_ns), "parent_frame_id": parent, "child_frame_id": child, "translation": vec(x, y, z), "rotation": yaw(theta)}


def entity(t_ns: int, frame: str, eid: str, **prims: list[dict[str, Any]]) -> dict[str, Any]:
    return {"timestamp": stamp(t_ns), "frame_id": frame, "id": eid, "frame_locked": True, **prims}


def text(x: float, y: float, z: float, s: str, *, size: float = 14.0) -> dict[str, Any]:
    return {"pose": pose(x, y, z), "billboard": True, "font_size": size, "scale_invariant": True, "color": color(0.1, 0.1, 0.1), "text": s}
