"""A scenario as plain data: the flat, the robot, the people, their scripts.

Frozen dataclasses, no I/O, no time, no pymunk (sismic's ``model/``). The
loader (:mod:`homesim.scenario.loader`) builds these from XML and checks
them; the world, the human scripts and the hardware read them. Every item
keeps the line it came from so later checks can name it. Units: metres,
seconds, radians (the XML says degrees; the loader converts).
"""

from __future__ import annotations

from ..deployment import Override

from dataclasses import dataclass
from typing import Union

from ..colours import COLOURS, RGB  # noqa: F401 (COLOURS: the names a scenario may use, or #rrggbb)

Point = tuple[float, float]


@dataclass(frozen=True)
class Room:
    name: str
    polygon: tuple[Point, ...]
    line: int | None = None


@dataclass(frozen=True)
class Door:
    """A gap in a wall: centre ``at`` metres from the wall's start, ``width`` wide.

    An ``exit`` door leads out of the flat (people ``leave`` through it).
    """

    at: float
    width: float
    name: str | None = None
    exit: bool = False
    line: int | None = None


@dataclass(frozen=True)
class Wall:
    start: Point
    end: Point
    thickness: float
    doors: tuple[Door, ...] = ()
    line: int | None = None


@dataclass(frozen=True)
class Furniture:
    """A convex piece of furniture.

    ``clearance`` is the height of its underside: 0 for a cupboard or sofa
    that stands on the floor, e.g. 0.7 for a table whose top floats on legs
    of ``leg`` metres (square, at the corners). A laser at 0.30 m sees a
    piece whose solid part spans its height, and only the legs of a table.
    """

    name: str
    type: str
    polygon: tuple[Point, ...]
    height: float
    clearance: float = 0.0
    leg: float = 0.05
    line: int | None = None


@dataclass(frozen=True)
class Place:
    name: str
    x: float
    y: float
    line: int | None = None


@dataclass(frozen=True)
class ObjectSpec:
    """A small object (a cup, a plant) standing on a piece of furniture or the floor."""

    name: str
    type: str
    colour: RGB
    colour_name: str
    size: float
    height: float
    x: float
    y: float
    on: str | None = None
    line: int | None = None


@dataclass(frozen=True)
class Target:
    """What an action refers to: ``kind`` is one of place, room, object,
    furniture, human, robot, point, angle; ``name`` or (x, y) or angle."""

    kind: str
    name: str | None = None
    x: float = 0.0
    y: float = 0.0
    angle: float = 0.0


@dataclass(frozen=True)
class WalkTo:
    target: Target
    stop_at: float = 0.0  # stop this far from the target (people stop short of the robot)
    speed: float | None = None
    line: int | None = None


@dataclass(frozen=True)
class Face:
    target: Target
    body: bool = False  # turn the whole body, not only the head
    line: int | None = None


@dataclass(frozen=True)
class Say:
    """Say ``text``, or a phrasing of ``request`` drawn from the person's paraphrase bank.

    ``about`` fills the bank phrasing's ``{about}`` slot ("the kitchen",
    "my favourite cup"); ``side_of`` fills it, when she speaks, with an object's
    side among its neighbours as the robot sees them. With ``text`` and ``request`` both given, the text is
    said first and rephrasings come from the bank. ``wait=False`` does not
    freeze the person: the next action starts while she talks (``wait-speech``
    waits for the end).
    """

    text: str | None
    loudness: float | None = None  # dB SPL at 1 m; None: the speaker's own (60 for people)
    duration: float | None = None  # None: from the word count
    line: int | None = None
    request: str | None = None
    about: str | None = None
    wait: bool = True
    #: an object's name: ``{about}`` is its side ("left", "right", "middle") among the similar
    #: objects next to it, as the robot sees them now (a "which one" answered by position)
    side_of: str | None = None


@dataclass(frozen=True)
class PointAt:
    target: Target
    duration: float = 2.0
    line: int | None = None


@dataclass(frozen=True)
class Wait:
    duration: float
    line: int | None = None


@dataclass(frozen=True)
class WaitFor:
    """Wait until the robot says something matching ``robot_says`` (a regular
    expression, case-insensitive) or comes within ``robot_within`` metres,
    at most ``timeout`` seconds (None: forever).

    ``retries`` models a user who is not understood: when the robot asks for
    a repair (says something matching ``repair``) or the timeout passes, the
    person says her last utterance again and waits anew, up to ``retries``
    times (the papers' users repeat themselves; a script without it gives
    up at the first miss)."""

    robot_says: str | None = None
    robot_within: float | None = None
    timeout: float | None = None
    line: int | None = None
    retries: int = 0
    repair: str | None = None
    #: ``hears``: a word pattern (:mod:`homesim.scenario.wordpattern`) instead of ``robot_says``'s regex.
    hears: str | None = None
    #: Repairs the way people make them (instead of ``retries``' verbatim turn): a subset of
    #: REPAIR_STRATEGIES, () for none, None for the person's own (her profile's); ``patience``
    #: repairs at most, then she gives up (``give_up``: one of GIVE_UPS).
    repairs: tuple[str, ...] | None = None
    patience: int | None = None
    give_up: str | None = None
    #: Reactions that hold only during this wait (``<on>`` inside the ``<wait-for>``), checked
    #: before the person's own: the answer to "Is this the kitchen?" depends on what she just asked.
    handlers: tuple[Handler, ...] = ()


#: What a person may do when the robot does not understand her (``repairs=``).
REPAIR_STRATEGIES = ("rephrase", "louder", "closer", "face")
#: What a person does once her patience is used up (``give-up=``): carry on with her
#: script, say so and stop her script, or say so and leave the flat.
GIVE_UPS = ("skip", "stop", "leave")


@dataclass(frozen=True)
class WaitSpeech:
    """Wait until the person's own speech (a ``say wait="false"``) has ended."""

    line: int | None = None


@dataclass(frozen=True)
class StepCloser:
    """Step ``by`` metres towards the robot, never nearer than ``nearest``."""

    by: float = 0.5
    nearest: float = 0.6
    line: int | None = None


@dataclass(frozen=True)
class Leave:
    door: str | None = None
    line: int | None = None


@dataclass(frozen=True)
class Repeat:
    body: tuple[Action, ...]
    times: int | None = None  # None: for ever
    line: int | None = None


Action = Union[WalkTo, Face, Say, PointAt, Wait, WaitFor, Leave, Repeat, WaitSpeech, StepCloser]


@dataclass(frozen=True)
class Handler:
    """A reaction: when the robot says words matching ``hears`` (a word pattern), the
    person does ``body`` and then carries on where she was (an act pushed on her agenda).

    ``when``: ``always`` (at any point of her script: between actions, during a pause
    or a walk, while waiting) or ``waiting`` (only during a ``wait-for``). ``max``: how
    often it may fire (None: every time).
    """

    hears: str
    body: tuple[Action, ...]
    when: str = "always"
    max: int | None = None
    line: int | None = None


@dataclass(frozen=True)
class RobotSpec:
    x: float
    y: float
    heading: float
    max_speed: float = 0.5
    max_turn: float = 1.7453292519943295  # 100 deg/s
    laser_rate: float = 10.0
    camera_rate: float = 10.0
    audio_rate: float = 10.0
    odometry_rate: float = 10.0
    object_confusion: float = 0.05
    options: tuple[tuple[str, str], ...] = ()  # <option name value/>: for BIRON's modules
    profile: str | None = None  # <robot profile>: which robot (the run package knows the names); None: the default
    line: int | None = None
    memory_required: bool = False  # <robot memory="required">: starts from an earlier run's knowledge store


@dataclass(frozen=True)
class HumanSpec:
    name: str
    x: float
    y: float
    heading: float
    height: float = 1.75
    torso: RGB = COLOURS["blue"]
    torso_name: str = "blue"
    speed: float = 1.0
    script: tuple[Action, ...] = ()
    line: int | None = None
    #: A named user profile (data kept with the simulated people) whose traits are drawn
    #: from seeded distributions; ``traits`` are per-attribute values given in the file,
    #: which override the profile's draws (name -> value as written).
    profile: str | None = None
    traits: tuple[tuple[str, str], ...] = ()
    handlers: tuple[Handler, ...] = ()
    speed_given: bool = False


@dataclass(frozen=True)
class SourceSpec:
    """A sound source with no person: a radio or a TV."""

    name: str
    kind: str
    x: float
    y: float
    height: float = 1.0
    loudness: float = 60.0
    script: tuple[Action, ...] = ()
    line: int | None = None


@dataclass(frozen=True)
class Fault:
    """A robot module crashes or hangs at virtual time ``at`` (``kind``: crash | hang)."""

    kind: str
    module: str
    at: float
    line: int | None = None


@dataclass(frozen=True)
class Expectation:
    """A check on a run (see :mod:`homesim.tour.expect` for the kinds);
    ``attrs`` holds its typed parameters."""

    kind: str
    attrs: tuple[tuple[str, object], ...]
    line: int | None = None
    written: tuple[tuple[str, str], ...] | None = None  # the attributes as written in the file

    def get(self, key: str, default: object = None) -> object:
        for k, v in self.attrs:
            if k == key:
                return v
        return default

    def describe(self) -> str:
        args = "".join(f' {k}="{v}"' for k, v in (self.attrs if self.written is None else self.written))
        return f"<{self.kind}{args}/>"


@dataclass(frozen=True)
class Scenario:
    name: str
    source: str
    seed: int
    duration: float
    robot: RobotSpec
    rooms: tuple[Room, ...] = ()
    walls: tuple[Wall, ...] = ()
    furniture: tuple[Furniture, ...] = ()
    places: tuple[Place, ...] = ()
    objects: tuple[ObjectSpec, ...] = ()
    humans: tuple[HumanSpec, ...] = ()
    sources: tuple[SourceSpec, ...] = ()
    expectations: tuple[Expectation, ...] = ()
    faults: tuple[Fault, ...] = ()
    description: str = ""
    world_rate: float = 50.0
    deployment: Override | None = None  # <deployment>: what the scenario changes of the run's default deployment

    def room(self, name: str) -> Room:
        return _named(self.rooms, name, "room")

    def place(self, name: str) -> Place:
        return _named(self.places, name, "place")

    def object(self, name: str) -> ObjectSpec:
        return _named(self.objects, name, "object")

    def piece(self, name: str) -> Furniture:
        return _named(self.furniture, name, "furniture")

    def human(self, name: str) -> HumanSpec:
        return _named(self.humans, name, "human")

    def exits(self) -> list[tuple[Wall, Door]]:
        """Every door that leads out of the flat, in file order."""
        return [(w, d) for w in self.walls for d in w.doors if d.exit]


def _named(items: tuple, name: str, what: str):  # type: ignore[no-untyped-def]
    for it in items:
        if it.name == name:
            return it
    raise KeyError(f"no {what} named {name!r}")


def window_of(e: Expectation, duration: float) -> tuple[float, float]:
    """The time window an expectation looks at: ``between``, narrowed by ``after``/``by``; default the run."""
    w = e.get("between")
    t0, t1 = (0.0, duration) if w is None else (float(w[0]), float(w[1]))  # type: ignore[index]
    after, by = e.get("after"), e.get("by")
    if after is not None:
        t0 = max(t0, float(after))  # type: ignore[arg-type]
    if by is not None:
        t1 = min(t1, float(by))  # type: ignore[arg-type]
    return t0, t1
