"""Small objects of a generated flat: 3 to 15 of the lexicon's types, on furniture tops or the floor.

Each type has a realistic size and height, the colours it comes in, where it
stands (a surface, the floor or either) and, for some, the rooms it belongs
in (a kettle in a kitchen). Sometimes two similar objects (the same type)
stand side by side, 15 to 35 cm apart, in different colours or, now and then,
the same colour (the robot must then ask which one is meant). Objects never
stand inside a wall or a piece of furniture they are not on, and keep clear
of each other. A person can always stand 0.5 to 1.1 m from each of them, on
floor joined to the rest of the flat (never an object in a nook between a
wall and furniture, where nobody could point at it or show it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .flatgen import Flat, FurniturePlan, Rect, snap

#: type: (size, height, where ("surface" | "floor" | "both"), colours, rooms it belongs in (None: any))
KINDS: dict[str, tuple[float, float, str, tuple[str, ...], tuple[str, ...] | None]] = {
    "cup": (0.09, 0.1, "surface", ("red", "blue", "white", "yellow", "green", "black"), None),
    "glass": (0.07, 0.12, "surface", ("white", "grey", "blue"), ("kitchen", "dining room", "living room")),
    "bottle": (0.08, 0.3, "surface", ("green", "brown", "blue"), ("kitchen", "dining room", "living room")),
    "plant": (0.3, 0.5, "both", ("green",), None),
    "remote_control": (0.15, 0.03, "surface", ("black", "grey"), ("living room", "bedroom", "guest room")),
    "book": (0.2, 0.04, "surface", ("blue", "red", "green", "yellow", "brown"), None),
    "lamp": (0.25, 0.45, "surface", ("white", "yellow", "black"), None),
    "phone": (0.12, 0.02, "surface", ("black", "white"), None),
    "keys": (0.08, 0.02, "surface", ("grey",), None),
    "bag": (0.35, 0.3, "floor", ("brown", "black", "red"), None),
    "clock": (0.2, 0.2, "surface", ("white", "black"), None),
    "vase": (0.15, 0.3, "surface", ("blue", "white", "red"), None),
    "plate": (0.25, 0.03, "surface", ("white",), ("kitchen", "dining room")),
    "bowl": (0.18, 0.08, "surface", ("white", "red", "blue"), ("kitchen", "dining room", "living room")),
    "teapot": (0.2, 0.18, "surface", ("white", "brown"), ("kitchen", "dining room")),
    "kettle": (0.2, 0.25, "surface", ("white", "black", "grey"), ("kitchen",)),
    "computer": (0.35, 0.03, "surface", ("grey", "black"), ("study", "living room", "bedroom")),
    "glasses": (0.14, 0.04, "surface", ("black", "brown"), None),
    "ball": (0.22, 0.22, "floor", ("red", "blue", "yellow", "orange"), ("nursery", "living room", "corridor")),
    "toy": (0.25, 0.3, "both", ("brown", "pink", "yellow"), ("nursery", "living room", "guest room")),
    "umbrella": (0.3, 0.1, "floor", ("black", "blue", "red"), ("corridor",)),
    "shoes": (0.3, 0.12, "floor", ("black", "brown", "white"), ("corridor", "bedroom")),
}
SURFACE_MAX = 1.0  # metres: the robot's camera sees the tops of furniture up to about this height
GAP = 0.12  # metres between two objects' edges


@dataclass
class ObjectPlan:
    name: str
    type: str
    colour: str
    size: float
    height: float
    x: float
    y: float
    on: FurniturePlan | None
    room: int
    twin: str | None = None  # the name of a similar object right next to it


def generate_objects(rng: np.random.Generator, flat: Flat, *, count: int | None = None) -> list[ObjectPlan]:
    """``count`` (default 3 to 15) objects in the flat; see the module docstring."""
    n = int(rng.integers(3, 16)) if count is None else count
    out: list[ObjectPlan] = []
    names: set[str] = set()
    tries = 0
    while len(out) < n and tries < 400:
        tries += 1
        room = int(rng.integers(len(flat.rooms)))
        kind = flat.rooms[room].kind
        types = sorted(t for t, k in KINDS.items() if k[4] is None or kind in k[4])
        typ = types[int(rng.integers(len(types)))]
        size, height, where, colours, _ = KINDS[typ]
        colour = colours[int(rng.integers(len(colours)))]
        spot = _spot(rng, flat, room, size, where, out)
        if spot is None:
            continue
        x, y, piece = spot
        obj = ObjectPlan(_name(typ, colour, names), typ, colour, size, height, x, y, piece, room)
        names.add(obj.name)
        out.append(obj)
        if len(out) < n and rng.random() < 0.2:  # a similar one side by side
            twin_colour = colour if (len(colours) == 1 or rng.random() < 0.25) else next(
                c for c in (colours[int(i)] for i in rng.permutation(len(colours))) if c != colour)
            near = _beside(rng, flat, obj, out)
            if near is not None:
                twin = ObjectPlan(_name(typ, twin_colour, names), typ, twin_colour, size, height, near[0], near[1], piece, room, twin=obj.name)
                obj.twin = twin.name
                names.add(twin.name)
                out.append(twin)
    return out


def _name(typ: str, colour: str, names: set[str]) -> str:
    base = f"{colour} {typ.replace('_', ' ')}"
    if base not in names:
        return base
    k = 2
    while f"{base} {k}" in names:
        k += 1
    return f"{base} {k}"


def _clear_of(x: float, y: float, size: float, objs: list[ObjectPlan]) -> bool:
    return all(math.hypot(o.x - x, o.y - y) >= (o.size + size) / 2 + GAP for o in objs)


def _spot(rng: np.random.Generator, flat: Flat, room: int, size: float, where: str,
          objs: list[ObjectPlan]) -> tuple[float, float, FurniturePlan | None] | None:
    tops = [f for f in flat.furniture if f.room == room and f.surface and f.height <= SURFACE_MAX]
    on_floor = where == "floor" or (where == "both" and (not tops or rng.random() < 0.5))
    if not on_floor:
        if not tops:
            return None
        f = tops[int(rng.integers(len(tops)))]
        inner = f.rect.inset(size / 2 + 0.03)
        if inner.w <= 0 or inner.h <= 0:
            return None
        x, y = snap(float(rng.uniform(inner.x0, inner.x1))), snap(float(rng.uniform(inner.y0, inner.y1)))
        if not inner.contains((x, y)) or not _clear_of(x, y, size, objs) or not _within_reach(flat, x, y):
            return None
        return x, y, f
    # on the floor: near a wall or a piece of furniture (where people put things), never in a door's way
    room_plan = flat.rooms[room]
    part = room_plan.parts[int(rng.integers(len(room_plan.parts)))]
    inner = part.inset(0.05 + size / 2 + 0.08)
    if inner.w <= 0 or inner.h <= 0:
        return None
    side = int(rng.integers(4))
    t = float(rng.uniform(0, 1))
    x = inner.x0 + t * inner.w if side in (0, 2) else (inner.x0 if side == 3 else inner.x1)
    y = inner.y0 + t * inner.h if side in (1, 3) else (inner.y0 if side == 0 else inner.y1)
    x, y = snap(x), snap(y)
    if (not room_plan.contains((x, y)) or not _floor_free(flat, x, y, size) or not _clear_of(x, y, size, objs)
            or not _within_reach(flat, x, y)):
        return None
    return x, y, None


def _floor_free(flat: Flat, x: float, y: float, size: float) -> bool:
    """On the floor of the flat, not under or in furniture, not in a door's way, inside the walls."""
    r = size / 2 + 0.05
    box = Rect(x - r, y - r, x + r, y + r)
    if any(f.rect.overlaps(box) for f in flat.furniture):
        return False
    for d in flat.doors:
        dx, dy = d.point()
        if math.hypot(dx - x, dy - y) < d.width / 2 + 0.9:
            return False
    # clear of every wall piece (the walls are 0.1 m thick, centred on the room edges)
    return all(flat.rooms[k].contains(c) for k in [flat.room_at((x, y))] if k is not None for c in box.corners())


#: How far from an object a person may stand to show it (the ring :func:`_within_reach` tries).
REACH_RADII = (0.5, 0.7, 0.9, 1.1)


def _within_reach(flat: Flat, x: float, y: float) -> bool:
    """A person can stand 0.5-1.1 m from (x, y), on free floor inside a room of the flat joined to the rest of it.

    Checked on the flat's walking grid (a person's radius plus a margin, every piece of furniture
    blocking), so an object is never placed in a nook no one can get near (between a wall, the
    stove and a chair, say), whatever its room or its furniture. The grid covers the flat's bounding
    box, and floor outside the rooms is joined to the flat through its exit door: a standing point
    there does not count (review20 F3: seed 72's bowl on a counter was reachable only from outside the
    kitchen's outer walls).
    """
    grid = flat.walk_grid
    if grid is None:  # a flat not laid out by generate_flat (tests build some by hand)
        return True
    home = grid.component(flat.anchor)
    for r in REACH_RADII:
        for a in np.linspace(0, 2 * math.pi, 16, endpoint=False):
            p = (x + r * math.cos(a), y + r * math.sin(a))
            if flat.room_at(p) is not None and not grid.blocked[grid.cell_of(p)] and grid.component(p) == home:
                return True
    return False


def _beside(rng: np.random.Generator, flat: Flat, obj: ObjectPlan, objs: list[ObjectPlan]) -> tuple[float, float] | None:
    """A spot 15-35 cm (edge to edge) from ``obj`` on the same top (or floor)."""
    for _ in range(16):
        a = float(rng.uniform(0, 2 * math.pi))
        d = obj.size + float(rng.uniform(0.15, 0.35))
        x, y = snap(obj.x + d * math.cos(a)), snap(obj.y + d * math.sin(a))
        others = [o for o in objs if o is not obj]
        if not _clear_of(x, y, obj.size, others) or math.hypot(x - obj.x, y - obj.y) < obj.size + 0.12:
            continue
        if obj.on is not None:
            if obj.on.rect.inset(obj.size / 2 + 0.03).contains((x, y)) and _within_reach(flat, x, y):
                return x, y
        elif flat.room_at((x, y)) == obj.room and _floor_free(flat, x, y, obj.size) and _within_reach(flat, x, y):
            return x, y
    return None
