"""The scene model: BIRON's KB-manager over the object and place bases.

One participant, ``scene_model``, puts the knowledge bases behind one request
interface and routes every request to the right base:

* RPC ``scene_model/request`` (typed by ``homesim/schemas/memory.xsd``):
  ``<request kb="objects|places" op=...>`` as in :mod:`homesim.memory.protocol`;
  without ``kb`` the base is chosen by the document's tag (``OBJECT``/``PLACE``).
  Inserted and updated documents are made canonical and checked by their base
  first (``robot/schemas/knowledge.xsd``). Subscriptions publish
  ``<memory_event>`` on the channel the subscriber names.
* The ES's orders on ``/robot/es/orders/scene_model``: ``store_place`` (params
  ``place``: the speech frame's ``PLACE``; ``pose``: the localised ``POSE``),
  ``store_object`` (``object``: the object attention's ``OBJECT``) and
  ``query`` (``object``: the question's ``OBJECT`` frame). A query is answered
  ``cost`` seconds later with the ES event ``query_result`` carrying
  ``<RESULT found phrase><OBJECT/><PLACE/><FURNITURE/></RESULT>`` (see
  :mod:`robot.knowledge.where` for how the phrase is found).
* An order that cannot be carried out (a place without a pose, an object
  without a position) is refused on ``/robot/scene_model/refused`` with the
  reason, and nothing is stored.

Persistence: with ``store_dir`` the bases live in ``<store_dir>/scene_model.sqlite``
(:class:`homesim.memory.sqlite.SqliteStore`: loaded at start, every change
committed at once); without it they live in memory only and a run writes
nothing. The floor plan (room outlines, furniture) is asked of ``map_server``
once at start when one is on the bus.
"""

from __future__ import annotations

import asyncio
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from lxml import etree

import homesim
from homesim.errors import InputError, MemoryQueryError, RemoteCallTimeout, SchemaValidationError, UnknownParticipantError
from homesim.memory.core import Attachment
from homesim.memory.protocol import apply_request, reply
from homesim.memory.sqlite import SqliteStore
from homesim.message import Message
from homesim.module import Module

from robot.floorplan import MapFormatError

from robot.contract import ES_EVENTS, ES_ORDERS, SCENE_MODEL_REFUSED

from .bases import SCHEMA, KnowledgeBase, ObjectBase, PlaceBase, describe, said_position
from .where import Location, Plan, locate, parse_plan

NAME = "scene_model"
ORDERS = f"{ES_ORDERS}/{NAME}"
REFUSED = SCENE_MODEL_REFUSED
STORE_FILE = "scene_model.sqlite"
MEMORY_SCHEMA = Path(homesim.__file__).resolve().parent / "schemas" / "memory.xsd"  # shipped in the homesim package


class SceneModel(Module):
    """The KB-manager module (see the module docstring).

    ``store_dir``: directory of the persistent store (None: memory only).
    ``cost``: virtual seconds a query takes before its answer leaves.
    Raises :class:`MemoryStoreError` when the store is corrupt or newer.
    """

    def __init__(self, sim: Any, *, store_dir: str | os.PathLike[str] | None = None, name: str = NAME,
                 cost: float = 0.01, map_server: str | None = "map_server", heartbeat: float | None = 0.5) -> None:
        self.store = SqliteStore(Path(store_dir) / STORE_FILE) if store_dir is not None else None
        super().__init__(sim, name, heartbeat=heartbeat)
        self.objects = ObjectBase(store=self.store)
        self.places = PlaceBase(store=self.store)
        self.bases: dict[str, KnowledgeBase] = {"objects": self.objects, "places": self.places}
        self.cost = cost
        self.map_server = map_server
        self.plan: Plan | None = None
        self.refused = 0
        sim.bus.declare_channel(REFUSED, SCHEMA)
        self.bus.subscribe(ORDERS, self._on_order)
        self.bus.serve("request", self._on_request, request_schema=MEMORY_SCHEMA, reply_schema=MEMORY_SCHEMA)

    # ------------------------------------------------------------ main loop
    async def run(self) -> None:
        """Ask for the floor plan once, then beat."""
        if self.map_server is not None:
            await self._fetch_plan()
        while True:
            self.beat()
            await asyncio.sleep(self.heartbeat.interval if self.heartbeat else 1.0)

    async def _fetch_plan(self) -> None:
        try:
            msg = await self.bus.call(self.map_server, "map", etree.Element("map_request"), timeout=2.0)  # type: ignore[arg-type]
        except (UnknownParticipantError, RemoteCallTimeout):
            return  # no map server on this bus: rooms and furniture come from teaching only
        try:
            self.plan = parse_plan(msg.xml)
        except MapFormatError as exc:
            raise InputError(f"the map server's floor plan does not read: {exc}", source="<bus:map_server/map>") from exc

    def close(self) -> None:
        """Close the store (every change is already committed)."""
        if self.store is not None:
            self.store.close()

    # ------------------------------------------------------------ requests
    def _on_request(self, msg: Message) -> etree._Element:
        req = msg.xml
        kb = req.get("kb")
        if kb is None:
            child = next((c for c in req if isinstance(c.tag, str) and c.tag != "where"), None)
            kb = {"OBJECT": "objects", "PLACE": "places"}.get(child.tag if child is not None else "", "")
        base = self.bases.get(kb)
        if base is None:
            return reply(False, reason=f"no knowledge base {kb!r} (there are {sorted(self.bases)})")
        op = req.get("op")
        if op in ("insert", "update"):
            return self._write(base, req, msg.attachments)
        return apply_request(base.memory, req, msg.attachments, self._publish_event)

    def _write(self, base: KnowledgeBase, req: etree._Element, attachments: Mapping[str, Attachment]) -> etree._Element:
        docs = [c for c in req if isinstance(c.tag, str)]
        try:
            if len(docs) != 1:
                raise MemoryQueryError(f"<request op={req.get('op')!r}> needs exactly one document, got {len(docs)}")
            canon, att = base.canonical(docs[0], attachments, self.now)
            base.check(canon)
            if req.get("op") == "insert":
                doc_id = base.memory.insert(canon, att)
            else:
                doc_id = int(req.get("id", "0"))
                base.memory.update(doc_id, canon, att if att else None)
        except (MemoryQueryError, SchemaValidationError, ValueError) as exc:
            return reply(False, reason=getattr(exc, "message", str(exc)))
        out = reply(True, count=1)
        etree.SubElement(out, "doc", id=str(doc_id))
        return out

    def _publish_event(self, channel: str, xml: etree._Element, attachments: Mapping[str, Attachment]) -> None:
        if self.sim.bus.channel_schema(channel) is None:
            self.sim.bus.declare_channel(channel, MEMORY_SCHEMA)
        self.bus.publish(channel, xml, attachments=attachments, transfer=True)

    # -------------------------------------------------------------- orders
    def _on_order(self, msg: Message) -> None:
        order = msg.xml
        name = order.get("name")
        try:
            if name == "store_place":
                place = _param(order, "place", "PLACE")
                pose = _param(order, "pose", "POSE")
                if place is None:
                    raise MemoryQueryError("store_place without a PLACE")
                if pose is not None:
                    place.append(pose)
                self.places.store(place, now=self.now)
            elif name == "store_object":
                obj = _param(order, "object", "OBJECT")
                if obj is None:
                    raise MemoryQueryError("store_object without an OBJECT")
                self.objects.store(obj, now=self.now)
            elif name == "query":
                result = self.answer(_param(order, "object", "OBJECT"))
                self.sim.call_at(self.now + self.cost, self._send_result, result, msg.id)
            else:
                raise MemoryQueryError(f"unknown order {name!r} (the scene model knows store_place, store_object, query)")
        except (MemoryQueryError, SchemaValidationError) as exc:
            self.refused += 1
            self.bus.publish(REFUSED, etree.Element("refused", order=str(name), event=order.get("event", ""),
                                                    reason=getattr(exc, "message", str(exc))), causes=(msg.id,))

    def _send_result(self, result: etree._Element, cause: str) -> None:
        if self.bus.closed or self.bus.hung:
            return
        event = etree.Element("event", name="query_result")
        event.append(result)
        self.bus.publish(ES_EVENTS, event, causes=(cause,), transfer=True)

    # --------------------------------------------------------------- where
    def _location(self, obj: etree._Element) -> Location:
        """Where a stored object is: from its position (rooms and furniture), or what was said."""
        said = said_position(obj)
        if obj.get("x") is None:  # taught from speech alone: only what the user said about where it is
            return Location(furniture=said[1], relation=said[0] or "near", furniture_source="speech") if said else Location()
        return locate(float(obj.get("x")), float(obj.get("y")), self.places.taught(), self.plan,  # type: ignore[arg-type]
                      said=said)

    def answer(self, query: etree._Element | None) -> etree._Element:
        """The ``<RESULT>`` for a question's ``OBJECT`` frame (found or not), from memory only."""
        found = self.objects.find(query) if query is not None else []
        if not found:
            result = etree.Element("RESULT", found="false")
            if query is not None:
                result.append(query)
            return result
        obj = found[0].xml
        other = _other_owners(query, found)
        if other is not None and describe(other.xml)["owner"] == "partner":
            obj, other = other.xml, found[0]  # hers first: the speaker's own is the likelier meant
        loc = self._location(obj)
        result = etree.Element("RESULT", found="true", phrase=loc.phrase())
        if other is not None:
            # "where is the cup?" with her cup and her husband's stored, the question saying no owner:
            # both fit alike, so the answer says both, each with its owner ("Your cup is on the counter in
            # the kitchen, and husband's cup is on the desk in the study"), never one of them as "the cup"
            there = self._location(other.xml).phrase()
            if loc.phrase() and there:
                result.set("whose", _whose(obj).capitalize())
                result.set("also", f"{_whose(other.xml)} is {there}")
        result.append(obj)
        if loc.room is not None:
            place = etree.SubElement(result, "PLACE", name=loc.room, relation="in", source=loc.room_source or "")
            if loc.room_place is not None:
                place.set("x", f"{loc.room_place.x:.4f}")
                place.set("y", f"{loc.room_place.y:.4f}")
                place.set("theta", f"{loc.room_place.theta:.5f}")
        if loc.furniture is not None:
            etree.SubElement(result, "FURNITURE", name=loc.furniture, relation=loc.relation or "near",
                             source=loc.furniture_source or "")
        return result


def _whose(obj: etree._Element) -> str:
    """ "your cup", "husband's cup", "the cup": a stored object named with its owner, as the robot says it."""
    d = describe(obj)
    noun = d["name"] or d["type"].replace("_", " ")
    owner = d["owner"]
    if owner == "partner":
        return f"your {noun}"
    return f"{owner}'s {noun}" if owner else f"the {noun}"


def _other_owners(query: etree._Element, found: list[Any]) -> Any | None:
    """The second answer to a question that names no owner when the two best stored objects fit it
    alike (the same type and name) but belong to different owners: the question does not single one
    out. None otherwise (an owner asked for, one object, or the same owner)."""
    if describe(query)["owner"] or len(found) < 2:
        return None
    a, b = describe(found[0].xml), describe(found[1].xml)
    if (a["type"], a["name"]) != (b["type"], b["name"]) or a["owner"] == b["owner"]:
        return None
    return found[1]


def _param(order: etree._Element, name: str, tag: str) -> etree._Element | None:
    """The ``tag`` element inside ``<param name=name>`` (a copy, detached), or None."""
    for p in order.iterchildren("param"):
        if p.get("name") == name:
            el = p.find(tag)
            if el is not None:
                p.remove(el)
                el.tail = None
                return el
    return None
