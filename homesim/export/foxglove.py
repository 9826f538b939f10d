"""The Foxglove messages homesim writes: Foxglove's official JSON Schemas, and builders that fill them.

Foxglove recognises a channel by its schema *name* (``foxglove.LaserScan``,
``foxglove.FrameTransforms``, ``foxglove.SceneUpdate``, ``foxglove.PoseInFrame``,
``foxglove.Log``) and reads JSON messages with those fields. The schemas are
Foxglove's own, vendored verbatim from ``@foxglove/schemas`` (see
``foxglove_schemas/README.md``: no PyPI package carries the JSON Schemas), and
written into the MCAP as they are, so a viewer or a generic JSON-Schema
validator checks every message against what Foxglove publishes. The builders
fill every field the official schemas require (an entity's lifetime, metadata
and all eight primitive lists; a line's per-point colours and indices), so a
caller names only what it draws. Times are ``{"sec", "nsec"}`` of virtual time.

``homesim.BusMessage`` is homesim's own schema (one per bus channel); it is not
a Foxglove name, so Foxglove shows it in its raw-message and plot panels.
"""

from __future__ import annotations

import json
import math
from functools import cache
from importlib import resources
from typing import Any

#: The Foxglove schemas homesim writes (files in ``foxglove_schemas/``, named as upstream).
FOXGLOVE_SCHEMAS = ("FrameTransforms", "LaserScan", "Log", "PoseInFrame", "SceneUpdate")
#: Which ``@foxglove/schemas`` release the vendored files are.
FOXGLOVE_SCHEMAS_VERSION = "2.1.0"

#: Foxglove's log levels (foxglove.LogLevel).
INFO = 2
WARNING = 3
#: Foxglove's scene-entity deletion types (foxglove.SceneEntityDeletionType).
DELETE_ID = 0
DELETE_ALL = 1
#: Foxglove's line types (foxglove.LineType).
LINE_STRIP, LINE_LOOP, LINE_LIST = 0, 1, 2

_OBJ = {"type": "object"}
#: A bus message as homesim writes it on its own channel (one MCAP channel per bus channel).
BUS_MESSAGE: dict[str, Any] = {
    "title": "homesim.BusMessage", "type": "object",
    "properties": {
        "kind": {"type": "string", "enum": ["publish", "request", "reply", "error"]}, "sender": {"type": "string"},
        "id": {"type": "string"}, "receivers": {"type": "array", "items": {"type": "string"}},
        "causes": {"type": "array", "items": {"type": "string"}}, "created": {"type": "number"}, "xml": {"type": "string"},
        "attachments": {"type": "object", "additionalProperties": {
            "title": "homesim.Attachment", "type": "object",
            "properties": {"sha256": {"type": "string"}, "dtype": {"type": "string"}, "shape": {"type": "array", "items": {"type": "integer"}}},
            "required": ["sha256", "dtype", "shape"]}},
    },
    "required": ["kind", "sender", "id", "receivers", "causes", "created", "xml"],
}


@cache
def schema_bytes(name: str) -> bytes:
    """The schema called ``name`` (``foxglove.SceneUpdate``, ``homesim.BusMessage``) as written into an MCAP.

    Foxglove's come byte for byte from the vendored files; ours is canonical JSON.
    """
    if name.startswith("foxglove.") and name[9:] in FOXGLOVE_SCHEMAS:
        return resources.files(__package__).joinpath("foxglove_schemas", f"{name[9:]}.json").read_bytes()
    if name == BUS_MESSAGE["title"]:
        return dumps(BUS_MESSAGE)
    raise KeyError(f"no schema called {name!r}")


def schema(name: str) -> dict[str, Any]:
    """The schema called ``name`` as a JSON object (a fresh copy)."""
    return json.loads(schema_bytes(name))


#: Every schema name an export may use.
SCHEMA_NAMES = tuple(f"foxglove.{n}" for n in FOXGLOVE_SCHEMAS) + (BUS_MESSAGE["title"],)


def dumps(obj: Any) -> bytes:
    """Canonical JSON bytes (sorted keys, no spaces): the same object gives the same bytes."""
    return json.dumps(obj, sort_keys=True, separators=(",", ":"), allow_nan=False, ensure_ascii=False).encode("utf-8")


def topic(channel: str) -> str:
    """The MCAP topic of a bus channel: ROS-style, with one leading slash (RPC services have none on the bus)."""
    return "/" + channel.lstrip("/")


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


def transform(t_ns: int, parent: str, child: str, x: float, y: float, theta: float, z: float = 0.0) -> dict[str, Any]:
    """One ``foxglove.FrameTransform``: ``child`` in ``parent`` (planar pose, height ``z``)."""
    return {"timestamp": stamp(t_ns), "parent_frame_id": parent, "child_frame_id": child, "translation": vec(x, y, z), "rotation": yaw(theta)}


def pose_in_frame(t_ns: int, frame: str, x: float, y: float, theta: float) -> dict[str, Any]:
    """A ``foxglove.PoseInFrame``: a planar pose in ``frame``."""
    return {"timestamp": stamp(t_ns), "frame_id": frame, "pose": pose(x, y, 0.0, theta)}


def log(t_ns: int, name: str, message: str, *, level: int = INFO, file: str = "", line: int = 0) -> dict[str, Any]:
    """A ``foxglove.Log`` line: ``name`` (who) said or reported ``message``."""
    return {"timestamp": stamp(t_ns), "level": level, "message": message, "name": name, "file": file, "line": int(line)}


_PRIMITIVES = ("arrows", "cubes", "spheres", "cylinders", "lines", "triangles", "texts", "models")


def entity(t_ns: int, frame: str, eid: str, *, frame_locked: bool = True, lifetime_ns: int = 0,
           metadata: dict[str, str] | None = None, **prims: list[dict[str, Any]]) -> dict[str, Any]:
    """A ``foxglove.SceneEntity`` with the given primitives (the others empty).

    ``lifetime_ns`` 0 keeps it until replaced (same ``eid`` on the same topic)
    or deleted; ``metadata`` are key/value strings a viewer shows on selection.
    """
    unknown = set(prims) - set(_PRIMITIVES)
    if unknown:
        raise TypeError(f"not a scene primitive list: {sorted(unknown)}")
    ent: dict[str, Any] = {"timestamp": stamp(t_ns), "frame_id": frame, "id": eid, "frame_locked": frame_locked,
                           "lifetime": {"sec": lifetime_ns // 1_000_000_000, "nsec": lifetime_ns % 1_000_000_000},
                           "metadata": [{"key": k, "value": str(v)} for k, v in (metadata or {}).items()]}
    for p in _PRIMITIVES:
        ent[p] = list(prims.get(p, ()))
    return ent


def deletion(t_ns: int, eid: str | None = None) -> dict[str, Any]:
    """A ``foxglove.SceneEntityDeletion``: the entity ``eid`` on the topic, or (``None``) all of them."""
    return {"timestamp": stamp(t_ns), "type": DELETE_ALL if eid is None else DELETE_ID, "id": eid or ""}


def scene_update(entities: list[dict[str, Any]], deletions: list[dict[str, Any]] | None = None) -> dict[str, Any]:
    """A ``foxglove.SceneUpdate`` (deletions are applied before the entities)."""
    return {"deletions": list(deletions or ()), "entities": list(entities)}


def line(points: list[dict[str, float]], rgba: dict[str, float], *, kind: int = LINE_STRIP, thickness: float = 0.03,
         scale_invariant: bool = False) -> dict[str, Any]:
    """A ``foxglove.LinePrimitive`` of one colour through ``points`` (no per-point colours, no indices)."""
    return {"type": kind, "pose": pose(0, 0), "thickness": thickness, "scale_invariant": scale_invariant, "points": points,
            "color": rgba, "colors": [], "indices": []}


def text(x: float, y: float, z: float, s: str, *, size: float = 14.0) -> dict[str, Any]:
    """A ``foxglove.TextPrimitive``: ``s`` facing the camera at a fixed on-screen size."""
    return {"pose": pose(x, y, z), "billboard": True, "font_size": size, "scale_invariant": True, "color": color(0.1, 0.1, 0.1), "text": s}
