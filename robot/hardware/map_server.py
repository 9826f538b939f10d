"""The map server: the robot's a-priori floor plan, as an operator gives it to a real robot.

A real BIRON is given a map of the flat before the home tour (a drawn floor
plan, or one an earlier run built): the walls with their door gaps, the
furniture's footprints and heights, the rooms, and where the robot starts.
This module plays that operator. It lives in ``robot/hardware`` because it
reads the scenario; every other robot module gets the plan only through the
RPC ``map_server/map`` (docs/robot-contract.md), whose reply is typed by
``robot/schemas/map.xsd``:

``<map frame="map"><wall x1 y1 x2 y2 thickness/>* <obstacle name type points bottom top/>*
<room name points/>* <start x y theta/></map>``

Walls are the solid pieces between door gaps (centre line and thickness);
a raised piece of furniture (a table) is its top (bottom = clearance) plus a
leg obstacle at each corner, so a consumer can cut the plan at any height
(the laser's 0.30 m sees walls, a sofa and table legs, never a table top).
The plan carries no people and no small objects: nothing that moves.

:func:`floor_plan` builds the plan from a scenario; :func:`parse_map` turns a
reply back into a :class:`FloorPlan` (what the localiser and the planner
use) and raises :class:`MapFormatError` on a reply it cannot read.
"""

from __future__ import annotations

import asyncio
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from lxml import etree

from homesim.errors import HomesimError
from homesim.message import Message
from homesim.module import Module
from homesim.world.geometry import polygon_area, split_wall, wall_rectangle, wrap_angle
from homesim.world.world import table_legs

if TYPE_CHECKING:
    from homesim.scenario.model import Scenario
    from homesim.sim import Simulation

#: The reply's schema (the request is not typed: any request gets the map).
MAP_SCHEMA = Path(__file__).resolve().parent.parent / "schemas" / "map.xsd"
SERVER = "map_server"
METHOD = "map"


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


def floor_plan(scenario: Scenario) -> FloorPlan:
    """The floor plan of ``scenario``: wall pieces between door gaps, furniture, legs, rooms, start."""
    walls: list[MapWall] = []
    for w in scenario.walls:
        for a, b in split_wall(w.start, w.end, [(d.at, d.width) for d in w.doors]):
            walls.append(MapWall(a[0], a[1], b[0], b[1], w.thickness))
    obstacles: list[MapObstacle] = []
    for f in scenario.furniture:
        obstacles.append(MapObstacle(f.name, f.type, _ccw(f.polygon), f.clearance, f.height))
        if f.clearance > 0:
            for i, leg in enumerate(table_legs(f)):
                obstacles.append(MapObstacle(f"{f.name}/leg{i + 1}", "leg", _ccw(leg), 0.0, f.clearance))
    rooms = tuple(MapRoom(r.name, tuple((float(x), float(y)) for x, y in r.polygon)) for r in scenario.rooms)
    r = scenario.robot
    return FloorPlan(tuple(walls), tuple(obstacles), rooms, (r.x, r.y, float(wrap_angle(r.heading))))


def _ccw(points) -> tuple[tuple[float, float], ...]:  # type: ignore[no-untyped-def]
    p = np.asarray(points, dtype=float)
    if polygon_area(p) < 0:
        p = p[::-1]
    return tuple((float(x), float(y)) for x, y in p)


def _num(v: float) -> str:
    return f"{v:.4f}"


def _pts(points: tuple[tuple[float, float], ...]) -> str:
    return " ".join(f"{x:.4f},{y:.4f}" for x, y in points)


def map_element(plan: FloorPlan) -> etree._Element:
    """The plan as the contract's ``<map frame="map">`` element."""
    root = etree.Element("map", frame="map")
    for w in plan.walls:
        etree.SubElement(root, "wall", x1=_num(w.x1), y1=_num(w.y1), x2=_num(w.x2), y2=_num(w.y2), thickness=_num(w.thickness))
    for o in plan.obstacles:
        etree.SubElement(root, "obstacle", name=o.name, type=o.type, points=_pts(o.points), bottom=_num(o.bottom), top=_num(o.top))
    for r in plan.rooms:
        etree.SubElement(root, "room", name=r.name, points=_pts(r.points))
    x, y, th = plan.start
    etree.SubElement(root, "start", x=_num(x), y=_num(y), theta=f"{min(max(th, -3.1416), 3.1416):.5f}")
    return root


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


class MapServer(Module):
    """Serves ``map_server/map``: every request gets the same plan (built once)."""

    def __init__(self, sim: Simulation, scenario: Scenario, *, name: str = SERVER) -> None:
        super().__init__(sim, name, host="robot")
        self.plan = floor_plan(scenario)
        self._reply = map_element(self.plan)
        self.bus.serve(METHOD, self._on_request, reply_schema=MAP_SCHEMA)

    def _on_request(self, msg: Message) -> etree._Element:
        return self._reply

    async def run(self) -> None:
        while True:
            self.beat()
            await asyncio.sleep(0.5)
