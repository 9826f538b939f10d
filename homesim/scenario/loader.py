"""Load a scenario file: checked pipeline text -> parse -> XSD -> model -> checks.

1. :func:`homesim.xmlio.parse_file` (the one hardened parser);
2. ``homesim/schemas/scenario.xsd`` (structure and value types);
3. build the plain :class:`~homesim.scenario.model.Scenario` (units converted);
4. :func:`homesim.scenario.checks.check` (names, references, geometry).

Every failure is a :class:`~homesim.errors.ScenarioError` that names the
file, the line, the element and the problem, re-raised ``from`` the
underlying error. The model is built completely and checked before it is
returned, so a caller never sees a half-loaded scenario.
"""

from __future__ import annotations

import copy

import math
import os
import re
from pathlib import Path

from lxml import etree

from ..deployment import Override, override_from_element
from ..errors import InputError, ScenarioError
from ..xmlio import Schema, load_schema, parse_bytes, parse_file
from .schemawords import Wording, describe_all, element_attributes, element_children, local_type_words, type_words
from . import checks
from .model import (
    COLOURS,
    RGB,
    Action,
    Door,
    Expectation,
    Face,
    Fault,
    Furniture,
    Handler,
    HumanSpec,
    Leave,
    ObjectSpec,
    Place,
    PointAt,
    Repeat,
    RobotSpec,
    Room,
    Say,
    Scenario,
    SourceSpec,
    StepCloser,
    Target,
    Wait,
    WaitFor,
    WaitSpeech,
    WalkTo,
    Wall,
)
from .wordpattern import PatternError, compile_words

#: Where the scenario schema lives: inside the package (``homesim/schemas/``), so an installed
#: wheel loads scenarios from any directory.
SCHEMA_PATH = Path(__file__).resolve().parent.parent / "schemas" / "scenario.xsd"

#: Coordinates in points and polygons (metres), as the XSD's ``coord`` type.
COORD_LIMIT = 1000.0
#: Times in windows (seconds), as the XSD's ``nonNegative`` type.
MAX_TIME_S = 1e6

_TARGET_KEYS = ("place", "room", "object", "furniture", "human", "robot", "point")

#: A person's traits a scenario may give on <human> (overriding her profile's draws), in draw order.
TRAIT_KEYS = ("voice", "distance", "speed", "patience", "off-axis", "pointing-error", "phrasing", "repairs", "give-up")


def scenario_schema() -> Schema:
    """The compiled scenario XSD (loaded once per process)."""
    return load_schema(SCHEMA_PATH)


def load_scenario(path: str | os.PathLike[str]) -> Scenario:
    """Load and check one scenario file; raise ScenarioError naming file and line."""
    source = str(path)
    try:
        root = parse_file(path)
    except InputError as exc:
        raise ScenarioError(exc.message, source=source, line=exc.line, element=exc.element) from exc
    return _from_root(root, source)


def load_scenario_text(text: str | bytes, *, source: str = "<scenario>") -> Scenario:
    """Load a scenario given as text (tests, notebooks); same checks as a file."""
    try:
        root = parse_bytes(text, source=source)
    except InputError as exc:
        raise ScenarioError(exc.message, source=source, line=exc.line, element=exc.element) from exc
    return _from_root(root, source)


def _from_root(root: etree._Element, source: str) -> Scenario:
    problems = schema_problems(root, source)
    if problems:
        first = problems[0]
        more = f" (and {len(problems) - 1} more problem(s))" if len(problems) > 1 else ""
        raise ScenarioError(first.message + more, source=source, line=first.line, element=first.element)
    scenario = _Builder(source).scenario(root)
    checks.check(scenario)
    return scenario


#: At most this many unexpected elements are taken out to look behind them (each costs one validation).
MAX_SCHEMA_ROUNDS = 50


def schema_problems(root: etree._Element, source: str) -> list[ScenarioError]:
    """Every scenario.xsd problem of ``root`` as ``file:line: <element>: what is wrong; expected ...``, by line.

    libxml2 stops checking an element's later children at the first child it
    does not expect (a misspelt ``<wiat>`` hides a wrong attribute two lines
    below), so each unexpected element is taken out of a copy and the copy
    validated again, until nothing new is unexpected. Problems a removal
    causes (the parent now misses a child) are not reported.
    """
    errors = scenario_schema().errors(root)
    found, seen = list(errors), set(errors)
    parents: dict[tuple[int, str], str] = {}
    doc = None
    for _ in range(MAX_SCHEMA_ROUNDS):
        unexpected = [(line, msg) for line, msg in errors if _is_unexpected(msg)]
        if not unexpected:
            break
        if doc is None:
            doc = copy.deepcopy(root)
        removed = 0
        for line, msg in unexpected:
            tag = msg.split("'", 2)[1]
            for el in doc.iter(tag):
                if el.sourceline == line and el.getparent() is not None:
                    parents[(line, tag)] = etree.QName(el.getparent()).localname
                    el.getparent().remove(el)
                    removed += 1
                    break
        if not removed:
            break
        errors = [e for e in scenario_schema().errors(doc) if e not in seen and "Missing child element" not in e[1]]
        found += errors
        seen.update(errors)
    ordered = sorted(found, key=lambda e: e[0] or 0)  # stable: libxml2's order within a line
    return [ScenarioError(f"{words} (scenario.xsd)", source=source, line=line or None, element=element)
            for line, element, words in describe_all(ordered, _wording(), parents)]


def _is_unexpected(message: str) -> bool:
    return message.startswith("Element '") and ": This element is not expected" in message


def _wording() -> Wording:
    """What scenario.xsd's patterns and simple types accept, in words (read once from the schema)."""
    global _WORDING
    if _WORDING is None:
        schema = parse_file(SCHEMA_PATH)
        _WORDING = Wording(patterns=_pattern_forms(), types=type_words(schema), attributes=element_attributes(schema),
                           children=element_children(schema), local=local_type_words(schema, _pattern_forms()))
    return _WORDING


_WORDING: Wording | None = None


def check_scenario_file(path: str | os.PathLike[str]) -> list[InputError]:
    """Every problem of a scenario file ([] when it loads): all schema problems, else every semantic one.

    The builder stops at its first problem (a value it cannot turn into the
    model); the schema stage and the checks report them all.
    """
    source = str(path)
    try:
        root = parse_file(path)
    except InputError as exc:
        return [ScenarioError(exc.message, source=source, line=exc.line, element=exc.element)]
    problems: list[InputError] = list(schema_problems(root, source))
    if problems:
        return problems
    try:
        scenario = _Builder(source).scenario(root)
    except InputError as exc:
        return [exc]
    return list(checks.problems(scenario))


#: What each pattern-restricted value of scenario.xsd must look like (by simple type or attribute name).
FORMS = {
    "name": "a name: a letter, then at most 63 letters, digits, '_', '-' or spaces",
    "polygon": "'x,y x,y ...' with at least 3 points (at most 65), numbers such as 1.5 or -2e3",
    "point": "'x y': two numbers separated by a space",
    "colour": "a colour name in lower case (e.g. red) or '#rrggbb'",
    "window": "'t0 t1': two times in seconds (not negative), separated by a space",
    "metric": "a dotted name of a summary value, e.g. following.mean_distance_m",
}


def _pattern_forms() -> dict[str, str]:
    """Pattern text -> the words for it, read from scenario.xsd (the simple type or attribute it restricts)."""
    global _FORMS_BY_PATTERN
    if _FORMS_BY_PATTERN is None:
        xs = "{http://www.w3.org/2001/XMLSchema}"
        out: dict[str, str] = {}
        for pat in parse_file(SCHEMA_PATH).iter(xs + "pattern"):
            owner = pat.getparent()
            while owner is not None and owner.get("name") is None:
                owner = owner.getparent()
            name = "" if owner is None else owner.get("name", "")
            if owner is not None and owner.tag == xs + "attribute":  # an anonymous type: say whose attribute
                host = owner.getparent()
                while host is not None and host.get("name") is None:
                    host = host.getparent()
                if host is not None and host.get("name") in FORMS:
                    name = host.get("name", "")
            out[pat.get("value", "")] = FORMS.get(name, f"the form of {name!r} in scenario.xsd")
        _FORMS_BY_PATTERN = out
    return _FORMS_BY_PATTERN


_FORMS_BY_PATTERN: dict[str, str] | None = None


class _Builder:
    """Turns a schema-valid element tree into model objects (degrees -> radians)."""

    def __init__(self, source: str) -> None:
        self.source = source

    def fail(self, el: etree._Element, message: str) -> ScenarioError:
        return ScenarioError(message, source=self.source, line=el.sourceline, element=_tag(el))

    # ----------------------------------------------------------- attributes
    def num(self, el: etree._Element, key: str, default: float | None = None) -> float:
        raw = el.get(key)
        if raw is None:
            if default is None:
                raise self.fail(el, f"attribute {key!r} is required")
            return default
        return self.number(el, key, raw, raw)

    def number(self, el: etree._Element, key: str, raw: str, text: str) -> float:
        """One finite number ``text`` (part of attribute ``key``'s value ``raw``), or an error with the line."""
        try:
            v = float(text)
        except ValueError as exc:
            raise self.fail(el, f"attribute {key}={raw!r}: {text!r} is not a number") from exc
        if not math.isfinite(v):
            raise self.fail(el, f"attribute {key}={raw!r}: {text!r} is not a finite number")
        return v

    def opt(self, el: etree._Element, key: str) -> float | None:
        return None if el.get(key) is None else self.num(el, key)

    def flag(self, el: etree._Element, key: str, default: bool = False) -> bool:
        raw = el.get(key)
        return default if raw is None else raw.strip() in ("true", "1")

    def coord(self, el: etree._Element, key: str, raw: str, text: str) -> float:
        """One coordinate (metres) inside ±COORD_LIMIT, as the XSD's ``coord`` type."""
        v = self.number(el, key, raw, text)
        if abs(v) > COORD_LIMIT:
            raise self.fail(el, f"attribute {key}={raw!r}: {text!r} is outside -{COORD_LIMIT:g} to {COORD_LIMIT:g} m")
        return v

    def point(self, el: etree._Element, key: str) -> tuple[float, float]:
        raw = el.get(key, "")
        parts = raw.split()
        if len(parts) != 2:
            raise self.fail(el, f"attribute {key}={raw!r} is not a point 'x y'")
        return self.coord(el, key, raw, parts[0]), self.coord(el, key, raw, parts[1])

    def polygon(self, el: etree._Element) -> tuple[tuple[float, float], ...]:
        raw = el.get("points", "")
        pts = []
        for pair in _pairs(raw):
            if len(pair) != 2:
                raise self.fail(el, f"points={raw!r} is not a list of 'x,y' pairs")
            pts.append((self.coord(el, "points", raw, pair[0]), self.coord(el, "points", raw, pair[1])))
        return tuple(pts)

    def colour(self, el: etree._Element, key: str, default: str) -> tuple[RGB, str]:
        raw = el.get(key, default)
        if raw.startswith("#"):
            return (int(raw[1:3], 16) / 255, int(raw[3:5], 16) / 255, int(raw[5:7], 16) / 255), raw
        if raw not in COLOURS:
            known = ", ".join(COLOURS)
            raise self.fail(el, f"unknown colour {raw!r}; use one of {known} or #rrggbb")
        return COLOURS[raw], raw

    def window(self, el: etree._Element) -> tuple[float, float] | None:
        raw = el.get("between")
        if raw is None:
            return None
        parts = raw.split()
        if len(parts) != 2:
            raise self.fail(el, f"between={raw!r} is not a time window 't0 t1'")
        t0, t1 = (self.number(el, "between", raw, v) for v in parts)
        if not (0 <= t0 <= MAX_TIME_S and 0 <= t1 <= MAX_TIME_S):
            raise self.fail(el, f"between={raw!r}: times must lie in 0 to {MAX_TIME_S:g} s")
        if t1 < t0:
            raise self.fail(el, f"between={raw!r}: the window ends before it starts")
        return t0, t1

    def target(self, el: etree._Element, *, allow_angle: bool = False, required: bool = True) -> Target | None:
        given = [k for k in _TARGET_KEYS if el.get(k) is not None]
        if allow_angle and el.get("angle") is not None:
            given.append("angle")
        if len(given) > 1:
            raise self.fail(el, f"give one target, not {len(given)} ({', '.join(given)})")
        if not given:
            if not required:
                return None
            options = ", ".join(_TARGET_KEYS + (("angle",) if allow_angle else ()))
            raise self.fail(el, f"a target is required: one of {options}")
        kind = given[0]
        if kind == "point":
            x, y = self.point(el, "point")
            return Target("point", x=x, y=y)
        if kind == "angle":
            return Target("angle", angle=math.radians(self.num(el, "angle")))
        if kind == "robot":
            if not self.flag(el, "robot"):
                raise self.fail(el, 'robot="false" is not a target; leave the attribute out')
            return Target("robot")
        return Target(kind, name=el.get(kind))

    # -------------------------------------------------------------- elements
    def scenario(self, root: etree._Element) -> Scenario:
        flat = root.find("flat")
        walls_el = flat.find("walls")
        default_thickness = self.num(walls_el, "thickness", 0.1)
        desc = root.find("description")
        objects_el = root.find("objects")
        humans_el = root.find("humans")
        sources_el = root.find("sources")
        expect_el = root.find("expect")
        faults_el = root.find("faults")
        return Scenario(
            name=root.get("name"),
            source=self.source,
            seed=int(root.get("seed", "0")),
            duration=self.num(root, "duration"),
            world_rate=self.num(root, "world-rate", 50.0),
            description=" ".join((desc.text or "").split()) if desc is not None else "",
            robot=self.robot(root.find("robot")),
            rooms=tuple(Room(r.get("name"), self.polygon(r), r.sourceline) for r in flat.iterfind("room")),
            walls=tuple(self.wall(w, default_thickness) for w in walls_el.iterfind("wall")),
            furniture=tuple(self.furniture(f) for f in flat.iterfind("furniture")),
            places=tuple(Place(p.get("name"), self.num(p, "x"), self.num(p, "y"), p.sourceline) for p in flat.iterfind("place")),
            objects=tuple(self.obj(o) for o in objects_el.iterfind("object")) if objects_el is not None else (),
            humans=tuple(self.human(h) for h in humans_el.iterfind("human")) if humans_el is not None else (),
            sources=tuple(self.sound_source(s) for s in _elements(sources_el)) if sources_el is not None else (),
            expectations=tuple(self.expectation(e) for e in _elements(expect_el)) if expect_el is not None else (),
            faults=tuple(Fault(_tag(f), f.get("module"), self.num(f, "at"), f.sourceline) for f in _elements(faults_el)) if faults_el is not None else (),
            deployment=self.deployment(root.find("deployment")),
        )

    def robot(self, el: etree._Element) -> RobotSpec:
        return RobotSpec(
            x=self.num(el, "x"),
            y=self.num(el, "y"),
            heading=math.radians(self.num(el, "heading", 0.0)),
            max_speed=self.num(el, "max-speed", 0.5),
            max_turn=math.radians(self.num(el, "max-turn", 100.0)),
            laser_rate=self.num(el, "laser-rate", 10.0),
            camera_rate=self.num(el, "camera-rate", 10.0),
            audio_rate=self.num(el, "audio-rate", 10.0),
            odometry_rate=self.num(el, "odometry-rate", 10.0),
            object_confusion=self.num(el, "object-confusion", 0.05),
            options=self.options(el),
            profile=el.get("profile"),
            line=el.sourceline,
            memory_required=el.get("memory") == "required",
        )

    def deployment(self, el: etree._Element | None) -> Override | None:
        """The scenario's ``<deployment>`` override (children checked against the deployment schema)."""
        if el is None:
            return None
        try:
            return override_from_element(el, source=self.source)
        except InputError as exc:
            raise ScenarioError(exc.message, source=self.source, line=exc.line, element=exc.element) from exc

    def options(self, el: etree._Element) -> tuple[tuple[str, str], ...]:
        seen: dict[str, int] = {}
        out = []
        for o in el.iterfind("option"):
            name = o.get("name")
            if name in seen:
                raise self.fail(o, f"option {name!r} is already given on line {seen[name]}")
            seen[name] = o.sourceline
            out.append((name, o.get("value")))
        return tuple(out)

    def when(self, el: etree._Element) -> list[tuple[str, object]]:
        """between / after / by / never of a robot-level check."""
        attrs: list[tuple[str, object]] = [("between", self.window(el)), ("after", self.opt(el, "after")), ("by", self.opt(el, "by"))]
        return attrs + [("never", self.flag(el, "never"))]

    def wall(self, el: etree._Element, default_thickness: float) -> Wall:
        doors = tuple(
            Door(
                at=self.num(d, "at"),
                width=self.num(d, "width"),
                name=d.get("name"),
                exit=self.flag(d, "exit"),
                line=d.sourceline,
            )
            for d in el.iterfind("door")
        )
        return Wall(self.point(el, "from"), self.point(el, "to"), self.num(el, "thickness", default_thickness), doors, el.sourceline)

    def furniture(self, el: etree._Element) -> Furniture:
        return Furniture(
            name=el.get("name"),
            type=el.get("type"),
            polygon=self.polygon(el),
            height=self.num(el, "height"),
            clearance=self.num(el, "clearance", 0.0),
            leg=self.num(el, "leg", 0.05),
            line=el.sourceline,
        )

    def obj(self, el: etree._Element) -> ObjectSpec:
        rgb, cname = self.colour(el, "colour", "grey")
        return ObjectSpec(
            name=el.get("name"),
            type=el.get("type"),
            colour=rgb,
            colour_name=cname,
            size=self.num(el, "size", 0.1),
            height=self.num(el, "height", 0.1),
            x=self.num(el, "x"),
            y=self.num(el, "y"),
            on=el.get("on"),
            line=el.sourceline,
        )

    def human(self, el: etree._Element) -> HumanSpec:
        rgb, cname = self.colour(el, "torso", "blue")
        return HumanSpec(
            name=el.get("name"),
            x=self.num(el, "x"),
            y=self.num(el, "y"),
            heading=math.radians(self.num(el, "heading", 0.0)),
            height=self.num(el, "height", 1.75),
            torso=rgb,
            torso_name=cname,
            speed=self.num(el, "speed", 1.0),
            script=self.script(el.find("script")),
            line=el.sourceline,
            profile=el.get("profile"),
            traits=tuple((k, el.get(k)) for k in TRAIT_KEYS if el.get(k) is not None),
            handlers=tuple(self.handler(h) for h in el.iterfind("on")),
            speed_given=el.get("speed") is not None,
        )

    def words(self, el: etree._Element, key: str) -> str | None:
        """A word-pattern attribute, refused with its line and column when it is not one."""
        raw = el.get(key)
        if raw is None:
            return None
        try:
            compile_words(raw)
        except PatternError as exc:
            raise self.fail(el, f"{key}={raw!r}: {exc}") from exc
        return raw

    def handler(self, el: etree._Element) -> Handler:
        times = el.get("max")
        return Handler(self.words(el, "hears") or "", tuple(self.action(a) for a in _elements(el)), when=el.get("when", "always"),
                       max=None if times is None else int(times), line=el.sourceline)

    def sound_source(self, el: etree._Element) -> SourceSpec:
        return SourceSpec(
            name=el.get("name"),
            kind=_tag(el),
            x=self.num(el, "x"),
            y=self.num(el, "y"),
            height=self.num(el, "height", 1.0),
            loudness=self.num(el, "loudness", 60.0),
            script=self.script(el.find("script")),
            line=el.sourceline,
        )

    def script(self, el: etree._Element | None) -> tuple[Action, ...]:
        if el is None:
            return ()
        return tuple(self.action(a) for a in _elements(el))

    def action(self, el: etree._Element) -> Action:
        tag, line = _tag(el), el.sourceline
        if tag == "walk-to":
            return WalkTo(self.target(el), stop_at=self.num(el, "stop-at", 0.0), speed=self.opt(el, "speed"), line=line)
        if tag == "face":
            return Face(self.target(el, allow_angle=True), body=self.flag(el, "body"), line=line)
        if tag == "say":
            if el.get("text") is None and el.get("request") is None:
                raise self.fail(el, "<say> needs text= or request= (a phrasing drawn from the paraphrase bank)")
            for slot in ("about", "side-of"):
                if el.get(slot) is not None and el.get("request") is None:
                    raise self.fail(el, f"{slot}= fills a bank phrasing's slot: it needs request=")
            if el.get("about") is not None and el.get("side-of") is not None:
                raise self.fail(el, "about= and side-of= both fill the one slot: give one")
            return Say(el.get("text"), loudness=self.opt(el, "loudness"), duration=self.opt(el, "duration"), line=line,
                       request=el.get("request"), about=el.get("about"), wait=self.flag(el, "wait", True),
                       side_of=el.get("side-of"))
        if tag == "wait-speech":
            return WaitSpeech(line=line)
        if tag == "step-closer":
            return StepCloser(by=self.num(el, "by", 0.5), nearest=self.num(el, "nearest", 0.6), line=line)
        if tag == "point":
            return PointAt(self.target(el), duration=self.num(el, "duration", 2.0), line=line)
        if tag == "wait":
            return Wait(self.num(el, "for"), line=line)
        if tag == "wait-for":
            retries = el.get("retries")
            repairs = el.get("repairs")
            patience = el.get("patience")
            if el.get("robot-says") is not None and el.get("hears") is not None:
                raise self.fail(el, "give robot-says= (a regular expression) or hears= (a word pattern), not both")
            if retries is not None and (repairs is not None or patience is not None or el.get("give-up") is not None):
                raise self.fail(el, "retries= (the turn again, word for word) cannot be combined with repairs=, patience= or give-up=")
            return WaitFor(el.get("robot-says"), self.opt(el, "robot-within"), self.opt(el, "timeout"), line=line,
                           retries=0 if retries is None else int(retries), repair=el.get("repair"), hears=self.words(el, "hears"),
                           repairs=None if repairs is None else (() if repairs == "none" else tuple(repairs.split())),
                           patience=None if patience is None else int(patience), give_up=el.get("give-up"),
                           handlers=tuple(self.handler(h) for h in el.iterfind("on")))
        if tag == "leave":
            return Leave(el.get("door"), line=line)
        if tag == "repeat":
            times = el.get("times")
            return Repeat(tuple(self.action(a) for a in _elements(el)), None if times is None else int(times), line=line)
        raise self.fail(el, f"unknown action <{tag}>")  # the XSD forbids this

    def expectation(self, el: etree._Element) -> Expectation:
        tag = _tag(el)
        attrs: list[tuple[str, object]] = []
        if tag == "reached":
            attrs += [("who", el.get("who")), ("target", self.target(el)), ("within", self.num(el, "within", 0.5))]
            if el.get("by") is not None:
                attrs.append(("by", self.num(el, "by")))
        elif tag in ("legs-seen", "face-seen", "sound-heard"):
            attrs += [("bearing", math.radians(self.num(el, "bearing"))), ("tolerance", math.radians(self.num(el, "tolerance", 10.0)))]
            attrs += [("between", self.window(el)), ("absent", self.flag(el, "absent"))]
        elif tag == "no-collision":
            attrs += [("with", el.get("with")), ("between", self.window(el))]
        elif tag == "robot-inside":
            attrs += [("between", self.window(el))]
        elif tag == "robot-near":
            attrs += [("target", self.target(el)), ("within", self.num(el, "within", 1.0))] + self.when(el)
        elif tag == "robot-says":
            pattern = el.get("pattern")
            try:
                re.compile(pattern)
            except re.error as exc:
                raise self.fail(el, f"pattern={pattern!r} is not a regular expression: {exc}") from exc
            attrs += [("pattern", pattern)] + self.when(el)
        elif tag == "state-reached":
            attrs += [("state", el.get("state"))] + self.when(el)
        elif tag == "event-rejected":
            attrs += [("event", el.get("event")), ("reason", el.get("reason")), ("state", el.get("state"))] + self.when(el)
        elif tag == "event-applied":
            attrs += [("event", el.get("event")), ("state", el.get("state"))] + self.when(el)
        elif tag in ("object-learned", "place-learned"):
            keys = ("type", "name", "owner", "colour", "attribute", "use") if tag == "object-learned" else ("name",)
            attrs += [(k, el.get(k)) for k in keys if el.get(k) is not None]
            if not attrs:
                raise self.fail(el, f"<{tag}> needs at least one of {', '.join(keys)}")
            if tag == "place-learned":
                attrs += [("where", self.target(el, required=False)), ("within", self.opt(el, "within"))]
            attrs.append(("never", self.flag(el, "never")))
        elif tag == "following-distance":
            attrs += [("who", el.get("who")), ("min", self.num(el, "min")), ("max", self.num(el, "max")),
                      ("fraction", self.num(el, "fraction", 0.9)), ("settle", self.num(el, "settle", 2.0)), ("between", self.window(el))]
            if attrs[2][1] < attrs[1][1]:  # type: ignore[operator]
                raise self.fail(el, f"max={el.get('max')} is below min={el.get('min')}")
        elif tag == "metric":
            attrs += [("name", el.get("name")), ("min", self.opt(el, "min")), ("max", self.opt(el, "max"))]
            if el.get("min") is None and el.get("max") is None:
                raise self.fail(el, "<metric> needs min=, max= or both")
        else:  # pragma: no cover - the XSD forbids this
            raise self.fail(el, f"unknown expectation <{tag}>")
        return Expectation(tag, tuple(attrs), el.sourceline, tuple((str(k), str(v)) for k, v in el.attrib.items()))


def _pairs(raw: str) -> list[list[str]]:
    """The "x,y" pairs of a points attribute (the XSD allows blanks around the comma)."""
    return [p.split(",") for p in re.sub(r"\s*,\s*", ",", raw.strip()).split()]


def _tag(el: etree._Element) -> str:
    return etree.QName(el).localname if isinstance(el.tag, str) else "#comment"


def _elements(el: etree._Element):  # type: ignore[no-untyped-def]
    """Child elements only (comments and processing instructions skipped)."""
    return (c for c in el if isinstance(c.tag, str))
