"""The planner (deliberative layer): a global path to a learned place.

On the ES condition ``navigate`` (``/robot/es/conditions/planner``, param
``goal`` = the ``SPEECH/PLACE`` frame, e.g. ``<PLACE><TITLE name="kitchen"/></PLACE>``)
it

1. asks the scene model for the place (``scene_model/request``,
   ``<request kb="places" op="query"><where index="name" value="kitchen"/></request>``)
   and takes the pose of the stored ``<PLACE name x y theta frame="map"/>`` (the
   last one, if the place was taught twice);
2. gets the floor plan once (``map_server/map``) and builds the inflated
   occupancy grid (:mod:`robot.navigation.grid`);
3. plans from the latest localised pose (``/robot/localisation/pose``) and
   publishes ``/robot/navigation/plan`` (map frame).

Anything that prevents a plan (unknown place, no map, not localised, no
free path) is published as a plan with ``failed`` set, so the sequencer
reports ``navigation_failed`` with that reason. ``navigation_cancelled``
drops a request still being planned.

The first plan and every replan see the people in the way the same way.
Replanning (``/robot/navigation/replan``, from the sequencer when the player
has been blocked a while), and the first plan of a go-to: the echoes of the next laser scan
(``/robot/laser/scan``, legs inflated to bodies) within :data:`LOCAL_RANGE` m
that the floor plan does not explain (more than :data:`UNMAPPED` m from every
mapped obstacle) are marked in a copy of the grid, a local costmap, and the
path to the same goal is planned again from the latest pose. The people in
that scan (pairs of legs) get their space on it (:func:`social_grid`): the path
keeps the robot's centre :data:`~robot.navigation.player.PERSON_CLEAR` m from theirs (what the player's
dynamic window drives past), and further where the room allows; where no such
way exists it keeps only their bodies clear. The answer has
``replan="true"``: a path round the obstacle, or ``failed`` when there is
none (one door, a person standing in it), and then the sequencer just keeps
waiting until its timeout.

Watching (``/robot/navigation/replan`` with ``watch="true"``, from the sequencer after a go-to
failed ``blocked`` and the robot asked for help): the same replan, answered with
``watch="true"``, but a way counts as clear only when it gives every person in the scan their
space (no falling back to their bodies) and its first :data:`LOCAL_RANGE` m lie where the laser
looks (within :data:`WATCH_FIELD` of the robot's heading): a way the laser does not see (the
robot turned to someone behind it) is not known to be clear (``failed="unseen"``). Such an answer says
where the way goes (``look``: its bearing from the robot's heading, rad, :func:`way_bearing`), so that a
robot asking for help with nobody to turn to looks along its way and sees when it clears
(:mod:`robot.attention.module`; fresh5/stair_goto_passage_person: it faced a door off its way, the way
was never in view, and it never went on after the lodger had left the passage).

Where it was blocked (``/robot/navigation/replan`` with ``blocked="true"``, from the sequencer when a go-to
fails ``blocked``): the planner remembers the spot of its path :data:`AVOID_AHEAD` m ahead of where the
robot stood, for :data:`AVOID_FOR` s (the robot's own map of where it was blocked; at most
:data:`AVOID_MAX` spots). Every plan and replan in that time (the watch, the plan of the resumed go-to, a
new request to any goal) pays :data:`AVOID_COST` per metre within :data:`AVOID_RADIUS` m of such a spot:
a second way, even a much longer one, is taken before the blocked one is tried again, and where there is
no other way the path still goes through it (a cost, not an obstacle: no route is lost).
fresh7/split_goto_ramp_child seed 2: blocked by a child on the ramp, told the way was clear, it drove up
to the same ramp three times and asked for help again each time; the way round through the utility room
was never tried.

Who stood in the way: a replan (not a watch question) remembers the people of its scan who stand on the
way still ahead of the robot (within :data:`BLOCKER_NEAR` m of the path being driven) where they stood, at
most :data:`BLOCKER_MAX`. Every later plan gives them their space as if it saw them (:func:`social_grid`,
falling back as for people seen) and pays the blocked spots' cost round them (:data:`AVOID_COST` within
:data:`AVOID_RADIUS` m: the fallback path too goes another way where there is one) until a scan looks at
that place and finds it empty
(:meth:`~robot.navigation.local.LatestScan.sees_through`, a :data:`BLOCKER_SEEN` m disc; checked before each
replan and first plan) or :data:`BLOCKER_FOR` s have passed: out of the laser's sight he has not gone. A watch
question is answered by what the laser sees now (remembered people only pay the cost there): a person remembered
out of sight in the only way would answer "no path" with no bearing to look along, and it would never look. The
replan that first sees them plans as before (their space on the social grid). tests/scenarios/nav/
goto_two_ways_passage_end: blocked by a man at the passage's east end, it replanned round him (the kitchen
way), was held up there by its partner, replanned with him out of sight, went back to the passage, and so
on, four times (217 s for a 7.4 m way).
"""

from __future__ import annotations

import asyncio
import math
from collections import deque
from pathlib import Path
from typing import Any

import numpy as np
from lxml import etree

from homesim.errors import BusError, HomesimError
from homesim.message import Message
from homesim.module import Module

from robot.contract import ES_CONDITIONS, PLAN, POSE, REPLAN, SCAN

from .config import Limits, limits_from_config
from .grid import MapError, NoPathError, OccupancyGrid, parse_map, path_length, without_end_corner
from .local import LatestScan
from .player import PERSON_CLEAR
from .route import body_points

CONDITIONS = f"{ES_CONDITIONS}/planner"
#: m: laser echoes further than this from the robot are not marked when replanning.
LOCAL_RANGE = 3.0
#: m: an echo this much clear of every mapped obstacle is something the map does not hold.
UNMAPPED = 0.10
#: s: the first plan of a go-to waits this long for a fresh scan (people and obstacles the floor plan
#: does not hold: the replan's local costmap), else it plans on the floor plan alone.
SCAN_WAIT = 0.5
SCHEMA = Path(__file__).resolve().parent.parent / "schemas" / "navigation" / "plan.xsd"
#: rad: a watched way is known to be clear only this far either side of the heading (the laser's
#: half circle, less a margin for the legs at its edge it does not pair).
WATCH_FIELD = math.radians(80.0)
#: m: path points nearer the robot's centre than this lie under its own footprint (not looked at).
WATCH_NEAR = 0.35
#: m: a plan's last corner nearer the place than this is dropped where the straight leg to the place is
#: free (:func:`~robot.navigation.grid.without_end_corner`): the place's own arrival tolerance (0.15 m),
#: within which arriving at the place is arriving at the corner. Not the two step tolerances together
#: (0.40 m): a free straight leg cut a niche's corner 0.35 m from its place, and the robot arrived at an
#: angle from which it could not turn to the place's heading (tests/test_nav_mapguard.py).
END_CORNER = 0.15
# PERSON_CLEAR (imported from the player, whose window's rule it is): how near a path's centre line may come to a
# person's centre: their body, the go-to's air to it (GOTO_SOCIAL_GAP) and the footprint's half width. A path any
# nearer is one the player's window will not drive: it stood blocked beside Ida for 14 s in goto_standing_person
# seed 2, replanned three times past her at 0.55 m.
#: m: the spot remembered as blocked lies this far along the path ahead of where the robot stood blocked
#: (the player stops about a body's length short of what blocks it).
AVOID_AHEAD = 0.6
#: m: the radius round a blocked spot a path pays for.
AVOID_RADIUS = 0.6
#: cost per metre of path within a blocked spot's radius (on top of the grid's own cost, 1 per metre in
#: the open): crossing one costs about 2 * AVOID_RADIUS * AVOID_COST m of detour.
AVOID_COST = 25.0
#: s: how long a blocked spot is remembered.
AVOID_FOR = 150.0
#: the most blocked spots remembered (the oldest is forgotten first).
AVOID_MAX = 4
#: m: a person in a replan's scan whose centre is this near the path being driven (ahead of the robot) is
#: what blocked it: the planner remembers where he stood (see the module docstring, "Who stood in the way").
BLOCKER_NEAR = PERSON_CLEAR + 0.3
#: m: the disc round a remembered person the laser must look through, empty, for him to be gone.
BLOCKER_SEEN = 0.3
#: s: how long a person who stood in the way is remembered there without being seen gone.
BLOCKER_FOR = 120.0
#: the most such people remembered (the oldest is forgotten first).
BLOCKER_MAX = 4


def social_grid(grid: OccupancyGrid, people: np.ndarray) -> OccupancyGrid:
    """``grid`` with a disc round each person (map-frame centres, (K, 2)) such that its free cells keep
    the robot's centre :data:`~robot.navigation.player.PERSON_CLEAR` m from them; the grid's clearance cost then keeps paths a
    further ``soft`` m off them where there is room (personal space, not just the body)."""
    return grid.with_obstacles(body_points(people, radius=max(PERSON_CLEAR - grid.radius, 0.0), cell=grid.cell))


def in_view(points: list[tuple[float, float]], pose: tuple[float, float, float], *, reach: float,
            field: float = WATCH_FIELD, near: float = WATCH_NEAR, step: float = 0.1) -> bool:
    """Whether the path ``points`` (map frame), sampled every ``step`` m, lies within ``field`` rad of
    the heading of ``pose`` wherever it is between ``near`` and ``reach`` m of the robot's centre
    (up to the first point beyond ``reach``): ground the laser looks at, so what it sees there is
    known. A path that turns back behind the robot within reach is not in view."""
    x, y, th = pose
    for (ax, ay), (bx, by) in zip(points, points[1:]):
        n = max(int(math.hypot(bx - ax, by - ay) / step), 1)
        for k in range(n + 1):
            px, py = ax + (bx - ax) * k / n, ay + (by - ay) * k / n
            d = math.hypot(px - x, py - y)
            if d > reach:
                return True
            if d >= near and abs(math.remainder(math.atan2(py - y, px - x) - th, 2 * math.pi)) > field:
                return False
    return True


def way_bearing(points: list[tuple[float, float]], pose: tuple[float, float, float], *,
                near: float = WATCH_NEAR, reach: float = 1.5) -> float | None:
    """The bearing (rad, from the heading of ``pose``) of the first point of the path ``points`` at least
    ``reach`` m from the robot's centre (else its end, if at least ``near`` m off): where to look to see
    the way's beginning. None for a path that ends within ``near`` m."""
    x, y, th = pose
    best = None
    for px, py in points:
        d = math.hypot(px - x, py - y)
        if d >= near:
            best = (px, py)
        if d >= reach:
            break
    if best is None:
        return None
    return math.remainder(math.atan2(best[1] - y, best[0] - x) - th, 2 * math.pi)


def nearest_on_path(path: list[tuple[float, float]], at: tuple[float, float]) -> tuple[int, float]:
    """(segment index, fraction along it) of the point of ``path`` nearest to ``at``: where a robot at ``at``
    is on its way (the first of equally near points)."""
    best, where = math.inf, (0, 0.0)
    for k, ((ax, ay), (bx, by)) in enumerate(zip(path, path[1:])):
        dx, dy = bx - ax, by - ay
        n2 = dx * dx + dy * dy
        t = 0.0 if n2 == 0 else min(max(((at[0] - ax) * dx + (at[1] - ay) * dy) / n2, 0.0), 1.0)
        d = math.hypot(ax + t * dx - at[0], ay + t * dy - at[1])
        if d < best:
            best, where = d, (k, t)
    return where


def point_ahead(path: list[tuple[float, float]], at: tuple[float, float], ahead: float) -> tuple[float, float]:
    """The point ``ahead`` m along ``path`` past the point of the path nearest to ``at`` (its end, if the
    path ends sooner)."""
    k, t = nearest_on_path(path, at)
    left = ahead
    for j in range(k, len(path) - 1):
        (ax, ay), (bx, by) = path[j], path[j + 1]
        seg = math.hypot(bx - ax, by - ay)
        start = t * seg if j == k else 0.0
        if seg - start >= left:
            f = (start + left) / seg if seg > 0 else 0.0
            return ax + (bx - ax) * f, ay + (by - ay) * f
        left -= seg - start
    return path[-1]


def near_path_ahead(path: list[tuple[float, float]], at: tuple[float, float], point: tuple[float, float],
                    within: float) -> bool:
    """Whether ``point`` lies within ``within`` m of ``path`` past the point of the path nearest to ``at``
    (the part of the way still ahead of a robot at ``at``)."""
    k, t0 = nearest_on_path(path, at)
    for j in range(k, len(path) - 1):
        (ax, ay), (bx, by) = path[j], path[j + 1]
        dx, dy = bx - ax, by - ay
        n2 = dx * dx + dy * dy
        t = 0.0 if n2 == 0 else min(max(((point[0] - ax) * dx + (point[1] - ay) * dy) / n2, 0.0), 1.0)
        if j == k:
            t = max(t, t0)
        if math.hypot(ax + t * dx - point[0], ay + t * dy - point[1]) <= within:
            return True
    return False


def place_title(place: etree._Element | None) -> str | None:
    """The name in a PLACE frame's TITLE (``<PLACE><TITLE name="kitchen"/></PLACE>``), or None."""
    if place is None:
        return None
    title = place.find(".//TITLE")
    if title is not None and title.get("name"):
        return str(title.get("name"))
    return place.get("name")


def place_names(title: str) -> list[str]:
    """The stored names a go-to's ``title`` may mean, in the order to try them: her own words first,
    then the same words with or without a trailing "room".

    She names a room in her words ("this is the study") and asks for it in others ("go to the study
    room"), or the reverse; the stored name stays hers (docs/semantics.md §4), so the look-up forgives
    the word "room" (a bare "room" is no name and is never taken off).
    """
    name = " ".join(title.strip().lower().split())
    if not name:
        return []
    words = name.split()
    other = " ".join(words[:-1]) if len(words) > 1 and words[-1] == "room" else f"{name} room"
    return [name] if other == "room room" else [name, other]


def find_place_pose(reply: etree._Element, title: str) -> tuple[float, float, float] | None:
    """The pose of the last place in a KB reply named ``title`` (case-insensitive), or None.

    A stored place (docs/robot-contract.md) is ``<PLACE name x y theta frame="map"/>``
    (inside ``<doc id>``); a PLACE speech frame with a ``POSE`` inside or beside it
    (``<PLACE><TITLE name/></PLACE><POSE x y theta/>``) is read too.
    """
    found = None
    want = title.strip().lower()
    for doc in reply.iter():
        if not isinstance(doc.tag, str) or doc.tag.upper() != "PLACE":
            continue
        if (place_title(doc) or "").strip().lower() != want:
            continue
        pose = doc if doc.get("x") is not None else _first_pose(doc)
        parent = doc.getparent()
        if pose is None and parent is not None and parent is not reply:
            pose = _first_pose(parent)  # stored beside the PLACE frame, in one document
        if pose is None:
            continue
        try:
            x, y = float(pose.get("x")), float(pose.get("y"))  # type: ignore[arg-type]
            th = float(pose.get("theta", "0"))
        except (TypeError, ValueError):
            continue
        if all(math.isfinite(v) for v in (x, y, th)):
            found = (x, y, th)
    return found


def _first_pose(el: etree._Element) -> etree._Element | None:
    return next((p for p in el.iter() if isinstance(p.tag, str) and p.tag.upper() == "POSE"), None)


class Planner(Module):
    """Plans a path to the place named in ``navigate`` (see the module docstring)."""

    def __init__(self, sim: Any, *, name: str = "planner", limits: Limits | None = None, timeout: float = 2.0) -> None:
        super().__init__(sim, name)
        self.limits = limits or Limits()
        self.timeout = timeout
        sim.bus.declare_channel(PLAN, SCHEMA)
        self.grid: OccupancyGrid | None = None
        self._pose_xml: etree._Element | None = None  # the latest pose message's payload, parsed when planning
        self._request = 0  # the navigate request being planned (cancel bumps it)
        self._pending: deque[tuple[int, etree._Element | None]] = deque(maxlen=4)
        self.goal: tuple[str, tuple[float, float, float]] | None = None  # the last goal planned to
        self.scan = LatestScan()
        self._scan_sub: Any = None  # subscribed only while a replan waits for a fresh scan
        self._watch = False  # the replan waiting for that scan is a watch question (see the module docstring)
        self.path: list[tuple[float, float]] = []  # the last path published (the one being driven)
        self.avoid: deque[tuple[float, float, float]] = deque(maxlen=AVOID_MAX)  # blocked spots (x, y, since)
        self.blockers: deque[tuple[float, float, float]] = deque(maxlen=BLOCKER_MAX)  # who stood in the way (x, y, since)
        self.bus.subscribe(CONDITIONS, self._on_condition)
        self.bus.subscribe(POSE, self._on_pose)
        self.bus.subscribe(REPLAN, self._on_replan)

    def respawn(self) -> Planner:
        return Planner(self.sim, name=self.name, limits=self.limits, timeout=self.timeout)

    def _on_pose(self, msg: Message) -> None:
        self._pose_xml = msg.xml  # this receiver's own copy: read only when a plan needs the pose

    @property
    def pose(self) -> tuple[float, float, float] | None:
        """The latest localised pose (map frame), None before the first."""
        x = self._pose_xml
        return None if x is None else (float(x.get("x")), float(x.get("y")), float(x.get("theta")))  # type: ignore[arg-type]

    def _on_condition(self, msg: Message) -> None:
        name = msg.xml.get("name")
        if name == "navigate":
            self._request += 1
            goal = msg.xml.find("param[@name='goal']/PLACE")
            self._pending.append((self._request, goal))
        elif name == "navigation_cancelled":
            self._request += 1

    async def _map(self) -> OccupancyGrid:
        if self.grid is None:
            reply = await self.bus.call("map_server", "map", etree.Element("request"), timeout=self.timeout)
            self.grid = OccupancyGrid(parse_map(reply.xml), radius=self.limits.radius)
        return self.grid

    async def _place(self, title: str) -> tuple[float, float, float] | None:
        for name in place_names(title):
            req = etree.Element("request", kb="places", op="query")
            etree.SubElement(req, "where", index="name", value=name)
            reply = await self.bus.call("scene_model", "request", req, timeout=self.timeout)
            pose = find_place_pose(reply.xml, name)
            if pose is not None:
                return pose
        return None

    def _publish(self, title: str, points: list[tuple[float, float]], theta: float | None = None, failed: str | None = None,
                 replan: bool = False, watch: bool = False, look: float | None = None) -> None:
        if points and self.grid is not None:
            # a last corner within the sequencer's two step tolerances of the place is no step of its own
            # when the leg to the place clears the floor plan (hall_goto_doorway_person seed 1: a corner
            # 7 cm from the place held the robot up); one it turns at round a jamb stays (review9 item 2)
            points = without_end_corner(points, self.grid, END_CORNER)
        el = etree.Element("plan", goal=title, length=f"{path_length(points):.4f}" if points else "0")
        if failed:
            el.set("failed", failed)
        if replan:
            el.set("replan", "true")
        if watch:
            el.set("watch", "true")
        if look is not None:
            el.set("look", f"{look:.5f}")
        if points and not failed and not watch:
            self.path = list(points)
        for i, (x, y) in enumerate(points):
            wp = etree.SubElement(el, "waypoint", x=f"{x:.4f}", y=f"{y:.4f}")
            if theta is not None and i == len(points) - 1:
                wp.set("theta", f"{theta:.5f}")
        self.bus.publish(PLAN, el)

    async def plan_for(self, goal: etree._Element | None) -> list[tuple[float, float]] | None:
        """Plan to the PLACE frame ``goal`` and publish the result (or the reason it failed)."""
        req = self._request
        title = place_title(goal) or ""
        if not title:
            self._publish("unknown", [], failed="unknown_place")
            return None
        try:
            place = await self._place(title)
        except (BusError, HomesimError, asyncio.TimeoutError):
            place = None
        if req != self._request:
            return None
        if place is None:
            self._publish(title, [], failed="unknown_place")
            return None
        try:
            grid = await self._map()
        except (BusError, MapError, HomesimError, asyncio.TimeoutError):
            self._publish(title, [], failed="no_map")
            return None
        if req != self._request:
            return None
        if self.pose is None:
            self._publish(title, [], failed="not_localised")
            return None
        scan = await self._next_scan()
        if req != self._request:
            return None
        if scan is not None:
            self.scan.update(scan)
            self.forget_seen_gone()
        try:
            # the first plan sees the people and unmapped obstacles of a fresh scan as a replan does; where
            # they close every way (someone standing in the only door), it plans on the floor plan alone:
            # people move, and the player waits for them at a polite distance (a replan then tries again)
            try:
                points = self._plan_round(place, squeeze=False) if scan is not None \
                    else self._avoiding(grid).plan(self.pose[:2], place[:2])
            except NoPathError:
                points = self._avoiding(grid).plan(self.pose[:2], place[:2])
        except NoPathError as e:
            self._publish(title, [], failed=e.reason)
            return None
        self.goal = (title, place)
        self._publish(title, points, theta=place[2])
        return points

    async def _next_scan(self) -> Message | None:
        """The next laser scan (None if none comes within :data:`SCAN_WAIT` s: planned on the floor plan alone).
        Subscribed for that one scan only, as for a replan."""
        got: asyncio.Future[Message] = asyncio.get_running_loop().create_future()

        def once(msg: Message) -> None:
            if not got.done():
                got.set_result(msg)

        sub = self.bus.subscribe(SCAN, once)
        try:
            return await asyncio.wait_for(got, SCAN_WAIT)
        except asyncio.TimeoutError:
            return None
        finally:
            sub.close()

    def _on_replan(self, msg: Message) -> None:
        """Replan on the next laser scan (the planner listens to the laser only for that one scan:
        every delivery draws a network delay, so a standing subscription would change every run)."""
        title = msg.xml.get("goal", "")
        if msg.xml.get("blocked") == "true":
            self.remember_blocked()
            return
        watch = msg.xml.get("watch") == "true"
        if self.goal is None or self.goal[0] != title or self.grid is None or self.pose is None:
            self._publish(title, [], failed="no_plan", replan=True, **({"watch": True} if watch else {}))
            return
        self._watch = watch
        if self._scan_sub is None:
            self._scan_sub = self.bus.subscribe(SCAN, self._on_scan)

    def _on_scan(self, msg: Message) -> None:
        if self._scan_sub is not None:
            self._scan_sub.close()
            self._scan_sub = None
        self.scan.update(msg)
        if self.goal is not None and self.grid is not None and self.pose is not None:
            self.replan(watch=self._watch)

    def remember_blocked(self) -> tuple[float, float] | None:
        """Remember the spot of the path being driven :data:`AVOID_AHEAD` m ahead of the robot's position
        (projected on the path) as blocked, for :data:`AVOID_FOR` s; the spot, or None without a path or pose."""
        if self.pose is None or len(self.path) < 2:
            return None
        spot = point_ahead(self.path, self.pose[:2], AVOID_AHEAD)
        self.avoid.append((spot[0], spot[1], self.now))
        return spot

    def avoided(self) -> list[tuple[float, float]]:
        """The blocked spots remembered now (younger than :data:`AVOID_FOR` s) and the places of the people
        who stood in the way and have not been seen gone (younger than :data:`BLOCKER_FOR` s)."""
        return [(x, y) for x, y, t in self.avoid if self.now - t < AVOID_FOR] \
            + [(x, y) for x, y, t in self.blockers if self.now - t < BLOCKER_FOR]

    def remembered_people(self) -> np.ndarray:
        """Map-frame centres ((K, 2)) of the people remembered standing in the way (younger than
        :data:`BLOCKER_FOR` s)."""
        pts = [(x, y) for x, y, t in self.blockers if self.now - t < BLOCKER_FOR]
        return np.array(pts, dtype=float).reshape(-1, 2)

    def remember_blockers(self, people: np.ndarray) -> list[tuple[float, float]]:
        """Remember the people of ``people`` (map-frame centres) who stand on the way still ahead of the robot
        (within :data:`BLOCKER_NEAR` m of the path being driven): where they stood; returns them."""
        if self.pose is None or len(self.path) < 2:
            return []
        got = [(float(px), float(py)) for px, py in people
               if near_path_ahead(self.path, self.pose[:2], (float(px), float(py)), BLOCKER_NEAR)]
        for px, py in got:  # one standing where another was remembered replaces him
            self.blockers = deque([b for b in self.blockers if math.hypot(b[0] - px, b[1] - py) > BLOCKER_SEEN],
                                  maxlen=BLOCKER_MAX)
            self.blockers.append((px, py, self.now))
        return got

    def forget_seen_gone(self) -> None:
        """Forget every remembered person whose place the latest scan looks at and finds empty (he has gone),
        and those remembered longer than :data:`BLOCKER_FOR` s."""
        if self.pose is None:
            return
        x, y, th = self.pose
        c, s = math.cos(th), math.sin(th)
        keep = []
        for bx, by, t in self.blockers:
            dx, dy = bx - x, by - y
            if self.now - t >= BLOCKER_FOR or self.scan.sees_through(c * dx + s * dy, -s * dx + c * dy, BLOCKER_SEEN):
                continue
            keep.append((bx, by, t))
        self.blockers = deque(keep, maxlen=BLOCKER_MAX)

    def _avoiding(self, grid: OccupancyGrid) -> OccupancyGrid:
        """``grid`` with the remembered blocked spots made costly (see the module docstring)."""
        return grid.with_cost(self.avoided(), radius=AVOID_RADIUS, cost=AVOID_COST)

    def unmapped(self) -> np.ndarray:
        """The latest scan's echoes (map frame, (N, 2)) near the robot that the floor plan does not explain."""
        pts = self.scan.points()
        if self.pose is None or self.grid is None or not len(pts):
            return np.zeros((0, 2))
        pts = pts[np.hypot(pts[:, 0], pts[:, 1]) <= LOCAL_RANGE]
        return self._unmapped(self._to_map(pts))

    def people(self) -> np.ndarray:
        """Map-frame centres ((K, 2)) of the people (pairs of legs) in the latest scan within
        :data:`LOCAL_RANGE` m whom the floor plan does not explain."""
        pts = self.scan.bodies()
        if self.pose is None or self.grid is None or not len(pts):
            return np.zeros((0, 2))
        pts = pts[np.hypot(pts[:, 0], pts[:, 1]) <= LOCAL_RANGE]
        return self._unmapped(self._to_map(pts))

    def _to_map(self, pts: np.ndarray) -> np.ndarray:
        assert self.pose is not None
        x, y, th = self.pose
        c, s = math.cos(th), math.sin(th)
        return np.column_stack((x + c * pts[:, 0] - s * pts[:, 1], y + s * pts[:, 0] + c * pts[:, 1]))

    def _unmapped(self, mp: np.ndarray) -> np.ndarray:
        """The map-frame points of ``mp`` more than :data:`UNMAPPED` m from every mapped obstacle."""
        g = self.grid
        assert g is not None
        i = np.floor((mp[:, 0] - g.origin[0]) / g.cell).astype(int)
        j = np.floor((mp[:, 1] - g.origin[1]) / g.cell).astype(int)
        inside = (i >= 0) & (i < g.nx) & (j >= 0) & (j < g.ny)
        keep = np.zeros(len(mp), dtype=bool)
        keep[inside] = g.clearance[i[inside], j[inside]] > UNMAPPED
        return mp[keep]

    def replan(self, *, watch: bool = False) -> list[tuple[float, float]] | None:
        """Plan to the last goal again round the unmapped echoes of the latest scan; publish the answer.

        People in the scan (pairs of legs) get their space on the plan (:func:`social_grid`): a path
        the player's window may drive, past them with :data:`~robot.navigation.player.GOTO_SOCIAL_GAP`
        of air and more where the room allows. Only where there is none (a person in a door of the
        only way) the plan keeps just their body clear, as before, and the player waits.

        ``watch``: is the way clear now (see the module docstring)? Only a path that gives everyone
        their space and that the laser looks along counts; the answer says ``watch="true"``.
        """
        assert self.goal is not None and self.grid is not None and self.pose is not None
        title, place = self.goal
        self.forget_seen_gone()
        if not watch:  # who stands on the way ahead is remembered there for the plans to come (not this one)
            blockers = self.people()
        try:
            # watching: a way only past someone's body is no clear way; and what it sees now answers (a person
            # remembered out of sight would close the way with no bearing to look along: it never looked again)
            points = self._plan_round(place, squeeze=not watch, remembered=not watch)
        except NoPathError as e:
            if not watch:
                self.remember_blockers(blockers)
            self._publish(title, [], failed=e.reason, replan=True, **({"watch": True} if watch else {}))
            return None
        if watch and not in_view(points, self.pose, reach=LOCAL_RANGE):
            self._publish(title, [], failed="unseen", replan=True, watch=True, look=way_bearing(points, self.pose))
            return None
        if not watch:
            self.remember_blockers(blockers)
        self._publish(title, points, theta=place[2], replan=True, **({"watch": True} if watch else {}))
        return points

    def _plan_round(self, place: tuple[float, float, float], *, squeeze: bool = True,
                    remembered: bool = True) -> list[tuple[float, float]]:
        """A path from the latest pose to ``place`` round the latest scan's unmapped echoes, giving the people
        in it their space (:func:`social_grid`) where the room allows, else (``squeeze``) keeping only their
        bodies clear (raises :class:`NoPathError` when there is no such way)."""
        assert self.grid is not None and self.pose is not None
        grid = self.grid.with_obstacles(self.unmapped())
        people = self.people()
        gone = self.remembered_people() if remembered else np.zeros((0, 2))  # out of sight, still where they stood
        if len(gone):
            people = np.vstack((people.reshape(-1, 2), gone))
        if len(people):
            try:
                return self._avoiding(social_grid(grid, people)).plan(self.pose[:2], place[:2])
            except NoPathError:
                if not squeeze:
                    raise
        return self._avoiding(grid).plan(self.pose[:2], place[:2])

    async def run(self) -> None:
        while True:
            self.beat()
            while self._pending:
                req, goal = self._pending.popleft()
                if req == self._request:
                    await self.plan_for(goal)
            await asyncio.sleep(0.1)
