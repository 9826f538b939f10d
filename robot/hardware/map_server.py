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
use; it lives in :mod:`robot.floorplan`, the robot's side, which imports nothing of
the world) and raises :class:`MapFormatError` on a reply it cannot read.
"""

from __future__ import annotations

import asyncio
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from lxml import etree

from homesim.message import Message
from homesim.module import Module
from homesim.geometry import polygon_area, split_wall, wrap_angle
from homesim.world.world import table_legs
from robot.floorplan import FloorPlan, MapFormatError, MapObstacle, MapRoom, MapWall, parse_map

__all__ = ["MAP_SCHEMA", "MapServer", "floor_plan", "map_element", "parse_map", "FloorPlan", "MapFormatError"]

if TYPE_CHECKING:
    from homesim.scenario.model import Scenario
    from homesim.sim import Simulation

#: The reply's schema (the request is not typed: any request gets the map).
MAP_SCHEMA = Path(__file__).resolve().parent.parent / "schemas" / "map.xsd"
SERVER = "map_server"
METHOD = "map"


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
