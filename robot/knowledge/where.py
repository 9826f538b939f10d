"""Where an object is, in words: "on the table in the living room".

Pure functions over the robot's own knowledge: the object's stored position
(map frame, from the object attention's estimate), the places it was taught
(a name and the pose where the robot stood when told), and, when the map
server answered, the a-priori floor plan (room outlines, furniture footprints
with their heights and types). Never the world.

How the answer is built:

* **room**: with a floor plan, the room outline that contains the object; it
  is named by a place taught inside the same outline (a room word such as
  "kitchen" first, the nearest pose among equals), else by the plan's own
  name for it. Without a plan: the nearest taught room-like place within
  :data:`ROOM_REACH` metres. A room is never named across a wall from a
  place taught in another room.
* **furniture**: with a plan, the footprint (not a table leg) that contains
  the object, or whose edge is within :data:`ON_MARGIN` of it: "on" a surface
  (a top at least :data:`SURFACE_MIN` m high), "next to" anything else; named
  by its type. Otherwise what the user said when teaching ("at the window"),
  else the nearest taught landmark place (not a room word) within
  :data:`LANDMARK_REACH` metres.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from lxml import etree

from robot.floorplan import parse_map

#: Words that name rooms (a taught place with one of them, or containing "room", is a room).
ROOM_WORDS = frozenset({
    "kitchen", "living room", "bedroom", "bathroom", "hall", "hallway", "corridor", "dining room",
    "office", "study", "lobby", "entrance", "toilet", "garage", "nursery", "lounge", "workshop",
    "laundry", "pantry", "cellar", "attic", "landing", "porch", "balcony", "terrace",
})
#: Furniture one puts things "on" (beside the height test for map footprints).
SURFACES = frozenset({
    "table", "desk", "shelf", "counter", "worktop", "cupboard", "sideboard", "dresser", "windowsill",
    "bench", "chair", "sofa", "couch", "bed", "stove", "cooker", "fridge", "cabinet", "nightstand",
    "bookshelf", "tv stand", "coffee table", "dining table",
})
ROOM_REACH = 6.0
LANDMARK_REACH = 1.5
ON_MARGIN = 0.10
SURFACE_MIN = 0.20


@dataclass(frozen=True)
class TaughtPlace:
    """A place as stored: its name and the robot's pose when told (map frame)."""

    name: str
    x: float
    y: float
    theta: float = 0.0

    @property
    def is_room(self) -> bool:
        return is_room_word(self.name)


@dataclass(frozen=True)
class Footprint:
    """A piece of furniture from the floor plan."""

    name: str
    type: str
    points: np.ndarray  # (n, 2)
    bottom: float
    top: float


@dataclass(frozen=True)
class Outline:
    """A room outline from the floor plan."""

    name: str
    points: np.ndarray  # (n, 2)


@dataclass(frozen=True)
class Plan:
    """What the knowledge needs of the floor plan."""

    rooms: tuple[Outline, ...]
    furniture: tuple[Footprint, ...]


@dataclass(frozen=True)
class Location:
    """The answer: a room (name, where its name came from) and furniture (relation, name, source)."""

    room: str | None = None
    room_source: str | None = None  # "place" (taught) or "map"
    room_place: TaughtPlace | None = None
    furniture: str | None = None
    relation: str | None = None
    furniture_source: str | None = None  # "map", "speech" or "place"

    def phrase(self) -> str:
        """E.g. "on the table in the living room"; "" when nothing is known."""
        parts = []
        if self.furniture:
            parts.append(f"{self.relation} the {self.furniture}")
        if self.room:
            parts.append(f"in the {self.room}")
        return " ".join(parts)


def is_room_word(name: str) -> bool:
    n = " ".join(name.lower().split())
    return n in ROOM_WORDS or n.endswith(" room") or n == "room"


def point_in_polygon(x: float, y: float, poly: np.ndarray) -> bool:
    """Even-odd rule (points on an edge may fall either way)."""
    px, py = poly[:, 0], poly[:, 1]
    qx, qy = np.roll(px, -1), np.roll(py, -1)
    crosses = (py > y) != (qy > y)
    with np.errstate(divide="ignore", invalid="ignore"):
        xs = px + (y - py) * (qx - px) / (qy - py)
    return bool(np.count_nonzero(crosses & (x < xs)) % 2)


def distance_to_polygon(x: float, y: float, poly: np.ndarray) -> float:
    """0 inside, else the distance to the nearest edge."""
    if point_in_polygon(x, y, poly):
        return 0.0
    a = poly
    b = np.roll(poly, -1, axis=0)
    ab = b - a
    ap = np.array([x, y]) - a
    t = np.clip(np.einsum("ij,ij->i", ap, ab) / np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-12), 0.0, 1.0)
    d = ap - ab * t[:, None]
    return float(np.sqrt(np.einsum("ij,ij->i", d, d)).min())


def parse_plan(el: etree._Element) -> Plan:
    """The parts of a ``map_server/map`` reply the knowledge uses: room outlines and furniture
    (table legs left out). Raises :class:`robot.floorplan.MapFormatError` on a reply that does not read."""
    fp = parse_map(el)
    rooms = tuple(Outline(r.name, np.array(r.points, dtype=float)) for r in fp.rooms)
    furniture = tuple(Footprint(o.name, o.type, o.polygon(), o.bottom, o.top) for o in fp.obstacles if o.type != "leg")
    return Plan(rooms, furniture)


def _nearest(places: Sequence[TaughtPlace], x: float, y: float) -> tuple[TaughtPlace | None, float]:
    best, best_d = None, math.inf
    for p in places:  # first taught wins ties: deterministic
        d = math.hypot(p.x - x, p.y - y)
        if d < best_d:
            best, best_d = p, d
    return best, best_d


def locate(x: float, y: float, places: Sequence[TaughtPlace], plan: Plan | None = None, *,
           said: tuple[str, str] | None = None) -> Location:
    """Where the object at (x, y) is (see the module docstring). ``said``: (relation, landmark) from teaching."""
    room = room_source = None
    room_place = None
    if plan is not None and plan.rooms:
        outline = next((r for r in plan.rooms if point_in_polygon(x, y, r.points)), None)
        if outline is not None:
            inside = [p for p in places if point_in_polygon(p.x, p.y, outline.points)]
            rooms_inside = [p for p in inside if p.is_room]
            room_place, _ = _nearest(rooms_inside or inside, x, y)
            if room_place is not None and room_place.is_room:
                room, room_source = room_place.name, "place"
            elif outline.name:
                room, room_source, room_place = outline.name, "map", None
    else:
        room_place, d = _nearest([p for p in places if p.is_room], x, y)
        if room_place is not None and d <= ROOM_REACH:
            room, room_source = room_place.name, "place"
        else:
            room_place = None

    furniture = relation = fsource = None
    if plan is not None:
        best = None
        for f in plan.furniture:
            d = distance_to_polygon(x, y, f.points)
            if d <= ON_MARGIN and (best is None or d < best[0] or (d == best[0] and f.top > best[1].top)):
                best = (d, f)
        if best is not None:
            f = best[1]
            furniture = f.type or f.name
            relation = "on" if f.top >= SURFACE_MIN or f.type in SURFACES else "next to"
            fsource = "map"
    if furniture is None and said is not None and said[1]:
        relation, furniture, fsource = (said[0] or "near"), said[1], "speech"
    if furniture is None:
        landmark, d = _nearest([p for p in places if not p.is_room], x, y)
        if landmark is not None and d <= LANDMARK_REACH:
            furniture = landmark.name
            relation = "on" if landmark.name.lower() in SURFACES else "near"
            fsource = "place"
    return Location(room, room_source, room_place, furniture, relation, fsource)
