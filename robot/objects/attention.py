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
3. collects ``/robot/camera/objects`` detections for ``look_time`` s (when
   nothing fits and the pointing person stands between the camera and where
   she points, it first asks her to step aside through the ES (event ``occluded``,
   the dialog's condition ``step_aside``, its answer back as the order ``asked_aside``),
   waits until ``/robot/attention/partner`` shows her out of the way, and looks
   again at where she points then), places
   each in the map frame with the localised pose (``/robot/localisation/pose``)
   and the floor plan's furniture heights (``map_server/map``), and merges them
   into candidates (:mod:`robot.objects.resolve`);
4. resolves the reference from the frame's type, name and colour, the
   pointing ray and the distance; when two or more fit about equally it asks
   the partner through the ES (event ``clarification``; the ES sends the dialog
   the condition ``ask``, "Do you mean the cup on the left or the one on the
   right?", and the dialog's answer back as the order ``clarified``) and takes
   the answer: an option ("the blue one", "the left one"), "this one" with a
   new pointing gesture (resolved again among the options, by the gesture
   alone), or "the one on the table" (the only option standing on it, from the
   floor plan); the object stored is the chosen candidate's own position (the
   mean of its own detections), never a mix of candidates;
5. sends ES event ``object_recognized`` with ``<OBJECT type name [owner]
   colour x y z [size] frame="map">`` (``size``: metres across, measured from
   the image extent the camera reports and the distance) plus the colour features as an inline
   ``<attachment>`` (ES orders carry no binaries) and the frame's
   ``ATTRIBUTE`` / ``POSITION`` children, or ``object_not_found`` with
   ``reason`` = ``nothing_seen``, ``no_match``, ``unclear`` (the partner did
   not choose) or ``no_pose`` (no localisation yet).

Owner: "my" (``OWNER name="speaker"``) is stored as ``partner``: the robot
does not know names unless told ("this cup belongs to Anna" gives ``anna``).
A new ``find_object`` cancels a search in progress; so does the order ``cancel`` (the ES, on
good-bye or partner lost during ObjectTeaching, with a ``stop`` to the player), without a result.
"""

from __future__ import annotations

import asyncio
import dataclasses
import math
from collections import deque
from typing import TYPE_CHECKING, Any

from lxml import etree

from homesim.memory.protocol import attachment_element
from homesim.message import Message
from homesim.module import Module
from robot.floorplan import FloorPlan, parse_map

from robot.contract import ES_EVENTS, ES_ORDERS, FOCUS, GESTURES, OBJECTS, PARTNER, PLAYER_STATUS, POSE, TRACKS

from .gestures import CAMERA_HEIGHT, CAMERA_OFFSET, GestureTracker, camera_to_map
from .resolve import AIM_SIGMA, MERGE_BEARING, Candidate, Pointing, Resolution, Wanted, along_ray, choose_pointed, learned_type, merge, option_texts, resolve
from .viewpoint import ARRIVE_TOLERANCE, CAMERA_RANGE, POINT_REACH, cover_views, in_range, pointed_spot, search_area, sees, sight_clear, viewpoint, viewpoint_route

if TYPE_CHECKING:
    from homesim.sim import Simulation

ORDERS = f"{ES_ORDERS}/object_attention"
EVENTS = ES_EVENTS
VIEW_HALF_WIDTH = math.radians(24.0)  # the camera's half field of view
IMAGE_HALF_HEIGHT = math.radians(18.8)  # the camera's half field of view up and down (the EVI-D31's 37.6 deg)
RANGE_NOISE = 0.06  # the camera's object distance error, relative (one standard deviation, its data sheet)
RANGE_TOL = 2 * RANGE_NOISE  # looking up, a surface fits when a distance this much off puts the object on it
RANGE_STEPS = 6  # steps of that tolerance tried, smallest first
BODY_HALF_WIDTH = 0.3  # metres either side of a person's centre that hide what is behind (shoulders, arm)
PERSON_TOP = 1.95  # m: no one standing hides what the camera sees over this height where she stands (a tall adult's head)
GESTURE_LEAD = 3.0  # s: a pointing that goes with a sentence may begin this long before its first word
SENTENCE_RECENT = 15.0  # s: a sentence begun this long ago is still the one being resolved (said, understood, sent)
SEARCH_OFFSETS = (math.radians(-35.0), math.radians(-70.0), math.radians(35.0), math.radians(70.0))  # off her bearing, one side then the other
SEARCH_LOOK = 1.0  # s the camera dwells on each side of her
SEARCH_RADIUS = 1.5  # m: what she shows without a gesture the camera saw stands this near her
# Then, nothing of it found there, further round on both sides (off her bearing): standing close to the
# robot she points past its side or behind it, her hand leaves the image at once (at 1 m the image at
# hand height is 0.9 m wide) and the camera never sees the gesture; beyond the pan-tilt unit's 100
# degrees the image still reaches 124 degrees. What she shows there stands within ``SEARCH_RADIUS_WIDE``
# of her (an arm's reach and a step: the plant by the armchair 1.6 m from her, diag_step_aside_child).
SEARCH_OFFSETS_WIDE = (math.radians(-105.0), math.radians(105.0))
SEARCH_RADIUS_WIDE = 2.0
#: m round where her ray shows an object: the part of it no look had in view is brought into view before "could not
#: find" (her aim, 6 deg, over 3 m is 0.3 m; twice that)
COVER_RAY = 0.6
# The pan-tilt unit (Sony EVI-D31's data sheet): it pans at most this fast and this far. A look of
# SEARCH_LOOK s begins when the camera has got there: swinging from one side of her to the other (140
# degrees) takes 1.75 s, and a look timed from the order saw the far side for no frame at all.
PAN_SPEED = math.radians(80.0)
PAN_LIMIT = math.radians(100.0)
TURN_TO_LOOK = 5.0  # s: a look at a spot beyond the pan range waits at most this long for the base's turn to it
GLIMPSE = 2  # detections as the thing named: fewer in a look and it is not taken for the one she means (one can be a confusion)
POSE_WAIT = 0.3  # s: a percept waits this long for the localised pose of its capture time
PARTNER_FAR = 2.6  # m: a partner farther away is approached when neither her gesture nor what she shows was seen
MOVE_TIMEOUT = 20.0  # s: a drive to a better viewpoint that has not arrived by then is given up
MOVE_BLOCKED = 4.0  # s: ... and one the player reports blocked this long, the robot standing all that time
MOVE_STILL = 0.05  # m: ... standing: its localised position moved less than this (a turn on the spot is standing)
TABLE_HEIGHT = 0.8  # m: the height the person attention tilts to without a focus height
HEIGHT_OFF = 0.3  # m: a region this far above or below it is sent with its height (the floor; not a table top, where the
# default view is the one measured: mugs_in_a_row seed 8 placed a mug 0.15 m off with the sideboard's own 0.9 m)
STEP_ASIDE_ASK = 20.0  # s: the question "could you step aside" is said within this (through the ES and the dialog)
STEP_ASIDE_STIR = 3.0  # s after the question: a partner who has not begun to step aside by then is not going to
STEP_ASIDE_START = 0.25  # m: that far from where she stood when asked, she has begun to move
UPRIGHT_STEPS = 8  # placements with the height the image shows (each 2-5x nearer; within 1 mm after a few)
ROW_GAP = 0.4  # m: things alike stand this close side by side (books in a row, cups on a table): one seen this near the
# strip a person's body hides may have a look-alike hidden next to it
#: s: after stepping aside she has come to a stand within this (a 2 m step at 0.45 m/s and her turn back to the robot)
STILL_WAIT = 6.0
#: s a look dwells before what the camera points at counts as viewed (the pan-tilt unit's 80 deg/s, the image settling)
VIEW_SETTLE = 0.6
STEP_ASIDE_AGAIN = 60.0  # s: a partner asked this recently who stays in the way is not asked again (the robot moves)

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


Seen = tuple[str, float, float, float, tuple[float, float, float], float | None, float | None]


def upright(pose: tuple[float, float, float], bearing: float, distance: float, x: float, y: float, z: float,
            rise: float | None) -> tuple[float, float, float | None]:
    """An object placed at (x, y) on a surface (``z`` 0.05 above it) from a detection at ``bearing``
    and ``distance``, placed again with the height the image shows (``rise``, rad; None: as it is):
    the camera's distance is to the object's middle, not to its foot, so a plant 0.6 m tall on the
    floor placed as if its middle were at the floor comes 0.1-0.2 m too near. Returns x, y and its
    height (m, None without ``rise``)."""
    if rise is None:
        return x, y, None
    tall = object_tall(pose, x, y, z, rise)
    for _ in range(UPRIGHT_STEPS):  # its height from where it stands, where it stands from its height
        x, y = camera_to_map(pose, bearing, distance, z - 0.05 + tall / 2)
        now = object_tall(pose, x, y, z, rise)
        if abs(now - tall) < 1e-3:
            return x, y, now
        tall = now
    return x, y, tall


def object_tall(pose: tuple[float, float, float], x: float, y: float, z: float, rise: float) -> float:
    """How tall (m) an object standing at (x, y) on a surface at ``z`` - 0.05 is, from the angle
    ``rise`` (rad) it spans up the image seen from the camera at ``pose``: its top is where the sight
    line that much above the one to its bottom meets its own upright."""
    cx, cy = pose[0] + CAMERA_OFFSET * math.cos(pose[2]), pose[1] + CAMERA_OFFSET * math.sin(pose[2])
    horiz = max(math.hypot(x - cx, y - cy), 1e-3)
    base = z - 0.05
    up = math.atan2(base - CAMERA_HEIGHT, horiz) + rise
    if up >= math.pi / 2 - 1e-3:
        return 0.0
    return max(0.0, CAMERA_HEIGHT + horiz * math.tan(up) - base)


def one_surface(seen: list[Seen], rays: list[tuple[tuple[float, float, float], float, float, float | None]]) -> list[Seen]:
    """Detections of one object placed on one surface.

    Each detection is placed on the surface under it (:meth:`ObjectAttention.place`), but the
    camera's distance errs by ~6 %: a mug near a counter's edge is now and then placed past the
    edge, on the floor (0.3 m off in depth, 0.9 m too low), and the object's mean position and
    height then lie between the two. A detection whose ray (map bearing within ``MERGE_BEARING``,
    colour alike) is shared by detections that mostly stand on another surface is placed again,
    on theirs (``rays``: each detection's pose, bearing and slant distance).
    """
    out = list(seen)
    if len(seen) != len(rays):
        return out
    heads = [r[0][2] + r[1] for r in rays]
    for i, det in enumerate(seen):
        votes: dict[float, int] = {}
        for j, other in enumerate(seen):
            if abs(math.remainder(heads[i] - heads[j], 2 * math.pi)) < MERGE_BEARING and \
                    sum((a - b) ** 2 for a, b in zip(det[4], other[4])) <= 0.35 ** 2:
                votes[other[3]] = votes.get(other[3], 0) + 1
        z = max(sorted(votes), key=lambda h: votes[h])
        if votes.get(det[3], 0) < votes[z]:
            x, y = camera_to_map(rays[i][0], rays[i][1], rays[i][2], z)
            x, y, tall = upright(rays[i][0], rays[i][1], rays[i][2], x, y, z, rays[i][3] if len(rays[i]) > 3 else None)  # type: ignore[misc]
            out[i] = (det[0], x, y, z, det[4], det[5], tall)
    return out


class ObjectAttention(Module):
    """Gestures + camera objects + localised pose -> the object meant (see the module docstring)."""

    def __init__(self, sim: Simulation, *, name: str = "object_attention", gesture_wait: float = 1.5, look_time: float = 2.0, ask_timeout: float = 15.0,
                 step_aside_wait: float = 10.0) -> None:
        super().__init__(sim, name, host="robot")
        self.step_aside_wait = step_aside_wait
        self._partner: tuple[float, float, float] | None = None  # time, bearing (rad), distance of the partner (person attention)
        self.gesture_wait = gesture_wait
        self.look_time = look_time
        self.ask_timeout = ask_timeout
        self.gestures = GestureTracker()
        self.pose: tuple[float, float, float] | None = None
        self.plan: FloorPlan | None = None
        self._looking = False
        self._seen: list[Seen] = []
        self._focus_bearing = 0.0  # rad, robot frame: where the last focus sent the camera
        self._frames: list[float] = []  # each seen detection's capture time (its camera frame)
        self._rays: list[tuple[tuple[float, float, float], float, float, float | None]] = []  # each one's pose, bearing, distance, rise
        self._search: asyncio.Task[None] | None = None
        self._answer: asyncio.Future[etree._Element] | None = None  # waiting for the order "clarified"
        self._asked_aside: asyncio.Future[bool] | None = None  # waiting for the order "asked_aside"
        #: where the camera looked during this search (camera x, y, bearing in the map, rounded: one entry per view)
        self._views: dict[tuple[float, float, float], None] = {}
        self._asked_where: tuple[float, tuple[float, float] | None] | None = None  # when she was last asked to step aside, where she stood
        self.last: Resolution | None = None  # the latest resolution (for tests and introspection)
        self.bus.subscribe(ORDERS, self._on_order)
        self.bus.subscribe(GESTURES, self._on_gestures)
        self.bus.subscribe(OBJECTS, self._on_objects)
        self.bus.subscribe(POSE, self._on_pose)
        self.bus.subscribe(PARTNER, self._on_partner)
        self._people: tuple[float, list[tuple[float, float]]] | None = None  # time, people's (bearing, distance), robot frame
        self._player: tuple[str, float] | None = None  # the player's last state and when it came
        self.moves = 0  # drives to a better viewpoint (for tests and introspection)
        self._subs: list[Any] = []  # people's tracks and the player's status, only while a search runs
        self._finds = 0  # searches begun
        self._told_moving = False  # this search has told the ES (and so her) that the robot moves to see
        self._answer_owner = ""  # the owner her which-one answer named (her request named none)
        self._poses: deque[tuple[float, tuple[float, float, float]]] = deque(maxlen=30)  # (time, pose), the last 3 s
        self._pending: list[tuple[float, str, etree._Element]] = []  # percepts waiting for the pose of their time

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
        t = float(x.get("time", msg.created))  # type: ignore[arg-type]
        if self._poses and t < self._poses[-1][0]:
            return  # an older pose delivered late: the history stays in time order
        self._poses.append((t, self.pose))
        self._flush()

    def pose_at(self, t: float) -> tuple[float, float, float] | None:
        """The localised pose at time ``t`` (interpolated between the two poses around it; the
        latest one if ``t`` is newer): an image is placed with the pose of its capture, not the
        latest one, so what the camera saw while the robot turned stays where it is."""
        poses = self._poses
        if not poses:
            return None
        if t >= poses[-1][0]:
            return poses[-1][1]
        prev = poses[0]
        if t <= prev[0]:
            return prev[1]
        for cur in poses:
            if cur[0] >= t:
                (t0, a), (t1, b) = prev, cur
                f = 0.0 if t1 <= t0 else (t - t0) / (t1 - t0)
                th = a[2] + f * math.remainder(b[2] - a[2], 2 * math.pi)
                return a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]), math.remainder(th, 2 * math.pi)
            prev = cur
        return poses[-1][1]

    def _flush(self) -> None:
        """Place the percepts waiting for the pose of their capture time (all once it has come,
        or when they waited ``POSE_WAIT`` s: then with the latest pose)."""
        if not self._pending or not self._poses:
            return
        latest = self._poses[-1][0]
        keep = []
        for t, kind, el in self._pending:
            if t > latest + 1e-9 and self.now - t < POSE_WAIT:
                keep.append((t, kind, el))
                continue
            pose = self.pose_at(t)
            assert pose is not None
            if kind == "g":
                for p in el.iterfind("pointing"):
                    self.gestures.add(t, pose, float(p.get("bearing")), float(p.get("distance")), float(p.get("direction")), float(p.get("elevation")), float(p.get("hand_height")))  # type: ignore[arg-type]
            elif self._looking:
                tilt = math.radians(float(el.get("tilt", "-90")))
                up = tilt >= 0.0  # the camera looked level or up (a high shelf)
                for o in el.iterfind("object"):
                    b, d = math.radians(float(o.get("bearing"))), float(o.get("distance"))  # type: ignore[arg-type]
                    x, y, z = self.place(pose, b, d, high=up, tilt=tilt if up else None)
                    w, h = o.get("width"), o.get("height")
                    # The size across: the image extent at the measured (slant) distance.
                    size = 2 * d * math.tan(math.radians(float(w)) / 2) if w is not None else None
                    rise = math.radians(float(h)) if h is not None else None
                    x, y, tall = upright(pose, b, d, x, y, z, rise)
                    self._seen.append((o.get("type", ""), x, y, z, (float(o.get("r")), float(o.get("g")), float(o.get("b"))), size, tall))  # type: ignore[arg-type]
                    self._frames.append(t)
                    self._rays.append((pose, b, d, rise))
        self._pending = keep

    def _on_gestures(self, msg: Message) -> None:
        if self.pose is None or msg.xml.find("pointing") is None:
            return
        self._pending.append((float(msg.xml.get("time", msg.created)), "g", msg.xml))  # type: ignore[arg-type]
        self._flush()

    def _on_objects(self, msg: Message) -> None:
        if not self._looking or self.pose is None or msg.xml.find("object") is None:
            return
        self._pending.append((float(msg.xml.get("time", msg.created)), "o", msg.xml))  # type: ignore[arg-type]
        self._flush()

    def place(self, pose: tuple[float, float, float], bearing: float, distance: float, *, high: bool = False,
              tilt: float | None = None) -> tuple[float, float, float]:
        """Map position of an object seen at ``bearing``/``distance``: first assume it stands on a
        table-high surface, then take the height of the plan's furniture under that point (or
        the floor) and place it again with that height. Furniture taller than the camera counts
        only in an image taken looking level or up (``high``: the camera was turned up to a high
        shelf she pointed at; looking down, a mug on a counter placed a little too far by the
        range noise would otherwise land on top of the fridge behind it).

        Looking level or down, that placement must agree with itself: an object on the floor is seen
        further than the camera stands above the floor, and one on a piece of furniture stands inside
        its footprint. Seen close, the table-high guess falls short of a higher surface: a vase on a
        0.9 m shelf 0.83 m from the camera was guessed 0.56 m out, before the shelf's edge, then placed
        on the floor, where a slant distance shorter than the camera's height puts it under the robot
        (tour-1000-044: "Sorry, I could not find your vase" three times while the camera saw it
        where she pointed). Then the surface it does stand on is the one whose footprint holds the
        position placed at its height (:meth:`_surface`).

        Looking level or up with the camera's ``tilt`` known (rad, up positive), the table-high guess is
        not made: from 2.7 m a range 6 % short put it before a bookcase's front edge and a book on its
        1.85 m top went to the floor in half the detections (high22's G). The surface is the one whose
        top fits the camera's ray instead (:meth:`_surface_up`)."""
        if high and tilt is not None and self.plan is not None:
            h = self._surface_up(pose, bearing, distance, tilt)
            if h is not None:
                x, y = camera_to_map(pose, bearing, distance, h + 0.05)
                return x, y, h + 0.05
        z = 0.8
        x, y = camera_to_map(pose, bearing, distance, z)
        top = 0.0
        if self.plan is not None:
            for o in self.plan.obstacles:
                if o.type != "leg" and (high or o.top < CAMERA_HEIGHT) and _inside(x, y, o.points):
                    top = max(top, o.top)
        z = top + 0.05
        x, y = camera_to_map(pose, bearing, distance, z)
        if self.plan is not None and not high and not self._on_surface(x, y, top, distance):
            other = self._surface(pose, bearing, distance)
            if other is not None:
                z = other + 0.05
                x, y = camera_to_map(pose, bearing, distance, z)
        return x, y, z

    def _on_surface(self, x: float, y: float, top: float, distance: float) -> bool:
        """Does an object placed at (x, y) standing on a surface ``top`` m high agree with the plan?
        On the floor: seen from further than the camera stands above it, and inside no piece of
        furniture that blocks the view (it would stand on it, or in it); on furniture: inside a
        footprint of that height."""
        assert self.plan is not None
        surfaces = [o for o in self.plan.obstacles if o.type != "leg" and o.top < CAMERA_HEIGHT]
        if top <= 0.0:
            return distance > CAMERA_HEIGHT - 0.05 and not any(o.bottom <= 0.05 and _inside(x, y, o.points) for o in surfaces)
        return any(abs(o.top - top) < 1e-9 and _inside(x, y, o.points) for o in surfaces)

    def _surface(self, pose: tuple[float, float, float], bearing: float, distance: float) -> float | None:
        """The height of the surface an object seen at ``bearing``/``distance`` can stand on: a piece
        of furniture whose footprint holds the position placed at its top's height (the one nearest
        the table height of the first guess when several do), else None."""
        assert self.plan is not None
        fits = []
        for o in self.plan.obstacles:
            if o.type == "leg" or o.top >= CAMERA_HEIGHT or distance <= CAMERA_HEIGHT - o.top - 0.05:
                continue
            x, y = camera_to_map(pose, bearing, distance, o.top + 0.05)
            if _inside(x, y, o.points):
                fits.append(o.top)
        return min(fits, key=lambda h: (abs(h - 0.8), h)) if fits else None

    def _surface_up(self, pose: tuple[float, float, float], bearing: float, distance: float, tilt: float) -> float | None:
        """Looking level or up (``tilt``, rad): the height of the surface an object seen at
        ``bearing``/``distance`` stands on. Every surface of the plan counts (furniture of any height,
        and the floor where no furniture stands): placed at its top, the object must lie inside its
        footprint for some distance within ``RANGE_TOL`` of the measured one (the camera's range error,
        two standard deviations), and in the image (its elevation from the camera within the image's
        half height of the tilt, and a margin). Of those, the one that needs the smallest range error
        and lies nearest the middle of the image (each measured in its own spread) is taken; None when
        none fits."""
        assert self.plan is not None
        best: tuple[float, float] | None = None
        tops = [0.0] + sorted({o.top for o in self.plan.obstacles if o.type != "leg" and o.top > 0.0})
        for h in tops:
            z = h + 0.05
            dz = z - CAMERA_HEIGHT
            err = None
            for k in range(RANGE_STEPS + 1):  # the smallest range error that puts it inside a footprint of that height
                for sign in ((1.0,) if k == 0 else (1.0, -1.0)):
                    d = distance * (1.0 + sign * RANGE_TOL * k / RANGE_STEPS)
                    if d <= abs(dz):
                        continue
                    x, y = camera_to_map(pose, bearing, d, z)
                    if h == 0.0:
                        fits = not any(o.type != "leg" and o.bottom <= 0.05 and _inside(x, y, o.points) for o in self.plan.obstacles)
                    else:
                        fits = any(o.type != "leg" and abs(o.top - h) < 1e-9 and _inside(x, y, o.points) for o in self.plan.obstacles)
                    if fits:
                        err = RANGE_TOL * k / RANGE_STEPS
                        break
                if err is not None:
                    break
            if err is None or distance <= abs(dz):
                continue
            elev = math.atan2(dz, math.sqrt(distance * distance - dz * dz))
            if abs(elev - tilt) > IMAGE_HALF_HEIGHT + math.radians(2.0):
                continue  # the camera could not have seen it there
            cost = (err / RANGE_NOISE) ** 2 + ((elev - tilt) / IMAGE_HALF_HEIGHT) ** 2
            if best is None or cost < best[0]:
                best = (cost, h)
        return best[1] if best is not None else None

    # ------------------------------------------------------------ orders
    def _on_order(self, msg: Message) -> None:
        if msg.xml.get("name") == "asked_aside":  # the dialog asked her to step aside, through the ES
            said = next((p.text for p in msg.xml.iterfind("param") if p.get("name") == "said"), None)
            if self._asked_aside is not None and not self._asked_aside.done():
                self._asked_aside.set_result((said or "").strip() == "true")
            return
        if msg.xml.get("name") == "clarified":  # the partner's answer to our question, through the ES
            answer = next((p.find("ANSWER") for p in msg.xml.iterfind("param") if p.find("ANSWER") is not None), None)
            if self._answer is not None and not self._answer.done() and answer is not None:
                self._answer.set_result(answer)
            return
        if msg.xml.get("name") == "cancel":  # good-bye or partner lost: the search ends, no result
            if self._search is not None and not self._search.done():
                self._search.cancel()
            return
        if msg.xml.get("name") != "find_object":
            return
        if self._search is not None and not self._search.done():
            self._search.cancel()
        obj = None
        said: float | None = None
        for p in msg.xml.iterfind("param"):
            if p.get("name") == "object":
                obj = p.find("OBJECT")
            elif p.get("name") == "said" and p.find("TIMESTAMP") is not None:  # the sentence's start (ms)
                said = float(p.find("TIMESTAMP").get("val", "nan")) / 1000.0  # type: ignore[union-attr]
        self._search = self.sim.spawn(self.find(obj, msg.id, said), name=f"{self.name}:find")

    async def find(self, obj: etree._Element | None, cause: str, said: float | None = None) -> None:
        """One search (see the module docstring); always ends with an ES event. ``said``: when the
        sentence began (s, the frame's ``TIMESTAMP``), if the order carries it."""
        wanted = wanted_from(obj)
        self._answer_owner = ""  # whose it is, said in her answer to a which-one question
        self._finds += 1
        token = self._finds
        self._views = {}
        self._told_moving = False  # "I will move over to see it": once per search, not per viewpoint
        try:
            waited = 0.0
            start = self._gesture_start(said)
            while self.gestures.pointing(self.now, start=start) is None and waited < self.gesture_wait:
                await asyncio.sleep(0.1)
                waited += 0.1
            pointing = self.gestures.pointing(self.now, start=start)
            if self.pose is None:
                self._not_found("no_pose", cause)
                return
            res = await self._look(wanted, pointing, cause)
            # she stood in front of the camera as it looked ahead (the searches below may turn the base away)
            in_view = self._partner_in_view()
            if res.kind == "none" and pointing is None and self._named_spot(obj) is not None:
                # No gesture seen, but she said what it stands on ("the blue vase on the sideboard") and the
                # map knows that piece of furniture: look there first (fresh6 div_long_tour: "could not find
                # the blue vase" ~4 m away, her gesture never seen), coming closer if it cannot be seen from here.
                res = await self._look_on_named(wanted, obj, cause) or res
            if res.kind == "none" and pointing is None:
                # No gesture seen (her arm swung out of the image: she stands close, or pointed
                # before the camera was on her hands) and nothing of the kind ahead: look on both
                # sides of her for what she named.
                near = await self._search_near_partner(wanted, cause)
                if near is not None and near.kind != "none":
                    res = near
                elif near is not None:
                    # nothing round her either: bring what no look had in view (beside or behind the robot, under the
                    # camera's minimum range) into view before asking her to step aside (she does not hide that)
                    res = await self._cover_area(wanted, cause) or res
            asked = False
            if res.kind != "none" and self._lookalike_hidden(res, pointing) and not self._asked_in_vain():
                # What she named found just beside the strip her body hides (her gesture unseen, or her ray
                # coming down in that strip): a thing like it may stand hidden next to it, the one she means
                # (fresh9 bay_three_books: the east one of three books behind him stored in 6 of 10 runs).
                # Ask her to step aside and look again; if she does not, it is not found here (below: the
                # robot moves to see where she points, or says it could not find it), never the neighbour.
                asked = True
                res, pointing = await self._unhide(wanted, pointing, cause, [(c.x, c.y) for c in res.fitting()])
            # Out of the camera's range (she points from afar, or up at a high shelf across the room):
            # no one hides it, the robot must come closer (below), not ask her to step aside
            # (fresh3 open_sofa_guest, angle_point_far: "you are standing in front of it" was untrue).
            far = pointing is not None and self._out_of_range(pointing)
            hidden = pointing is not None and not far and self._partner_in_the_way(pointing)
            if res.kind == "none" and not asked and (hidden or (pointing is None and (in_view or self._partner_in_view()))) and not self._asked_in_vain():
                # She stands between the camera and what she points at: ask her to step aside,
                # wait until she has, and look again (at where she points then, if she does).
                # If she does not step aside, the robot moves to see instead (below).
                asked = True
                res, pointing = await self._step_aside_and_look(res, wanted, pointing, cause)
            if res.kind == "none" and pointing is not None:
                # Still nothing where she points: if the camera cannot see that spot from here (her,
                # someone else, furniture or a wall in the way, or out of its range), drive to a
                # place from which it can and look again.
                moved = await self._move_to_see(pointing, cause)
                if moved:
                    res = await self._look(wanted, pointing, cause)
                elif far and not asked and self._partner_in_the_way(pointing) and not self._asked_in_vain():
                    # Out of range and no place to see it from while she stands on the sight line (a
                    # small bedroom, she stands between the robot and the chest): coming closer needs
                    # her out of the way first (fresh6 cellar_hidden_clock: "could not find" in 10/10).
                    res, pointing = await self._step_aside_and_look(res, wanted, pointing, cause)
                    if res.kind == "none" and pointing is not None and await self._move_to_see(pointing, cause):
                        res = await self._look(wanted, pointing, cause)
            elif res.kind == "none" and pointing is None and self._partner_far():
                # No gesture seen and nothing found: she stands too far for the camera to see her
                # hand or what she shows (the robot lagged behind). Come closer, then look for her
                # gesture and what she named again.
                since = self.now
                near = self._partner_map()
                if near is not None and await self._move_to_see_spot((near[0], near[1], 1.0), cause):
                    waited = 0.0
                    while self.gestures.pointing(self.now, since=since) is None and waited < self.gesture_wait:
                        await asyncio.sleep(0.1)
                        waited += 0.1
                    pointing = self.gestures.pointing(self.now, since=since)
                    res = await self._look(wanted, pointing, cause)
                    if res.kind == "none" and pointing is None:
                        res = await self._search_near_partner(wanted, cause) or res
            if res.kind == "none" and pointing is not None and self._named_spot(obj) is not None:
                # Nothing found where she pointed (her ray ends elsewhere, or the drive to see failed), but she
                # said what it stands on and the map knows it: look there before saying "could not find".
                res = await self._look_on_named(wanted, obj, cause) or res
            if res.kind == "none" and (wanted.type or wanted.name):
                # Nothing found: before saying so, bring the rest of the search area (round her, or round where her
                # ray comes down) into view, what lay beyond the pan-tilt's reach (turn the base) or too close under
                # the camera (back off): generated tour 9100-00, a bag 0.7 m beside-behind the robot.
                res = await self._cover_area(wanted, cause, pointing) or res
            pose = self.pose
            assert pose is not None
            if res.kind == "none":
                self._not_found(res.reason, cause)
                return
            chosen = await self._choose(res, obj, wanted, pose, cause, pointing)
            if chosen is not None and chosen.two:
                # Two things the camera saw there but could not tell apart (one behind the other on
                # its line of sight, closer in depth than it resolves): its position lies between
                # them. Look from another side, where they stand apart, before storing either.
                stood = (pose[0], pose[1])
                if await self._move_to_see_spot((chosen.x, chosen.y, chosen.z), cause, apart_from=stood):
                    again = await self._look(wanted, pointing, cause)
                    if again.kind != "none":
                        pose = self.pose
                        assert pose is not None
                        chosen = await self._choose(again, obj, wanted, pose, cause, pointing)
                if chosen is not None and chosen.two:
                    # No place to see them apart from, or still two from there: never store the point
                    # between them (issue 26 item 5, review17 F2): ask which one she means, the front
                    # or the back one, and with no answer (or no two to offer) it did not find it.
                    parts = list(chosen.parts)
                    chosen = await self._ask(parts, wanted, pose, cause, pointing) if len(parts) == 2 else None
            if chosen is None:
                self._not_found("unclear", cause)
                return
            if self._answer_owner and not wanted.owner:
                wanted = dataclasses.replace(wanted, owner=self._answer_owner)
            self._recognized(chosen, wanted, obj, cause)
        finally:
            self._looking = False
            if token == self._finds:  # not a search cancelled by the next one (that one listens on)
                self._listen(False)

    async def _choose(self, res: Resolution, obj: etree._Element | None, wanted: Wanted, pose: tuple[float, float, float], cause: str,
                      pointing: Pointing | None) -> Candidate | None:
        """The candidate a resolution (not ``none``) singles out: its best, or among several that fit
        alike the one her words place (:meth:`_said_where`), else the one she chooses when asked
        (None: she did not choose)."""
        if res.kind != "ambiguous":
            return res.best
        chosen = self._said_where(res.fitting(), obj)
        if chosen is None:
            chosen = await self._ask(res.fitting()[:3], wanted, pose, cause, pointing)
        return chosen

    async def _step_aside_and_look(self, res: Resolution, wanted: Wanted, pointing: Pointing | None, cause: str) -> tuple[Resolution, Pointing | None]:
        """Ask her to step aside (through the ES), wait until she has, and look again at where she
        points then (her new gesture, else the old one). The resolution (``res`` as it was when she was
        not asked or did not step aside) and the pointing to go on with."""
        since, stood = self.now, self._partner_map()
        if await self._ask_step_aside(cause):
            self._asked_where = (since, stood)
            if await self._wait_partner_clear(pointing, stood):
                res, pointing = await self._look_after_aside(wanted, pointing, cause, since, stood)
        return res, pointing

    async def _look_after_aside(self, wanted: Wanted, pointing: Pointing | None, cause: str,
                                since: float, stood: tuple[float, float] | None = None) -> tuple[Resolution, Pointing | None]:
        """She has stepped aside (asked at ``since``, standing at ``stood``): first (unless her ray shows a spot out of
        the camera's range) until she has got where she steps to (:meth:`_until_still`: her track moving, then standing, bounded), then her gesture since the question (else
        ``pointing``); look where it points, and with no gesture at all round her where she stands now (the camera
        followed her: ahead is no longer where she stood). The time the look counts begins once she stands (fresh12
        kink_long_tour: with her old ray the robot looked at once, as she walked, and said "could not find" while she
        stepped aside, defect J). A ray out of the camera's range goes on at once: the robot drives to see where it
        comes down, planned while she still walks off its way (perceive/study_far_behind_user: waiting, the base
        turned after her and no drive was found)."""
        if pointing is None or not self._out_of_range(pointing):
            await self._until_still(stood)
        waited = 0.0
        while self.gestures.pointing(self.now, since=since) is None and waited < self.gesture_wait:
            await asyncio.sleep(0.1)
            waited += 0.1
        pointing = self.gestures.pointing(self.now, since=since) or pointing
        res = await self._look(wanted, pointing, cause)
        if res.kind == "none" and pointing is None:
            res = await self._search_near_partner(wanted, cause) or res
        return res, pointing

    async def _until_still(self, stood: tuple[float, float] | None = None) -> None:
        """Wait (at most ``STILL_WAIT`` s) until the partner stands: she moved less than ``STEP_ASIDE_START``
        / 5 in the last 0.5 s (she points again once she has got where she steps to), and, when known where she stood
        when asked (``stood``), only once she has moved ``STEP_ASIDE_START`` from there (her step, then her stand)."""
        waited, last = 0.0, self._partner_map()
        while waited < STILL_WAIT:
            await asyncio.sleep(0.5)
            waited += 0.5
            here = self._partner_map()
            if here is None or last is None:
                return
            stepped = stood is None or math.hypot(here[0] - stood[0], here[1] - stood[1]) >= STEP_ASIDE_START
            if stepped and math.hypot(here[0] - last[0], here[1] - last[1]) < STEP_ASIDE_START / 5:
                return
            last = here

    def _lookalike_hidden(self, res: Resolution, pointing: Pointing | None) -> bool:
        """A fitting candidate of ``res`` stands just beside the strip the partner's body hides from the
        camera (:func:`beside_her_shadow`), and she may hide what she means: no gesture of hers was seen,
        or her ray comes down in that strip and none of them stands on it (:func:`on_her_ray`: the camera saw
        the thing where she points, over or beside her: tests/scenarios/lang_names, his mug on the desk behind him
        1 deg off his ray, was doubted and the robot drove round him)."""
        pose, her = self.pose, self._partner_map()
        if pose is None or her is None:
            return False
        if pointing is not None and (self._out_of_range(pointing) or not self._partner_in_the_way(pointing)
                                     or any(on_her_ray(pointing, (c.x, c.y)) for c in res.fitting())):
            return False
        cam = (pose[0] + CAMERA_OFFSET * math.cos(pose[2]), pose[1] + CAMERA_OFFSET * math.sin(pose[2]))
        return any(beside_her_shadow(cam, her, (c.x, c.y)) for c in res.fitting())

    async def _unhide(self, wanted: Wanted, pointing: Pointing | None, cause: str,
                      found: list[tuple[float, float]]) -> tuple[Resolution, Pointing | None]:
        """Ask her to step aside and, once she has (:meth:`_stepped_off` the things ``found`` beside her), look
        again: where she points then (her new gesture, else the old one), else round her. A ``none``
        resolution when she was not asked or did not step aside."""
        since, stood = self.now, self._partner_map()
        res = Resolution("none", (), "nothing_seen")
        if not await self._ask_step_aside(cause):
            return res, pointing
        self._asked_where = (since, stood)
        if not await self._stepped_off(stood, found):
            return res, pointing
        return await self._look_after_aside(wanted, pointing, cause, since, stood)

    async def _stepped_off(self, stood: tuple[float, float] | None, found: list[tuple[float, float]]) -> bool:
        """Wait (up to ``step_aside_wait`` s) until the partner has moved ``STEP_ASIDE_START`` m from where she
        stood when asked and no longer hides the strip beside the things ``found``; True then (after a moment
        to come to a stop). False when she has not begun to move within ``STEP_ASIDE_STIR`` s or did not clear it.
        Her own movement is the evidence, not her bearing (the base may turn meanwhile)."""
        waited = 0.0
        while waited < self.step_aside_wait and stood is not None:
            pose, here = self.pose, self._partner_map()
            if pose is not None and here is not None:
                moved = math.hypot(here[0] - stood[0], here[1] - stood[1])
                cam = (pose[0] + CAMERA_OFFSET * math.cos(pose[2]), pose[1] + CAMERA_OFFSET * math.sin(pose[2]))
                if moved >= STEP_ASIDE_START and not any(beside_her_shadow(cam, here, f) for f in found):
                    await asyncio.sleep(0.5)  # and come to a stop
                    return True
                if waited >= STEP_ASIDE_STIR and moved < STEP_ASIDE_START:
                    return False
            await asyncio.sleep(0.2)
            waited += 0.2
        return False

    def _listen(self, on: bool) -> None:
        """Follow the people's tracks and the player's status from when a search considers moving
        until it ends, and only then (every delivery draws a network delay from the run's
        generator: a subscription held longer would change every run with object teaching)."""
        if on and not self._subs:
            self._subs = [self.bus.subscribe(TRACKS, self._on_tracks), self.bus.subscribe(PLAYER_STATUS, self._on_player)]
        elif not on:
            for sub in self._subs:
                sub.close()
            self._subs = []
            self._people = None

    async def _listening(self) -> bool:
        """Start following the people around and the player's status (:meth:`_listen`) if this search has not yet,
        and give the first tracks 0.3 s to come in. True when it started them now (the pose may have moved on)."""
        if self._subs:
            return False
        self._listen(True)
        await asyncio.sleep(0.3)
        return True

    async def _look(self, wanted: Wanted, pointing: Pointing | None, cause: str, spot: tuple[float, float, float] | None = None,
                    on: str | None = None, near: tuple[float, float, float] | None = None) -> Resolution:
        """Look where she points for ``look_time`` s, merge the detections, resolve the reference.
        ``spot``: where to look without a gesture; ``on``: only what stands on that furniture counts."""
        self._seen, self._frames, self._rays = [], [], []
        self._looking = True
        fallback = self._target_3d(pointing) if pointing is not None else spot
        t_end = self.now + self.look_time
        latest = t_end + TURN_TO_LOOK
        while self.now < t_end - 1e-9:
            self._publish_focus(cause, fallback)
            if self.now >= t_end - self.look_time + VIEW_SETTLE:
                self._viewed(self._focus_bearing)
            if abs(self._focus_bearing) > PAN_LIMIT and t_end < latest:
                # beyond the pan-tilt unit's reach (she points behind the robot): the person attention
                # turns the base towards it; the look begins when the camera can get there
                t_end = min(latest, self.now + self.look_time)
            await asyncio.sleep(0.2)
        self._looking = False
        pose = self.pose
        assert pose is not None
        cands = merge(one_surface(self._seen, self._rays), (pose[0], pose[1]), eye_height=CAMERA_HEIGHT, frames=self._frames)
        if on is not None:
            cands = [c for c in cands if self._on_furniture(c, on)]
        if near is not None:  # only what stands within near[2] m of (near[0], near[1]) counts (the search area round her)
            cands = [c for c in cands if math.hypot(c.x - near[0], c.y - near[1]) <= near[2]]
        res = without_glimpses(resolve(cands, wanted, pointing, (pose[0], pose[1])), cands, wanted, pointing, (pose[0], pose[1]))
        self.last = res
        return res

    def _named_spot(self, obj: etree._Element | None) -> tuple[float, float, float] | None:
        """The middle of the top of the one piece of furniture of the floor plan her request names as where
        the thing is ("my vase on the sideboard": ``POSITION/TITLE``), a little above it; None when she named
        none, or the plan has none or several of that name or type."""
        ground = obj.find("POSITION/TITLE") if obj is not None else None
        if ground is None or self.plan is None:
            return None
        w = ground.get("name", "").lower().replace("_", " ")
        if not w:
            return None
        hits = [o for o in self.plan.obstacles if o.type != "leg" and 0.0 < o.top < PERSON_TOP
                and (o.name.lower() == w or o.type.lower() == w or w in o.name.lower().split())]
        if len(hits) != 1:
            return None
        pts = hits[0].points
        return sum(x for x, _ in pts) / len(pts), sum(y for _, y in pts) / len(pts), hits[0].top + 0.05

    def _partner_before(self, spot: tuple[float, float, float]) -> bool:
        """The partner stands between the camera and ``spot`` (within ``BODY_HALF_WIDTH`` + 0.3 m of the
        sight line, nearer than the spot)."""
        pose, her = self.pose, self._partner_map()
        if pose is None or her is None:
            return False
        dx, dy = spot[0] - pose[0], spot[1] - pose[1]
        length = math.hypot(dx, dy)
        if length < 1e-6:
            return False
        along = ((her[0] - pose[0]) * dx + (her[1] - pose[1]) * dy) / length
        across = abs((her[0] - pose[0]) * dy - (her[1] - pose[1]) * dx) / length
        return 0.0 < along < length - 0.2 and across <= BODY_HALF_WIDTH + 0.3

    async def _look_on_named(self, wanted: Wanted, obj: etree._Element | None, cause: str) -> Resolution | None:
        """Look for what she named on the furniture she named (:meth:`_named_spot`), driving first to a place
        that sees it when the camera cannot from here (too far, or she or something else in the way). Only
        what stands on that furniture counts. None when there is no such spot or nothing was named."""
        spot = self._named_spot(obj)
        if spot is None or self.pose is None or not (wanted.type or wanted.name):
            return None
        await self._listening()
        pose = self.pose
        cam = (pose[0] + CAMERA_OFFSET * math.cos(pose[2]), pose[1] + CAMERA_OFFSET * math.sin(pose[2]), CAMERA_HEIGHT)
        if self.plan is not None and (not in_range(cam, spot) or not sight_clear(self.plan, cam, spot, self._people_map(pose))):
            moved = await self._move_to_see_spot(spot, cause)
            if not moved and self._partner_before(spot) and not self._asked_in_vain():
                # no place to see it from while she stands between the robot and that furniture (fresh6
                # div_long_tour: Hanna 0.9 m ahead on the line to the sideboard 4 m away): ask her to step
                # aside, then drive (she no longer blocks the ways and places)
                since, stood = self.now, self._partner_map()
                if await self._ask_step_aside(cause):
                    self._asked_where = (since, stood)
                    await self._wait_partner_clear(None, stood)
                    await self._move_to_see_spot(spot, cause)
        ground = obj.find("POSITION/TITLE") if obj is not None else None
        return await self._look(wanted, None, cause, spot=spot, on=ground.get("name", "") if ground is not None else None)

    async def _search_near_partner(self, wanted: Wanted, cause: str) -> Resolution | None:
        """Look to either side of the partner (``SEARCH_OFFSETS`` off her bearing, ``SEARCH_LOOK`` s
        each) and resolve what she named among the objects within ``SEARCH_RADIUS`` of her, by
        type, name and colour alone (nearer to her preferred); two that fit alike: ask. Nothing
        found there: further round, beside and behind the robot (``SEARCH_OFFSETS_WIDE``, within
        ``SEARCH_RADIUS_WIDE`` of her). None when
        there is no partner to search around or nothing was named (an unnamed "this" needs the
        gesture)."""
        p, pose = self._partner, self.pose
        if p is None or pose is None or self.now - p[0] > 1.0 or not (wanted.type or wanted.name):
            return None
        _, pb, pd = p
        px, py = pose[0] + pd * math.cos(pose[2] + pb), pose[1] + pd * math.sin(pose[2] + pb)
        self._seen, self._frames, self._rays = [], [], []
        pan = max(-PAN_LIMIT, min(PAN_LIMIT, pb))  # the camera is on her hands

        async def look(off: float) -> None:
            nonlocal pan
            to = max(-PAN_LIMIT, min(PAN_LIMIT, pb + off))
            t_end = self.now + SEARCH_LOOK + abs(to - pan) / PAN_SPEED
            pan = to
            self._looking = True
            try:
                while self.now < t_end - 1e-9:
                    self.bus.publish(FOCUS, etree.Element("focus", bearing=f"{math.degrees(pb + off):.2f}", distance=f"{max(0.8, pd):.3f}"), causes=(cause,))
                    if self.now >= t_end - SEARCH_LOOK + VIEW_SETTLE:
                        self._viewed(pb + off)
                    await asyncio.sleep(0.2)
            finally:
                self._looking = False

        def found(radius: float) -> Resolution:
            pose = self.pose
            assert pose is not None
            merged = merge(one_surface(self._seen, self._rays), (pose[0], pose[1]), eye_height=CAMERA_HEIGHT, frames=self._frames)
            res = resolve_near(merged, wanted, (px, py), radius)
            self.last = res
            return res

        self._tell_acting("round", cause)  # a silent search of 6 s or more looks like no answer (look24)
        for off in SEARCH_OFFSETS:
            await look(off)
        res = found(SEARCH_RADIUS)
        # the nearer side first, and done as soon as it is found there
        for off in sorted(SEARCH_OFFSETS_WIDE, key=lambda o: abs(max(-PAN_LIMIT, min(PAN_LIMIT, pb + o)) - pan)):
            if res.kind != "none":
                break
            await look(off)
            res = found(SEARCH_RADIUS_WIDE)
        return res

    def _viewed(self, bearing: float) -> None:
        """Note where the camera looks now: ``bearing`` (robot frame) as far as the pan-tilt unit reaches."""
        pose = self.pose
        if pose is None:
            return
        b = pose[2] + max(-PAN_LIMIT, min(PAN_LIMIT, bearing))
        cam = (pose[0] + CAMERA_OFFSET * math.cos(pose[2]), pose[1] + CAMERA_OFFSET * math.sin(pose[2]))
        self._views[(round(cam[0], 2), round(cam[1], 2), round(math.remainder(b, 2 * math.pi), 2))] = None

    def unseen(self, centre: tuple[float, float], radius: float) -> list[tuple[float, float, float]]:
        """The spots of the search area (:func:`search_area`, ``radius`` m round ``centre``) no view of this
        search has had in the camera's image and range (:func:`sees`; the people as they stand now)."""
        pose = self.pose
        if pose is None or self.plan is None:
            return []
        people = self._people_map(pose)
        views = [((x, y, CAMERA_HEIGHT), b) for x, y, b in self._views]
        return [s for s in search_area(self.plan, centre, radius) if not any(sees(self.plan, cam, b, s, people) for cam, b in views)]

    async def _cover_area(self, wanted: Wanted, cause: str, pointing: Pointing | None = None) -> Resolution | None:
        """Bring the part of the search area, ``SEARCH_RADIUS`` round her, or with a gesture ``COVER_RAY`` round where
        her ray shows an object (:meth:`_target_3d`), that no look of this search had in view into
        view (:func:`cover_views`: turned on the spot, or a short straight move that takes it nearer to no
        one) and look there, each view through the ES like a drive to a viewpoint (event ``view_blocked``, one leg,
        turned to the view); done when what she named is found within that radius (resolved against her ray, if any).
        None: no partner, no plan, nothing left unseen that a pose in reach sees, or nothing found."""
        her, pose = self._partner_map(), self.pose
        radius = SEARCH_RADIUS
        if pointing is not None:
            target = self._target_3d(pointing)
            her, radius = (None, radius) if target is None else ((target[0], target[1]), COVER_RAY)
        if her is None or pose is None or self.plan is None:
            return None
        if await self._listening():
            pose = self.pose
            assert pose is not None
        unseen = self.unseen(her, radius)
        views = cover_views(self.plan, pose, unseen, self._people_map(pose), camera_height=CAMERA_HEIGHT, camera_offset=CAMERA_OFFSET)
        res: Resolution | None = None
        for x, y, b, got in views:
            pose = self.pose
            assert pose is not None
            if math.hypot(x - pose[0], y - pose[1]) > ARRIVE_TOLERANCE / 2 or abs(math.remainder(b - pose[2], 2 * math.pi)) > PAN_LIMIT:
                self.moves += 1
                state = await self._drive_leg((x, y, b), True, cause)
                if state == "failed":
                    self.bus.publish(ES_EVENTS, etree.Element("event", name="view_stop"), causes=(cause,))
                    await asyncio.sleep(0.5)
                    continue
            n = len(got)
            spot = (sum(unseen[i][0] for i in got) / n, sum(unseen[i][1] for i in got) / n, sum(unseen[i][2] for i in got) / n)
            res = await self._look(wanted, pointing, cause, spot=spot, near=(her[0], her[1], radius))
            if res.kind != "none":
                return res
        return res

    def _people_map(self, pose: tuple[float, float, float]) -> list[tuple[float, float]]:
        """Where the people the person attention tracks stand (map frame, from their fresh bearing
        and distance), the partner among them."""
        out = []
        if self._people is not None and self.now - self._people[0] < 1.0:
            out = [(pose[0] + d * math.cos(pose[2] + b), pose[1] + d * math.sin(pose[2] + b)) for b, d in self._people[1]]
        p = self._partner
        if p is not None and self.now - p[0] < 1.0:
            out.append((pose[0] + p[2] * math.cos(pose[2] + p[1]), pose[1] + p[2] * math.sin(pose[2] + p[1])))
        return out

    def _target_3d(self, pointing: Pointing) -> tuple[float, float, float] | None:
        """Where the ray most likely shows an object (:func:`pointed_spot`: the last stretch of it
        low over a surface before the ray ends), else where it comes down (:meth:`_ray_target`), with the height of
        what it stands on."""
        if self.plan is not None:
            spot = pointed_spot(self.plan, (pointing.x, pointing.y, pointing.z), pointing.direction, pointing.elevation)
            if spot is not None:
                return spot
        t = self._ray_target(pointing)
        if t is None:
            return None
        return t[0], t[1], self._top_under(t[0], t[1], CAMERA_HEIGHT) + 0.05

    def view_blocked(self, pointing: Pointing) -> bool:
        """Whether the camera, from where the robot stands, cannot see where ``pointing`` comes
        down: out of its range, or a wall, furniture (the floor plan) or a person in the way."""
        pose, target = self.pose, self._target_3d(pointing)
        if pose is None or target is None or self.plan is None:
            return False
        cam = (pose[0] + CAMERA_OFFSET * math.cos(pose[2]), pose[1] + CAMERA_OFFSET * math.sin(pose[2]), CAMERA_HEIGHT)
        return not in_range(cam, target) or not sight_clear(self.plan, cam, target, self._people_map(pose))

    async def _move_to_see(self, pointing: Pointing, cause: str) -> bool:
        """Drive to a place from which the camera sees where she points (:func:`viewpoint`), through
        the ES (event ``view_blocked`` with the ``POSE``; the ES orders the player ``move_to``), and
        wait until the player has arrived (or is blocked, or ``MOVE_TIMEOUT`` s passed: the ES is
        asked to stop it, event ``view_stop``). False when the view is not blocked or there is no
        such place."""
        target = self._target_3d(pointing)
        if target is None or self.pose is None or self.plan is None:
            return False
        await self._listening()
        if not self.view_blocked(pointing):
            return False
        # her aim (AIM_SIGMA) over the way from her hand to the spot: how far beside it the thing may stand
        spread = math.hypot(target[0] - pointing.x, target[1] - pointing.y) * math.tan(AIM_SIGMA)
        return await self._move_to_see_spot(target, cause, spread=spread)

    def _tell_acting(self, how: str, cause: str) -> None:
        """Tell the ES, once per search, that the robot acts to find what she showed (event ``moving_to_see``,
        ``how`` = ``drive``: to a viewpoint, ``round``: looks round her); in ObjectTeaching the dialog says so. Only
        the first such act of a search is told: one sentence, never one per viewpoint."""
        if self._told_moving:
            return
        self._told_moving = True
        self.bus.publish(ES_EVENTS, etree.Element("event", name="moving_to_see", how=how), causes=(cause,))

    def _partner_map(self) -> tuple[float, float] | None:
        """Where the partner stands (map frame), if the person attention reported her lately."""
        pose, p = self.pose, self._partner
        if pose is None or p is None or self.now - p[0] > 1.0:
            return None
        return pose[0] + p[2] * math.cos(pose[2] + p[1]), pose[1] + p[2] * math.sin(pose[2] + p[1])

    def _partner_far(self) -> bool:
        """She stands farther than the camera sees a hand or an object near her well."""
        p = self._partner
        return p is not None and self.now - p[0] <= 1.0 and p[2] > PARTNER_FAR

    async def _move_to_see_spot(self, target: tuple[float, float, float], cause: str, apart_from: tuple[float, float] | None = None,
                                spread: float = 0.0) -> bool:
        """Drive to the nearest place from which the camera sees ``target`` (see :meth:`_move_to_see`);
        with ``apart_from``, one that sees it from another side than from there (:func:`viewpoint`)."""
        if self.pose is None or self.plan is None:
            return False
        await self._listening()
        pose = self.pose
        assert pose is not None
        people = self._people_map(pose)
        # A place one straight leg away first (the player's own leg, the surest drive); only when there
        # is none, one round a corner (legs through waypoints).
        one = viewpoint(self.plan, (pose[0], pose[1]), target, people, camera_height=CAMERA_HEIGHT, camera_offset=CAMERA_OFFSET, apart_from=apart_from,
                        spread=spread)
        route = [one] if one is not None else viewpoint_route(self.plan, (pose[0], pose[1]), target, people, camera_height=CAMERA_HEIGHT,
                                                              camera_offset=CAMERA_OFFSET, apart_from=apart_from, spread=spread)
        if route is None:
            return False
        self.moves += 1
        # A robot that drives off silently after "Let me have a look." looks to her like no answer (gen24:
        # 9700-10 gave the tour up, 9700-16 rephrased vaguely during an 8-10 s drive)
        self._tell_acting("drive", cause)
        for k, goal in enumerate(route):
            state = await self._drive_leg(goal, k == len(route) - 1, cause)
            if state == "stopped":  # the ES stopped the base: no further leg
                return True
            if state != "reached":
                self.bus.publish(ES_EVENTS, etree.Element("event", name="view_stop"), causes=(cause,))
                await asyncio.sleep(0.5)
                return True
        await asyncio.sleep(0.5)  # let the camera settle on the spot
        return True

    async def _drive_leg(self, goal: tuple[float, float, float], last: bool, cause: str) -> str:
        """One straight leg of the drive to a viewpoint, through the ES (event ``view_blocked`` with
        the ``POSE``; the ES orders the player ``move_to``): a waypoint on the way round a corner
        (``last`` False: no turn on the spot there), or the viewpoint itself, turned towards the
        target. ``reached`` or ``stopped`` as the player reports it; ``failed`` when it has not
        arrived within ``MOVE_TIMEOUT`` s or has been blocked for ``MOVE_BLOCKED`` s standing (moved less than
        ``MOVE_STILL`` m: the player's own way out, a back-off and on again, is no blockage; view_round_corner
        seed 8: blocked at a bookcase's end, it stood 1 s, backed off 3 s and had just driven on when the look
        gave the leg up, 4 s after "blocked")."""
        ev = etree.Element("event", name="view_blocked")
        etree.SubElement(ev, "POSE", x=f"{goal[0]:.3f}", y=f"{goal[1]:.3f}", theta=f"{goal[2]:.4f}", frame="map",
                         tolerance=f"{ARRIVE_TOLERANCE:g}", align="true" if last else "false")
        sent = self.now
        self._player = None
        self.bus.publish(ES_EVENTS, ev, causes=(cause,))
        blocked_since: float | None = None
        still_at: tuple[float, float, float] | None = None  # where it stood when the blockage (re)started
        while self.now - sent < MOVE_TIMEOUT:
            await asyncio.sleep(0.2)
            st = self._player
            if st is None or st[1] < sent:
                continue
            if st[0] in ("reached", "stopped"):
                return st[0]
            if st[0] == "blocked":
                if blocked_since is None:
                    blocked_since, still_at = st[1], self.pose
                elif (still_at is not None and self.pose is not None
                      and math.hypot(self.pose[0] - still_at[0], self.pose[1] - still_at[1]) >= MOVE_STILL):
                    blocked_since, still_at = self.now, self.pose  # it moves (its own way out): not blocked standing
                if self.now - blocked_since >= MOVE_BLOCKED:
                    return "failed"
            else:
                blocked_since = None
        return "failed"

    def _on_tracks(self, msg: Message) -> None:
        people = []
        for tr in msg.xml.iterfind("track"):
            if tr.get("confirmed") == "true":
                people.append((math.radians(float(tr.get("bearing"))), float(tr.get("distance"))))  # type: ignore[arg-type]
        self._people = (msg.created, people)

    def _on_player(self, msg: Message) -> None:
        state = msg.xml.get("state")
        if state:
            self._player = (state, msg.created)

    def _top_under(self, x: float, y: float, below: float) -> float:
        """The height of the highest piece of the plan's furniture lower than ``below`` whose footprint
        holds (x, y), else the floor (0): what a pointed-at object there stands on."""
        top = 0.0
        if self.plan is not None:
            for o in self.plan.obstacles:
                if o.type != "leg" and o.top < below and _inside(x, y, o.points):
                    top = max(top, o.top)
        return top

    def _landing(self, pointing: Pointing) -> tuple[float, float, float] | None:
        """Where the ray first comes down on a surface (:meth:`_ray_target`, with that surface's height):
        what she may stand in front of, and how far the camera must see. A ray that does not come down
        (she points up, at a book on a tall shelf): where it shows an object (:meth:`_target_3d`)."""
        if pointing.elevation >= -math.radians(3):
            return self._target_3d(pointing)
        t = self._ray_target(pointing)
        if t is None:
            return None
        return t[0], t[1], self._top_under(t[0], t[1], pointing.z) + 0.05

    def _out_of_range(self, pointing: Pointing) -> bool:
        """Where ``pointing`` comes down (:meth:`_landing`) lies beyond the camera's reliable object range from here."""
        pose, target = self.pose, self._landing(pointing)
        if pose is None or target is None:
            return False
        cam = (pose[0] + CAMERA_OFFSET * math.cos(pose[2]), pose[1] + CAMERA_OFFSET * math.sin(pose[2]), CAMERA_HEIGHT)
        return math.dist(cam, target) > CAMERA_RANGE[1]

    def _in_the_way(self, bearing: float, distance: float, pointing: Pointing) -> bool:
        """Whether a person at ``bearing``/``distance`` (robot frame) hides where ``pointing`` shows an
        object (her body, ``BODY_HALF_WIDTH`` either side and up to ``PERSON_TOP``, nearer to the camera
        than that spot): the sight line to a book on top of a tall shelf passes over her head."""
        pose = self.pose
        target = self._landing(pointing)
        if pose is None or target is None:
            return False
        dx, dy = target[0] - pose[0], target[1] - pose[1]
        t_dist = math.hypot(dx, dy)
        t_bearing = math.remainder(math.atan2(dy, dx) - pose[2], 2 * math.pi)
        if distance >= t_dist - 0.1:
            return False
        if CAMERA_HEIGHT + (target[2] - CAMERA_HEIGHT) * distance / max(t_dist, 1e-6) > PERSON_TOP:
            return False  # the sight line passes over her head
        return abs(math.remainder(bearing - t_bearing, 2 * math.pi)) <= math.atan2(BODY_HALF_WIDTH, max(distance, 0.3))

    def _partner_in_the_way(self, pointing: Pointing) -> bool:
        """The pointing person hides the spot: the partner where the person attention has her, or
        without it, where the camera saw her hand."""
        pose = self.pose
        if pose is None:
            return False
        p = self._partner
        if p is not None and self.now - p[0] < 0.5:
            return self._in_the_way(p[1], p[2], pointing)
        dx, dy = pointing.x - pose[0], pointing.y - pose[1]
        return self._in_the_way(math.remainder(math.atan2(dy, dx) - pose[2], 2 * math.pi), math.hypot(dx, dy), pointing)

    def _ray_target(self, p: Pointing) -> tuple[float, float] | None:
        """Where a pointing ray first comes down onto a piece of furniture (its top, from the floor
        plan) or the floor, within ``POINT_REACH`` (5 m) of the hand; 1 m along it if it does not come down."""
        if p.elevation >= -math.radians(3):
            return p.x + math.cos(p.direction), p.y + math.sin(p.direction)
        tops = sorted({o.top for o in self.plan.obstacles if o.type != "leg" and 0.0 < o.top < p.z} if self.plan else set(), reverse=True)
        for h in [*tops, 0.0]:
            reach = (p.z - h) / math.tan(-p.elevation)
            if reach > POINT_REACH:
                break
            x, y = p.x + reach * math.cos(p.direction), p.y + reach * math.sin(p.direction)
            if h == 0.0 or any(abs(o.top - h) < 1e-9 and _inside(x, y, o.points) for o in self.plan.obstacles):  # type: ignore[union-attr]
                return x, y
        return p.x + math.cos(p.direction), p.y + math.sin(p.direction)

    async def _ask_step_aside(self, cause: str) -> bool:
        """Ask the partner to step aside, through the ES (the papers' control flow): the event
        ``occluded`` becomes the dialog's condition ``step_aside``; once the question has been said
        the dialog's answer comes back as the order ``asked_aside`` (param ``said``). False if it
        was not said within ``STEP_ASIDE_ASK`` s (no dialog, or the ES rejected the event)."""
        fut: asyncio.Future[bool] = self.sim.loop.create_future()
        self._asked_aside = fut
        self.bus.publish(ES_EVENTS, etree.Element("event", name="occluded"), causes=(cause,), transfer=True)
        try:
            async with asyncio.timeout(STEP_ASIDE_ASK):
                return await fut
        except TimeoutError:
            return False
        finally:
            self._asked_aside = None

    def _asked_in_vain(self) -> bool:
        """She was asked to step aside within ``STEP_ASIDE_AGAIN`` s and still stands where she
        stood then: asking the same again would loop (she repeats her request, the robot its
        question); the robot moves to see instead."""
        if self._asked_where is None:
            return False
        t, where = self._asked_where
        here = self._partner_map()
        return (self.now - t <= STEP_ASIDE_AGAIN and where is not None and here is not None
                and math.hypot(here[0] - where[0], here[1] - where[1]) < STEP_ASIDE_START)

    def _partner_in_view(self) -> bool:
        """No pointing seen and nothing found, with the partner standing in front of the camera:
        her body may hide both her hand and what she shows."""
        p = self._partner
        return p is not None and self.now - p[0] < 0.5 and abs(p[1]) <= VIEW_HALF_WIDTH and p[2] <= 3.0

    async def _wait_partner_clear(self, pointing: Pointing | None, stood: tuple[float, float] | None = None) -> bool:
        """Wait (up to ``step_aside_wait`` s) until the partner no longer stands in the way; True
        when she has stepped aside. She may not have heard or may not want to: when she has not
        begun to move (``STEP_ASIDE_START`` m) within ``STEP_ASIDE_STIR`` s, waiting longer is
        pointless (False: the robot moves to see instead)."""
        waited = 0.0
        # where she stood when the robot chose to ask (the question may be said seconds later, after
        # another sentence, and she may have stepped aside as soon as she heard it)
        start = stood if stood is not None else self._partner_map()
        while waited < self.step_aside_wait:
            p, here = self._partner, self._partner_map()
            # no gesture to go by: she is off the camera's axis, or has stepped her body's width away from where
            # she stood (the person attention turns the base after her, so her bearing may stay small)
            away = here is not None and start is not None and math.hypot(here[0] - start[0], here[1] - start[1]) >= 2 * BODY_HALF_WIDTH
            if p is not None and self.now - p[0] < 0.5 and (
                    not self._in_the_way(p[1], p[2], pointing) if pointing is not None else (abs(p[1]) > math.radians(10.0) or away)):
                await asyncio.sleep(0.5)  # and come to a stop
                return True
            if waited >= STEP_ASIDE_STIR and start is not None:
                here = self._partner_map()
                if here is not None and math.hypot(here[0] - start[0], here[1] - start[1]) < STEP_ASIDE_START:
                    return False
            await asyncio.sleep(0.2)
            waited += 0.2
        return False

    def _gesture_start(self, said: float | None) -> float | None:
        """Where to look back for the gesture that went with the request: from ``GESTURE_LEAD`` s
        before the sentence began (``said``, from the order's ``TIMESTAMP``), if it began within
        ``SENTENCE_RECENT`` s (she points, then speaks: by the time the request is understood and
        reaches this module the arm is down again); None: the gesture tracker's own window."""
        if said is None or math.isnan(said) or self.now - said > SENTENCE_RECENT:
            return None
        return said - GESTURE_LEAD

    def _on_partner(self, msg: Message) -> None:
        x = msg.xml
        self._partner = (msg.created, math.radians(float(x.get("bearing"))), float(x.get("distance")))  # type: ignore[arg-type]

    def _publish_focus(self, cause: str, fallback: tuple[float, float, float] | None = None) -> None:
        """Where the camera looks: where the pointing seen now comes down, else ``fallback`` (where
        an earlier pointing came down, with the height of what it stands on: she pointed, then
        stepped aside), else ahead and down. The region's height goes with it when known, so the
        camera tilts down to the floor for what lies there (not to a table top's height)."""
        pose = self.pose
        assert pose is not None
        target = self.gestures.target(self.now) or fallback
        el = etree.Element("focus")
        if target is None:  # no gesture: look ahead and down, at a table in front of the robot
            bearing, dist = 0.0, 1.2
        else:
            dx, dy = target[0] - pose[0], target[1] - pose[1]
            bearing = math.remainder(math.atan2(dy, dx) - pose[2], 2 * math.pi)
            dist = max(0.3, math.hypot(dx, dy) - CAMERA_OFFSET)
        self._focus_bearing = bearing
        el.set("bearing", f"{math.degrees(bearing):.2f}")
        el.set("distance", f"{dist:.3f}")
        if target is not None and abs(target[2] - TABLE_HEIGHT) > HEIGHT_OFF:
            # far from the table height the person attention assumes: the floor, a high shelf
            el.set("height", f"{min(3.0, max(0.0, target[2])):.2f}")
        self.bus.publish(FOCUS, el, causes=(cause,))

    async def _ask(self, cands: list[Candidate], wanted: Wanted, pose: tuple[float, float, float], cause: str,
                   first: Pointing | None = None) -> Candidate | None:
        """Ask the partner which candidate they mean, through the ES (the papers' control flow):
        the event ``clarification`` (``<OPTIONS timeout><option index text/>+</OPTIONS>``) becomes the
        dialog's condition ``ask``; the dialog's answer comes back as the order ``clarified``
        (``<ANSWER index/>`` or ``none``). No answer within 2 ``ask_timeout`` + 20 s: None. The
        dialog gives her ``ask_timeout`` s (15) after the question to answer: room for one misheard
        answer and the question again, and a gesture before the words ("this one")."""
        depth = along_ray(cands, first)
        if depth is not None:  # one behind the other along her arm: asked from the front one back
            cands = [cands[i] for i in depth]
        for n in range(MAX_ASKINGS):
            asked = self.now
            answer = await self._put(cands, wanted, pose, cause, first, again=n > 0)
            if answer is None:
                return None
            chosen = await self._chosen(answer, cands, wanted, pose, asked, first)
            if chosen is None and answer.get("deixis") != "true":
                # her words picked none (misheard, or "the one on the table" with both on it), but she may have
                # pointed as she answered: what the camera saw since the question decides when it singles one out
                chosen = self._pointed_since(cands, asked, first)
            if chosen is not None and not wanted.owner and answer.find("OWNER") is not None:
                # her answer said whose it is ("this red book is mine" again, pointing), her request did not
                self._answer_owner = wanted_from(answer).owner
            if chosen is not None or not _answered_none_of_them(answer):
                return chosen
            # "the one on the table" with both on the table (perceive/cups_on_table seed 5): an answer that
            # picks none of the options she was asked about; asked again, not taken as "not found"
        return None

    async def _put(self, cands: list[Candidate], wanted: Wanted, pose: tuple[float, float, float], cause: str,
                   first: Pointing | None, again: bool = False) -> etree._Element | None:
        """Put the question once (:meth:`_ask`): the dialog's ``ANSWER``, or None when none came in time.
        ``again``: the second putting (``OPTIONS again="true"``): the dialog counts it with the first's
        askings, so its own re-ask never makes it a third."""
        texts = option_texts(cands, wanted, pose, first)
        opts = etree.Element("OPTIONS", timeout=f"{self.ask_timeout:g}")
        if again:
            opts.set("again", "true")
        for i, t in enumerate(texts):
            etree.SubElement(opts, "option", index=str(i), text=t)
        ev = etree.Element("event", name="clarification")
        ev.append(opts)
        fut: asyncio.Future[etree._Element] = self.sim.loop.create_future()
        self._answer = fut
        self.bus.publish(ES_EVENTS, ev, causes=(cause,), transfer=True)
        watch = self.sim.spawn(self._watch_answer(cands, cause), name=f"{self.name}:watch")
        try:
            # the question itself takes a while to say, and the dialog may ask it twice (an answer it did not understand)
            async with asyncio.timeout(2 * self.ask_timeout + 20.0):
                answer = await fut
        except TimeoutError:  # no dialog, or the ES did not route the question: the partner could not be asked
            return None
        finally:
            self._answer = None
            watch.cancel()
        return answer

    async def _chosen(self, answer: etree._Element, cands: list[Candidate], wanted: Wanted, pose: tuple[float, float, float],
                      asked: float, first: Pointing | None) -> Candidate | None:
        """The candidate the dialog's ``ANSWER`` picks: an option's index, the one on the furniture she
        named, or where she points now ("this one"); None when it picks none."""
        idx = answer.get("index")
        if idx is not None and idx.isdigit() and int(idx) < len(cands) and answer.get("none") != "true":
            return cands[int(idx)]
        on_it = self._said_where(cands, answer)  # "the one on the table": the only candidate standing on it
        if on_it is not None:
            # also when a "that" came with it ("that one on the table", the recogniser's "that" for
            # "the", cups_on_table seed 6): the place she named decides without waiting for a gesture
            return on_it
        if answer.get("deixis") == "true":  # "this one": where she points now
            return await self._pointed_again(cands, wanted, pose, asked, first)
        return None

    async def _watch_answer(self, cands: list[Candidate], cause: str) -> None:
        """While the question waits for its answer, keep the camera where her answer's gesture will
        be ("this one" with pointing): between her and the options asked about, where her hand
        reaches when she points at one of them (at her, when they lie too far apart for one image)."""
        while True:
            pose, p = self.pose, self._partner
            if pose is not None and p is not None and self.now - p[0] < 1.0 and cands:
                mx, my = sum(c.x for c in cands) / len(cands), sum(c.y for c in cands) / len(cands)
                ob = math.remainder(math.atan2(my - pose[1], mx - pose[0]) - pose[2], 2 * math.pi)
                gap = math.remainder(ob - p[1], 2 * math.pi)
                # too far apart for one image: still turned towards them by part of the image, her body kept in it
                # (centred on her, the hand she stretches towards them left the image: fresh7 corr_nonnative_books)
                bearing = p[1] + gap / 2 if abs(gap) < 2 * VIEW_HALF_WIDTH * 0.8 else p[1] + math.copysign(ASK_VIEW_OFF * VIEW_HALF_WIDTH, gap)
                self.bus.publish(FOCUS, etree.Element("focus", bearing=f"{math.degrees(bearing):.2f}", distance=f"{max(0.8, p[2]):.3f}"), causes=(cause,))
            await asyncio.sleep(0.2)

    async def _pointed_again(self, cands: list[Candidate], wanted: Wanted, pose: tuple[float, float, float], since: float,
                             first: Pointing | None = None) -> Candidate | None:
        """"This one" after the question: the asked candidates resolved by the pointing the camera
        saw since the question (waiting up to ``gesture_wait`` s for it) together with ``first``, the
        gesture of the request (all point at the same object: each gesture, the request's and every
        one since the question (:meth:`~robot.objects.gestures.GestureTracker.bouts`), aims with its
        own error, so their likelihoods multiply, :func:`~robot.objects.resolve.choose_pointed`);
        None if they still do not single one out."""
        waited = 0.0
        while waited < self.gesture_wait + 1e-9:
            # since the question, however long ago (she points, then says "this one": by the time
            # the answer has been understood and reached this module her arm may be down again)
            p = self.gestures.pointing(self.now, since=since, start=since)
            if p is not None:
                res = resolve(cands, Wanted(type=wanted.type, name=wanted.name), p, (pose[0], pose[1]))
                self.last = res
                if res.kind == "one":
                    return res.best
                # each time she pointed since the question is its own aim (she may have pointed twice,
                # asked again), and so is the request's gesture
                again = self.gestures.bouts(self.now, since) or [p]
                return choose_pointed(cands, again if first is None else [*again, first])
            await asyncio.sleep(0.1)
            waited += 0.1
        return None

    def _pointed_since(self, cands: list[Candidate], since: float, first: Pointing | None) -> Candidate | None:
        """The candidate her pointing since the question (``since``) singles out, with the request's gesture
        ``first`` (:func:`~robot.objects.resolve.choose_pointed`); None when she did not point since, or her
        gestures do not single one out. No waiting: an answer already given."""
        bouts = self.gestures.bouts(self.now, since)
        if not bouts:
            return None
        return choose_pointed(cands, bouts if first is None else [*bouts, first])

    def _said_where(self, cands: list[Candidate], obj: etree._Element | None) -> Candidate | None:
        """The one candidate standing on the furniture she named with the request ("my cup on the
        table", or "the one on the table" in answer to "Is this your cup?"): no need to ask which one.
        None when she named none, or it does not single one out."""
        ground = obj.find("POSITION/TITLE") if obj is not None else None
        if ground is None:
            return None
        on = [c for c in cands if self._on_furniture(c, ground.get("name", ""))]
        return on[0] if len(on) == 1 else None

    def _on_furniture(self, c: Candidate, word: str) -> bool:
        """Whether a candidate stands on a piece of furniture called or of type ``word`` (the floor plan)."""
        if self.plan is None or not word:
            return False
        w = word.lower().replace("_", " ")
        for o in self.plan.obstacles:
            if o.type != "leg" and (o.name.lower() == w or o.type.lower() == w or w in o.name.lower().split()) and _inside(c.x, c.y, o.points):
                return True
        return False

    # ------------------------------------------------------------ results
    def _recognized(self, c: Candidate, wanted: Wanted, obj: etree._Element | None, cause: str) -> None:
        typ = learned_type(c, wanted)
        el = etree.Element("OBJECT", type=typ, name=wanted.name or typ)
        if wanted.owner:
            el.set("owner", wanted.owner)
        el.set("colour", wanted.colour or c.colour)
        el.set("x", f"{c.x:.3f}")
        el.set("y", f"{c.y:.3f}")
        el.set("z", f"{c.z:.3f}")
        el.set("frame", "map")
        if c.size is not None:
            el.set("size", f"{c.size:.3f}")
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


def evidence(c: Candidate, wanted: Wanted) -> int:
    """How many of a candidate's detections say it is what she named (its type or her word); all of them
    when she named nothing ("look at this")."""
    kinds = {t for t in (wanted.type, wanted.name) if t}
    return sum(v for t, v in c.types.items() if t in kinds) if kinds else c.n


def beside_her_shadow(cam: tuple[float, float], her: tuple[float, float], thing: tuple[float, float],
                      half_width: float = BODY_HALF_WIDTH, gap: float = ROW_GAP) -> bool:
    """Whether ``thing`` (map x, y) stands behind the person at ``her``, seen from the camera at ``cam``, within
    ``gap`` of the strip her body hides (``half_width`` either side of her, widening with the distance behind
    her): a thing like it could stand next to it in that strip, unseen (three books in a row behind him, the
    camera sees the one at the end). Something in the strip itself (seen over her) counts too."""
    dx, dy = her[0] - cam[0], her[1] - cam[1]
    d_her = math.hypot(dx, dy)
    if d_her < 1e-6:
        return False
    ux, uy = dx / d_her, dy / d_her
    tx, ty = thing[0] - cam[0], thing[1] - cam[1]
    along = tx * ux + ty * uy
    if along <= d_her:
        return False  # not behind her: she hides nothing next to it
    across = abs(-tx * uy + ty * ux)
    return across - half_width * along / d_her <= gap


def on_her_ray(pointing: Pointing, thing: tuple[float, float]) -> bool:
    """Whether ``thing`` (map x, y) lies within her ray's own uncertainty (:attr:`Pointing.spread`, one sigma:
    her aim and the camera's estimate of her arm) of where she points, seen from her hand
    (:meth:`Pointing.angle_off`): seen there, it is what she shows, not a neighbour of a thing she hides (a
    look-alike beside it in a row stands a row's gap off her ray: the jar 0.3 m beside the one she points at,
    30 deg off her ray from 0.6 m)."""
    return pointing.angle_off(thing[0], thing[1]) <= pointing.spread


def without_glimpses(res: Resolution, cands: list[Candidate], wanted: Wanted, pointing: Pointing | None,
                     origin: tuple[float, float]) -> Resolution:
    """A resolution that would store a candidate the camera saw as the thing named fewer than ``GLIMPSE``
    times is ``none``: one detection (a glimpse as the camera swung away, or the detector's one
    confusion of another thing for the type named) is never stored as it (fresh8
    terr_twin_cups_nonnative 6, 9: a white cup once seen as a "kettle", in the look's first frames
    while the camera still turned from the table, stored as the kettle 1.9 m from the real one). Not
    resolved again without it: the glimpse may be the thing she points at, and another one that fits
    less would be stored in its place. An ambiguous resolution with a better-seen option stays as it is
    (she is asked); one whose fitting candidates are all glimpses is ``none`` too."""
    fitting = res.fitting()
    if res.kind == "none" or not fitting:
        return res
    best = res.best
    if (res.kind == "one" and best is not None and evidence(best, wanted) < GLIMPSE) or all(evidence(c, wanted) < GLIMPSE for c in fitting):
        return Resolution("none", (), "nothing_seen")
    return res


def resolve_near(cands: list[Candidate], wanted: Wanted, her: tuple[float, float], radius: float) -> Resolution:
    """What she named, found without a gesture: resolved among ``cands`` within ``radius`` of where she stands
    (``her``, map frame), nearer preferred. The radius is a guess at how near her a thing she shows stands, not
    evidence: a thing that fits as well just beyond it is as likely hers (fresh12/studio_three_mugs seed 3: "blue"
    misheard, no gesture seen, the yellow of three mugs 0.25 m apart stored unasked, 1.42 m from her, the blue one
    1.59 m). One found within ``radius`` is kept only when it is also clear of what fits out to
    ``SEARCH_RADIUS_WIDE``; else the question is which one (all of those as options)."""
    near = [c for c in cands if math.hypot(c.x - her[0], c.y - her[1]) <= radius]
    res = without_glimpses(resolve(near, wanted, None, her), near, wanted, None, her)
    if res.kind == "one" and radius < SEARCH_RADIUS_WIDE:
        wide = [c for c in cands if math.hypot(c.x - her[0], c.y - her[1]) <= SEARCH_RADIUS_WIDE]
        rivals = without_glimpses(resolve(wide, wanted, None, her), wide, wanted, None, her)
        if rivals.kind == "ambiguous":
            return rivals
    return res


def _copy(el: etree._Element) -> etree._Element:
    """A detached deep copy of an element, without its tail."""
    out = etree.Element(el.tag, dict(el.attrib))
    out.text = el.text
    for ch in el:
        if isinstance(ch.tag, str):
            out.append(_copy(ch))
    return out


#: While a which-one answer is awaited with the options too far apart for one image: how far (share of the
#: image's half width) the camera looks from her towards them.
ASK_VIEW_OFF = 0.6

#: How often the object attention puts one which-one question: at most twice in all (issue 26 item 7).
MAX_ASKINGS = 2


def _answered_none_of_them(answer: etree._Element) -> bool:
    """Whether the dialog's ``ANSWER`` is an answer she gave that picks none of the options, to a question
    put only once so far: it fits them all or none ("the one on the table" with both on it, a misheard "that
    the table" taken as an object); also a "this one" (or her teaching said again with pointing) whose
    gesture the camera did not see or that does not single one out: asked again rather than given up
    (fresh7 corr_nonnative_books). Not no answer in time
    (the dialog says how often it asked only with an answer she gave)."""
    if answer.get("none") != "true":
        return False
    asked = answer.get("asked", "")
    return asked.isdigit() and int(asked) < MAX_ASKINGS
