"""``homesim generate``: random flats with a home tour, written as ordinary scenario files.

``homesim generate --seed N [--count K] --out DIR`` writes ``DIR/tour-N-k.xml``
for k = 0 .. K-1. Each file is a plain scenario (it passes ``homesim check``
and runs with ``homesim run``): a flat from :mod:`homesim.tour.flatgen`,
objects from :mod:`homesim.tour.objectgen`, the robot, a user who gives the
robot a home tour, 0 to 3 bystanders, sometimes a radio or a TV, and the
expectations that follow from the tour.

The tour (:class:`TourWriter`): the user greets the robot, then, in a varied
order and subset, asks what it can do, teaches the room she is in, has it
follow her through the flat (through doors and corridors, at a walking pace
of 0.35 to 0.6 m/s), stops and teaches objects by pointing and speech (from
a spot 0.6 to 0.9 m from the object from which the object can be seen, and
from which the robot, too, has a place to see it from), asks where an object
she taught is, sends the robot to a room she taught (then walks over to it
and greets it again), and says good-bye. Every request is worded from the
users' one paraphrase bank (``humans/phrasings.xml``, :mod:`humans.phrasings`), which is kept
apart from the robot's understanding corpus. She waits for
the robot's answer to each request and repeats her turn when it asks her to
or does not answer (at most twice), like the library's users.

The expectations say what the tour must achieve and never how: the greeting
answered and the interaction started; the self-explanation given; each room
she taught learned under her word for it; each object she taught learned
with its type (and owner, colour or "favourite" when she said them), and
nothing stored that she did not point at; the robot in every room she led it
to, at a following distance of 0.5 to 2.5 m for 80 % of the time, the partner
never lost; each "where is" answered; each go-to reached without asking for
help; good-bye answered; no collision at all.

The run lasts long enough for her to reach her good-bye even when every request had to be
said twice with the robot silent (each wait to its timeout), so a robot that fails early is
not also charged with a good-bye she never got to say.

Determinism: file k of seed N is drawn from ``numpy.random.default_rng([N, k])``
alone (it does not depend on K); the same seed gives byte-identical files.
"""

from __future__ import annotations

import argparse
import math
import re
import sys
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from lxml import etree

from ..cliargs import OptionError, count
from ..world.acoustics import speech_duration
from ..scenario.pathplan import NoPathError
from . import usergen as U
from .flatgen import WALL, Flat, RoomPlan, generate_flat, snap
from .objectgen import ObjectPlan, generate_objects
from humans.phrasings import default_bank

Point = tuple[float, float]

USER_NAMES = ("anna", "maria", "lena", "sara", "eva", "julia", "tom", "marc", "paul", "jan", "ben", "david")
TORSOS = ("red", "blue", "green", "yellow", "orange", "purple", "pink", "brown", "black", "white", "grey", "beige")
FOLLOW_SPEED = (0.35, 0.6)  # m/s: how fast she walks with the robot behind her
WALK_SPEED = (0.8, 1.2)  # m/s: her own pace (and bystanders')
ANSWER_S = 3.0  # typical seconds from the end of a request to the robot's answer (an estimate, for timing)
MAX_COUNT = 10_000
#: The bystanders' scripts are made for a run this long (a user repairing every request this many
#: times), whatever the user's profile: the same home under every users mix.
BYSTANDER_PATIENCE = 3
#: What she mentions when she teaches an object: (owner "my", "favourite", its colour), one
#: drawn alike; with a similar object next to it she always says the colour.
MENTIONS = ((True, False, False), (True, True, False), (False, False, False), (False, False, False),
            (True, False, False), (False, False, True), (True, False, True))
MENTIONS_SIMILAR = ((False, False, True), (True, False, True), (True, False, True))
#: Why draws were refused by the scenario checks (for the generator's tests and debugging).
REFUSED: list[str] = []


def fmt(v: float) -> str:
    """A short, stable decimal: 2.5, 3, -0.15."""
    s = f"{v:.2f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def rx(text: str) -> str:
    """``text`` as a regular expression matching itself (spaces and letters stay readable)."""
    return re.sub(r"([.^$*+?{}\[\]\\|()])", r"\\\1", text)


def pt(p: Point) -> str:
    return f"{fmt(p[0])} {fmt(p[1])}"


# ----------------------------------------------------------------- geometry
#: How far a line of sight keeps from a room's inner corner: the wall's half thickness and a
#: margin (the corner of an L-shaped room's walls stands out into the room by half a wall).
CORNER_CLEAR = WALL / 2 + 0.1


def sight(room: RoomPlan, a: Point, b: Point, step: float = 0.05) -> bool:
    """The segment a-b stays inside the room (no wall between the two points).

    The room's polygon runs along the walls' centre lines, so a segment that only grazes an
    L-shaped room's inner corner is inside the polygon yet passes through the wall's thickness:
    it must keep :data:`CORNER_CLEAR` from every inner (reflex) corner. A person told apart
    from the robot by that corner is out of its sight and hearing (tour-3000-07: she greeted
    three times from behind the corner and the robot never knew she was there).
    """
    n = max(2, int(math.hypot(b[0] - a[0], b[1] - a[1]) / step))
    if not all(room.contains((a[0] + (b[0] - a[0]) * i / n, a[1] + (b[1] - a[1]) * i / n)) for i in range(n + 1)):
        return False
    return all(_point_segment(c, a, b) >= CORNER_CLEAR for c in inner_corners(room.polygon))


def inner_corners(polygon: tuple[Point, ...]) -> list[Point]:
    """The reflex vertices of a simple polygon (the inner corner of an L), in either winding."""
    n = len(polygon)
    area2 = sum(polygon[i][0] * polygon[(i + 1) % n][1] - polygon[(i + 1) % n][0] * polygon[i][1] for i in range(n))
    out = []
    for i in range(n):
        (px, py), (cx, cy), (nx, ny) = polygon[i - 1], polygon[i], polygon[(i + 1) % n]
        cross = (cx - px) * (ny - cy) - (cy - py) * (nx - cx)
        if cross * area2 < 0:
            out.append(polygon[i])
    return out


def free(flat: Flat, p: Point, *, robot: bool = False) -> bool:
    """Free for a person (or the robot) and joined to the rest of the flat (not in a pocket behind furniture)."""
    grid = flat.grid if robot else flat.walk_grid
    assert grid is not None
    c = grid.cell_of(p)
    return not grid.blocked[c] and grid.component(p) == grid.component(flat.anchor)


def free_point(rng: np.random.Generator, flat: Flat, room: int, *, robot: bool = False, margin: float = 0.0,
               away: tuple[Point, ...] = (), gap: float = 1.0) -> Point | None:
    """A random point of the room, free for a person (or the robot), ``gap`` from the ``away`` points."""
    r = flat.rooms[room]
    for _ in range(60):
        part = r.parts[int(rng.integers(len(r.parts)))]
        inner = part.inset(0.4 + margin)
        if inner.w <= 0 or inner.h <= 0:
            continue
        p = snap(float(rng.uniform(inner.x0, inner.x1))), snap(float(rng.uniform(inner.y0, inner.y1)))
        if not r.contains(p) or not free(flat, p, robot=robot):
            continue
        if margin and not all(free(flat, (p[0] + dx, p[1] + dy), robot=robot) for dx, dy in ((margin, 0), (-margin, 0), (0, margin), (0, -margin))):
            continue
        if all(math.hypot(p[0] - q[0], p[1] - q[1]) >= gap for q in away):
            return p
    return None


def _point_segment(p: Point, a: Point, b: Point) -> float:
    ax, ay = a
    dx, dy = b[0] - ax, b[1] - ay
    L = dx * dx + dy * dy
    t = 0.0 if L == 0 else max(0.0, min(1.0, ((p[0] - ax) * dx + (p[1] - ay) * dy) / L))
    return math.hypot(p[0] - ax - t * dx, p[1] - ay - t * dy)


def teaching_spot(rng: np.random.Generator, flat: Flat, o: ObjectPlan) -> Point | None:
    """Where she stands to point at ``o``: 0.6-0.9 m from it, free, with a clear view of it, and
    with a spot for the robot 1.0-1.8 m from her from which the robot sees the object past her."""
    room = flat.rooms[o.room]
    spots = []
    for k in range(24):
        a = 2 * math.pi * k / 24
        for r in (0.6, 0.75, 0.9):
            d = r + o.size / 2
            p = snap(o.x + d * math.cos(a)), snap(o.y + d * math.sin(a))
            if math.hypot(p[0] - o.x, p[1] - o.y) > 0.9 + o.size / 2 or not room.contains(p) or not free(flat, p) or not sight(room, p, (o.x, o.y)):
                continue
            if _robot_view(flat, room, p, o):
                spots.append(p)
    if not spots:
        return None
    return spots[int(rng.integers(len(spots)))]


def _robot_view(flat: Flat, room: RoomPlan, p: Point, o: ObjectPlan) -> bool:
    for k in range(16):
        a = 2 * math.pi * k / 16
        for r in (1.0, 1.4, 1.8):
            q = p[0] + r * math.cos(a), p[1] + r * math.sin(a)
            d = math.hypot(q[0] - o.x, q[1] - o.y)
            if not (0.9 <= d <= 3.0) or not room.contains(q) or not free(flat, q, robot=True):
                continue
            if _point_segment(p, q, (o.x, o.y)) >= 0.4 and sight(room, q, (o.x, o.y)):
                return True
    return False


def aside_spot(flat: Flat, o: ObjectPlan, spot: Point) -> Point | None:
    """Where she steps when the robot says she stands in front of the object: round it by 40 to 70
    degrees (either way), as close to it as before, free, with a clear view of it, in its room."""
    room = flat.rooms[o.room]
    a0 = math.atan2(spot[1] - o.y, spot[0] - o.x)
    r = math.hypot(spot[0] - o.x, spot[1] - o.y)
    for deg in (40, -40, 55, -55, 70, -70):
        a = a0 + math.radians(deg)
        p = snap(o.x + r * math.cos(a)), snap(o.y + r * math.sin(a))
        if room.contains(p) and free(flat, p) and sight(room, p, (o.x, o.y)):
            return p
    return None


def path_length(flat: Flat, a: Point, b: Point) -> float:
    """Walking distance a -> b (straight-line times 1.3 when no plan is found)."""
    assert flat.walk_grid is not None
    try:
        pts = flat.walk_grid.plan(a, b)
    except NoPathError:
        return 1.3 * math.hypot(b[0] - a[0], b[1] - a[1])
    total, cur = 0.0, a
    for q in pts:
        total += math.hypot(q[0] - cur[0], q[1] - cur[1])
        cur = q
    return total


def where_it_stands(o: ObjectPlan) -> str:
    """"on the coffee table", "on the kitchen counter", "on the floor": what a person says of where ``o`` stands."""
    if o.on is None:
        return "on the floor"
    return "on the " + re.sub(r"\s+\d+$", "", o.on.name)


# ------------------------------------------------------------------ the tour
@dataclass
class TourWriter:
    """Writes the user's script and collects the expectations, keeping an estimate of the time."""

    rng: np.random.Generator
    flat: Flat
    user: str
    pos: Point
    room: int
    script: etree._Element
    t: float = 0.0
    expect: list[tuple[str, dict[str, str], str]] = field(default_factory=list)  # (tag, attrs, comment)
    taught_places: dict[int, tuple[str, Point]] = field(default_factory=dict)  # room -> (word, where she stood)
    taught_objects: list[tuple[ObjectPlan, str]] = field(default_factory=list)
    led_to: list[int] = field(default_factory=list)  # rooms she led the robot into
    gotos: int = 0
    timeline: list[tuple[float, int, Point]] = field(default_factory=list)
    interacting: bool = False
    asked_capabilities: bool = False
    slack_base: float = 0.0  # extra seconds when the robot is silent: each wait to its timeout, one question answered
    slack_repair: float = 0.0  # and per repair of every request (a gap, her turn again, the wait)
    patience: int = 2  # the most repairs her profile makes for one request
    objects: dict[str, ObjectPlan] = field(default_factory=dict)  # the flat's objects, by name

    def pick(self, options: tuple) -> object:  # type: ignore[type-arg]
        return options[int(self.rng.integers(len(options)))]

    def phrase(self, request: str, about: str | None = None, *, slotted: bool = False) -> str:
        """A phrasing of ``request`` from the users' bank (any style), its slot filled with ``about``."""
        bank = default_bank()
        return bank.render(bank.draw(self.rng, request, slotted=slotted, about=about), about)

    def act(self, tag: str, **attrs: str) -> None:
        etree.SubElement(self.script, tag, {k.replace("_", "-"): v for k, v in attrs.items()})

    def wait(self, lo: float, hi: float) -> None:
        s = snap(float(self.rng.uniform(lo, hi)))
        if s > 0:
            self.act("wait", **{"for": fmt(s)})
            self.t += s

    def say(self, text: str, answer: str, timeout: float = 6.0, *, request: str, about: str | None = None,
            answers: list[U.Reaction] | None = None, words: bool = False) -> None:
        """Make a request and wait for the robot's answer (matching ``answer``).

        She words it from the paraphrase bank in her profile's style (``request``, ``about``);
        with ``words`` she says ``text`` first (the tour's expectations depend on its words) and
        draws from the bank only when she rephrases. ``text`` also times the turn. She answers the
        robot's questions about it (``answers``, reactions inside the wait) and repairs her
        profile's way, giving up after her patience.
        """
        attrs = {"request": request}
        if words:
            attrs = {"text": text, **attrs}
        if about is not None:
            attrs["about"] = about
        self.act("say", **attrs)
        self.act("wait-for", robot_says=answer, timeout=fmt(timeout))
        if answers:
            U.attach(self.script[-1], answers)
        d = speech_duration(text)
        self.t += d + ANSWER_S
        # the robot silent: the wait to its timeout, then each repair (a gap, her turn again, the wait);
        # and one question of the robot's answered (about 4 s)
        self.slack_base += (timeout - ANSWER_S) + (4.0 if answers else 0.0)
        self.slack_repair += d + timeout + 1.0

    def duration(self, patience: int) -> int:
        """Seconds for her to get to her good-bye even when every request was repaired ``patience``
        times with the robot silent (a robot that fails early is not also charged with a good-bye
        she never got to say)."""
        return math.ceil((self.t + self.slack_base + patience * self.slack_repair + 30) / 10) * 10

    def face_robot(self) -> None:
        self.act("face", robot="true")
        self.t += 0.5

    def note(self) -> None:
        self.timeline.append((self.t, self.room, self.pos))

    # --------------------------------------------------------------- steps
    def greet(self, again: bool = False) -> None:
        self.face_robot()
        request = "greet-again" if again else "greet"
        self.say(self.phrase(request), U.GREETED, 6, request=request,
                 answers=U.reactions("greet"))
        self.interacting = True
        self.note()

    def capabilities(self) -> None:
        self.wait(0.5, 1.5)
        self.face_robot()
        self.say(self.phrase("capabilities"), U.EXPLAINED, 10, request="capabilities")
        self.asked_capabilities = True
        self.t += 6  # the robot's explanation is long

    def teach_place(self) -> None:
        room = self.flat.rooms[self.room]
        word = room.name
        self.wait(0.5, 1.5)
        self.face_robot()
        about = f"the {word}"
        text = self.phrase("teach-place", about)
        self.say(text, U.PLACE_LEARNED, 6, request="teach-place", about=about,
                 answers=U.reactions("place", words=[word], about=about))
        self.taught_places[self.room] = (word, self.pos)
        self.note()

    def follow_to(self, goal: Point, room: int) -> None:
        """"Follow me", walk to ``goal`` with the robot behind her, "stop"."""
        self.wait(0.5, 1.5)
        self.face_robot()
        self.say(self.phrase("follow"), U.FOLLOWING, 6, request="follow", answers=U.reactions("follow"))
        self.wait(0.3, 1.2)
        speed = snap(float(self.rng.uniform(*FOLLOW_SPEED)))
        self.act("walk-to", point=pt(goal), speed=fmt(speed))
        self.t += path_length(self.flat, self.pos, goal) / speed + 2
        self.pos, self.room = goal, room
        self.face_robot()
        self.say(self.phrase("stop"), U.STOPPED, 6, request="stop")
        self.wait(1.0, 3.0)  # the robot comes up to her
        if room not in self.led_to:
            self.led_to.append(room)
        self.note()

    def step_to(self, goal: Point) -> None:
        """A step or two without the robot (the robot turns to her, and should come closer)."""
        self.act("walk-to", point=pt(goal), speed=fmt(snap(float(self.rng.uniform(*FOLLOW_SPEED)))))
        self.t += path_length(self.flat, self.pos, goal) / FOLLOW_SPEED[0] + 1
        self.pos = goal
        self.face_robot()
        self.wait(1.0, 2.5)

    def teach_object(self, o: ObjectPlan, spot: Point) -> None:
        if math.hypot(spot[0] - self.pos[0], spot[1] - self.pos[1]) > 1.2 or self.flat.room_at(spot) != self.room:
            self.follow_to(spot, o.room)
        else:
            self.step_to(spot)
        words = default_bank().object_words[o.type]
        word = words[0] if self.rng.random() < 0.6 else str(self.pick(words))
        owner, favourite, colour = self.pick(MENTIONS_SIMILAR if o.twin else MENTIONS)  # type: ignore[misc]
        # what she calls it, in her sentence and when she rephrases or answers: mine, favourite, colour
        about = ("my " if owner else "the ") + ("favourite " if favourite else "") + (f"{o.colour} " if colour else "") + word
        text = self.phrase("teach-object", about, slotted=True)
        self.act("point", object=o.name, duration=fmt(snap(float(self.rng.uniform(1.5, 2.5)))))
        answers = U.reactions("object", words=[word, o.type.replace("_", " ")], about=about, colour=o.colour, obj=o.name,
                              which=self.which_answer(o))
        aside = aside_spot(self.flat, o, spot)
        if aside is not None:  # "Could you step aside, please?": she steps round the object and points again
            answers.append(U.step_aside(pt(aside), o.name))
        self.say(text, U.OBJECT_LEARNED, 8, request="teach-object", about=about, words=True, answers=answers)
        self.t += 2
        attrs = {"type": o.type}
        if owner:
            attrs["owner"] = "partner"
        if favourite:
            attrs["attribute"] = "favourite"
        if colour:
            attrs["colour"] = o.colour
        self.expect.append(("object-learned", attrs, f"{self.user} taught the {o.name} ({text!r})"))
        self.taught_objects.append((o, word))
        self.note()

    def which_answer(self, o: ObjectPlan) -> list[etree._Element]:
        """How she answers "Which one do you mean?" about ``o``, one way drawn among those that
        tell it from its twin: by colour (not when the twin has the same colour), by position as
        the robot sees them, by where it stands (not when the twin stands there too), by pointing."""
        twin = self.objects.get(o.twin) if o.twin else None
        place = where_it_stands(o)
        kinds = [k for k in U.WHICH_KINDS
                 if not (k == "colour" and twin is not None and twin.colour == o.colour)
                 and not (k == "place" and twin is not None and where_it_stands(twin) == place)]
        kind = kinds[int(self.rng.integers(len(kinds)))]
        return U.which_answer(kind, o.name, colour=o.colour, place=place)

    def where_is(self) -> None:
        plain = [(o, w) for o, w in self.taught_objects if o.twin is None]
        if not plain:
            return
        o, word = plain[int(self.rng.integers(len(plain)))]
        self.wait(0.5, 2.0)
        self.face_robot()
        about = ("my " if self.rng.random() < 0.6 else "the ") + word
        text = self.phrase("where-is", about)
        names = "|".join(sorted({rx(word), rx(o.type.replace("_", " "))}))
        self.say(text, f"\\b({names}) (is|are)\\b|" + U.SEEN, 8, request="where-is", about=about,
                 answers=U.reactions("where", about=about))
        self.expect.append(("robot-says", {"pattern": f"\\b({names}) (is|are)\\b"}, f"{self.user} asks where the {o.name} is ({text!r})"))
        self.note()

    def go_to(self, target: int, more: bool) -> None:
        word, where = self.taught_places[target]
        self.wait(0.5, 1.5)
        self.face_robot()
        about = f"the {word}"
        text = self.phrase("go-to", about)
        self.say(text, U.GOING, 6, request="go-to", about=about, answers=U.reactions("goto", words=[word], about=about))
        self.gotos += 1
        self.expect.append(("robot-says", {"pattern": f"going to the {rx(word)}"}, f"{self.user}: {text!r}"))
        drive = path_length(self.flat, self.pos, where) / 0.35 + 10
        self.wait(drive, drive + 5)
        # she walks over to the robot: to start again, or to say good-bye where it hears and sees her (a
        # good-bye called from the room it left is none to it: nobody ends a conversation from another room)
        self.act("walk-to", robot="true", stop_at="1.2")
        self.t += path_length(self.flat, self.pos, where) / 1.0 + 2
        self.pos, self.room = where, target
        if more:  # and starts again
            self.greet(again=True)

    def goodbye(self) -> None:
        self.wait(0.5, 1.5)
        self.face_robot()
        self.say(self.phrase("goodbye"), "^good-?bye", 6, request="goodbye", answers=U.reactions("goodbye"))
        self.note()


# ------------------------------------------------------------------ scenario
@dataclass
class Generated:
    name: str
    xml: bytes
    summary: dict[str, object]


def article(word: str) -> str:
    """"an" before a vowel ("an impatient user"), else "a"."""
    return "an" if word[:1].lower() in "aeiou" else "a"


def tour_name(seed: int, k: int, count: int) -> str:
    return f"tour-{seed}-{k:0{max(1, len(str(count - 1)))}d}"


def generate_one(seed: int, k: int, *, name: str | None = None, users: tuple[tuple[str, float], ...] = U.DEFAULT_MIX) -> Generated:
    """Scenario k of seed: drawn from ``numpy.random.default_rng([seed, k])`` alone, its user's
    profile from ``users`` with ``default_rng([seed, k, 1])`` (the same flat and tour under any mix)."""
    rng = np.random.default_rng([seed, k])
    profile = U.draw_user(seed, k, users)
    from ..errors import ScenarioError
    from ..scenario.loader import load_scenario_text

    for _ in range(50):
        got = _attempt(rng, name or tour_name(seed, k, k + 1), seed, k, profile)
        if got is None:
            continue
        try:  # a draw the scenario checks refuse (a walk target in a pocket, say) is drawn again
            load_scenario_text(got.xml, source=f"{got.name}.xml")
        except ScenarioError as exc:
            REFUSED.append(str(exc))
            continue
        return got
    raise RuntimeError(f"no tour could be generated for seed {seed}, k {k}")  # pragma: no cover


def _attempt(rng: np.random.Generator, name: str, seed: int, k: int, profile: str = "typical") -> Generated | None:
    flat = generate_flat(rng)
    objects = generate_objects(rng, flat)
    start_rooms = [i for i, r in enumerate(flat.rooms) if not r.corridor]
    start = start_rooms[int(rng.integers(len(start_rooms)))]
    robot = free_point(rng, flat, start, robot=True, margin=0.25)
    if robot is None:
        return None
    heading = float(rng.uniform(-180, 180))
    user_pos = None
    for _ in range(40):
        a = math.radians(heading + float(rng.uniform(-90, 90)))
        d = float(rng.uniform(1.4, 2.4))
        p = snap(robot[0] + d * math.cos(a)), snap(robot[1] + d * math.sin(a))
        if flat.rooms[start].contains(p) and free(flat, p) and sight(flat.rooms[start], robot, p):
            user_pos = p
            break
    if user_pos is None:
        return None
    user = USER_NAMES[int(rng.integers(len(USER_NAMES)))]
    script = etree.Element("script")
    tw = TourWriter(rng, flat, user, user_pos, start, script, patience=U.max_patience(profile),
                    objects={o.name: o for o in objects})
    tw.wait(0.5, 2.0)
    tw.greet()
    _agenda(rng, tw, objects)
    tw.goodbye()
    # Long enough for her to get to her good-bye even when every request had to be said twice
    # (a robot that fails early is not also charged with a good-bye she never got to say).
    duration = tw.duration(tw.patience)
    doc = _document(rng, name, flat, objects, robot, heading, tw, duration, seed, k, profile)
    summary = {"name": name, "layout": flat.layout, "rooms": [r.name for r in flat.rooms],
               "doors": [d.width for d in flat.doors], "objects": len(objects), "duration": duration,
               "taught_objects": len(tw.taught_objects), "taught_places": len(tw.taught_places), "gotos": tw.gotos,
               "user": profile}
    return Generated(name, doc, summary)


def _agenda(rng: np.random.Generator, tw: TourWriter, objects: list[ObjectPlan]) -> None:
    """The middle of the tour: a varied order and subset of the home tour's requests."""
    flat = tw.flat
    if rng.random() < 0.6:
        tw.capabilities()
    # the rooms she shows, in an order a person walks them (each a neighbour of the rooms seen so far)
    neighbours: dict[int, set[int]] = {i: set() for i in range(len(flat.rooms))}
    for d in flat.doors:
        if len(d.rooms) == 2:
            a, b = d.rooms
            neighbours[a].add(b)
            neighbours[b].add(a)
    order = [tw.room]
    frontier = sorted(neighbours[tw.room])
    visits = int(rng.integers(1, len(flat.rooms) + 1))
    while frontier and len(order) < visits:
        nxt = frontier.pop(int(rng.integers(len(frontier))))
        if nxt in order:
            continue
        order.append(nxt)
        frontier = sorted((set(frontier) | neighbours[nxt]) - set(order))
    spots: dict[str, Point] = {}
    for o in objects:
        s = teaching_spot(rng, flat, o)
        if s is not None:
            spots[o.name] = s
    going_done = False
    for i, room in enumerate(order):
        if i > 0:
            goal = _room_goal(rng, tw, room)
            if goal is None:
                continue
            tw.follow_to(goal, room)
        r = flat.rooms[room]
        if rng.random() < (0.3 if r.corridor else 0.75):
            tw.teach_place()
        here = [o for o in objects if o.room == room and o.name in spots]
        here = [here[j] for j in rng.permutation(len(here))][: int(rng.integers(0, 4))]
        for o in here:
            tw.teach_object(o, spots[o.name])
        if tw.taught_objects and rng.random() < 0.3:
            tw.where_is()
        if i < len(order) - 1 and not going_done and rng.random() < 0.2:
            going_done = _maybe_goto(rng, tw, more=True)
    if tw.taught_objects and rng.random() < 0.4:
        tw.where_is()
    if not going_done and rng.random() < 0.5:
        _maybe_goto(rng, tw, more=rng.random() < 0.5)


def _maybe_goto(rng: np.random.Generator, tw: TourWriter, *, more: bool) -> bool:
    targets = sorted(r for r in tw.taught_places if r != tw.room)
    if not targets:
        return False
    tw.go_to(targets[int(rng.integers(len(targets)))], more)
    return True


def _room_goal(rng: np.random.Generator, tw: TourWriter, room: int) -> Point | None:
    """Where she stops in a room she leads the robot into: well inside it, with room for the robot."""
    return free_point(rng, tw.flat, room, robot=True, margin=0.3, away=(), gap=0.0)


# ------------------------------------------------------------------ bystanders
def _bystanders(rng: np.random.Generator, flat: Flat, tw: TourWriter, taken: list[Point], duration: float,
                names: set[str]) -> list[etree._Element]:
    n = int(rng.integers(0, 4))
    people: list[etree._Element] = []
    pool = [u for u in USER_NAMES if u != tw.user]
    kinds: list[str] = []
    if n >= 2 and rng.random() < 0.5:
        kinds = ["pair", "pair"] + [("walker", "crosser")[int(rng.integers(2))] for _ in range(n - 2)]
    else:
        kinds = [("walker", "crosser")[int(rng.integers(2))] for _ in range(n)]
    pair: list[tuple[str, Point]] = []
    for kind in kinds:
        who = pool.pop(int(rng.integers(len(pool))))
        if kind == "pair" and pair:
            room = flat.room_at(pair[0][1])
            assert room is not None
            p = None
            for _ in range(30):
                a = float(rng.uniform(0, 2 * math.pi))
                q = snap(pair[0][1][0] + 1.2 * math.cos(a)), snap(pair[0][1][1] + 1.2 * math.sin(a))
                if flat.rooms[room].contains(q) and free(flat, q) and all(math.hypot(q[0] - t[0], q[1] - t[1]) > 1.0 for t in taken):
                    p = q
                    break
            if p is None:
                continue
        else:
            room = int(rng.integers(len(flat.rooms)))
            p = free_point(rng, flat, room, away=tuple(taken), gap=1.5)
            if p is None:
                continue
        taken.append(p)
        h = etree.Element("human", name=who, x=fmt(p[0]), y=fmt(p[1]), heading=fmt(snap(float(rng.uniform(-180, 180)))),
                          height=fmt(snap(float(rng.uniform(1.5, 1.95)))), torso=str(TORSOS[int(rng.integers(len(TORSOS)))]),
                          speed=fmt(snap(float(rng.uniform(*WALK_SPEED)))))
        s = etree.SubElement(h, "script")
        if kind == "pair":
            pair.append((who, p))
            if len(pair) == 2:
                _chat(rng, pair, people[-1].find("script"), s, duration)
        elif kind == "walker":
            rep = etree.SubElement(s, "repeat", times=str(int(rng.integers(2, 5))))
            for _ in range(2):
                goal_room = int(rng.integers(len(flat.rooms)))
                q = free_point(rng, flat, goal_room)
                if q is None:
                    continue
                etree.SubElement(rep, "walk-to", point=pt(q))
                etree.SubElement(rep, "wait", **{"for": fmt(snap(float(rng.uniform(3, 15))))})
                if rng.random() < 0.3:
                    etree.SubElement(rep, "say", text=default_bank().line(rng, "chat"))
            if len(rep) == 0:
                etree.SubElement(rep, "wait", **{"for": "5"})
        else:  # crosser: comes through where the tour is, at about the time it is there
            if not tw.timeline:
                continue
            t, room_c, u = tw.timeline[int(rng.integers(len(tw.timeline)))]
            a = free_point(rng, flat, room_c, away=(u,), gap=1.2)
            b = free_point(rng, flat, room_c, away=(u, a) if a else (u,), gap=2.0)
            if a is None or b is None:
                etree.SubElement(s, "wait", **{"for": "1"})
            else:
                lead = max(0.0, t - path_length(flat, p, a) / 1.0 - 3)
                if lead > 0:
                    etree.SubElement(s, "wait", **{"for": fmt(snap(lead))})
                etree.SubElement(s, "walk-to", point=pt(a))
                etree.SubElement(s, "walk-to", point=pt(b))
                etree.SubElement(s, "wait", **{"for": fmt(snap(float(rng.uniform(5, 20))))})
                back = free_point(rng, flat, int(rng.integers(len(flat.rooms))))
                if back is not None:
                    etree.SubElement(s, "walk-to", point=pt(back))
        names.add(who)
        people.append(h)
    return people


def _chat(rng: np.random.Generator, pair: list[tuple[str, Point]], a: etree._Element | None, b: etree._Element,
          duration: float) -> None:
    """Two people face each other and talk, taking turns, for most of the run."""
    if a is None:
        return
    (na, _), (nb, _) = pair
    etree.SubElement(a, "face", human=nb)
    etree.SubElement(b, "face", human=na)
    turns = int(min(40, max(3, duration / 12)))
    t_a = t_b = 0.0
    for i in range(turns):
        line = default_bank().line(rng, "chat")
        gap = snap(float(rng.uniform(3, 10)))
        speaker, other = (a, b) if i % 2 == 0 else (b, a)
        # the speaker waits for her turn, says her line; the other waits through it
        d = speech_duration(line)
        etree.SubElement(speaker, "wait", **{"for": fmt(gap)})
        etree.SubElement(speaker, "say", text=line)
        etree.SubElement(other, "wait", **{"for": fmt(snap(gap + d + 0.2))})
        t_a += gap + d
        t_b += gap + d


def _source(rng: np.random.Generator, flat: Flat, taken: list[Point]) -> etree._Element | None:
    if rng.random() >= 0.35:
        return None
    room = int(rng.integers(len(flat.rooms)))
    p = free_point(rng, flat, room, away=tuple(taken), gap=0.5)
    if p is None:
        return None
    kind = "radio" if rng.random() < 0.5 else "tv"
    el = etree.Element(kind, name=f"{flat.rooms[room].name} {kind}", x=fmt(p[0]), y=fmt(p[1]), height="1",
                       loudness=fmt(snap(float(rng.uniform(50, 62)))))
    s = etree.SubElement(el, "script")
    etree.SubElement(s, "wait", **{"for": fmt(snap(float(rng.uniform(0, 20))))})
    rep = etree.SubElement(s, "repeat")
    for _ in range(3):
        talk = "broadcast-greeting" if rng.random() < 0.2 else "broadcast"
        etree.SubElement(rep, "say", text=default_bank().line(rng, talk))
        etree.SubElement(rep, "wait", **{"for": fmt(snap(float(rng.uniform(3, 12))))})
    return el


# ------------------------------------------------------------------ document
def _document(rng: np.random.Generator, name: str, flat: Flat, objects: list[ObjectPlan], robot: Point, heading: float,
              tw: TourWriter, duration: float, seed: int, k: int, profile: str = "typical") -> bytes:
    root = etree.Element("scenario", name=name, seed="0", duration=fmt(duration))
    root.append(etree.Comment(f" generated by 'homesim generate' with seed {seed} (tour {k}): a {flat.layout} flat of "
                              f"{len(flat.rooms)} rooms; edit freely, it is an ordinary scenario "))
    desc = etree.SubElement(root, "description")
    desc.text = (f"{tw.user.capitalize()} ({article(profile)} {profile} user) shows the robot the flat ({', '.join(r.name for r in flat.rooms)}): "
                 f"{count(len(tw.taught_places), 'place')} and {count(len(tw.taught_objects), 'object')} taught, "
                 f"{count(len(tw.led_to), 'room')} led to, {count(tw.gotos, 'go-to request')}.")
    fl = etree.SubElement(root, "flat")
    for r in flat.rooms:
        etree.SubElement(fl, "room", name=r.name, points=" ".join(f"{fmt(x)},{fmt(y)}" for x, y in r.polygon))
    walls = etree.SubElement(fl, "walls", thickness="0.1")
    for w in flat.walls:
        we = etree.SubElement(walls, "wall", {"from": pt(w.start), "to": pt(w.end)})
        for at, d in w.doors:
            attrs = {"name": d.name, "at": fmt(at), "width": fmt(d.width)}
            if d.exit:
                attrs["exit"] = "true"
            etree.SubElement(we, "door", attrs)
    for f in flat.furniture:
        attrs = {"name": f.name, "type": f.type, "points": " ".join(f"{fmt(x)},{fmt(y)}" for x, y in f.rect.corners()),
                 "height": fmt(f.height)}
        if f.clearance > 0:
            attrs["clearance"] = fmt(f.clearance)
            attrs["leg"] = fmt(f.leg)
        etree.SubElement(fl, "furniture", attrs)
    for pname, (x, y), _ in flat.places:
        etree.SubElement(fl, "place", name=pname, x=fmt(x), y=fmt(y))
    objs = etree.SubElement(root, "objects")
    for o in objects:
        attrs = {"name": o.name, "type": o.type, "colour": o.colour, "size": fmt(o.size), "height": fmt(o.height),
                 "x": fmt(o.x), "y": fmt(o.y)}
        if o.on is not None:
            attrs["on"] = o.on.name
        etree.SubElement(objs, "object", attrs)
    etree.SubElement(root, "robot", x=fmt(robot[0]), y=fmt(robot[1]), heading=fmt(snap(heading)))
    humans = etree.SubElement(root, "humans")
    # her voice, distance, walking speed, patience, ... are her profile's, drawn with the run's seed
    u = etree.SubElement(humans, "human", name=tw.user, x=fmt(tw.timeline[0][2][0]), y=fmt(tw.timeline[0][2][1]),
                         heading=fmt(snap(float(rng.uniform(-180, 180)))), height=fmt(snap(float(rng.uniform(1.55, 1.9)))),
                         torso=str(TORSOS[int(rng.integers(len(TORSOS)))]), profile=profile)
    for hears, acts in U.comeback():  # her own reactions, at any point of the tour
        on = etree.SubElement(u, "on", hears=hears, max=str(U.ANSWERS))
        for a in acts:
            on.append(a)
    u.append(tw.script)
    taken = [robot, tw.timeline[0][2]]
    names: set[str] = {tw.user}
    # the bystanders' day does not depend on the user's profile (the same home under every mix)
    for h in _bystanders(rng, flat, tw, taken, tw.duration(BYSTANDER_PATIENCE), names):
        humans.append(h)
    src = _source(rng, flat, taken)
    if src is not None:
        etree.SubElement(root, "sources").append(src)
    ex = etree.SubElement(root, "expect")
    for tag, attrs, comment in _expectations(tw):
        if comment:
            ex.append(etree.Comment(f" {comment} "))
        etree.SubElement(ex, tag, attrs)
    etree.indent(root, space="  ")
    return etree.tostring(root, xml_declaration=True, encoding="UTF-8", pretty_print=True)


def _expectations(tw: TourWriter) -> list[tuple[str, dict[str, str], str]]:
    out: list[tuple[str, dict[str, str], str]] = [
        ("state-reached", {"state": "Interacting"}, "the greeting starts the interaction"),
        ("robot-says", {"pattern": "I am BIRON"}, ""),
    ]
    if tw.asked_capabilities:
        out.append(("robot-says", {"pattern": "ask me to follow you|show me objects"}, "the self-explanation"))
    for room, (word, _) in sorted(tw.taught_places.items()):
        out.append(("place-learned", {"name": word, "room": tw.flat.rooms[room].name},
                    f"{tw.user} taught the {word} (her word for it) in the {tw.flat.rooms[room].name}"))
    if tw.led_to:
        out.append(("state-reached", {"state": "Following"}, "following her through the flat"))
        out.append(("following-distance", {"who": tw.user, "min": "0.5", "max": "2.5", "fraction": "0.8"}, ""))
        for room in tw.led_to:
            out.append(("robot-near", {"room": tw.flat.rooms[room].name}, ""))
    out += tw.expect
    if tw.taught_objects:
        out.append(("metric", {"name": "teaching.precision", "min": "1"}, "nothing stored that she did not point at"))
        out.append(("event-rejected", {"event": "object_teaching", "never": "true"}, ""))
    if tw.gotos:
        out.append(("robot-says", {"pattern": "arrived"}, "go-to: it gets there on its own"))
        out.append(("metric", {"name": "navigation.reached", "min": str(tw.gotos)}, ""))
        out.append(("state-reached", {"state": "AskingForHelp", "never": "true"}, ""))
    out.append(("robot-says", {"pattern": "^good-?bye"}, "good-bye ends the interaction"))
    out.append(("event-applied", {"event": "goodbye"}, ""))
    if not tw.gotos:
        out.append(("event-applied", {"event": "partner_lost", "never": "true"}, "the partner is never lost"))
    out.append(("no-collision", {}, "the robot touches nothing and nobody"))
    return out


# ------------------------------------------------------------------ command
def generate(seed: int, count: int, out: Path, users: tuple[tuple[str, float], ...] = U.DEFAULT_MIX) -> list[Generated]:
    """Write ``count`` tours of ``seed`` into ``out`` (users drawn from the ``users`` mix); return them."""
    out.mkdir(parents=True, exist_ok=True)
    made = []
    for k in range(count):
        g = generate_one(seed, k, name=tour_name(seed, k, count), users=users)
        (out / f"{g.name}.xml").write_bytes(g.xml)
        made.append(g)
    return made


def _count(text: str) -> int:
    if not (text.strip().isascii() and text.strip().isdigit()) or not 1 <= int(text) <= MAX_COUNT:
        raise argparse.ArgumentTypeError(f"{text[:25]!r} is not a count (1 to {MAX_COUNT})")
    return int(text)


def generate_command(a: argparse.Namespace) -> int:
    made = generate(a.seed, a.count, Path(a.out), users_option(a.users))
    for g in made:
        s = g.summary
        print(f"{a.out}/{g.name}.xml: {article(str(s['user']))} {s['user']} user, {s['layout']} flat, {count(len(s['rooms']), 'room')} "  # type: ignore[arg-type]
              f"({', '.join(s['rooms'])}), {count(s['objects'], 'object')}, {count(s['taught_places'], 'place')} and "  # type: ignore[arg-type]
              f"{count(s['taught_objects'], 'object')} taught, {s['gotos']} go-to, {s['duration']} s")
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``homesim generate``."""
    from .. import cliargs

    p = sub.add_parser("generate", help="write random flats with a home tour as scenario files (same seed, same files)",
                       examples=["homesim generate --seed 1000 --count 200 -o out/generated"])
    p.add_argument("--seed", type=cliargs.seed, required=True, help="the generator's seed (file k is drawn from [seed, k])")
    p.add_argument("--count", type=_count, default=1, help="how many tours")
    p.add_argument("-o", "--out", required=True, metavar="DIR", help="directory for the scenario files")
    p.add_argument("--users", default=None, metavar="MIX",
                   help="the user profiles to draw each tour's user from: typical+impatient (alike) or typical:3+silent:1 "
                        "(weights; the same syntax as a study's users= condition, ',' also accepted); "
                        f"default {U.mix_text(U.DEFAULT_MIX)} (the flats and tours are the same under any mix)")
    p.set_defaults(func=generate_command)


def users_option(text: str | None) -> tuple[tuple[str, float], ...]:
    """``--users``: a mix of humans/profiles.xml's profiles (OptionError naming the option when bad)."""
    if text is None:
        return U.DEFAULT_MIX
    try:
        return U.parse_mix(text)
    except U.MixError as exc:
        raise OptionError("--users", str(exc)) from None
