"""The Player-like hardware interface: the execution supervisor's orders to the base and display.

Orders arrive on ``/robot/es/orders/player`` (docs/robot-contract.md):

* ``move_to`` (param ``pose``: ``<POSE x y theta frame="map" [tolerance] [align]/>``):
  a local controller drives there. Each control step it takes the localised
  pose (``/robot/localisation/pose``, advanced by the odometry since that
  pose's time), the laser scan and the base's speed, and asks the dynamic
  window (:func:`robot.navigation.local.dwa`) for a velocity toward the pose
  that keeps the footprint clear of every laser echo, so people and
  furniture that are not on the map are driven around, or waited for.
  It steers at a point 0.7 m ahead on the leg (pure pursuit: the leg starts
  where the previous ``move_to`` ended, or where the robot stood), so it keeps
  to the planned line through doorways; a goal more than 60 degrees off its
  heading is turned to on the spot first (a leg that starts where the robot stands, the first of a
  plan or a replan, already when it is more than :data:`TURN_FIRST` off: an arc from standing swings
  it off the line, into a door jamb); a turn on the spot never swings a corner into a tracked
  person's body (:func:`~robot.navigation.local.turn_clear`); when that is impossible (stopped
  close in front of something) it backs off up to 0.3 m the way it came, never toward a person
  tracked behind it, and not at all while someone the tracker lost sight of in the last 10 s could
  have walked behind it since (the laser does not look behind). Near people (the attention's
  confirmed tracks, ``/robot/attention/tracks``) it slows down: at most
  0.2 m/s within 1.2 m of anyone, full speed from 2 m
  (:func:`~robot.navigation.local.social_speed_limit`).
  Within ``tolerance`` (default 0.2 m) it turns to ``theta`` when ``align`` is
  true, then stops and reports ``reached``. Held up near the place by someone standing on it
  (:func:`goal_taken`) it arrives beside them and reports ``reached`` with ``beside="true"``.
* ``stop``: zero velocity at once, the goal is dropped.
* ``show_attention``: the avatar's attentive expression on the display.

``/robot/player/status`` says ``moving``, ``blocked`` (no admissible arc, or
less than 5 cm of progress in ``stall_time``: the way is blocked, it waits),
``reached`` or ``stopped`` on each change; the sequencer decides how long
waiting is acceptable. The player drives the base only while executing a
``move_to`` (the base's watchdog stops the robot when it goes quiet).
"""

from __future__ import annotations

import asyncio
import math
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
from lxml import etree

from homesim.errors import BusError, HomesimError
from homesim.message import Message
from homesim.module import Module

from robot.blindside import SonarEchoes, blind_clear, blind_points, explained_by_points
from robot.bumpers import BACKOFF_SPEED, BACKOFF_TIME, BumperReflex, own_reflex
from robot.footprint import contact_speed_limit
from robot.contract import BASE_CMD, BUMPERS, DISPLAY_CMD, ES_ORDERS, ODOMETRY, PLAYER_STATUS, POSE, SCAN, SONAR, TRACKS

from .blind import blind_speed_limit, scan_corners
from .config import Limits, limits_from_config
from .follow import sweep_allowed
from .grid import MapError, parse_map
from .local import (BODY, HALF_LENGTH, HALF_WIDTH, SOCIAL_SPEED, Command, DWAParams, LatestScan, arcs_at, carrot, dwa, footprint_distance,
                    heading_speed, people_gaps, social_speed_limit, sweep_clearance, turn_clear)
from .outline import FloorOutline
from .people import (BACK_GAP, BODY_RADIUS, People, behind_clear, closing_in, in_the_way, maybe_behind, nearest, passing_close,
                     waits_for)

ORDERS = f"{ES_ORDERS}/player"
#: m/s: the contact limit (robot.footprint.contact_speed_limit) this low stands it for someone walking into its way
STAND_FOR = 0.02
#: s: standing for walkers (that limit, the yield) counts as no progress only beyond this much of one stall: someone
#: walking at it passes; someone who keeps walking into its way blocks it
YIELD_HOLD = 8.0
#: s: the go-to stands this long after the sonar last heard someone walking up beside or behind it (_heard_closing):
#: a transducer's reading comes round every 0.3 s, and the walker reaches the laser's view in about a second
HEARD_HOLD = 1.0
#: m: how far ahead on the leg the controller steers (pure pursuit).
LOOKAHEAD = 0.7
#: m: how far the player backs off, at most, per ``move_to``, to get room to turn.
BACK_OFF = 0.3
#: m the robot backs off, standing with its partner, when told it is in someone's way ("you are in my way":
#: the ES's order make_way); only where the sonar's blind half, the floor plan and the people behind leave room
MAKE_WAY_BACK = 0.5
#: s the make-way back-off waits for the first sonar packet and the first person tracks after the order
#: (both are subscribed with it): backing off on empty echo and track buffers would be backing off blind.
#: The sonar sends at 10 Hz and the tracker at its scan rate; heard nothing in this time, it stays.
MAKE_WAY_WAIT = 1.5
#: rad: a goal further off the heading than this has to be turned to (see :func:`heading_speed`).
BACK_OFF_BEARING = math.pi / 3
#: rad: the carrot of a leg that starts where the robot stands, further off its heading than this, is
#: turned to on the spot before the robot drives: an arc begun 47 degrees off swung it 8 cm off the
#: leg, its corner to a door jamb, where it stood wedged and backed off (goto_l_flat seeds 7, 9)
TURN_FIRST = math.radians(30)
#: s, m, m: standing this long with something within WEDGED_GAP of the footprint and nobody within WEDGED_PERSON
#: (a footprint corner at a door jamb, no arc that gets it through), it backs off too.
WEDGED = 1.0
WEDGED_PERSON = 1.0
WEDGED_GAP = 0.15
#: m: air the go-to keeps to a tracked person's body: the 0.25 m the robot promises (SOCIAL_GAP) and the
#: few centimetres by which the tracker misplaces someone standing (goto_standing_person passed Ida 0.244 m off)
GOTO_SOCIAL_GAP = 0.30
#: m, m/s: where that gap leaves no way on at all past someone standing beside its way (a man 0.8 m inside
#: a 1.1 m door, by its jamb: the only line through the door passes him with 0.25-0.29 m of air, so the
#: window turned on the spot to and fro until the go-to failed; goto_corridor seeds 0, 2, 3, 4, 8), it
#: passes them slowly with this much air (the robot's promised 0.25 m and a little of the tracker's error);
#: someone standing in its lane is still waited for (WAIT_GAP), someone walking still yielded to
SQUEEZE_GAP = 0.27
SQUEEZE_SPEED = 0.15
#: m: the nearest the go-to's window drives its centre past a person's centre: their body, GOTO_SOCIAL_GAP of air, its
#: half width. The one rule of a passable way past someone: the planner gives people this much on every plan
#: (robot.navigation.planner.social_grid), so it never plans past someone nearer than the window drives
PERSON_CLEAR = BODY + GOTO_SOCIAL_GAP + HALF_WIDTH
#: m: air the go-to leaves to someone standing in its lane when it stops to wait (people.standing_in_the_way):
#: outside their personal space (0.45 m, BACK_GAP) by the few centimetres the tracker misplaces them
WAIT_GAP = BACK_GAP + 0.05
#: rad: held by someone standing in the lane of its heading, with the leg further off the heading than
#: this and the lane toward the leg clear of them, it turns on the spot toward the leg (the way round them)
WAY_ROUND = math.radians(5)
#: rad: a leg at most this far off the heading, when the sonar's blind half stops the window's turn on the spot
#: toward it, is arced onto forwards instead (see control_step), turning no faster than the first of ARC_ON_TURNS
#: (rad/s) that the guards let pass
ARC_ON_BEARING = math.radians(60)
ARC_ON_TURNS = (0.3, 0.1, 0.002)
#: rad/s: a turn on the spot slower than this toward its leg is no turn (a radian takes ten seconds): see :func:`turns_to`
TURN_PROGRESS = 0.1
#: rad: a leg this far round (behind it) is turned to either way round
TURN_EITHER = math.radians(150)
#: m, m/s: with someone this near walking toward its centre faster than this, it stands (yields)
YIELD_NEAR = 1.6
YIELD_SPEED = 0.15
#: m: with someone this near walking toward its centre faster than YIELD_SPEED, it backs off out of their way
#: (ring_goto_other_way: Ben walked out of the kitchen through the opening the robot stood in and was held
#: at its front for 3 s, 0.02 m of air, before it turned away)
GIVE_WAY_NEAR = 1.0
#: m/s: ... and walking at it at least this fast (a walk, not a step toward its side)
GIVE_WAY_SPEED = 0.3
#: m: someone standing with their centre this near the goal occupies it (the robot cannot stand there and
#: keep GOTO_SOCIAL_GAP of air to them: their body, the air and its half width) ...
GOAL_TAKEN = PERSON_CLEAR
#: m: ... and held up this near the goal by them, with nothing of the floor plan between it and the goal
#: (the same room, no furniture between), the robot has arrived beside them (a man standing at the
#: kitchen counter where the kitchen was taught: it waited 10 s at 0.6 m and asked for help, and
#: blocked 1.25 m off went round the table into the partner; hall_goto_doorway_person seed 1)
ARRIVE_BESIDE = 1.5
#: m: a turn on the spot at the goal (``align``) or a back-off keeps the footprint this far from the floor
#: plan's walls and furniture (they sweep ground the laser does not see), or it is not made.
SWEEP_MARGIN = 0.05
#: s: how far ahead such a command is checked (a few control steps).
SWEEP_TIME = 0.5
#: m: a final turn begun clear goes on while its next steps keep this much air (the sweep check is sampled)
TURN_GUARD = 0.02
#: m: how far it backs out of a spot too tight to turn in at the goal, at most, to turn to the goal's heading.
ALIGN_BACK = 0.6
SCHEMA = Path(__file__).resolve().parent.parent / "schemas" / "navigation" / "player-status.xsd"


def turns_to(w: float, bearing: float) -> bool:
    """Whether turning on the spot at ``w`` (rad/s) turns the robot toward a leg ``bearing`` (rad) off its heading:
    the short way round at :data:`TURN_PROGRESS` at least, or either way round to a leg behind it (:data:`TURN_EITHER`).
    The dynamic window admits any turn on the spot that brings no corner nearer the floor plan than it is, so where
    the turn toward the leg is closed (a stair's side at its back) it may offer a creeping turn the other way, which
    gets it nowhere."""
    if abs(w) < TURN_PROGRESS:
        return False
    return abs(bearing) > TURN_EITHER or w * bearing > 0.0


def wrap(a: float) -> float:
    return math.remainder(a, 2 * math.pi)


def turned(people: np.ndarray, turn: float) -> np.ndarray:
    """``people`` ((K, 4) robot-frame centres and velocities) in the frame of the robot turned on the spot by ``turn`` rad."""
    c, s = math.cos(turn), math.sin(turn)
    rot = np.array([[c, -s], [s, c]])  # row vectors: (x, y) @ rot = (c x + s y, -s x + c y)
    out = np.array(people, dtype=float, copy=True)
    out[:, :2] = out[:, :2] @ rot
    out[:, 2:4] = out[:, 2:4] @ rot
    return out


class Odometry:
    """The latest odometry pose and speed, read from the message only when asked (most control steps are idle).

    ``update`` keeps the message's payload (the receiver's own copy); ``pose``,
    ``v`` and ``w`` parse it on first use, so an idle player pays nothing per
    odometry message. A malformed message raises on that first use.
    """

    def __init__(self) -> None:
        self.xml: etree._Element | None = None
        self._parsed: etree._Element | None = None
        self._pose: tuple[float, float, float] | None = None
        self._v = 0.0
        self._w = 0.0

    def update(self, xml: etree._Element) -> None:
        self.xml = xml

    def _parse(self) -> None:
        xml = self.xml
        if xml is not None and xml is not self._parsed:
            self._pose = pose_of(xml)
            self._v, self._w = float(xml.get("v", "0")), float(xml.get("w", "0"))
            self._parsed = xml

    @property
    def pose(self) -> tuple[float, float, float] | None:
        self._parse()
        return self._pose

    @property
    def v(self) -> float:
        self._parse()
        return self._v

    @property
    def w(self) -> float:
        self._parse()
        return self._w


def pose_of(xml: etree._Element) -> tuple[float, float, float]:
    """``(x, y, theta)`` of a pose or odometry message."""
    return (float(xml.get("x")), float(xml.get("y")), float(xml.get("theta")))  # type: ignore[arg-type]


def local_goal(pose: tuple[float, float, float], goal: tuple[float, float]) -> tuple[float, float]:
    """``goal`` (map frame) in the frame of the robot at ``pose``."""
    x, y, th = pose
    c, s = math.cos(th), math.sin(th)
    dx, dy = goal[0] - x, goal[1] - y
    return c * dx + s * dy, -s * dx + c * dy


def goal_taken(people: np.ndarray, goal: tuple[float, float], *, radius: float = GOAL_TAKEN, speed: float = 0.3) -> bool:
    """Whether someone standing (slower than ``speed`` m/s) has their centre within ``radius`` m of
    ``goal`` (``people``: (K, >=4) robot-frame centres and velocities, :meth:`People.around`; ``goal``
    in the robot frame): the place is theirs for now, the robot cannot stand on it."""
    if not len(people):
        return False
    standing = np.hypot(people[:, 2], people[:, 3]) < speed
    return bool(np.any(standing & (np.hypot(people[:, 0] - goal[0], people[:, 1] - goal[1]) < radius)))


def in_sight(goal: tuple[float, float], mapped: np.ndarray, *, width: float = 0.05) -> bool:
    """Whether no point of the floor plan's outline (``mapped``, robot frame) lies within ``width`` m of
    the straight line from the robot's centre to ``goal`` (robot frame): no wall, no furniture between."""
    gx, gy = goal
    length = math.hypot(gx, gy)
    if length < 1e-9 or not len(mapped):
        return True
    ux, uy = gx / length, gy / length
    along = mapped[:, 0] * ux + mapped[:, 1] * uy
    across = np.abs(-mapped[:, 0] * uy + mapped[:, 1] * ux)
    return not bool(np.any((along > 0.0) & (along < length) & (across < width)))


def standing_beside(moving: np.ndarray, *, near: float = 1.5, speed: float = YIELD_SPEED) -> bool:
    """Whether ``moving`` ((K, 4) robot-frame x, y, vx, vy of the tracked people) holds someone within
    ``near`` m of the centre, and every such person stands (slower than ``speed``): the people a go-to
    may pass slowly at :data:`SQUEEZE_GAP` (someone walking near is waited for instead)."""
    if not len(moving):
        return False
    close = np.hypot(moving[:, 0], moving[:, 1]) < near
    return bool(close.any() and np.all(np.hypot(moving[close, 2], moving[close, 3]) < speed))


def arc_air(v: float, w: float, people: np.ndarray, params: DWAParams) -> float:
    """The least air (m) between the footprint and the bodies of ``people`` (robot frame, (K, 2)) along
    the arc (v, w) over the window's horizon (inf without people)."""
    if not len(people):
        return math.inf
    t = np.linspace(params.horizon / params.steps, params.horizon, params.steps)
    x, y, th = arcs_at(np.full(len(t), v), np.full(len(t), w), t)
    return float(people_gaps(x, y, th, people).min())


def compose_delta(map_pose: tuple[float, float, float], odo_then: tuple[float, float, float],
                  odo_now: tuple[float, float, float]) -> tuple[float, float, float]:
    """``map_pose`` moved by the odometry increment odo_then -> odo_now (taken in the robot frame)."""
    dx, dy = odo_now[0] - odo_then[0], odo_now[1] - odo_then[1]
    c, s = math.cos(odo_then[2]), math.sin(odo_then[2])
    fx, fy = c * dx + s * dy, -s * dx + c * dy
    x, y, th = map_pose
    cm, sm = math.cos(th), math.sin(th)
    return x + cm * fx - sm * fy, y + sm * fx + cm * fy, wrap(th + odo_now[2] - odo_then[2])


class Player(Module):
    """Executes ``move_to``/``stop``/``show_attention`` (see the module docstring)."""

    #: nothing pressed, and never told otherwise: for the rules' unit tests, which build a player without a bus
    #: (__init__ gives each player its own, heard on the bus)
    bumpers = own_reflex()

    def __init__(self, sim: Any, *, name: str = "player", limits: Limits | None = None, rate: float = 10.0,
                 tolerance: float = 0.2, stall_time: float = 2.0, params: DWAParams = DWAParams()) -> None:
        super().__init__(sim, name)
        self.limits = limits or Limits()
        self.period = 1.0 / rate
        self.tolerance = tolerance
        self.stall_time = stall_time
        self.params = params
        # the go-to's own margin to people (its dynamic window's; the follower keeps the default)
        self._goto_params = replace(params, social_gap=max(params.social_gap, GOTO_SOCIAL_GAP))
        self._squeeze_params = replace(params, social_gap=max(params.social_gap, SQUEEZE_GAP))
        sim.bus.declare_channel(PLAYER_STATUS, SCHEMA)
        self.goal: tuple[float, float, float, float, bool] | None = None  # x, y, theta, tolerance, align
        self._reached: tuple[float, float, float, float, bool] | None = None  # the step just reached
        self.state = "idle"
        self.odo = Odometry()
        # the latest localised pose's payload and the odometry payload current when it came (parsed when driving)
        self._pose_xml: etree._Element | None = None
        self._odo_xml_at_pose: etree._Element | None = None
        self.scan = LatestScan()
        self.leg_start: tuple[float, float] | None = None
        self.people = People()  # the attention's confirmed tracks, while driving
        self._backed = 0.0  # m backed off during the present move_to
        self._gave_way = False  # the back-off under way is a give-way (it stops when nobody walks at it)
        self._stuck_since: float | None = None  # since when no arc was admissible
        self._best = math.inf
        self._best_t = 0.0
        self._yielded = 0.0  # s of the present stall spent standing for walkers (not counted, up to YIELD_HOLD)
        self._heard_at = -math.inf  # when the sonar last heard someone walking up in the blind half (_heard_closing)
        self.bus.subscribe(ORDERS, self._on_order)
        self.bus.subscribe(POSE, self._on_pose)
        self.bus.subscribe(SCAN, self._on_scan)
        self.bus.subscribe(ODOMETRY, self._on_odometry)
        self._tracks_sub: Any = None  # subscribed only while driving (see _listen_to_people)
        self._sonar_sub: Any = None
        self.sonar = SonarEchoes()  # the sonar rings' echoes, while driving (robot.blindside)
        self.bumpers = BumperReflex()  # the bumper rings (robot.bumpers): sent on a change and while one stays pressed
        self.bus.subscribe(BUMPERS, lambda m: self.bumpers.update(m.xml, self.now))
        self.outline: FloorOutline | None = None  # the floor plan round the robot (asked at the first move_to)
        self._map_asked = False
        self._aligning: float | None = None  # m backed off to make room for the final turn (None: not there yet)
        self._turning = False  # the final turn has begun (its whole sweep was clear)
        self._facing = False  # turning to face a first leg before driving it (see TURN_FIRST)
        self._make_way = 0.0  # m still to back off out of someone's way (order make_way; 0: not making way)
        self._make_way_at = 0.0  # when the make_way order came (see MAKE_WAY_WAIT)
        self._sonar_at: float | None = None  # when the newest sonar packet came (None: none since subscribing)
        self._tracks_at: float | None = None  # when the newest person tracks came (None: none since subscribing)
        self._corners_of: Any = None  # the scan whose blind corners are in _corners
        self._corners = np.zeros((0, 2))

    def respawn(self) -> Player:
        """A fresh instance with the same configuration (what a process manager's restart gives)."""
        return Player(self.sim, name=self.name, limits=self.limits, rate=1.0 / self.period, tolerance=self.tolerance,
                      stall_time=self.stall_time, params=self.params)

    # ------------------------------------------------------------- inputs
    def _on_order(self, msg: Message) -> None:
        name = msg.xml.get("name")
        if name == "move_to":
            pose = msg.xml.find("param[@name='pose']/POSE")
            if pose is None:
                return
            try:
                x, y = float(pose.get("x")), float(pose.get("y"))
                th = float(pose.get("theta", "0"))
                tol = float(pose.get("tolerance", str(self.tolerance)))
            except (TypeError, ValueError):
                return
            # the leg runs from the plan's previous waypoint (the step just reached, if the robot is
            # still there) or from where the robot stands (a plan's first step starts there)
            prev, here = self._reached, self.pose()
            if here is None:
                self.leg_start = None
            elif prev is not None and math.hypot(prev[0] - here[0], prev[1] - here[1]) <= prev[3] + 0.2:
                self.leg_start = (prev[0], prev[1])
            else:
                self.leg_start = (here[0], here[1])
            # a leg from where the robot stands (a plan's or a replan's first) is faced before it drives
            self._facing = prev is None or self.leg_start != (prev[0], prev[1])
            self._reached = None
            self.goal = (x, y, th, tol, pose.get("align") == "true")
            self._listen_to_people(True)
            self._best, self._best_t = math.inf, self.now
            self._yielded = 0.0
            self._backed = 0.0
            self._gave_way = False
            self._aligning = None
            self._turning = False
            self._stuck_since = None
            self._make_way = 0.0
            self.state = ""  # a new pose: say "moving" even when it was already moving
            self._set_state("moving")
        elif name == "make_way":
            # "you are in my way" while it stands with its partner: back off MAKE_WAY_BACK m, straight, as
            # far as the floor plan and the people behind it allow (no goal, no status: it is no go-to)
            if self.goal is None:
                self._make_way = MAKE_WAY_BACK
                self._make_way_at = self.now
                self._listen_to_people(True)
        elif name == "stop":
            self._make_way = 0.0
            self.goal = self._reached = None
            self._aligning = None
            self._turning = False
            self._listen_to_people(False)
            self.bus.publish(BASE_CMD, etree.Element("velocity", v="0", w="0"))
            self._set_state("stopped")
        elif name == "show_attention":
            self.bus.publish(DISPLAY_CMD, etree.Element("expression", name="attentive"))

    def _on_pose(self, msg: Message) -> None:
        self._pose_xml = msg.xml
        self._odo_xml_at_pose = self.odo.xml

    def _on_scan(self, msg: Message) -> None:
        self.scan.update(msg)  # turned into points only when a control step needs them

    def _on_odometry(self, msg: Message) -> None:
        self.odo.update(msg.xml)

    def _listen_to_people(self, on: bool) -> None:
        """Subscribe to the person tracks while a ``move_to`` runs, and only then.

        Every delivery draws a network delay from the run's generator, so a
        subscription held all the time would change every run, navigating or not.
        """
        if on and self._tracks_sub is None:
            self._tracks_sub = self.bus.subscribe(TRACKS, self._on_tracks)
            self._sonar_sub = self.bus.subscribe(SONAR, self._on_sonar)
        elif not on and self._tracks_sub is not None:
            self._tracks_sub.close()
            self._tracks_sub = None
            self.people.clear()
            self._sonar_sub.close()
            self._sonar_sub = None
            self.sonar = SonarEchoes()
            self._sonar_at = self._tracks_at = None

    def _on_sonar(self, msg: Message) -> None:
        self.sonar.hear(msg, self.odo.pose, self.now)
        self._sonar_at = self.now

    def _on_tracks(self, msg: Message) -> None:
        self.people.update(msg.xml)  # read only when a control step needs it
        self._tracks_at = self.now

    def people_around(self) -> np.ndarray:
        """Robot-frame centres of the confirmed people the attention tracks (predicted to now), (K, 2)."""
        odo = self.odo.pose
        return self.people.around(odo, self.now) if odo is not None else np.zeros((0, 2))

    def _waits_for(self, people: np.ndarray, odo: tuple[float, float, float] | None, travel: float, turn: float = 0.0) -> bool:
        """Whether someone stands in its lane (:func:`~robot.navigation.people.waits_for`; ``people``: the
        tracks and then the ghosts, as :meth:`People.around` lists them with the scan's echoes), or would,
        turned on the spot by ``turn`` rad first (the lane it drives along once it faces the way round)."""
        seen = self.people.around(odo, self.now, velocity=True) if odo is not None else np.zeros((0, 4))
        if turn:
            people = turned(people, turn)
        return waits_for(people[:len(seen)], people[len(seen):], half_length=HALF_LENGTH, half_width=HALF_WIDTH, travel=travel,
                         gap=WAIT_GAP)

    def _blind_corners(self, mapped: np.ndarray) -> np.ndarray:
        """The floor plan's corners in the latest scan that the laser does not see round (robot frame; computed
        once per scan: :func:`robot.navigation.blind.scan_corners`)."""
        msg = self.scan.latest
        if msg is not self._corners_of:
            self._corners_of = msg
            self._corners = scan_corners(msg, mapped)
        return self._corners

    def nearest_person(self) -> float:
        """Distance (m) to the nearest confirmed person track (inf: none)."""
        return nearest(self.people_around())

    async def _fetch_map(self) -> None:
        """The floor plan, once: without it the laser (forwards only) is the only guard."""
        self._map_asked = True
        try:
            reply = await self.bus.call("map_server", "map", etree.Element("request"), timeout=2.0)
            self.outline = FloorOutline(parse_map(reply.xml))
        except (BusError, MapError, HomesimError, asyncio.TimeoutError):
            pass

    def mapped(self, pose: tuple[float, float, float]) -> np.ndarray:
        """The floor plan's outline round ``pose`` (map frame) as robot-frame points ((0, 2) without a map)."""
        return self.outline.around(pose) if self.outline is not None else np.zeros((0, 2))

    def _sweep_ok(self, v: float, w: float, mapped: np.ndarray) -> bool:
        """Whether (v, w) for :data:`SWEEP_TIME` keeps the footprint :data:`SWEEP_MARGIN` off the floor plan
        (or brings it no closer than it is)."""
        if not len(mapped):
            return True
        gap = sweep_clearance(v, w, mapped, SWEEP_TIME)
        return gap >= SWEEP_MARGIN or gap >= sweep_clearance(0.0, 0.0, mapped, 0.0, steps=1) + 1e-3

    def _arrive(self, dist: float, turn: float, mapped: np.ndarray, *, beside: bool = False) -> tuple[float, float]:
        """At the goal: turn on the spot to its heading (``turn`` rad to go), then report ``reached``.

        Where turning would sweep a corner into the floor plan's furniture or walls (a goal
        between a bed and a wardrobe, at the end of a corridor), it backs out straight the way it
        came, up to :data:`ALIGN_BACK` m, until it can turn; where it cannot, it arrives as it stands.
        """
        if self._aligning is None:
            self._aligning = 0.0
        w = max(-self.limits.max_turn, min(self.limits.max_turn, 1.5 * turn))
        v = 0.0
        odo = self.odo.pose
        near = self.people.around(odo, self.now, echoes=self.scan.points()) if odo is not None else np.zeros((0, 2))
        if abs(turn) >= math.radians(8) and not turn_clear(w, near, duration=SWEEP_TIME):
            # the corners swing 0.34 m round, behind too: never into someone standing by the goal (the
            # floor plan checks below do not know people); arrive as it stands
            turn = 0.0
        if abs(turn) >= math.radians(8) and self._blind_checked(0.0, w, mapped) == (0.0, 0.0):
            turn = 0.0  # the sonar hears something unmapped beside or behind that a corner would swing toward: the same
        if abs(turn) >= math.radians(8) and self._turning:
            if len(mapped) and sweep_clearance(0.0, w, mapped, SWEEP_TIME) < TURN_GUARD:
                turn = 0.0  # the turn, clear when begun, is not any more (the pose drifts): arrive as it stands
        elif abs(turn) >= math.radians(8) and not self._turn_ok(turn, mapped):
            v, w = -0.5 * self.limits.max_reverse, 0.0
            if (self._aligning >= ALIGN_BACK or not self._sweep_ok(v, 0.0, mapped) or not self._behind_clear(ALIGN_BACK - self._aligning)
                    or self._blind_checked(v, 0.0, mapped) == (0.0, 0.0)):
                turn, v = 0.0, 0.0  # no room to turn, none to back into: arrive as it stands
        elif abs(turn) >= math.radians(8):
            self._turning = True  # the whole turn is clear: make it
        if abs(turn) < math.radians(8):
            self.bus.publish(BASE_CMD, etree.Element("velocity", v="0", w="0"))
            self._set_state("reached", dist, beside=beside)
            self._reached, self.goal = self.goal, None
            self._aligning = None
            self._turning = False
            self._listen_to_people(False)
            return (0.0, 0.0)
        v, w = self._guarded(v, w, mapped)
        self._aligning -= v * self.period
        self.bus.publish(BASE_CMD, etree.Element("velocity", v=f"{v:.4f}", w=f"{w:.4f}"))
        return (v, w)

    def _guarded(self, v: float, w: float, mapped: np.ndarray) -> tuple[float, float]:
        """The last checks of a command it sends: a pressed bumper's reflex (:mod:`robot.bumpers`), then the
        sonar's blind half (:meth:`_blind_checked`)."""
        v, w = self.bumpers.command(v, w, self.now, lambda speed: self._may_back(speed, mapped))
        return self._blind_checked(v, w, mapped)

    def _may_back(self, speed: float, mapped: np.ndarray) -> bool:
        """The bumper reflex's back-off (straight, at ``speed``) held to the player's own rules: clear of the
        floor plan (:func:`robot.navigation.follow.sweep_allowed`: touching, it may only move away), backing
        with nobody tracked behind (:meth:`_behind_clear`), forward clear of the laser's echoes too."""
        if speed < 0.0:
            return sweep_allowed(speed, 0.0, mapped) and self._behind_clear(BACKOFF_SPEED * BACKOFF_TIME)
        pts = self.scan.points()
        return sweep_allowed(speed, 0.0, np.concatenate((mapped, pts)) if len(pts) else mapped)

    def _blind_checked(self, v: float, w: float, mapped: np.ndarray) -> tuple[float, float]:
        """(v, w), or a stop where it would bring the footprint toward what the sonar hears in the blind half
        that the floor plan (``mapped``) does not explain (:func:`robot.blindside.blind_clear`)."""
        if v == 0.0 and w == 0.0:
            return v, w
        arcs = self.sonar.arcs(self.odo.pose, self.now)
        if arcs and not blind_clear(v, w, blind_points(arcs, explained_by_points(mapped)), duration=SWEEP_TIME):
            return 0.0, 0.0
        return v, w

    def _behind_clear(self, reach: float) -> bool:
        """Whether backing up to ``reach`` m keeps every tracked person behind out of personal space
        (:func:`robot.navigation.people.behind_clear`; the laser does not look behind)."""
        odo = self.odo.pose
        if odo is not None and maybe_behind(self.people, odo, self.now, reach=max(reach, 0.0) + HALF_LENGTH + BACK_GAP + BODY_RADIUS):
            return False  # someone lost from view may have walked there: the laser does not look behind
        return behind_clear(self.people_around(), length=2 * HALF_LENGTH, width=2 * HALF_WIDTH, reach=max(reach, 0.0))

    def _turn_ok(self, turn: float, mapped: np.ndarray) -> bool:
        """Whether turning on the spot through the whole of ``turn`` (rad) keeps the footprint
        :data:`SWEEP_MARGIN` off the floor plan (a turn begun and then blocked half way would leave
        the robot askew, its backing no longer the way it came)."""
        if not len(mapped):
            return True
        steps = max(int(abs(turn) / math.radians(10)) + 1, 2)
        return sweep_clearance(0.0, math.copysign(1.0, turn), mapped, abs(turn), steps=steps) >= SWEEP_MARGIN

    # ------------------------------------------------------------- control
    def pose(self) -> tuple[float, float, float] | None:
        """The localised pose advanced by odometry since it was estimated (None before the first)."""
        map_pose = self.map_pose
        if map_pose is None:
            return None
        odo_now = self.odo.pose
        if self._odo_xml_at_pose is None or odo_now is None:
            return map_pose
        return compose_delta(map_pose, pose_of(self._odo_xml_at_pose), odo_now)

    @property
    def map_pose(self) -> tuple[float, float, float] | None:
        """The latest localised pose (map frame), None before the first."""
        return None if self._pose_xml is None else pose_of(self._pose_xml)

    def _set_state(self, state: str, distance: float | None = None, *, beside: bool = False) -> None:
        if state == self.state:
            return
        self.state = state
        el = etree.Element("player", state=state)
        if beside:
            el.set("beside", "true")  # reached: it stopped short beside someone standing on the place (goal_taken)
        if self.goal is not None and state not in ("idle", "stopped"):
            el.set("x", f"{self.goal[0]:.4f}")
            el.set("y", f"{self.goal[1]:.4f}")
            if distance is not None:
                el.set("distance", f"{distance:.4f}")
        self.bus.publish(PLAYER_STATUS, el)

    def control_step(self) -> tuple[float, float] | None:
        """One step of ``move_to``: the velocity sent, or None when not driving."""
        if self.goal is None:
            return self._making_way() if self._make_way > 0.0 else None
        pose = self.pose()
        if pose is None:
            self._set_state("blocked")
            return None
        gx, gy, gth, tol, align = self.goal
        x, y, th = pose
        dist = math.hypot(gx - x, gy - y)
        mapped = self.mapped(pose)
        if dist <= tol or self._aligning is not None:
            return self._arrive(dist, wrap(gth - th) if align else 0.0, mapped)
        c, s = math.cos(th), math.sin(th)
        ax, ay = carrot(self.leg_start, (gx, gy), (x, y), LOOKAHEAD) if self.leg_start is not None else (gx, gy)
        local = (c * (ax - x) + s * (ay - y), -s * (ax - x) + c * (ay - y))
        echoes = self.scan.points()
        odo = self.odo.pose
        moving = self.people.around(odo, self.now, echoes=echoes, velocity=True) if odo is not None else np.zeros((0, 4))
        people = moving[:, :2]
        # the laser's echoes ahead, the floor plan all round (the corners sweep ground the laser does not see)
        points = np.concatenate((echoes, mapped)) if len(mapped) else echoes
        cap = social_speed_limit(nearest(people), self.limits.max_speed)
        # and round a corner ahead it cannot see behind (a door's jamb), a speed it can stop from (blind.py)
        # (a hard limit down to the social speed, the speed it keeps near people anyway; below that only the speed it
        # prefers: a hard limit of 0.12 m/s stalled the window in a niche between a bed and a wardrobe's end, nav_mapguard)
        blind = blind_speed_limit(self._blind_corners(mapped), cap, decel=self.limits.max_accel)
        squeezable = cap > SQUEEZE_SPEED  # (not facing a first leg: below)
        cap_hard = min(cap, max(blind, SOCIAL_SPEED))
        # never faster than it can stop from before anyone walking into its way (robot.footprint.contact_speed_limit),
        # on any turn rate the base reaches in one step (the window may turn toward someone: review18 F4)
        contact = (contact_speed_limit(in_the_way(self.people, odo, self.now, echoes=echoes), cap_hard,
                                       decel=self.limits.max_accel, w=self.odo.w,
                                       dw=self.limits.max_turn_accel * self.period) if odo is not None else cap_hard)
        cap_hard = min(cap_hard, contact)
        # standing for someone walking into its way is a yield, not a blocked way (below)
        for_walker = odo is not None and contact <= STAND_FOR
        limits = self.limits if cap_hard >= self.limits.max_speed else replace(self.limits, max_speed=cap_hard)  # a hard limit
        bearing = math.atan2(local[1], local[0])
        v_pref = heading_speed(min(cap, blind, contact, 0.25 + 0.6 * dist), bearing)
        arc_limits = limits
        if self._facing and abs(bearing) > TURN_FIRST:
            # the first leg, from where it stood (facing anywhere), is turned to on the spot first: a
            # forward arc while turning swings the robot off the planned line, into a door jamb
            # (goto_l_flat seeds 7, 9). At a corner between legs it arcs on: it comes along the line,
            # and a turn on the spot swings the rear corners through ground the laser does not see
            limits = replace(limits, max_speed=0.0)
        elif abs(bearing) <= TURN_FIRST:
            self._facing = False
        # everyone's space: wait at a polite distance, never at the body
        cmd = dwa(self.odo.v, self.odo.w, local, points, limits, v_pref=v_pref, params=self._goto_params, people=people)
        if limits is not arc_limits and (not cmd.ok or not turns_to(cmd.w, bearing)):
            # no room to turn on the spot toward the leg (a wall or a jamb at its back: it stood just outside a door it
            # had backed out of, open_island_goto seeds 0, 3, 7, blocked for a minute with the way free; the side of
            # the stairs at its back, the window offering only a creeping turn the other way: stair_goto_passage_person
            # seeds 1, 9 dithered a minute at the passage's end): arc round to the leg as the window allows, every rule
            # of driving kept: it prefers to move (the leg's heading alone prefers standing), at most at the speed it
            # can stop from round a blind corner (a jamb at its back is where they are), which here is a hard limit
            # too (review14 F2). No arc either: the turn on the spot stands, whatever it was
            arc_limits = replace(arc_limits, max_speed=min(arc_limits.max_speed, blind))
            arc = dwa(self.odo.v, self.odo.w, local, points, arc_limits, v_pref=max(v_pref, min(SOCIAL_SPEED, blind)),
                      params=self._goto_params, people=people)
            if arc.ok or not cmd.ok:
                cmd = arc
        if abs(cmd.v) < 0.02 and squeezable and limits.max_speed > 0.0 and standing_beside(moving):
            # no arc on past someone standing beside the way at the full gap: pass them slowly at SQUEEZE_GAP
            slow = replace(limits, max_speed=min(SQUEEZE_SPEED, limits.max_speed))
            squeeze = dwa(self.odo.v, self.odo.w, local, points, slow, v_pref=min(v_pref, slow.max_speed),
                          params=self._squeeze_params, people=people)
            if squeeze.ok and squeeze.v > 0.02 and arc_air(squeeze.v, squeeze.w, moving[:, :2], self._squeeze_params) >= SQUEEZE_GAP:
                cmd = squeeze  # (the whole arc at SQUEEZE_GAP: not the window's "no nearer than now", which turns ratchet down)
        refused = False  # a turn on the spot the window chose, refused for the people round it (below)
        if cmd.ok and abs(cmd.v) < 0.02 and cmd.w != 0.0 and not turn_clear(cmd.w, people, duration=SWEEP_TIME):
            # the window lets any turn on the spot pass people (nobody comes nearer the centre), but the
            # corners swing out, behind too, where the laser does not look: not into a tracked body
            cmd = Command(0.0, 0.0, False, cmd.clearance)
            refused = True
        held = False  # someone standing in its lane holds it up (the wait below)
        travel = cmd.v * self.period
        if cmd.ok and cmd.v > 0.0 and self._waits_for(moving, odo, travel):
            # someone stands in its lane: wait outside their personal space (a replan may find a way round)
            cmd = Command(0.0, 0.0, False, cmd.clearance)
            held = True
        yielding = cmd.ok and cmd.v > 0.0 and (self._yields(moving, odo) or self._heard_closing(mapped))
        if yielding:
            # someone near walks at it, or by it inside their personal space (BACK_GAP, 0.45 m of air; the
            # tracker misplaces people by a decimetre): stand and let them pass (yield), turning on the spot at most
            cmd = Command(0.0, cmd.w if abs(cmd.v) < 0.02 else 0.0, True, cmd.clearance)
        # someone walking at it this close (out of the door it drives into): it steps back out of their way,
        # as far as a back-off goes (BACK_OFF), where the floor plan, the people behind and the sonar leave room
        # (only someone ahead of it, walking at it, not drifting toward its side: goto seed 0 backed from a
        # woman 0.9 m beside it stepping at 0.19 m/s)
        if odo is not None:
            ahead = np.concatenate((moving, self.people.emerging(odo, self.now, moving=YIELD_SPEED, reach=GIVE_WAY_NEAR)))
            giving_way = closing_in(ahead[ahead[:, 0] > 0.0], near=GIVE_WAY_NEAR, speed=GIVE_WAY_SPEED)
        else:
            giving_way = False
        if giving_way and cmd.v > 0.0:
            cmd = Command(0.0, 0.0, True, cmd.clearance)
        # held up for them, or standing where it would report (or has reported) ``blocked``: the window finds no
        # arc past their space, or no progress for stall_time (approaching them from the side the window stops it
        # short of their space before the lane's wait does; blocked there it replanned and asked for help)
        stuck = held or self.state == "blocked" or (not cmd.ok and not for_walker) or self.now - self._best_t > self.stall_time
        if (stuck and align and dist <= ARRIVE_BESIDE and goal_taken(moving, local_goal(pose, (gx, gy)))
                and in_sight(local_goal(pose, (gx, gy)), mapped)):
            # someone standing on the place itself holds it up (waiting for them, not turning to a leg or
            # finding no arc): it has arrived as near as it politely can
            # (it does not turn to the place's heading beside them: the corners swing behind it); it reports
            # that it stopped beside someone (``beside``), and the dialog says so
            return self._arrive(dist, 0.0, mapped, beside=True)
        if held and abs(bearing) > WAY_ROUND and not self._waits_for(moving, odo, travel, turn=bearing):
            # held by someone standing in the lane of its heading while the leg (a replan's way round
            # them) points past them: turn on the spot toward the leg, if that swings no corner into
            # anyone or the floor plan; facing the leg they stand beside the lane and the window takes
            # it past them at its social gap (it stood held 1 m from a man, 20 degrees short of a way
            # round him, until it asked for help: lang_names seed 0). The whole turn must keep the
            # corners off everyone and off the floor plan (the window exempts turns on the spot)
            w = max(-limits.max_turn, min(limits.max_turn, 1.5 * bearing))
            if turn_clear(w, people, duration=max(SWEEP_TIME, bearing / w)) and self._turn_ok(bearing, mapped):
                cmd = Command(0.0, w, True, cmd.clearance)
        if cmd.ok and (abs(cmd.v) > 0.02 or (abs(cmd.v) < 0.02 and turns_to(cmd.w, bearing)
                                             and self._blind_checked(cmd.v, cmd.w, mapped) != (0.0, 0.0))):
            # (turning on the spot toward its leg is no standing wedged: backing off then, a turn under way broken
            # off, took it back into the stairs' side that its rear was turning clear of, stair_goto_passage_person;
            # but a turn the sonar's blind-half guard refuses leaves it standing, and standing it is: review17 F3)
            self._stuck_since = None
        elif self._stuck_since is None:
            self._stuck_since = self.now
        wedged = (self._stuck_since is not None and self.now - self._stuck_since >= WEDGED and nearest(people) > WEDGED_PERSON
                  and cmd.clearance < WEDGED_GAP)
        if (self._backed < BACK_OFF and ((self._backed > 0.0 and not self._gave_way) or wedged or giving_way
                                         or (not cmd.ok and abs(bearing) > BACK_OFF_BEARING))
                and self._sweep_ok(-0.5 * limits.max_reverse, 0.0, mapped)
                and self._behind_clear(BACK_OFF - self._backed)
                and self._blind_checked(-0.5 * limits.max_reverse, 0.0, mapped) != (0.0, 0.0)):
            # stopped close in front of something with the way off to the side (a new leg after a
            # replan), or wedged with a corner at a door jamb (standing for WEDGED s, something within
            # WEDGED_GAP, nobody near): turning on the spot would sweep the corners into it, so back off BACK_OFF m
            # first, straight the way it came (the laser does not see behind: the floor plan must leave room)
            v = -0.5 * limits.max_reverse
            cmd = Command(v, 0.0, True, cmd.clearance)
            # a back-off begun to give way lasts only while someone walks at it (no latch: goto seed 0 went on
            # backing 12 s later, 0.3 m for nobody)
            self._gave_way = giving_way and (self._backed == 0.0 or self._gave_way)
            self._backed -= v * self.period
        bv, bw = self._guarded(cmd.v, cmd.w, mapped)
        refused = refused or ((bv, bw) == (0.0, 0.0) and cmd.ok and cmd.w != 0.0 and cmd.v >= 0.0)
        if (refused and not held and not yielding and not giving_way and self._backed == 0.0
                and abs(bearing) <= ARC_ON_BEARING and not self._yields(moving, odo)):
            # the turn (on the spot or an arc) the window chose swings a corner into a tracked person or toward what the
            # sonar hears in the blind half (the partner standing close beside and behind its side after a
            # stop: stair_names_snug seeds 0, 2 stood blocked in the utility room until it asked for help): with
            # the leg no further off than ARC_ON_BEARING, a gentle forward arc toward it takes the robot away
            # from them; asked of the window with the turn rate held to ARC_ON_TURNS, every rule of driving kept:
            # never while it stands for someone near walking at it or by it (the yield: the arc is a forward
            # drive like any other, review15 F1), and no faster than it can stop from round a blind corner, a
            # hard limit as for the arc above (review15 F2)
            gentle = replace(arc_limits, max_speed=min(arc_limits.max_speed, blind))
            for turn in ARC_ON_TURNS:  # the sharpest arc the guard lets pass (a gentler one swings the rear less)
                arc = dwa(self.odo.v, self.odo.w, local, points, replace(gentle, max_turn=turn),
                          v_pref=max(v_pref, min(0.5 * SOCIAL_SPEED, blind)), params=self._goto_params, people=people)
                if not arc.ok or arc.v <= 0.02 or self._waits_for(moving, odo, arc.v * self.period):
                    break
                if self._guarded(arc.v, arc.w, mapped) == (arc.v, arc.w):
                    cmd, (bv, bw) = arc, (arc.v, arc.w)
                    break
        if (bv, bw) != (cmd.v, cmd.w):
            cmd = Command(bv, bw, False, cmd.clearance)
        self.bus.publish(BASE_CMD, etree.Element("velocity", v=f"{cmd.v:.4f}", w=f"{cmd.w:.4f}"))
        if self.state == "blocked":
            # blocked until the way is really clear: 0.3 m of progress, not a nudge
            if dist < self._best - 0.3:
                self._best, self._best_t = dist, self.now
                self._set_state("moving", dist)
            return (cmd.v, cmd.w)
        if dist < self._best - 0.05:
            self._best, self._best_t = dist, self.now
            self._yielded = 0.0
        if (for_walker or yielding) and self._yielded < YIELD_HOLD:
            # it stands for someone walking into its way (the contact limit, the yield): they pass, and the way is
            # free again; that time is not "no progress" (goto_standing_person seeds 3, 6 asked for help while a
            # man walked at them), up to YIELD_HOLD s (someone who keeps walking at it does block it)
            self._best_t += self.period
            self._yielded += self.period
        stalled = self.now - self._best_t > self.stall_time
        if (not cmd.ok and not for_walker) or stalled:
            self._best = min(self._best, dist)
            self._set_state("blocked", dist)
        else:
            self._set_state("moving", dist)
        return (cmd.v, cmd.w)

    def _yields(self, moving: np.ndarray, odo: tuple[float, float, float] | None) -> bool:
        """The yield rule for a forward drive: someone within YIELD_NEAR walks at the robot (a confirmed track, or
        one just seen coming round a jamb, tentative still: People.emerging), or someone walks by it inside their
        personal space (BACK_GAP). It stands for them then, turning on the spot at most."""
        coming = (np.concatenate((moving, self.people.emerging(odo, self.now, moving=YIELD_SPEED, reach=YIELD_NEAR)))
                  if odo is not None else moving)
        return bool(closing_in(coming, near=YIELD_NEAR, speed=YIELD_SPEED) or passing_close(
            moving, footprint_distance(moving[:, 0], moving[:, 1]) - BODY_RADIUS, gap=BACK_GAP, speed=YIELD_SPEED))

    def _heard_closing(self, mapped: np.ndarray) -> bool:
        """The yield rule's blind half: the sonar hears something the floor plan does not explain walking up beside or
        behind the robot (:meth:`robot.blindside.SonarEchoes.closing`), now or within :data:`HEARD_HOLD` s. The laser
        looks ahead only: a child running past from behind (fresh7/split_goto_ramp_child seed 2: 0.9 m/s on its right
        while it drove on at 0.16 m/s, 0.03 m of air) is tracked only once level with it; a robot that stands
        while she passes does not crowd her, and she is seen and let pass by the tracked rules from there."""
        if self.sonar.closing(self.odo.pose, self.now, explained_by_points(mapped)):
            self._heard_at = self.now
        return self.now - self._heard_at <= HEARD_HOLD

    def _making_way(self) -> tuple[float, float] | None:
        """One step of backing off out of someone's way (order make_way): straight back at half the reverse
        speed, held like every other base command to the sonar's blind-half rule (:meth:`_blind_checked`),
        and to the floor plan and the tracked people behind. It starts only once a sonar packet and the
        person tracks have come in after the order (:data:`MAKE_WAY_WAIT`); without a floor plan it does not
        move at all (an empty neighbourhood on the plan is room). Stops when done or when the room ends."""
        pose = self.pose()
        if pose is None or self.outline is None:
            if self._map_asked:  # no floor plan to back into: it stays where it is
                return self._stay_put()
            return None
        if self._sonar_at is None or self._tracks_at is None:
            if self.now - self._make_way_at > MAKE_WAY_WAIT:
                return self._stay_put()  # no sonar or no tracks: it cannot know what is behind it
            return None  # not yet heard behind it: nothing sent
        mapped = self.mapped(pose)
        v = -0.5 * self.limits.max_reverse
        if ((not len(mapped) or self._sweep_ok(v, 0.0, mapped)) and self._behind_clear(self._make_way)
                and self._guarded(v, 0.0, mapped) == (v, 0.0)):  # the bumper reflex too: a pressed rear ring ends it
            self.bus.publish(BASE_CMD, etree.Element("velocity", v=f"{v:.4f}", w="0.0000"))
            self._make_way += v * self.period
            if self._make_way > 0.0:
                return (v, 0.0)
        return self._stay_put()

    def _stay_put(self) -> tuple[float, float]:
        """End a make-way back-off: stop, and stop listening behind."""
        self._make_way = 0.0
        self._listen_to_people(False)
        self.bus.publish(BASE_CMD, etree.Element("velocity", v="0", w="0"))
        return (0.0, 0.0)

    async def run(self) -> None:
        while True:
            self.beat()
            if (self.goal is not None or self._make_way > 0.0) and not self._map_asked:
                await self._fetch_map()
            self.control_step()
            await asyncio.sleep(self.period)


def install(run: Any) -> dict[str, Module]:
    """The player module with the run's speed limits (``run.config``: max_speed, max_turn)."""
    player = Player(run.sim, limits=limits_from_config(getattr(run, "config", {}) or {}))
    player.start()
    return {"player": player}
