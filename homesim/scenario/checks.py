"""Semantic checks of a scenario: what the XSD cannot say.

Names are unique (one namespace for everything a script can refer to),
references resolve to the right kind of thing, rooms are simple polygons
that do not overlap, furniture is convex, door gaps fit their walls, start
poses lie inside a room and clear of walls and furniture, objects stand on
what they say they stand on, radios only say and wait, a script never
has actions after a ``repeat`` that runs for ever, and every ``repeat``
contains an action that can take time and no ``leave``. A reaction
(``<on>``) must end: no ``leave``, no ``repeat`` for ever, no ``wait-for``
without a timeout in it, no ``<on>`` inside. Packages outside the kernel
add checks of their own (e.g. the simulated people's: profile names,
paraphrase banks, reactions that trigger each other for ever) through the
``homesim.scenario_checks`` entry points, without the kernel naming them. Every door is
wide enough for a person and not blocked; every fixed place a person walks
to, and the exit they leave by, is reachable from where they start. The first
problem found raises a :class:`ScenarioError` naming the file, the line
and the element.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable, Iterator
from functools import lru_cache
from importlib.metadata import entry_points

import numpy as np

from ..errors import ScenarioError
from ..geometry import (
    distance_points_segments,
    is_convex,
    point_in_polygon,
    polygon_area,
    polygon_centroid,
    polygon_edges,
    polygon_problem,
    polygons_overlap,
    split_wall,
    wall_rectangle,
)
from .pathplan import MIN_DOOR_WIDTH, WALKER_RADIUS, Grid, door_sides
from .model import (
    GIVE_UPS,
    REPAIR_STRATEGIES,
    Action,
    Expectation,
    Face,
    Leave,
    PointAt,
    Repeat,
    Say,
    Scenario,
    StepCloser,
    Target,
    Wait,
    WaitFor,
    WaitSpeech,
    WalkTo,
    window_of,
)

ROBOT_RADIUS = 0.30
HUMAN_RADIUS = 0.25
MAX_EXTENT = 50.0  # metres: the largest flat (rooms and walls) a scenario may describe
#: Most elements of each kind a scenario may hold: a flat, not a city. The
#: checks and the world's set-up cost grows with these (some pairwise), so
#: they are refused before any geometry is looked at.
MAX_COUNTS = {"room": 100, "wall": 1000, "furniture": 500, "place": 500, "object": 1000, "human": 50, "source": 50, "expectation": 500}

# Which target kinds each action accepts.
_TARGET_KINDS = {
    "walk-to": {"place", "room", "object", "furniture", "human", "robot", "point"},
    "face": {"place", "room", "object", "furniture", "human", "robot", "point", "angle"},
    "point": {"place", "room", "object", "furniture", "point"},
    "reached": {"place", "room", "object", "furniture", "human", "robot", "point"},
    "robot-near": {"place", "room", "object", "furniture", "human", "point"},
}


#: Entry-point group of checks other packages add: ``check(scenario) -> None`` raising ScenarioError.
CHECKS_GROUP = "homesim.scenario_checks"


@lru_cache(maxsize=1)
def extra_checks() -> tuple[Callable[[Scenario], None], ...]:
    """The checks registered under :data:`CHECKS_GROUP` (by entry-point name order)."""
    return tuple(ep.load() for ep in sorted(entry_points(group=CHECKS_GROUP), key=lambda e: e.name))


def check(sc: Scenario) -> None:
    """Raise ScenarioError for the first semantic problem in ``sc``."""
    _Checker(sc).run()
    for extra in extra_checks():
        extra(sc)


class _Checker:
    def __init__(self, sc: Scenario) -> None:
        self.sc = sc
        self.kinds: dict[str, tuple[str, int | None]] = {}

    def fail(self, line: int | None, element: str, message: str) -> ScenarioError:
        return ScenarioError(message, source=self.sc.source, line=line, element=element)

    def run(self) -> None:
        sc = self.sc
        self.counts()
        self.names()
        self.extent()
        for k, room in enumerate(sc.rooms):
            problem = polygon_problem(np.array(room.polygon))
            if problem is not None:
                raise self.fail(room.line, "room", f"room {room.name!r} is not a simple polygon: {problem}")
            if abs(polygon_area(np.array(room.polygon))) < 1e-6:
                raise self.fail(room.line, "room", f"room {room.name!r} has no area")
            for other in sc.rooms[:k]:
                if polygons_overlap(np.array(room.polygon), np.array(other.polygon)):
                    raise self.fail(room.line, "room", f"room {room.name!r} overlaps room {other.name!r} (line {other.line}); rooms may share walls, not floor")
        for wall in sc.walls:
            if np.hypot(wall.end[0] - wall.start[0], wall.end[1] - wall.start[1]) < 1e-6:
                raise self.fail(wall.line, "wall", "a wall needs two distinct end points")
            try:
                split_wall(wall.start, wall.end, [(d.at, d.width) for d in wall.doors])
            except ValueError as exc:
                raise self.fail(wall.line, "wall", str(exc)) from exc
        for f in sc.furniture:
            poly = np.array(f.polygon)
            if not is_convex(poly):
                raise self.fail(f.line, "furniture", f"furniture {f.name!r} is not convex: split it into convex pieces")
            if f.clearance >= f.height:
                raise self.fail(f.line, "furniture", f"furniture {f.name!r}: clearance {f.clearance} m must be below its height {f.height} m")
            if f.clearance > 0:
                span = poly.max(axis=0) - poly.min(axis=0)
                if 2 * f.leg >= span.min():
                    raise self.fail(f.line, "furniture", f"furniture {f.name!r}: legs of {f.leg} m do not fit under it")
        for p in sc.places:
            self.inside_flat((p.x, p.y), p.line, "place", f"place {p.name!r}")
        for o in sc.objects:
            if o.on is not None:
                if self.kinds.get(o.on, ("",))[0] != "furniture":
                    raise self.fail(o.line, "object", f"object {o.name!r} stands on {o.on!r}, which is not a piece of furniture")
                if not point_in_polygon((o.x, o.y), np.array(sc.piece(o.on).polygon)):
                    raise self.fail(o.line, "object", f"object {o.name!r} at ({o.x}, {o.y}) is not on {o.on!r}")
            else:
                self.inside_flat((o.x, o.y), o.line, "object", f"object {o.name!r}")
        r = sc.robot
        self.clear((r.x, r.y), ROBOT_RADIUS, r.line, "robot", "the robot's start")
        for k, h in enumerate(sc.humans):
            self.clear((h.x, h.y), HUMAN_RADIUS, h.line, "human", f"human {h.name!r}")
            if np.hypot(h.x - r.x, h.y - r.y) < ROBOT_RADIUS + HUMAN_RADIUS:
                raise self.fail(h.line, "human", f"human {h.name!r} starts at ({h.x:g}, {h.y:g}), on the robot (line {r.line}): "
                                                 f"start at least {ROBOT_RADIUS + HUMAN_RADIUS:g} m from it")
            for other in sc.humans[:k]:
                if np.hypot(h.x - other.x, h.y - other.y) < 2 * HUMAN_RADIUS:
                    raise self.fail(h.line, "human", f"human {h.name!r} starts on top of {other.name!r} (line {other.line})")
            self.script(h.script, h.name, person=True)
            for hd in h.handlers:
                self.handler_body(hd.body, h.name, hd.line)
                self.script(hd.body, h.name, person=True)
        for s in sc.sources:
            self.inside_flat((s.x, s.y), s.line, s.kind, f"{s.kind} {s.name!r}")
            self.script(s.script, s.name, person=False)
        self.walkable()
        for e in sc.expectations:
            self.expectation(e)
        for f in sc.faults:
            if f.at > sc.duration:
                raise self.fail(f.line, f.kind, f"at={f.at:g} is after the end of the run ({sc.duration:g} s)")

    # ---------------------------------------------------------------- sizes
    def counts(self) -> None:
        sc = self.sc
        groups = {
            "room": sc.rooms, "wall": sc.walls, "furniture": sc.furniture, "place": sc.places,
            "object": sc.objects, "human": sc.humans, "source": sc.sources, "expectation": sc.expectations,
        }
        for kind, items in groups.items():
            limit = MAX_COUNTS[kind]
            if len(items) > limit:
                first = items[limit]
                raise self.fail(getattr(first, "line", None), kind, f"{len(items)} elements of kind {kind}: a scenario holds at most {limit}")

    # ---------------------------------------------------------------- names
    def names(self) -> None:
        sc = self.sc
        named: list[tuple[str, str, int | None]] = []
        named += [("room", x.name, x.line) for x in sc.rooms]
        named += [("furniture", x.name, x.line) for x in sc.furniture]
        named += [("place", x.name, x.line) for x in sc.places]
        named += [("door", d.name, d.line) for w in sc.walls for d in w.doors if d.name]
        named += [("object", x.name, x.line) for x in sc.objects]
        named += [("human", x.name, x.line) for x in sc.humans]
        named += [(x.kind, x.name, x.line) for x in sc.sources]
        for kind, name, line in named:
            if name == "robot":
                raise self.fail(line, kind, "the name 'robot' is reserved for the robot")
            if name in self.kinds:
                other, oline = self.kinds[name]
                raise self.fail(line, kind, f"name {name!r} is already used by the {other} at line {oline}")
            self.kinds[name] = (kind, line)

    # ------------------------------------------------------------- geometry
    def extent(self) -> None:
        """The flat (rooms and walls) fits in a MAX_EXTENT square: people plan walks on a 5 cm grid of it."""
        items = [(r.line, "room", list(r.polygon)) for r in self.sc.rooms]
        items += [(w.line, "wall", [w.start, w.end]) for w in self.sc.walls]
        pts = np.array([p for _, _, ps in items for p in ps], dtype=float)
        lo = pts.min(axis=0)
        for line, element, ps in items:
            far = np.array(ps, dtype=float) - lo
            if far.max() > MAX_EXTENT:
                raise self.fail(line, element, f"this {element} reaches {far.max():.0f} m from the flat's corner at ({lo[0]:g}, {lo[1]:g}): "
                                               f"a flat must fit in {MAX_EXTENT:g} x {MAX_EXTENT:g} m")

    def inside_flat(self, xy: tuple[float, float], line: int | None, element: str, what: str) -> None:
        if not any(point_in_polygon(xy, np.array(room.polygon)) for room in self.sc.rooms):
            raise self.fail(line, element, f"{what} at ({xy[0]}, {xy[1]}) is not inside any room")

    def clear(self, xy: tuple[float, float], radius: float, line: int | None, element: str, what: str) -> None:
        self.inside_flat(xy, line, element, what)
        for wall in self.sc.walls:
            for a, b in split_wall(wall.start, wall.end, [(d.at, d.width) for d in wall.doors]):
                rect = wall_rectangle(a, b, wall.thickness)
                if _overlaps(xy, radius, rect):
                    raise self.fail(line, element, f"{what} at ({xy[0]}, {xy[1]}) overlaps the wall at line {wall.line}")
        for f in self.sc.furniture:
            if _overlaps(xy, radius, np.array(f.polygon)):
                raise self.fail(line, element, f"{what} at ({xy[0]}, {xy[1]}) overlaps furniture {f.name!r}")

    # -------------------------------------------------------------- scripts
    def script(self, actions: tuple[Action, ...], owner: str, *, person: bool, repeat: Repeat | None = None) -> None:
        for i, act in enumerate(actions):
            tag = _action_tag(act)
            if not person and tag not in ("say", "wait", "wait-for", "repeat"):
                raise self.fail(act.line, tag, f"{owner!r} is a sound source: it can only say, wait, wait-for and repeat")
            if isinstance(act, (WalkTo, Face, PointAt)):
                self.target(act.target, tag, act.line, owner)
            elif isinstance(act, Say):
                if not person and act.request is not None:
                    raise self.fail(act.line, tag, f"{owner!r} is a sound source: it says text=, it has no paraphrase bank (request=)")
            elif isinstance(act, StepCloser):
                if act.nearest < ROBOT_RADIUS + HUMAN_RADIUS - 1e-9:
                    raise self.fail(act.line, tag, f"nearest={act.nearest:g} m would put her on the robot: at least {ROBOT_RADIUS + HUMAN_RADIUS:g} m")
            elif isinstance(act, WaitFor):
                if act.robot_says is None and act.robot_within is None and act.hears is None:
                    raise self.fail(act.line, tag, "wait-for needs robot-says or robot-within (or hears, a word pattern)")
                if (act.repairs or act.patience is not None or act.give_up is not None) and act.robot_says is None and act.hears is None:
                    raise self.fail(act.line, tag, "repairs=, patience= and give-up= need robot-says or hears (the answer she repairs for)")
                if any(r not in REPAIR_STRATEGIES for r in act.repairs or ()):
                    raise self.fail(act.line, tag, f"repairs: one or more of {', '.join(REPAIR_STRATEGIES)}")
                if act.give_up is not None and act.give_up not in GIVE_UPS:
                    raise self.fail(act.line, tag, f"give-up={act.give_up!r}: one of {', '.join(GIVE_UPS)}")
                if act.give_up == "leave" and not self.sc.exits():
                    raise self.fail(act.line, tag, 'give-up="leave": no door of the flat has exit="true"')
                for key, pattern in (("robot-says", act.robot_says), ("repair", act.repair)):
                    if pattern is None:
                        continue
                    try:
                        re.compile(pattern)
                    except re.error as exc:
                        raise self.fail(act.line, tag, f"{key}={pattern!r} is not a regular expression: {exc}") from exc
                if act.retries and act.robot_says is None:
                    raise self.fail(act.line, tag, "retries= needs robot-says (what answer the person repeats herself for)")
                if act.handlers and not person:
                    raise self.fail(act.line, tag, f"{owner!r} is a sound source: it does not react (<on>)")
                for hd in act.handlers:  # a wait's own reactions must end like any other
                    self.handler_body(hd.body, owner, hd.line)
                    self.script(hd.body, owner, person=person)
            elif isinstance(act, Leave):
                exits = [d for _, d in self.sc.exits()]
                if not exits:
                    raise self.fail(act.line, tag, "nobody can leave: no door of the flat has exit=\"true\"")
                if act.door is not None and act.door not in [d.name for d in exits]:
                    raise self.fail(act.line, tag, f"door {act.door!r} is not an exit door")
                if repeat is not None:
                    raise self.fail(act.line, tag, f"<leave> cannot be inside the <repeat> at line {repeat.line}: {owner!r} can leave the flat only once")
                if i != len(actions) - 1:
                    raise self.fail(actions[i + 1].line, _action_tag(actions[i + 1]), f"{owner!r} has left the flat: nothing can follow <leave>")
            elif isinstance(act, Repeat):
                if not act.body:
                    raise self.fail(act.line, tag, "repeat needs at least one action")
                if act.times is None and i != len(actions) - 1:
                    raise self.fail(actions[i + 1].line, _action_tag(actions[i + 1]), "unreachable: the repeat before it runs for ever")
                if not _takes_time(act.body):
                    raise self.fail(act.line, tag, "a repeat must wait, walk, point or say, or it never lets time pass")
                self.script(act.body, owner, person=person, repeat=act)

    def handler_body(self, actions: tuple[Action, ...], owner: str, line: int | None) -> None:
        """A reaction must end: it cannot leave, repeat for ever or wait without a timeout."""
        for act in _walk(actions):
            tag = _action_tag(act)
            if isinstance(act, Leave):
                raise self.fail(act.line, tag, f"<leave> cannot be inside the <on> at line {line}: a reaction ends and {owner!r} carries on her script")
            if isinstance(act, Repeat) and act.times is None:
                raise self.fail(act.line, tag, f"a <repeat> for ever inside the <on> at line {line} never ends: give times=")
            if isinstance(act, WaitFor) and act.timeout is None:
                raise self.fail(act.line, tag, f"a wait-for without timeout= inside the <on> at line {line} may never end: give timeout=")
            if isinstance(act, WaitFor) and act.give_up == "leave":
                raise self.fail(act.line, tag, f'give-up="leave" cannot be inside the <on> at line {line}: a reaction ends and {owner!r} carries on her script')

    # ------------------------------------------------------------- walking
    def walkable(self) -> None:
        """Every door lets a person through; every fixed walk target and exit is reachable."""
        sc = self.sc
        grid = Grid.for_scenario(sc)
        for wall in sc.walls:
            for d in wall.doors:
                what = f"door {d.name!r}" if d.name else f"the door at {d.at:g} m"
                if d.width < MIN_DOOR_WIDTH - 1e-9:
                    raise self.fail(d.line, "door", f"{what} is {d.width:g} m wide: a person ({WALKER_RADIUS:g} m radius) needs at least {MIN_DOOR_WIDTH:.2f} m")
                if not grid.passable(wall, d):
                    raise self.fail(d.line, "door", f"{what} cannot be walked through: walls or furniture next to it leave no room for a person ({WALKER_RADIUS:g} m radius)")
        for h in sc.humans:
            home = grid.component((h.x, h.y))
            for act in _walk(h.script + tuple(a for hd in h.handlers for a in hd.body)):
                if isinstance(act, WalkTo) and act.target.kind not in ("robot", "human"):
                    goal = self.fixed_point(act.target)
                    what = f"{act.target.kind} {act.target.name!r}" if act.target.name else f"({goal[0]:g}, {goal[1]:g})"
                elif isinstance(act, Leave):
                    wall, door = next((w, d) for w, d in sc.exits() if act.door is None or d.name == act.door)
                    a, b = door_sides(wall, door)
                    goal = b if any(point_in_polygon(a, np.array(r.polygon)) for r in sc.rooms) else a
                    what = f"the exit {door.name!r}" if door.name else "the exit"
                else:
                    continue
                if grid.component(goal) != home:
                    raise self.fail(act.line, _action_tag(act), f"{h.name!r} cannot reach {what} from the start at ({h.x:g}, {h.y:g}): walls or furniture close it off")

    def fixed_point(self, t: Target) -> tuple[float, float]:
        """Where a fixed target is (as World.target_point)."""
        sc = self.sc
        if t.kind == "point":
            return t.x, t.y
        if t.kind == "place":
            p = sc.place(t.name or "")
            return p.x, p.y
        if t.kind == "object":
            o = sc.object(t.name or "")
            return o.x, o.y
        poly = sc.room(t.name or "").polygon if t.kind == "room" else sc.piece(t.name or "").polygon
        return polygon_centroid(np.array(poly))

    def target(self, t: Target, tag: str, line: int | None, owner: str | None = None) -> None:
        if t.kind not in _TARGET_KINDS[tag]:
            raise self.fail(line, tag, f"<{tag}> cannot take a {t.kind} as its target")
        if t.kind == "point" and tag != "face":  # a place to go or point at: inside the flat, never clamped
            self.inside_flat((float(t.x or 0.0), float(t.y or 0.0)), line, tag, f"<{tag}> target point")
        if t.kind in ("robot", "point", "angle"):
            return
        found = self.kinds.get(t.name or "")
        if found is None or found[0] != t.kind:
            known = ", ".join(sorted(n for n, (k, _) in self.kinds.items() if k == t.kind)) or "none"
            raise self.fail(line, tag, f"there is no {t.kind} named {t.name!r} (known: {known})")
        if t.kind == "human" and t.name == owner:
            raise self.fail(line, tag, f"{owner!r} cannot target themselves")

    def expectation(self, e: Expectation) -> None:
        if e.kind == "reached":
            who = e.get("who")
            if self.kinds.get(str(who), ("",))[0] != "human":
                raise self.fail(e.line, e.kind, f"there is no human named {who!r}")
            self.target(e.get("target"), "reached", e.line, str(who))  # type: ignore[arg-type]
            by = e.get("by")
            if by is not None and float(by) > self.sc.duration:  # type: ignore[arg-type]
                raise self.fail(e.line, e.kind, f"by={by} is after the end of the run ({self.sc.duration} s)")
        if e.kind == "robot-near":
            self.target(e.get("target"), "robot-near", e.line)  # type: ignore[arg-type]
        if e.kind == "following-distance":
            who = e.get("who")
            if self.kinds.get(str(who), ("",))[0] != "human":
                raise self.fail(e.line, e.kind, f"there is no human named {who!r}")
        for key in ("after", "by"):
            t = e.get(key)
            if e.kind != "reached" and t is not None and float(t) > self.sc.duration:  # type: ignore[arg-type]
                raise self.fail(e.line, e.kind, f"{key}={t} is after the end of the run ({self.sc.duration} s)")
        if e.get("after") is not None and e.get("by") is not None and float(e.get("after")) > float(e.get("by")):  # type: ignore[arg-type]
            raise self.fail(e.line, e.kind, f"after={float(e.get('after')):g} is later than by={float(e.get('by')):g}")  # type: ignore[arg-type]
        if e.kind == "no-collision":
            what = e.get("with")
            if what is not None and what not in ("wall", "furniture") and self.kinds.get(str(what), ("",))[0] != "human":
                raise self.fail(e.line, e.kind, f"with={what!r}: use 'wall', 'furniture' or the name of a human")
        window = e.get("between")
        if window is not None and window[1] > self.sc.duration:  # type: ignore[index]
            raise self.fail(e.line, e.kind, f"the window ends at {window[1]} s, after the run ({self.sc.duration} s)")  # type: ignore[index]
        t0, t1 = window_of(e, self.sc.duration)
        if t1 < t0:
            raise self.fail(e.line, e.kind, f"the window is empty: between, after and by leave nothing from {t0:g} s to {t1:g} s")


def _overlaps(xy: tuple[float, float], radius: float, polygon: np.ndarray) -> bool:
    if point_in_polygon(xy, polygon):
        return True
    a, b = polygon_edges(polygon)
    return bool(distance_points_segments(np.array([xy]), a, b).min() < radius)


def _action_tag(act: Action) -> str:
    return {
        WalkTo: "walk-to",
        Face: "face",
        Say: "say",
        PointAt: "point",
        Wait: "wait",
        WaitFor: "wait-for",
        Leave: "leave",
        Repeat: "repeat",
        WaitSpeech: "wait-speech",
        StepCloser: "step-closer",
    }[type(act)]


def _takes_time(actions: Iterable[Action]) -> bool:
    for a in _walk(actions):
        if isinstance(a, (Wait, Say, WalkTo, PointAt, WaitFor, StepCloser)) and not (isinstance(a, Wait) and a.duration <= 0):
            return True
    return False


def _walk(actions: Iterable[Action]) -> Iterator[Action]:
    for a in actions:
        yield a
        if isinstance(a, Repeat):
            yield from _walk(a.body)
        elif isinstance(a, WaitFor):
            for hd in a.handlers:  # a wait's own reactions (<on> inside the wait-for)
                yield from _walk(hd.body)
