"""The 2005 demonstrator's object attention: objects taught from the verbal information only.

The COGNIRON deliverable on the home tour (D7.1.2, the "Robot Home-Tour" report) says
of the demonstrator: "BIRON currently only processes the verbal information
and does not have the COGNIRON functions for gesture recognition (CF-GR) and
object recognition (CF-OR) as well as the overall component for resolving
object references (CF-ROR) on-board". This module is the ``object_attention``
of the ``biron-2005`` profile (:mod:`robot.profiles`):

- on the ES order ``find_object`` it publishes ``<focus>`` at a fixed position
  (:data:`FIXED_BEARING`, :data:`FIXED_DISTANCE`: straight ahead, a table's
  distance away), so the person attention's Object state looks there whatever
  the user points at, for ``look_time`` s (the camera turning there and the
  user seeing it look);
- then it sends ``object_recognized`` with ``<OBJECT type name [owner] [use] [colour]>``
  and the frame's ``ATTRIBUTE`` / ``POSITION`` children: what the user said,
  and nothing seen (no position, no size, no visual features; a colour only as said);
- an utterance without an object type (``"this is mine"``) gives
  ``object_not_found`` with ``reason="no_type"``: there is nothing to store.

It reads no camera channel: it sees only its orders.
"""

from __future__ import annotations

import asyncio
from typing import Any

from lxml import etree

from homesim.message import Message
from homesim.module import Module

from robot.contract import ES_EVENTS, FOCUS

from .attention import ORDERS, _copy, wanted_from

#: Where the Object state looks (robot frame): straight ahead ...
FIXED_BEARING = 0.0
#: ... at a table in front of the robot (metres from the camera).
FIXED_DISTANCE = 1.2


class VerbalObjectAttention(Module):
    """``object_attention`` of the biron-2005 profile (see the module docstring)."""

    def __init__(self, sim: Any, *, name: str = "object_attention", look_time: float = 2.0) -> None:
        super().__init__(sim, name, host="robot")
        self.look_time = look_time
        self._search: asyncio.Task[None] | None = None
        self.bus.subscribe(ORDERS, self._on_order)

    async def run(self) -> None:
        while True:
            self.beat()
            await asyncio.sleep(0.5)

    def _on_order(self, msg: Message) -> None:
        if msg.xml.get("name") != "find_object":
            return
        if self._search is not None and not self._search.done():
            self._search.cancel()
        obj = None
        for p in msg.xml.iterfind("param"):
            if p.get("name") == "object":
                obj = p.find("OBJECT")
        self._search = self.sim.spawn(self.find(obj, msg.id), name=f"{self.name}:find")

    async def find(self, obj: etree._Element | None, cause: str) -> None:
        """Look at the fixed position for ``look_time`` s, then report what was said."""
        t_end = self.now + self.look_time
        while self.now < t_end - 1e-9:
            self.bus.publish(FOCUS, etree.Element("focus", bearing=f"{FIXED_BEARING:.2f}", distance=f"{FIXED_DISTANCE:.3f}"),
                             causes=(cause,))
            await asyncio.sleep(0.2)
        wanted = wanted_from(obj)
        if not wanted.type and not wanted.name:
            self.bus.publish(ES_EVENTS, etree.Element("event", name="object_not_found", reason="no_type"), causes=(cause,))
            return
        el = verbal_object(obj, wanted.type or wanted.name, wanted.name or wanted.type, wanted.owner, wanted.colour)
        ev = etree.Element("event", name="object_recognized")
        ev.append(el)
        self.bus.publish(ES_EVENTS, ev, causes=(cause,), transfer=True)


def verbal_object(obj: etree._Element | None, typ: str, name: str, owner: str, colour: str = "") -> etree._Element:
    """``<OBJECT type name [owner] [use] [colour] frame="map">`` + the frame's ATTRIBUTE/POSITION:
    what was said (a colour only if the user said one), no position."""
    el = etree.Element("OBJECT", type=typ, name=name)
    if owner:
        el.set("owner", owner)
    if colour:
        el.set("colour", colour)
    if obj is not None:
        use = obj.find("USE")
        if use is not None and use.get("name"):
            el.set("use", use.get("name", ""))
        elif obj.get("use"):
            el.set("use", obj.get("use", ""))
    el.set("frame", "map")
    if obj is not None:
        for tag in ("ATTRIBUTE", "POSITION"):
            for ch in obj.iterfind(tag):
                el.append(_copy(ch))
    return el
