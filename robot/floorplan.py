"""The floor plan as the robot holds it: parsed from the ``map_server/map`` reply.

Robot modules (the localiser, the planner, the scene model) get the plan
only over the bus (docs/robot-contract.md); :func:`parse_map` turns the
reply's ``<map frame="map">`` element into a :class:`FloorPlan` and raises
:class:`MapFormatError`, naming the element and line, on a reply it cannot
read. This module imports nothing of the world: it is the robot's side.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from lxml import etree

from homesim import geometry
from homesim.errors import HomesimError


def wall_rectangle(a: tuple[float, float], b: tuple[float, float], thickness: float) -> np.ndarray:
    """The counter-clockwise rectangle (4, 2) of a wall piece from a to b, ``thickness`` wide."""
    try:
        return geometry.wall_rectangle(a, b, thickness)
    except ValueError as exc:
        raise MapFormatError(f"map: {exc}") from exc


class MapFormatError(HomesimError):
    """A map reply that does not describe a floor plan (wrong root, bad numbers, no start)."""


@dataclass(frozen=True)
class MapWall:
    """One solid wall piece: centre line a -> b and thickness (metres)."""

    x1: float
    y1: float
    x2: float
    y2: float
    thickness: float

    def rectangle(self) -> np.ndarray:
        """The piece's counter-clockwise footprint (4, 2)."""
        return wall_rectangle((self.x1, self.y1), (self.x2, self.y2), self.thickness)


@dataclass(frozen=True)
class MapObstacle:
    """A convex footprint standing from ``bottom`` to ``top`` metres."""

    name: str
    type: str
    points: tuple[tuple[float, float], ...]
    bottom: float
    top: float

    def polygon(self) -> np.ndarray:
        return np.array(self.points, dtype=float)


@dataclass(frozen=True)
class MapRoom:
    name: str
    points: tuple[tuple[float, float], ...]


@dataclass(frozen=True)
class FloorPlan:
    """The plan as plain data (map frame, metres, radians)."""

    walls: tuple[MapWall, ...]
    obstacles: tuple[MapObstacle, ...]
    rooms: tuple[MapRoom, ...]
    start: tuple[float, float, float]
    _cache: dict[float, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict, compare=False, repr=False)

    def polygons_at(self, z: float) -> list[np.ndarray]:
        """Footprints of everything whose vertical span contains height ``z`` (walls: all)."""
        out = [w.rectangle() for w in self.walls]
        out += [o.polygon() for o in self.obstacles if o.bottom <= z <= o.top]
        return out

    def segments_at(self, z: float) -> tuple[np.ndarray, np.ndarray]:
        """Edges (a, b), each (n, 2), of every footprint :meth:`polygons_at` ``z`` returns."""
        key = round(z, 3)
        got = self._cache.get(key)
        if got is None:
            polys = self.polygons_at(z)
            if polys:
                a = np.concatenate(polys)
                b = np.concatenate([np.roll(p, -1, axis=0) for p in polys])
            else:
                a = b = np.zeros((0, 2))
            got = self._cache[key] = (a, b)
        return got

    def bounds(self) -> tuple[float, float, float, float]:
        """(xmin, ymin, xmax, ymax) of walls, obstacles and rooms."""
        pts = [w.rectangle() for w in self.walls] + [o.polygon() for o in self.obstacles]
        pts += [np.array(r.points, dtype=float) for r in self.rooms]
        pts.append(np.array([self.start[:2]]))
        allp = np.concatenate(pts)
        return float(allp[:, 0].min()), float(allp[:, 1].min()), float(allp[:, 0].max()), float(allp[:, 1].max())


def _points_attr(el: etree._Element) -> tuple[tuple[float, float], ...]:
    out = []
    for tok in (el.get("points") or "").split():
        xs, _, ys = tok.partition(",")
        out.append((float(xs), float(ys)))
    if len(out) < 3:
        raise MapFormatError(f"map: <{el.tag}> on line {el.sourceline} needs at least three points")
    return tuple(out)


def parse_map(el: etree._Element) -> FloorPlan:
    """A ``<map>`` reply back into a :class:`FloorPlan`; MapFormatError names what is wrong."""
    if el.tag != "map" or el.get("frame") != "map":
        raise MapFormatError(f"map: expected <map frame=\"map\">, got <{el.tag} frame={el.get('frame')!r}>")
    walls, obstacles, rooms = [], [], []
    start = None
    try:
        for c in el:
            if not isinstance(c.tag, str):
                continue
            if c.tag == "wall":
                walls.append(MapWall(*(float(c.get(k)) for k in ("x1", "y1", "x2", "y2", "thickness"))))  # type: ignore[arg-type]
            elif c.tag == "obstacle":
                obstacles.append(MapObstacle(c.get("name", ""), c.get("type", ""), _points_attr(c), float(c.get("bottom")), float(c.get("top"))))  # type: ignore[arg-type]
            elif c.tag == "room":
                rooms.append(MapRoom(c.get("name", ""), _points_attr(c)))
            elif c.tag == "start":
                start = (float(c.get("x")), float(c.get("y")), float(c.get("theta")))  # type: ignore[arg-type]
            else:
                raise MapFormatError(f"map: unknown element <{c.tag}> on line {c.sourceline}")
    except (TypeError, ValueError) as e:
        raise MapFormatError(f"map: a missing or malformed number ({e})") from e
    if start is None:
        raise MapFormatError("map: no <start> pose")
    vals = [v for w in walls for v in (w.x1, w.y1, w.x2, w.y2, w.thickness)] + list(start)
    vals += [v for o in obstacles for p in o.points for v in p]
    if not all(math.isfinite(v) for v in vals):
        raise MapFormatError("map: a coordinate is not finite")
    return FloorPlan(tuple(walls), tuple(obstacles), tuple(rooms), start)
