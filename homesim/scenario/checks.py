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
to, and the exit they leave by, is reachable from where they start. A name
that refers to nothing (a person, place, object, room, furniture) is refused
with the closest known name.

:func:`problems` lists every problem, one per element (two people outside
the flat: both named), each a :class:`ScenarioError` naming the file, the
line and the element; :func:`check` raises the first. Two stages stop what
follows them: too many elements (the checks' cost grows with them) and a
flat too large for the walking grid; the walking checks run only on a
scenario with no other problem (they need every name to resolve).
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable, Iterator, Sequence
from contextlib import contextmanager
from functools import cached_property, lru_cache
from importlib.metadata import entry_points

import numpy as np

from ..errors import ScenarioError
from ..suggest import closest, did_you_mean
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
    Furniture,
    HumanSpec,
    Leave,
    ObjectSpec,
    PointAt,
    Repeat,
    Room,
    Say,
    Scenario,
    StepCloser,
    Target,
    Wait,
    WaitFor,
    WaitSpeech,
    WalkTo,
    Wall,
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
    "place-learned": {"place", "room", "point"},
}


#: Entry-point group of checks other packages add: ``check(scenario)`` returning the problems it found
#: (a list of ScenarioError; None for none) or raising the first as ScenarioError.
CHECKS_GROUP = "homesim.scenario_checks"

ExtraCheck = Callable[[Scenario], "Sequence[ScenarioError] | None"]


@lru_cache(maxsize=1)
def extra_checks() -> tuple[ExtraCheck, ...]:
    """The checks registered under :data:`CHECKS_GROUP` (by entry-point name order)."""
    return tuple(ep.load() for ep in sorted(entry_points(group=CHECKS_GROUP), key=lambda e: e.name))


def problems(sc: Scenario) -> list[ScenarioError]:
    """Every semantic problem of ``sc`` (the kernel's rules, then the registered checks'), in that order."""
    found = _Checker(sc).run()
    for extra in extra_checks():
        try:
            found.extend(extra(sc) or ())
        except ScenarioError as exc:
            found.append(exc)
    return found


def check(sc: Scenario) -> None:
    """Raise ScenarioError for the first semantic problem in ``sc`` (saying how many more there are)."""
    found = problems(sc)
    if found:
        first = found[0]
        if len(found) == 1:
            raise first
        raise ScenarioError(f"{first.message} (and {len(found) - 1} more problem(s); 'homesim check' lists them)",
                            source=first.source, line=first.line, element=first.element)


def unknown_name(what: str, name: object, known: Iterable[str]) -> str:
    """``there is no place named 'kichen' (did you mean 'kitchen'?; known: ...)``."""
    names = sorted(set(known))
    near = closest(str(name), names)
    hint = f"did you mean {near!r}?; " if near is not None else ""
    listed = ", ".join(repr(n) for n in names[:12]) + (", ..." if len(names) > 12 else "") or "none"
    return f"there is no {what} named {name!r} ({hint}known: {listed})"


class _Checker:
    def __init__(self, sc: Scenario) -> None:
        self.sc = sc
        self.kinds: dict[str, tuple[str, int | None]] = {}
        self.found: list[ScenarioError] = []
        self.walls: list[Wall] = []

    def fail(self, line: int | None, element: str, message: str) -> ScenarioError:
        return ScenarioError(message, source=self.sc.source, line=line, element=element)

    @contextmanager
    def item(self) -> Iterator[None]:
        """Check one element: its first problem is kept and the checks go on with the next element."""
        try:
            yield
        except ScenarioError as exc:
            self.found.append(exc)

    def named(self, kind: str) -> list[str]:
        return [n for n, (k, _) in self.kinds.items() if k == kind]

    def run(self) -> list[ScenarioError]:
        sc = self.sc
        with self.item():
            self.counts()
        if self.found:
            return self.found
        self.names()
        with self.item():
            self.extent()
        if self.found:
            return self.found
        for k, room in enumerate(sc.rooms):
            with self.item():
                self.room(k, room)
        for wall in sc.walls:
            with self.item():
                self.wall(wall)
                self.walls.append(wall)  # only walls that can be cut at their doors are used by the checks below
        for f in sc.furniture:
            with self.item():
                self.piece(f)
        for p in sc.places:
            with self.item():
                self.inside_flat((p.x, p.y), p.line, "place", f"place {p.name!r}")
        for o in sc.objects:
            with self.item():
                self.obj(o)
        with self.item():
            r = sc.robot
            self.clear((r.x, r.y), ROBOT_RADIUS, r.line, "robot", "the robot's start")
        for k, h in enumerate(sc.humans):
            with self.item():
                self.human_start(k, h)
            self.script(h.script, h.name, person=True)
            for hd in h.handlers:
                with self.item():
                    self.handler_body(hd.body, h.name, hd.line)
                self.script(hd.body, h.name, person=True)
        for s in sc.sources:
            with self.item():
                self.inside_flat((s.x, s.y), s.line, s.kind, f"{s.kind} {s.name!r}")
            self.script(s.script, s.name, person=False)
        if not self.found:  # walking needs sound geometry and every name resolved
            self.walkable()
        for e in sc.expectations:
            with self.item():
                self.expectation(e)
        for f in sc.faults:
            if f.at > sc.duration:
                self.found.append(self.fail(f.line, f.kind, f"at={f.at:g} is after the end of the run ({sc.duration:g} s)"))
        return self.found

    # ------------------------------------------------------------ elements
    def room(self, k: int, room: Room) -> None:
        problem = polygon_problem(np.array(room.polygon))
        if problem is not None:
            raise self.fail(room.line, "room", f"room {room.name!r} is not a simple polygon: {problem}")
        if abs(polygon_area(np.array(room.polygon))) < 1e-6:
            raise self.fail(room.line, "room", f"room {room.name!r} has no area")
        for other in self.sc.rooms[:k]:
            if polygons_overlap(np.array(room.polygon), np.array(other.polygon)):
                raise self.fail(room.line, "room", f"room {room.name!r} overlaps room {other.name!r} (line {other.line}); rooms may share walls, not floor")

    def wall(self, wall: Wall) -> None:
        if np.hypot(wall.end[0] - wall.start[0], wall.end[1] - wall.start[1]) < 1e-6:
            raise self.fail(wall.line, "wall", "a wall needs two distinct end points")
        try:
            split_wall(wall.start, wall.end, [(d.at, d.width) for d in wall.doors])
        except ValueError as exc:
            raise self.fail(wall.line, "wall", str(exc)) from exc

    def piece(self, f: Furniture) -> None:
        poly = np.array(f.polygon)
        if not is_convex(poly):
            raise self.fail(f.line, "furniture", f"furniture {f.name!r} is not convex: split it into convex pieces")
        if f.clearance >= f.height:
            raise self.fail(f.line, "furniture", f"furniture {f.name!r}: clearance {f.clearance} m must be below its height {f.height} m")
        if f.clearance > 0:
            span = poly.max(axis=0) - poly.min(axis=0)
            if 2 * f.leg >= span.min():
                raise self.fail(f.line, "furniture", f"furniture {f.name!r}: legs of {f.leg} m do not fit under it")

    def obj(self, o: ObjectSpec) -> None:
        if o.on is not None:
            if self.kinds.get(o.on, ("",))[0] != "furniture":
                raise self.fail(o.line, "object", f"object {o.name!r} stands on {o.on!r}, which is not a piece of furniture "
                                                  f"({unknown_name('piece of furniture', o.on, self.named('furniture'))})")
            if not point_in_polygon((o.x, o.y), np.array(self.sc.piece(o.on).polygon)):
                raise self.fail(o.line, "object", f"object {o.name!r} at ({o.x}, {o.y}) is not on {o.on!r}")
        else:
            self.inside_flat((o.x, o.y), o.line, "object", f"object {o.name!r}")

    def human_start(self, k: int, h: HumanSpec) -> None:
        r = self.sc.robot
        self.clear((h.x, h.y), HUMAN_RADIUS, h.line, "human", f"human {h.name!r}")
        if np.hypot(h.x - r.x, h.y - r.y) < ROBOT_RADIUS + HUMAN_RADIUS:
            raise self.fail(h.line, "human", f"human {h.name!r} starts at ({h.x:g}, {h.y:g}), on the robot (line {r.line}): "
                                             f"start at least {ROBOT_RADIUS + HUMAN_RADIUS:g} m from it")
        for other in self.sc.humans[:k]:
            if np.hypot(h.x - other.x, h.y - other.y) < 2 * HUMAN_RADIUS:
                raise self.fail(h.line, "human", f"human {h.name!r} starts on top of {other.name!r} (line {other.line})")

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
                self.found.append(self.fail(getattr(first, "line", None), kind,
                                            f"{len(items)} elements of kind {kind}: a scenario holds at most {limit}"))

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
                self.found.append(self.fail(line, kind, "the name 'robot' is reserved for the robot"))
            elif name in self.kinds:
                other, oline = self.kinds[name]
                self.found.append(self.fail(line, kind, f"name {name!r} is already used by the {other} at line {oline}"))
            else:
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
        for wall in self.walls:
            for a, b in split_wall(wall.start, wall.end, [(d.at, d.width) for d in wall.doors]):
                rect = wall_rectangle(a, b, wall.thickness)
                if _overlaps(xy, radius, rect):
                    raise self.fail(line, element, f"{what} at ({xy[0]}, {xy[1]}) overlaps the wall at line {wall.line}")
        for f in self.sc.furniture:
            if _overlaps(xy, radius, np.array(f.polygon)):
                raise self.fail(line, element, f"{what} at ({xy[0]}, {xy[1]}) overlaps furniture {f.name!r}")

    # -------------------------------------------------------------- scripts
    def script(self, actions: tuple[Action, ...], owner: str, *, person: bool, repeat: Repeat | None = None) -> None:
        """Every action's first problem (a repeat's body is checked action by action too)."""
        for i, act in enumerate(actions):
            with self.item():
                self.action(actions, i, owner, person=person, repeat=repeat)

    def action(self, actions: tuple[Action, ...], i: int, owner: str, *, person: bool, repeat: Repeat | None) -> None:
        act = actions[i]
        tag = _action_tag(act)
        if not person and tag not in ("say", "wait", "wait-for", "repeat"):
            raise self.fail(act.line, tag, f"{owner!r} is a sound source: it can only say, wait, wait-for and repeat")
        if isinstance(act, (WalkTo, Face, PointAt)):
            self.target(act.target, tag, act.line, owner)
        elif isinstance(act, Say):
            if not person and act.request is not None:
                raise self.fail(act.line, tag, f"{owner!r} is a sound source: it says text=, it has no paraphrase bank (request=)")
            if act.side_of is not None:
                found = self.kinds.get(act.side_of)
                if found is None or found[0] != "object":
                    raise self.fail(act.line, tag, "side-of: " + unknown_name("object", act.side_of, self.named("object")))
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
        for act in walk_actions(actions):
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
                    self.found.append(self.fail(d.line, "door", f"{what} is {d.width:g} m wide: a person ({WALKER_RADIUS:g} m radius) "
                                                                f"needs at least {MIN_DOOR_WIDTH:.2f} m"))
                elif not grid.passable(wall, d):
                    self.found.append(self.fail(d.line, "door", f"{what} cannot be walked through: walls or furniture next to it "
                                                                f"leave no room for a person ({WALKER_RADIUS:g} m radius)"))
        for h in sc.humans:
            with self.item():
                self.reachable(grid, h)

    def reachable(self, grid: Grid, h: HumanSpec) -> None:
        """Every fixed place ``h`` walks to, and the exit she leaves by, is in the part of the flat she starts in (each one that is not, named)."""
        sc = self.sc
        home = grid.component((h.x, h.y))
        for act in walk_actions(h.script + tuple(a for hd in h.handlers for a in hd.body)):
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
                self.found.append(self.fail(act.line, _action_tag(act), f"{h.name!r} cannot reach {what} from the start at "
                                                                        f"({h.x:g}, {h.y:g}): walls or furniture close it off"))

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
            raise self.fail(line, tag, unknown_name(t.kind, t.name, self.named(t.kind)))
        if t.kind == "human" and t.name == owner:
            raise self.fail(line, tag, f"{owner!r} cannot target themselves")

    @cached_property
    def spoken(self) -> str:
        """Everything the people and sources say as written (``text=`` and ``about=``), lower case."""
        words = [w for h in self.sc.humans for a in walk_actions(h.script + tuple(x for hd in h.handlers for x in hd.body))
                 if isinstance(a, Say) for w in (a.text, a.about) if w]
        words += [w for s in self.sc.sources for a in walk_actions(s.script) if isinstance(a, Say) for w in (a.text, a.about) if w]
        return "\n".join(words).lower()

    def taught(self, e: Expectation, key: str, what: str, known: list[str]) -> None:
        """A name the robot should learn is one of the scenario's, or words somebody says (her word for it).

        A scenario that starts from an earlier run's knowledge (``<robot memory="required">``) may ask
        about anything that run taught."""
        value = e.get(key)
        if value is None or e.get("never") is True or self.sc.robot.memory_required:
            return
        text = str(value)
        if text in known or re.search(rf"\b{re.escape(text.lower())}\b", self.spoken):
            return
        raise self.fail(e.line, e.kind, f"{key}={text!r}: nobody says it and " + unknown_name(what, text, known)
                        + "; the robot can only learn a name somebody uses (knowledge from an earlier run: "
                        + '<robot memory="required">)')

    def expectation(self, e: Expectation) -> None:
        if e.kind == "place-learned":
            self.taught(e, "name", "room or place", self.named("room") + self.named("place"))
            if e.get("where") is not None:
                self.target(e.get("where"), "place-learned", e.line)  # type: ignore[arg-type]
        if e.kind == "object-learned":
            self.taught(e, "type", "object type", sorted({o.type for o in self.sc.objects}))
            self.taught(e, "name", "object", self.named("object"))
        if e.kind == "reached":
            who = e.get("who")
            if self.kinds.get(str(who), ("",))[0] != "human":
                raise self.fail(e.line, e.kind, unknown_name("human", who, self.named("human")))
            self.target(e.get("target"), "reached", e.line, str(who))  # type: ignore[arg-type]
            by = e.get("by")
            if by is not None and float(by) > self.sc.duration:  # type: ignore[arg-type]
                raise self.fail(e.line, e.kind, f"by={by} is after the end of the run ({self.sc.duration} s)")
        if e.kind == "robot-near":
            self.target(e.get("target"), "robot-near", e.line)  # type: ignore[arg-type]
        if e.kind == "following-distance":
            who = e.get("who")
            if self.kinds.get(str(who), ("",))[0] != "human":
                raise self.fail(e.line, e.kind, unknown_name("human", who, self.named("human")))
        for key in ("after", "by"):
            t = e.get(key)
            if e.kind != "reached" and t is not None and float(t) > self.sc.duration:  # type: ignore[arg-type]
                raise self.fail(e.line, e.kind, f"{key}={t} is after the end of the run ({self.sc.duration} s)")
        if e.get("after") is not None and e.get("by") is not None and float(e.get("after")) > float(e.get("by")):  # type: ignore[arg-type]
            raise self.fail(e.line, e.kind, f"after={float(e.get('after')):g} is later than by={float(e.get('by')):g}")  # type: ignore[arg-type]
        if e.kind == "no-collision":
            what = e.get("with")
            if what is not None and what not in ("wall", "furniture") and self.kinds.get(str(what), ("",))[0] != "human":
                raise self.fail(e.line, e.kind, f"with={what!r}: use 'wall', 'furniture' or the name of a human"
                                                f"{did_you_mean(str(what), ['wall', 'furniture', *self.named('human')])}")
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
    for a in walk_actions(actions):
        if isinstance(a, (Wait, Say, WalkTo, PointAt, WaitFor, StepCloser)) and not (isinstance(a, Wait) and a.duration <= 0):
            return True
    return False


def walk_actions(actions: Iterable[Action]) -> Iterator[Action]:
    """Every action of a script, depth first: repeats' bodies and a wait's own reactions included."""
    for a in actions:
        yield a
        if isinstance(a, Repeat):
            yield from walk_actions(a.body)
        elif isinstance(a, WaitFor):
            for hd in a.handlers:  # a wait's own reactions (<on> inside the wait-for)
                yield from walk_actions(hd.body)
