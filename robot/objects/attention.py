"""Object attention: find the object the partner shows, resolve the reference, report it to the ES.

Bus (docs/robot-contract.md). On the ES order ``find_object`` (on
``/robot/es/orders/object_attention``, param ``object`` = the speech frame's
``OBJECT``) the module

1. takes the partner's pointing ray (:mod:`robot.objects.gestures`: the camera
   sees pointing only while the hands are in its image; it waits up to
   ``gesture_wait`` s for one, then goes on without);
2. publishes ``<focus bearing distance/>`` on ``/robot/objects/focus`` (the
   region the ray comes down to, robot frame, every 0.2 s while looking) so
   the person attention turns the camera there;
3. collects ``/robot/camera/objects`` detections for ``look_time`` s, places
   each in the map frame with the localised pose (``/robot/localisation/pose``)
   and the floor plan's furniture heights (``map_server/map``), and merges them
   into candidates (:mod:`robot.objects.resolve`);
4. resolves the reference from the frame's type, name and colour, the
   pointing ray and the distance; when two or more fit about equally it asks
   the partner through the ES (event ``clarification``; the ES sends the dialog
   the condition ``ask``, "Do you mean the red cup or the blue one?", and the
   dialog's answer back as the order ``clarified``) and takes the answer;
5. sends ES event ``object_recognized`` with ``<OBJECT type name [owner]
   colour x y z frame="map">`` plus the colour features as an inline
   ``<attachment>`` (ES orders carry no binaries) and the frame's
   ``ATTRIBUTE`` / ``POSITION`` children, or ``object_not_found`` with
   ``reason`` = ``nothing_seen``, ``no_match``, ``unclear`` (the partner did
   not choose) or ``no_pose`` (no localisation yet).

Owner: "my" (``OWNER name="speaker"``) is stored as ``partner``: the robot
does not know names unless told ("this cup belongs to Anna" gives ``anna``).
A new ``find_object`` cancels a search in progress.
"""

from __future__ import annotations

import asyncio
import math
from typing import TYPE_CHECKING

from lxml import etree

from homesim.memory.protocol import attachment_element
from homesim.message import Message
from homesim.module import Module
from robot.floorplan import FloorPlan, parse_map

from robot.contract import ES_EVENTS, ES_ORDERS, FOCUS, GESTURES, OBJECTS, POSE

from .gestures import CAMERA_HEIGHT, CAMERA_OFFSET, GestureTracker, camera_to_map
from .resolve import Candidate, Resolution, Wanted, merge, option_texts, resolve

if TYPE_CHECKING:
    from homesim.sim import Simulation

ORDERS = f"{ES_ORDERS}/object_attention"

OWNER_WORDS = {"speaker": "partner", "my": "partner", "me": "partner", "mine": "partner"}


def wanted_from(obj: etree._Element | None) -> Wanted:
    """The speech frame's ``OBJECT`` (type, TITLE, COLOUR, OWNER, ATTRIBUTE) as a :class:`Wanted`."""
    if obj is None:
        return Wanted()

    def child(tag: str) -> str:
        el = obj.find(tag)
        return (el.get("name", "") if el is not None else "").strip().lower()

    owner = child("OWNER") or (obj.get("owner") or "").lower()
    return Wanted(
        type=(obj.get("type") or "").strip().lower(),
        name=child("TITLE") or (obj.get("name") or "").lower(),
        colour=child("COLOUR") or (obj.get("colour") or "").lower(),
        owner=OWNER_WORDS.get(owner, owner),
        attribute=child("ATTRIBUTE"),
    )


def _inside(px: float, py: float, poly: tuple[tuple[float, float], ...]) -> bool:
    inside = False
    n = len(poly)
    for i in range(n):
        (x1, y1), (x2, y2) = poly[i], poly[(i + 1) % n]
        if (y1 > py) != (y2 > py) and px < x1 + (py - y1) * (x2 - x1) / (y2 - y1):
            inside = not inside
    return inside


class ObjectAttention(Module):
    """Gestures + camera objects + localised pose -> the object meant (see the module docstring)."""

    def __init__(self, sim: Simulation, *, name: str = "object_attention", gesture_wait: float = 1.5, look_time: float = 2.0, ask_timeout: float = 8.0) -> None:
        super().__init__(sim, name, host="robot")
        self.gesture_wait = gesture_wait
        self.look_time = look_time
        self.ask_timeout = ask_timeout
        self.gestures = GestureTracker()
        self.pose: tuple[float, float, float] | None = None
        self.plan: FloorPlan | None = None
        self._looking = False
        self._seen: list[tuple[str, float, float, float, tuple[float, float, float]]] = []
        self._search: asyncio.Task[None] | None = None
        self._answer: asyncio.Future[etree._Element] | None = None  # waiting for the order "clarified"
        self.last: Resolution | None = None  # the latest resolution (for tests and introspection)
        self.bus.subscribe(ORDERS, self._on_order)
        self.bus.subscribe(GESTURES, self._on_gestures)
        self.bus.subscribe(OBJECTS, self._on_objects)
        self.bus.subscribe(POSE, self._on_pose)

    async def run(self) -> None:
        try:
            reply = await self.bus.call("map_server", "map", etree.Element("map_request"), timeout=1.0)
            self.plan = parse_map(reply.xml)
        except Exception:  # without a plan, objects are assumed on a table-high surface
            self.plan = None
        while True:
            self.beat()
            await asyncio.sleep(0.5)

    # ------------------------------------------------------------ percepts
    def _on_pose(self, msg: Message) -> None:
        x = msg.xml
        self.pose = (float(x.get("x")), float(x.get("y")), float(x.get("theta")))  # type: ignore[arg-type]

    def _on_gestures(self, msg: Message) -> None:
        if self.pose is None:
            return
        t = float(msg.xml.get("time", msg.created))  # type: ignore[arg-type]
        for p in msg.xml.iterfind("pointing"):
            self.gestures.add(t, self.pose, float(p.get("bearing")), float(p.get("distance")), float(p.get("direction")), float(p.get("elevation")), float(p.get("hand_height")))  # type: ignore[arg-type]

    def _on_objects(self, msg: Message) -> None:
        if not self._looking or self.pose is None:
            return
        for o in msg.xml.iterfind("object"):
            b, d = math.radians(float(o.get("bearing"))), float(o.get("distance"))  # type: ignore[arg-type]
            x, y, z = self.place(self.pose, b, d)
            self._seen.append((o.get("type", ""), x, y, z, (float(o.get("r")), float(o.get("g")), float(o.get("b")))))  # type: ignore[arg-type]

    def place(self, pose: tuple[float, float, float], bearing: float, distance: float) -> tuple[float, float, float]:
        """Map position of an object seen at ``bearing``/``distance``: first assume it stands on a
        table-high surface, then take the height of the plan's furniture under that point (or
        the floor) and place it again with that height."""
        z = 0.8
        x, y = camera_to_map(pose, bearing, distance, z)
        top = 0.0
        if self.plan is not None:
            for o in self.plan.obstacles:
                if o.type != "leg" and o.top < CAMERA_HEIGHT and _inside(x, y, o.points):
                    top = max(top, o.top)
        z = top + 0.05
        x, y = camera_to_map(pose, bearing, distance, z)
        return x, y, z

    # ------------------------------------------------------------ orders
    def _on_order(self, msg: Message) -> None:
        if msg.xml.get("name") == "clarified":  # the partner's answer to our question, through the ES
            answer = next((p.find("ANSWER") for p in msg.xml.iterfind("param") if p.find("ANSWER") is not None), None)
            if self._answer is not None and not self._answer.done() and answer is not None:
                self._answer.set_result(answer)
            return
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
        """One search (see the module docstring); always ends with an ES event."""
        wanted = wanted_from(obj)
        try:
            waited = 0.0
            while self.gestures.pointing(self.now) is None and waited < self.gesture_wait:
                await asyncio.sleep(0.1)
                waited += 0.1
            pointing = self.gestures.pointing(self.now)
            if self.pose is None:
                self._not_found("no_pose", cause)
                return
            self._seen = []
            self._looking = True
            t_end = self.now + self.look_time
            while self.now < t_end - 1e-9:
                self._publish_focus(cause)
                await asyncio.sleep(0.2)
            self._looking = False
            pose = self.pose
            cands = merge(self._seen, (pose[0], pose[1]), eye_height=CAMERA_HEIGHT)
            res = resolve(cands, wanted, pointing, (pose[0], pose[1]))
            self.last = res
            if res.kind == "none":
                self._not_found(res.reason, cause)
                return
            chosen = res.best
            if res.kind == "ambiguous":
                chosen = await self._ask(res.fitting()[:3], wanted, pose, cause)
                if chosen is None:
                    self._not_found("unclear", cause)
                    return
            assert chosen is not None
            self._recognized(chosen, wanted, obj, cause)
        finally:
            self._looking = False

    def _publish_focus(self, cause: str) -> None:
        pose = self.pose
        assert pose is not None
        target = self.gestures.target(self.now)
        if target is None:  # no gesture: look ahead and down, at a table in front of the robot
            bearing, dist = 0.0, 1.2
        else:
            dx, dy = target[0] - pose[0], target[1] - pose[1]
            bearing = math.remainder(math.atan2(dy, dx) - pose[2], 2 * math.pi)
            dist = max(0.3, math.hypot(dx, dy) - CAMERA_OFFSET)
        self.bus.publish(FOCUS, etree.Element("focus", bearing=f"{math.degrees(bearing):.2f}", distance=f"{dist:.3f}"), causes=(cause,))

    async def _ask(self, cands: list[Candidate], wanted: Wanted, pose: tuple[float, float, float], cause: str) -> Candidate | None:
        """Ask the partner which candidate they mean, through the ES (the papers' control flow):
        the event ``clarification`` (``<OPTIONS timeout><option index text/>+</OPTIONS>``) becomes the
        dialog's condition ``ask``; the dialog's answer comes back as the order ``clarified``
        (``<ANSWER index/>`` or ``none``). No answer within ``ask_timeout`` + 2 s: None."""
        texts = option_texts(cands, wanted, pose)
        opts = etree.Element("OPTIONS", timeout=f"{self.ask_timeout:g}")
        for i, t in enumerate(texts):
            etree.SubElement(opts, "option", index=str(i), text=t)
        ev = etree.Element("event", name="clarification")
        ev.append(opts)
        fut: asyncio.Future[etree._Element] = self.sim.loop.create_future()
        self._answer = fut
        self.bus.publish(ES_EVENTS, ev, causes=(cause,), transfer=True)
        try:
            async with asyncio.timeout(self.ask_timeout + 2.0):
                answer = await fut
        except TimeoutError:  # no dialog, or the ES did not route the question: the partner could not be asked
            return None
        finally:
            self._answer = None
        idx = answer.get("index")
        if answer.get("none") == "true" or idx is None or not idx.isdigit() or int(idx) >= len(cands):
            return None
        return cands[int(idx)]

    # ------------------------------------------------------------ results
    def _recognized(self, c: Candidate, wanted: Wanted, obj: etree._Element | None, cause: str) -> None:
        typ = wanted.type or c.type
        el = etree.Element("OBJECT", type=typ, name=wanted.name or typ)
        if wanted.owner:
            el.set("owner", wanted.owner)
        el.set("colour", wanted.colour or c.colour)
        el.set("x", f"{c.x:.3f}")
        el.set("y", f"{c.y:.3f}")
        el.set("z", f"{c.z:.3f}")
        el.set("frame", "map")
        if obj is not None:
            for tag in ("ATTRIBUTE", "USE", "POSITION"):  # USE: "my coffee cup" is for coffee
                for ch in obj.iterfind(tag):
                    el.append(_copy(ch))
        el.append(attachment_element("colour_features", c.features(), inline=True))
        ev = etree.Element("event", name="object_recognized")
        ev.append(el)
        self.bus.publish(ES_EVENTS, ev, causes=(cause,))

    def _not_found(self, reason: str, cause: str) -> None:
        self.bus.publish(ES_EVENTS, etree.Element("event", name="object_not_found", reason=reason), causes=(cause,))


def _copy(el: etree._Element) -> etree._Element:
    """A detached deep copy of an element, without its tail."""
    out = etree.Element(el.tag, dict(el.attrib))
    out.text = el.text
    for ch in el:
        if isinstance(ch.tag, str):
            out.append(_copy(ch))
    return out
