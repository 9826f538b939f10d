"""Helpers shared by the world and sensor tests: the sensor room and poses."""

from __future__ import annotations

import asyncio
import math
from pathlib import Path
from typing import Any

from lxml import etree

from homesim.scenario.loader import load_scenario
from homesim.scenario.model import Scenario
from homesim.world.world import World

HERE = Path(__file__).resolve().parent
ROOM = HERE / "scenarios" / "room.xml"
EXAMPLE = HERE.parent / "scenarios" / "two_people_radio.xml"

_cache: dict[Path, Scenario] = {}


def scenario(path: Path = ROOM) -> Scenario:
    """Load (once per session) a scenario file."""
    if path not in _cache:
        _cache[path] = load_scenario(path)
    return _cache[path]


def room() -> World:
    """A fresh world of the sensor room."""
    return World(scenario(ROOM))


def put_person(world: World, name: str, x: float, y: float, *, look_at: tuple[float, float] | None = None, heading: float | None = None) -> None:
    """Place a person standing still, facing a point or a heading (radians)."""
    h = world.humans[name]
    h.teleport(x, y)
    h.head = 0.0
    if look_at is not None:
        h.turn_to(math.atan2(look_at[1] - y, look_at[0] - x))
    elif heading is not None:
        h.turn_to(heading)
    h.advance(0.0)


def at_bearing(origin: tuple[float, float], heading: float, bearing: float, distance: float) -> tuple[float, float]:
    """The world point at a bearing (radians, + left) and distance from a pose."""
    a = heading + bearing
    return origin[0] + distance * math.cos(a), origin[1] + distance * math.sin(a)


def drive_base(stage: Any, v: float, w: float, *, period: float = 0.2, times: int | None = None) -> None:
    """Command the base like a navigation module would: a velocity every ``period`` s.

    Forever by default, or ``times`` commands (the base's watchdog then stops it).
    """
    driver = stage.sim.bus.participant("driver", host="robot")

    async def drive() -> None:
        n = 0
        while times is None or n < times:
            driver.publish("/robot/base/cmd", etree.Element("velocity", v=repr(v), w=repr(w)))
            n += 1
            await asyncio.sleep(period)

    stage.sim.spawn(drive(), name="driver")
