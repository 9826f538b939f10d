"""Generated flats: rooms of different shapes joined by doors, furniture, named places.

:func:`generate_flat` draws a flat from a seeded ``numpy.random.Generator``:
2 to 6 rooms laid out in a row, an L, along a corridor or as a random tree of
rooms attached to each other's walls; rooms are rectangles or L-shapes (a
rectangle with a corner cut away), corridors are 1.0 to 1.4 m wide. Each room
joined to the flat gets a door 0.9 to 1.4 m wide in the wall it shares with
the room it was attached to; the first room has the front door (an exit).
Furniture stands against the walls or free in the room: pieces that block
(sofa, shelf, counter, bed, cupboard) and pieces the laser at 0.30 m passes
under (tables and desks on legs, chairs). A piece is kept only if the robot
(with a margin) can still get from every door to every other door and to
the middle of every room: nothing generated is unreachable.

All coordinates are multiples of 5 cm, so the files are short and byte-stable.
Pure data out (:class:`Flat`); :mod:`homesim.tour.generate` writes the XML.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..geometry import point_in_polygon, polygon_centroid
from ..scenario.pathplan import Grid

Point = tuple[float, float]

GRID = 0.05  # metres: every generated coordinate is a multiple of this
WALL = 0.1  # wall thickness
DOOR_MIN, DOOR_MAX = 0.9, 1.4  # the range of door widths
EXIT_MIN, EXIT_MAX = 0.9, 1.1
DOOR_STUB = 0.3  # wall left at least either side of a door gap
CORRIDOR_MIN, CORRIDOR_MAX = 1.0, 1.4
ROBOT_CLEARANCE = 0.36  # the robot's radius (0.30) plus a margin: free space it must be able to use
KEEP_OUT = 1.1  # metres in front of a door (both sides) where no furniture stands


def snap(v: float) -> float:
    """Round to the 5 cm grid (and kill -0.0)."""
    return round(round(v / GRID) * GRID, 2) + 0.0


@dataclass(frozen=True)
class Rect:
    x0: float
    y0: float
    x1: float
    y1: float

    @property
    def w(self) -> float:
        return self.x1 - self.x0

    @property
    def h(self) -> float:
        return self.y1 - self.y0

    def overlaps(self, o: Rect, eps: float = 1e-6) -> bool:
        """Positive-area overlap (touching edges do not count)."""
        return self.x0 < o.x1 - eps and o.x0 < self.x1 - eps and self.y0 < o.y1 - eps and o.y0 < self.y1 - eps

    def inset(self, m: float) -> Rect:
        return Rect(self.x0 + m, self.y0 + m, self.x1 - m, self.y1 - m)

    def contains(self, p: Point, eps: float = 1e-9) -> bool:
        return self.x0 - eps <= p[0] <= self.x1 + eps and self.y0 - eps <= p[1] <= self.y1 + eps

    def corners(self) -> tuple[Point, ...]:
        return ((self.x0, self.y0), (self.x1, self.y0), (self.x1, self.y1), (self.x0, self.y1))


@dataclass
class RoomPlan:
    """A room: its kind (a word for what it is), the name the user calls it, its parts."""

    kind: str  # kitchen, living room, ..., corridor
    name: str
    parts: list[Rect]  # one rectangle, or two for an L-shape
    polygon: tuple[Point, ...]

    @property
    def corridor(self) -> bool:
        return self.kind == "corridor"

    def contains(self, p: Point) -> bool:
        return point_in_polygon(p, np.array(self.polygon))

    def area(self) -> float:
        return sum(r.w * r.h for r in self.parts)


@dataclass
class DoorPlan:
    """A door on the line ``axis`` = ``coord`` (axis "x": a vertical wall at x = coord), centred at ``centre`` along it."""

    axis: str
    coord: float
    centre: float
    width: float
    rooms: tuple[int, ...]  # the room(s) it joins (one for the exit)
    name: str
    exit: bool = False

    def point(self) -> Point:
        return (self.coord, self.centre) if self.axis == "x" else (self.centre, self.coord)

    def sides(self, d: float = 0.7) -> tuple[Point, Point]:
        """Two points ``d`` from the gap's centre, straight through it."""
        x, y = self.point()
        return ((x - d, y), (x + d, y)) if self.axis == "x" else ((x, y - d), (x, y + d))


@dataclass
class WallPlan:
    start: Point
    end: Point
    doors: list[tuple[float, DoorPlan]] = field(default_factory=list)  # (at, door)


@dataclass
class FurniturePlan:
    name: str
    type: str
    rect: Rect
    height: float
    clearance: float = 0.0
    leg: float = 0.05
    room: int = 0
    surface: bool = False  # objects can stand on it (a table top, a counter)

    @property
    def blocks_laser(self) -> bool:
        return self.clearance <= 0.30


@dataclass
class Flat:
    layout: str
    rooms: list[RoomPlan]
    doors: list[DoorPlan]
    walls: list[WallPlan]
    furniture: list[FurniturePlan]
    places: list[tuple[str, Point, int]]  # name, where, room index
    grid: Grid | None = None  # free space for the robot (ROBOT_CLEARANCE)
    walk_grid: Grid | None = None  # free space for a person
    anchor: Point = (0.0, 0.0)  # a point every reachable place is connected to (the middle of the first room)

    def room_at(self, p: Point) -> int | None:
        for k, r in enumerate(self.rooms):
            if r.contains(p):
                return k
        return None


# ------------------------------------------------------------------ rooms
#: Room kinds (what the user calls a room: each a word of the home tour; some have more than one
#: word a user may use, e.g. a study is also called an office).
ROOM_WORDS: dict[str, tuple[str, ...]] = {
    "kitchen": ("kitchen",),
    "living room": ("living room", "lounge", "sitting room"),
    "bedroom": ("bedroom",),
    "bathroom": ("bathroom",),
    "dining room": ("dining room",),
    "study": ("study", "office"),
    "guest room": ("guest room",),
    "nursery": ("nursery",),
    "laundry": ("laundry",),
}
CORRIDOR_WORDS = ("hall", "hallway", "corridor")


def _l_polygon(r: Rect, corner: int, cw: float, ch: float) -> tuple[tuple[Point, ...], list[Rect]]:
    """A rectangle with a cw x ch corner cut away (corner 0..3: SW, SE, NE, NW), counter-clockwise, and its two parts."""
    x0, y0, x1, y1 = r.x0, r.y0, r.x1, r.y1
    if corner == 0:
        poly = ((x0 + cw, y0), (x1, y0), (x1, y1), (x0, y1), (x0, y0 + ch), (x0 + cw, y0 + ch))
        parts = [Rect(x0 + cw, y0, x1, y0 + ch), Rect(x0, y0 + ch, x1, y1)]
    elif corner == 1:
        poly = ((x0, y0), (x1 - cw, y0), (x1 - cw, y0 + ch), (x1, y0 + ch), (x1, y1), (x0, y1))
        parts = [Rect(x0, y0, x1 - cw, y0 + ch), Rect(x0, y0 + ch, x1, y1)]
    elif corner == 2:
        poly = ((x0, y0), (x1, y0), (x1, y1 - ch), (x1 - cw, y1 - ch), (x1 - cw, y1), (x0, y1))
        parts = [Rect(x0, y0, x1, y1 - ch), Rect(x0, y1 - ch, x1 - cw, y1)]
    else:
        poly = ((x0, y0), (x1, y0), (x1, y1), (x0 + cw, y1), (x0 + cw, y1 - ch), (x0, y1 - ch))
        parts = [Rect(x0, y0, x1, y1 - ch), Rect(x0 + cw, y1 - ch, x1, y1)]
    return poly, parts


def _u(rng: np.random.Generator, lo: float, hi: float) -> float:
    """A uniform draw on the 5 cm grid (an empty range from rounding, hi a hair below lo, is the point lo)."""
    if hi < lo and lo - hi < 1e-6:
        hi = lo
    return snap(float(rng.uniform(lo, hi)))


def _edges(room: RoomPlan) -> list[tuple[str, float, float, float, int]]:
    """Boundary edges of a room: (axis, coord, lo, hi, outward sign); axis "x": a vertical edge at x = coord."""
    out = []
    poly = room.polygon
    n = len(poly)
    for i in range(n):
        (ax, ay), (bx, by) = poly[i], poly[(i + 1) % n]
        # counter-clockwise polygon: the outside is to the right of a -> b
        if abs(ax - bx) < 1e-9:
            out.append(("x", ax, min(ay, by), max(ay, by), 1 if by > ay else -1))
        else:
            out.append(("y", ay, min(ax, bx), max(ax, bx), -1 if bx > ax else 1))
    return out


def _room_shape(rng: np.random.Generator, kind: str, w: float, h: float) -> tuple[float, float]:
    return w, h


def _new_room_rect(rng: np.random.Generator, edge: tuple[str, float, float, float, int], corridor: bool,
                   door: float) -> Rect | None:
    """A rectangle outside ``edge`` sharing at least door + stubs of it."""
    axis, c, lo, hi, sign = edge
    need = door + 2 * DOOR_STUB + 0.1
    if hi - lo < need:
        return None
    if corridor:
        across = _u(rng, CORRIDOR_MIN, CORRIDOR_MAX)
        along = _u(rng, max(need, 3.5), 7.5)
    else:
        across = _u(rng, 2.6, 5.0)
        along = _u(rng, max(need, 2.6), 5.5)
    # the new room's span along the edge overlaps [lo, hi] by at least `need`
    start_lo, start_hi = lo - along + need, hi - need
    if start_hi < start_lo:
        return None
    s = _u(rng, start_lo, start_hi)
    if axis == "x":
        return Rect(c, s, c + across, s + along) if sign > 0 else Rect(c - across, s, c, s + along)
    return Rect(s, c, s + along, c + across) if sign > 0 else Rect(s, c - across, s + along, c)


def _shared(edge: tuple[str, float, float, float, int], r: Rect) -> tuple[float, float]:
    axis, c, lo, hi, _ = edge
    a, b = (r.y0, r.y1) if axis == "x" else (r.x0, r.x1)
    return max(lo, a), min(hi, b)


def _make_room(rng: np.random.Generator, kind: str, name: str, rect: Rect, *, l_shape: bool,
               keep: tuple[str, float, float, float] | None) -> RoomPlan:
    """A room on ``rect``; an L-shape cuts a corner that does not touch the ``keep`` span (its door)."""
    if l_shape and rect.w >= 3.4 and rect.h >= 3.4:
        for _ in range(4):
            corner = int(rng.integers(4))
            cw, ch = _u(rng, 1.2, max(1.2, rect.w - 2.2)), _u(rng, 1.2, max(1.2, rect.h - 2.2))
            poly, parts = _l_polygon(rect, corner, cw, ch)
            room = RoomPlan(kind, name, parts, poly)
            if keep is None or _edge_keeps(room, keep):
                return room
    return RoomPlan(kind, name, [rect], rect.corners())


def _edge_keeps(room: RoomPlan, keep: tuple[str, float, float, float]) -> bool:
    axis, c, lo, hi = keep
    for a, cc, elo, ehi, _ in _edges(room):
        if a == axis and abs(cc - c) < 1e-9 and elo <= lo + 1e-9 and hi <= ehi + 1e-9:
            return True
    return False


def _layout_rooms(rng: np.random.Generator, n: int, layout: str) -> tuple[list[RoomPlan], list[DoorPlan]] | None:
    """Place n rooms (names chosen later) and the doors between them; None when the draw does not fit."""
    kinds = _room_kinds(rng, n, corridor=layout == "corridor")
    rooms: list[RoomPlan] = []
    doors: list[DoorPlan] = []
    if layout == "corridor":
        first = Rect(0.0, 0.0, _u(rng, 5.0, 9.0), _u(rng, CORRIDOR_MIN, CORRIDOR_MAX))
        rooms.append(RoomPlan(kinds[0], "", [first], first.corners()))
    else:
        first = Rect(0.0, 0.0, _u(rng, 3.2, 5.5), _u(rng, 3.2, 5.5))
        rooms.append(_make_room(rng, kinds[0], "", first, l_shape=rng.random() < 0.3, keep=None))
    turn = int(rng.integers(1, n)) if layout == "L" else n
    for k in range(1, n):
        placed = False
        for _ in range(40):
            if layout == "row" or (layout == "L" and k < turn):
                parent = k - 1
                side = ("x", 1)
            elif layout == "L":
                parent = k - 1
                side = ("y", -1) if k == turn or rng.random() < 0.8 else ("x", 1)
            elif layout == "corridor":
                parent = 0 if rng.random() < 0.85 else int(rng.integers(len(rooms)))
                side = None
            else:
                parent = int(rng.integers(len(rooms)))
                side = None
            edges = [e for e in _edges(rooms[parent]) if side is None or (e[0], e[4]) == side]
            if not edges:
                break
            edge = edges[int(rng.integers(len(edges)))]
            width = _u(rng, DOOR_MIN, DOOR_MAX)
            corridor = layout == "tree" and kinds[k] == "corridor"
            rect = _new_room_rect(rng, edge, corridor, width)
            if rect is None or any(p.overlaps(rect) for r in rooms for p in r.parts):
                continue
            lo, hi = _shared(edge, rect)
            centre = _u(rng, lo + width / 2 + DOOR_STUB, hi - width / 2 - DOOR_STUB)
            if not (lo + width / 2 + DOOR_STUB - 1e-9 <= centre <= hi - width / 2 - DOOR_STUB + 1e-9):
                continue
            span = (edge[0], edge[1], snap(centre - width / 2 - DOOR_STUB), snap(centre + width / 2 + DOOR_STUB))
            room = _make_room(rng, kinds[k], "", rect, l_shape=not corridor and rng.random() < 0.25, keep=span)
            rooms.append(room)
            doors.append(DoorPlan(edge[0], edge[1], centre, width, (parent, k), ""))
            placed = True
            break
        if not placed:
            return None
    return rooms, doors


def _room_kinds(rng: np.random.Generator, n: int, *, corridor: bool) -> list[str]:
    """What each room is: a flat has a living room and (from three rooms) a kitchen; a corridor layout starts with the hall."""
    pool = ["bedroom", "bathroom", "dining room", "study", "guest room", "nursery", "laundry"]
    order = [pool[i] for i in rng.permutation(len(pool))]
    kinds = ["living room", "kitchen", *order][: n - (1 if corridor else 0)]
    if n >= 4 and not corridor and rng.random() < 0.35:  # a tree flat may have a hall too
        kinds[-1] = "corridor"
    kinds = [kinds[i] for i in rng.permutation(len(kinds))]
    return (["corridor"] if corridor else []) + kinds


def _exit_door(rng: np.random.Generator, rooms: list[RoomPlan], doors: list[DoorPlan]) -> DoorPlan | None:
    """The front door: in an outside wall of the first room (the hall, in a corridor flat)."""
    for _ in range(30):
        edges = _edges(rooms[0])
        edge = edges[int(rng.integers(len(edges)))]
        axis, c, lo, hi, sign = edge
        width = _u(rng, EXIT_MIN, EXIT_MAX)
        if hi - lo < width + 2 * DOOR_STUB + 0.1:
            continue
        centre = _u(rng, lo + width / 2 + DOOR_STUB, hi - width / 2 - DOOR_STUB)
        probe = (c + sign * 0.3, centre) if axis == "x" else (centre, c + sign * 0.3)
        if any(r.contains(probe) for r in rooms):
            continue  # an inside wall
        door = DoorPlan(axis, c, centre, width, (0,), "front door", exit=True)
        if all(not _doors_clash(door, d) for d in doors):
            return door
    return None


def _doors_clash(a: DoorPlan, b: DoorPlan) -> bool:
    (ax, ay), (bx, by) = a.point(), b.point()
    return math.hypot(ax - bx, ay - by) < (a.width + b.width) / 2 + 2 * DOOR_STUB + 0.3


def _walls(rooms: list[RoomPlan], doors: list[DoorPlan]) -> list[WallPlan]:
    """Every room edge, merged into the longest straight runs; each door goes on the run that holds it."""
    lines: dict[tuple[str, float], list[tuple[float, float]]] = {}
    for r in rooms:
        for axis, c, lo, hi, _ in _edges(r):
            lines.setdefault((axis, c), []).append((lo, hi))
    walls: list[tuple[str, float, float, float]] = []
    for (axis, c), spans in sorted(lines.items()):
        spans.sort()
        cur_lo, cur_hi = spans[0]
        for lo, hi in spans[1:]:
            if lo <= cur_hi + 1e-9:
                cur_hi = max(cur_hi, hi)
            else:
                walls.append((axis, c, cur_lo, cur_hi))
                cur_lo, cur_hi = lo, hi
        walls.append((axis, c, cur_lo, cur_hi))
    out = []
    for axis, c, lo, hi in walls:
        w = WallPlan((c, lo), (c, hi)) if axis == "x" else WallPlan((lo, c), (hi, c))
        for d in doors:
            if d.axis == axis and abs(d.coord - c) < 1e-9 and lo - 1e-9 <= d.centre - d.width / 2 and d.centre + d.width / 2 <= hi + 1e-9:
                w.doors.append((snap(d.centre - lo), d))
        w.doors.sort(key=lambda t: t[0])
        out.append(w)
    return out


# -------------------------------------------------------------- furniture
#: Furniture kinds: (type, name word, length range, depth range, height, clearance, against a wall, surface for objects)
PIECES: dict[str, tuple[str, str, tuple[float, float], tuple[float, float], float, float, bool, bool]] = {
    "sofa": ("sofa", "sofa", (1.6, 2.3), (0.8, 0.95), 0.8, 0.0, True, False),
    "armchair": ("chair", "armchair", (0.75, 0.9), (0.75, 0.9), 0.85, 0.0, False, False),
    "coffee table": ("table", "coffee table", (0.9, 1.3), (0.5, 0.7), 0.45, 0.35, False, True),
    "table": ("table", "table", (1.0, 1.6), (0.8, 1.0), 0.75, 0.7, False, True),
    "dining table": ("table", "dining table", (1.4, 2.0), (0.9, 1.1), 0.75, 0.7, False, True),
    "desk": ("table", "desk", (1.1, 1.6), (0.6, 0.8), 0.75, 0.7, True, True),
    "chair": ("chair", "chair", (0.45, 0.5), (0.45, 0.5), 0.9, 0.45, False, False),
    "shelf": ("shelf", "bookshelf", (0.8, 1.6), (0.3, 0.4), 1.9, 0.0, True, False),
    "sideboard": ("cupboard", "sideboard", (1.2, 1.8), (0.45, 0.5), 0.85, 0.0, True, True),
    "low shelf": ("shelf", "low shelf", (0.8, 1.4), (0.35, 0.4), 0.9, 0.0, True, True),
    "cupboard": ("cupboard", "cupboard", (0.8, 1.4), (0.55, 0.6), 2.0, 0.0, True, False),
    "counter": ("counter", "counter", (1.4, 2.6), (0.6, 0.65), 0.9, 0.0, True, True),
    "fridge": ("fridge", "fridge", (0.6, 0.7), (0.6, 0.7), 1.8, 0.0, True, False),
    "stove": ("stove", "stove", (0.6, 0.6), (0.6, 0.6), 0.9, 0.0, True, True),
    "bed": ("bed", "bed", (1.9, 2.1), (1.0, 1.6), 0.55, 0.0, True, False),
    "bedside table": ("table", "bedside table", (0.4, 0.5), (0.4, 0.45), 0.55, 0.0, True, True),
    "wardrobe": ("cupboard", "wardrobe", (1.0, 1.8), (0.6, 0.6), 2.0, 0.0, True, False),
    "bathtub": ("bathtub", "bathtub", (1.6, 1.7), (0.7, 0.75), 0.6, 0.0, True, False),
    "washbasin": ("sink", "washbasin", (0.6, 0.7), (0.45, 0.5), 0.85, 0.0, True, True),
    "washing machine": ("appliance", "washing machine", (0.6, 0.6), (0.6, 0.6), 0.85, 0.0, True, True),
    "toy box": ("box", "toy box", (0.6, 0.9), (0.4, 0.5), 0.5, 0.0, True, True),
    "shoe cabinet": ("cupboard", "shoe cabinet", (0.8, 1.2), (0.3, 0.35), 1.0, 0.0, True, True),
}

#: What each kind of room is furnished with: (piece, probability), in placing order (big pieces first).
FURNISH: dict[str, tuple[tuple[str, float], ...]] = {
    "living room": (("sofa", 0.95), ("shelf", 0.7), ("coffee table", 0.6), ("sideboard", 0.5), ("armchair", 0.5), ("table", 0.4), ("chair", 0.3)),
    "kitchen": (("counter", 1.0), ("fridge", 0.8), ("stove", 0.5), ("table", 0.75), ("chair", 0.6), ("chair", 0.4), ("cupboard", 0.3)),
    "bedroom": (("bed", 1.0), ("wardrobe", 0.8), ("bedside table", 0.7), ("desk", 0.3), ("low shelf", 0.3)),
    "bathroom": (("bathtub", 0.7), ("washbasin", 0.9), ("cupboard", 0.3)),
    "dining room": (("dining table", 1.0), ("chair", 0.8), ("chair", 0.8), ("sideboard", 0.7), ("shelf", 0.3)),
    "study": (("desk", 1.0), ("chair", 0.9), ("shelf", 0.8), ("low shelf", 0.4), ("armchair", 0.3)),
    "guest room": (("bed", 0.9), ("wardrobe", 0.5), ("table", 0.4), ("low shelf", 0.4)),
    "nursery": (("bed", 0.9), ("toy box", 0.8), ("table", 0.6), ("chair", 0.5), ("low shelf", 0.5)),
    "laundry": (("washing machine", 1.0), ("shelf", 0.6), ("low shelf", 0.5)),
    "corridor": (("shoe cabinet", 0.5),),
}


def _furnish(rng: np.random.Generator, flat: Flat) -> None:
    """Furniture for every room, keeping doors clear and every door and room middle reachable for the robot.

    The robot's free space is kept as a blocked-cell mask that each accepted piece is added to
    (one small grid per candidate piece, not the whole flat again)."""
    names: set[str] = set()
    base = robot_grid(flat)
    blocked = base.blocked.copy()
    keys = [base.cell_of(p) for p in _key_points(flat)]
    bounds = _bounds(flat)
    for k, room in enumerate(flat.rooms):
        budget = 0.35 * room.area()
        used = 0.0
        for piece, p in FURNISH[room.kind]:
            if rng.random() >= p:
                continue
            typ, word, (l0, l1), (d0, d1), height, clearance, wall, surface = PIECES[piece]
            length, depth = _u(rng, l0, l1), _u(rng, d0, d1)
            if used + length * depth > budget:
                continue
            for _ in range(12):
                rect = _spot(rng, room, length, depth, against_wall=wall or rng.random() < 0.3)
                if rect is None or not _fits(rect, flat, k):
                    continue
                mask = blocked | Grid([np.array(rect.corners(), dtype=float)], bounds, clearance=ROBOT_CLEARANCE).blocked
                if not _connected(mask, keys):
                    continue
                name = _unique(word if word not in names else f"{room.name} {word}", names)
                flat.furniture.append(FurniturePlan(name, typ, rect, height, clearance, 0.05, k, surface))
                names.add(name)
                used += length * depth
                blocked = mask
                break


def _connected(blocked: np.ndarray, cells: list[tuple[int, int]]) -> bool:
    """Every cell free and all in one 4-connected region (as the path planner moves)."""
    from scipy import ndimage

    if any(blocked[c] for c in cells):
        return False
    labels, _ = ndimage.label(~blocked)
    return len({int(labels[c]) for c in cells}) == 1


def _unique(name: str, names: set[str]) -> str:
    if name not in names:
        return name
    n = 2
    while f"{name} {n}" in names:
        n += 1
    return f"{name} {n}"


def _spot(rng: np.random.Generator, room: RoomPlan, length: float, depth: float, *, against_wall: bool) -> Rect | None:
    part = room.parts[int(rng.integers(len(room.parts)))]
    inner = part.inset(WALL / 2 + 0.05)
    if against_wall:
        side = int(rng.integers(4))
        w, h = (length, depth) if side in (0, 2) else (depth, length)
        if w > inner.w or h > inner.h:
            return None
        if side == 0:  # south wall
            x, y = _u(rng, inner.x0, inner.x1 - w), inner.y0
        elif side == 2:
            x, y = _u(rng, inner.x0, inner.x1 - w), inner.y1 - h
        elif side == 1:  # east
            x, y = inner.x1 - w, _u(rng, inner.y0, inner.y1 - h)
        else:
            x, y = inner.x0, _u(rng, inner.y0, inner.y1 - h)
        r = Rect(snap(x), snap(y), snap(x + w), snap(y + h))
    else:
        w, h = (length, depth) if rng.random() < 0.5 else (depth, length)
        free = inner.inset(0.6)
        if w > free.w or h > free.h:
            return None
        x, y = _u(rng, free.x0, free.x1 - w), _u(rng, free.y0, free.y1 - h)
        r = Rect(x, y, snap(x + w), snap(y + h))
    if not all(room.contains(c) for c in r.inset(-0.05).corners()):
        return None
    return r


def _fits(rect: Rect, flat: Flat, k: int) -> bool:
    """Clear of other furniture (0.1 m gap), of the doors' approaches, and inside room k."""
    for f in flat.furniture:
        if f.rect.inset(-0.1).overlaps(rect):
            return False
    for d in flat.doors:
        x, y = d.point()
        half = d.width / 2 + 0.3
        zone = Rect(x - KEEP_OUT, y - half, x + KEEP_OUT, y + half) if d.axis == "x" else Rect(x - half, y - KEEP_OUT, x + half, y + KEEP_OUT)
        if zone.overlaps(rect):
            return False
    return True


def _robot_polygons(flat: Flat) -> list[np.ndarray]:
    from ..geometry import split_wall, wall_rectangle

    polys = []
    for w in flat.walls:
        for a, b in split_wall(w.start, w.end, [(at, d.width) for at, d in w.doors]):
            polys.append(wall_rectangle(a, b, WALL))
    polys += [np.array(f.rect.corners(), dtype=float) for f in flat.furniture]
    return polys


def _bounds(flat: Flat) -> tuple[float, float, float, float]:
    pts = np.array([p for r in flat.rooms for p in r.polygon], dtype=float)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    return float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1])


def robot_grid(flat: Flat, clearance: float = ROBOT_CLEARANCE) -> Grid:
    """Free space of the flat for a disc of ``clearance`` radius (walls and all furniture block)."""
    return Grid(_robot_polygons(flat), _bounds(flat), clearance=clearance)


def _key_points(flat: Flat) -> list[Point]:
    pts: list[Point] = []
    for d in flat.doors:
        if d.exit:
            continue
        pts.extend(d.sides())
    for room in flat.rooms:
        pts.append(room_middle(room))
    return pts


def room_middle(room: RoomPlan) -> Point:
    """The middle of a room's largest part (inside it even for an L-shape)."""
    part = max(room.parts, key=lambda r: r.w * r.h)
    return snap((part.x0 + part.x1) / 2), snap((part.y0 + part.y1) / 2)


def _reachable(flat: Flat) -> bool:
    grid = robot_grid(flat)
    comps = set()
    for p in _key_points(flat):
        c = grid.cell_of(p)
        if grid.blocked[c]:
            return False
        comps.add(grid.component(p))
    return len(comps) == 1


# ------------------------------------------------------------------ names
def _name_rooms(rng: np.random.Generator, rooms: list[RoomPlan]) -> None:
    used: set[str] = set()
    for r in rooms:
        words = CORRIDOR_WORDS if r.corridor else ROOM_WORDS[r.kind]
        name = words[int(rng.integers(len(words)))] if rng.random() < 0.35 else words[0]
        if name in used:
            name = next((w for w in words if w not in used), f"{words[0]} 2")
        used.add(name)
        r.name = name


def _name_doors(flat: Flat) -> None:
    for d in flat.doors:
        if not d.exit:
            a, b = (flat.rooms[i].name for i in d.rooms)
            d.name = f"{a} {b} door"


def _places(flat: Flat) -> None:
    """A named place in the middle of every room, and one by a piece of furniture in some."""
    grid = robot_grid(flat)
    for k, room in enumerate(flat.rooms):
        p = room_middle(room)
        if not grid.blocked[grid.cell_of(p)]:
            flat.places.append((f"{room.name} middle", p, k))


LAYOUTS = ("row", "L", "corridor", "tree")


def generate_flat(rng: np.random.Generator, *, rooms: int | None = None) -> Flat:
    """A flat of 2 to 6 rooms (see the module docstring); every draw comes from ``rng``."""
    for _ in range(200):
        n = int(rng.integers(2, 7)) if rooms is None else rooms
        layout = LAYOUTS[int(rng.integers(len(LAYOUTS)))] if n >= 3 else ("row", "L", "tree")[int(rng.integers(3))]
        if layout == "corridor" and n < 3:
            layout = "row"
        placed = _layout_rooms(rng, n, layout)
        if placed is None:
            continue
        room_list, doors = placed
        exit_door = _exit_door(rng, room_list, doors)
        if exit_door is None:
            continue
        doors.append(exit_door)
        if any(_doors_clash(a, b) for i, a in enumerate(doors) for b in doors[:i] if not (a.exit or b.exit) and a.axis == b.axis and a.coord == b.coord):
            continue
        _name_rooms(rng, room_list)
        flat = Flat(layout, room_list, doors, _walls(room_list, doors), [], [])
        _name_doors(flat)
        if not _reachable(flat):
            continue
        _furnish(rng, flat)
        _places(flat)
        flat.grid = robot_grid(flat)
        flat.walk_grid = robot_grid(flat, 0.27)
        flat.anchor = _key_points(flat)[0]
        return flat
    raise RuntimeError("no flat could be laid out in 200 draws")  # pragma: no cover - the draws above always fit
