"""Social navigation, measured as the field measures it (ground truth; metric ``social``).

The figures SocNavBench (Biswas et al., 2022) and the principles-and-metrics framework of
Francis et al. (2023, "Principles and Guidelines for Evaluating Social Robot Navigation
Algorithms") report for a robot among people, for the whole run and separately while the
robot follows its partner (the supervisor in ``Following``) and while it drives to a place on
its own (``Navigating``, a go-to):

* collisions: contacts the robot began with a person (``collisions_people``) and with the
  flat, walls or furniture (``collisions_flat``), from the world's contact log;
* ``min_person_distance_m``: the smallest distance from the robot's centre to any person's
  centre (the SocNavBench "closest pedestrian distance"), and ``min_person_clearance_m``: the
  smallest air gap between the robot's footprint (0.51 x 0.43 m) and a person's body (the
  world's 0.25 m circle); a contact is a gap of 0; ``min_person_clearance_moving_m`` the same
  for the people the robot drives toward (moving faster than 5 cm/s, the person ahead of its
  centre in the direction it drives): a person walking past a robot standing still, or
  overtaking it from behind, comes close by their own choice;
* ``personal_space_s``: time with someone's body closer than :data:`INTIMATE` (0.45 m) to the
  robot's footprint: Hall's intimate zone measured as he measured it, between bodies (centre to
  centre that is about 0.95 m straight ahead; 0.45 m centre to centre would be a contact), and
  ``near_bystander_s``: time with anyone but the partner closer than :data:`PERSONAL` (1.2 m,
  Hall's personal zone, body to body);
* go-to: for each episode (entering ``Navigating`` to leaving it) the path driven and its time
  against the shortest collision-free path for the robot's radius from where it started to
  the plan's goal (the world's own planner; ``path_ratio`` = driven / shortest, ``time_ratio``
  = time / (shortest / top speed)), ``success`` when the episode ended in ``goal_reached``;
* following: the robot's path and the partner's over the same time (``path_ratio`` = robot /
  partner, both counted only while the partner is in the flat: a search after she left adds
  to ``path_length_m`` but not to the ratio);
* partner identity: each ``/robot/attention/partner`` message (bearing, distance of the
  partner track) is matched to the true person nearest that point (within 0.7 m); within one
  interaction (the supervisor leaving the idle states until it is back in one) a change of that
  person is an ``identity_switches``; ``partner_kept`` = no switch and no ``partner_lost`` event
  all run;
* catching up (issue 26 item 10): at the first teaching or query request from the dialog
  (``object_teaching``, ``place_teaching``, ``query_object``, ``goto``) after each time the robot
  followed, the true distance from the robot's centre to the partner and the partner's bearing
  off the robot's heading (``request_distance_max_m``, ``request_bearing_max_deg``): the robot
  should have come up to a comfortable interaction distance facing her when she asks (requests
  before any following, where she chose to stand, are not its doing).

Every figure is a number (or None when there was nothing to measure) at the top level of the
summary, so a study table can take any of them; ``following`` and ``goto`` hold the same
figures per mode. Constant memory: running sums only.
"""

from __future__ import annotations

import math
from typing import Any

from ...scenario.pathplan import NoPathError
from . import Observer

#: m, body to body: closer than this is inside someone's personal space (Hall's intimate zone).
INTIMATE = 0.45
#: m, body to body: closer than this to anyone but the partner counts as near a bystander (personal zone).
PERSONAL = 1.2
#: The robot's footprint (half length, half width) and a person's body radius, as the world has them (m).
HALF_LENGTH, HALF_WIDTH, BODY = 0.255, 0.215, 0.25
#: m: a partner message is matched to the true person nearest its point within this distance.
MATCH = 0.7
ROBOT_RADIUS = 0.30
#: Supervisor states in which there is no interaction (a new one starts when it leaves them).
IDLE = frozenset({"LookingAround", "PotentialPartner", "AskingForHelp", "TechnicalFailure"})
#: Dialog requests at which the catching-up figures are taken.
REQUESTS = frozenset({"object_teaching", "place_teaching", "query_object", "goto"})
MODES = {"Following": "following", "Navigating": "goto"}


class _Mode:
    """Running figures of one mode (or the whole run)."""

    def __init__(self) -> None:
        self.time = 0.0
        self.collisions_people = 0
        self.collisions_flat = 0
        self.min_person = math.inf
        self.min_gap = math.inf
        self.min_gap_moving = math.inf
        self.personal = 0.0
        self.bystander = 0.0
        self.path = 0.0

    def as_dict(self) -> dict[str, Any]:
        return {
            "time_s": round(self.time, 3),
            "collisions_people": self.collisions_people,
            "collisions_flat": self.collisions_flat,
            "min_person_distance_m": round(self.min_person, 3) if math.isfinite(self.min_person) else None,
            "min_person_clearance_m": round(self.min_gap, 3) if math.isfinite(self.min_gap) else None,
            "min_person_clearance_moving_m": round(self.min_gap_moving, 3) if math.isfinite(self.min_gap_moving) else None,
            "personal_space_s": round(self.personal, 3),
            "near_bystander_s": round(self.bystander, 3),
            "path_length_m": round(self.path, 3),
        }


class Social(Observer):
    """Streaming social-navigation figures (see the module docstring)."""

    channels = ("/robot/es/events", "/robot/es/log", "/robot/attention/partner", "/robot/navigation/plan")
    step_every = 1

    def __init__(self, run: Any) -> None:
        super().__init__(run)
        self.world = run.world
        self.dt = run.world.dt
        self.total = _Mode()
        self.modes = {m: _Mode() for m in MODES.values()}
        self.mode: str | None = None
        self.last: tuple[float, float] | None = None
        self.partner: str | None = None  # the true person the latest partner message points at
        self.partner_last: tuple[float, float] | None = None
        self.partner_path = 0.0
        self.follow_path = 0.0  # m the robot drove following while its partner was in the flat
        self.in_interaction = False
        self.identity_switches = 0
        self.partner_lost = 0
        # go-to episodes
        self.goto_n = self.goto_reached = 0
        self.goto_shortest = self.goto_driven = self.goto_time = self.goto_optimal_time = 0.0
        self._goto: dict[str, Any] | None = None
        self._goal: tuple[float, float] | None = None
        self._grid: Any = None
        spec = getattr(getattr(run, "scenario", None), "robot", None)
        self.max_speed = float(getattr(spec, "max_speed", 0.5) or 0.5)
        # catching up
        self.requests = 0
        self._followed = False  # the robot has followed since the last request measured
        self.request_distance_max = -math.inf
        self.request_bearing_max = -math.inf
        run.world.add_contact_listener(self._contact)

    # --------------------------------------------------------------- contacts
    def _contact(self, t: float, what: str) -> None:
        person = what not in ("wall", "furniture")
        for m in self._active():
            if person:
                m.collisions_people += 1
            else:
                m.collisions_flat += 1

    def _active(self) -> list[_Mode]:
        return [self.total] if self.mode is None else [self.total, self.modes[self.mode]]

    # --------------------------------------------------------------- bus
    def on_message(self, m: Any) -> None:
        ch = m.channel
        if ch == "/robot/es/log":
            self._on_log(m.xml)
        elif ch == "/robot/es/events":
            name = m.xml.get("name")
            if name == "partner_lost":
                self.partner_lost += 1
            elif name == "goal_reached" and self._goto is not None:
                self._goto["reached"] = True
            elif name in REQUESTS and self.in_interaction and self._followed:
                self._followed = False
                self._request()
        elif ch == "/robot/attention/partner":
            self._on_partner(m.xml)
        elif ch == "/robot/navigation/plan":
            wps = m.xml.findall("waypoint")
            if wps and not m.xml.get("failed") and self._goto is not None and self._goal is None:
                self._goal = (float(wps[-1].get("x")), float(wps[-1].get("y")))
                self._goto["shortest"] = self._shortest(self._goto["start"], self._goal)

    def _on_log(self, xml: Any) -> None:
        if xml.get("kind") in ("rejected", "retained"):
            return
        state = xml.get("to")
        if state is None:
            return
        mode = MODES.get(state)
        if mode != self.mode:
            if self.mode == "following":
                self._followed = True
            if self.mode == "goto":
                self._end_goto()
            if mode == "goto":
                x, y, _ = self.world.robot.pose
                self._goto = {"start": (x, y), "t0": self.world.time, "path": 0.0, "reached": False, "shortest": None}
                self._goal = None
            self.mode = mode
        interacting = state not in IDLE
        if interacting and not self.in_interaction:
            self.partner = None  # a new interaction: its partner is the one its messages point at
        self.in_interaction = interacting

    def _on_partner(self, xml: Any) -> None:
        if xml.get("visible", "true") != "true":
            return
        try:
            bearing, dist = math.radians(float(xml.get("bearing"))), float(xml.get("distance"))
        except (TypeError, ValueError):
            return
        rx, ry, rth = self.world.robot.pose
        px, py = rx + dist * math.cos(rth + bearing), ry + dist * math.sin(rth + bearing)
        near = [(math.hypot(h.position[0] - px, h.position[1] - py), n) for n, h in self.world.humans.items()
                if h.present]
        if not near or min(near)[0] > MATCH:
            return
        who = min(near)[1]
        if self.in_interaction and self.partner is not None and who != self.partner:
            self.identity_switches += 1
        if who != self.partner:
            self.partner_last = None
        self.partner = who

    def _request(self) -> None:
        if self.partner is None or self.partner not in self.world.humans:
            return
        h = self.world.humans[self.partner]
        rx, ry, rth = self.world.robot.pose
        d = math.hypot(h.position[0] - rx, h.position[1] - ry)
        b = abs(math.degrees(math.remainder(math.atan2(h.position[1] - ry, h.position[0] - rx) - rth, 2 * math.pi)))
        self.requests += 1
        self.request_distance_max = max(self.request_distance_max, d)
        self.request_bearing_max = max(self.request_bearing_max, b)

    # --------------------------------------------------------------- go-to
    def _shortest(self, start: tuple[float, float], goal: tuple[float, float]) -> float | None:
        if self._grid is None:
            self._grid = self.world.walk_grid(clearance=ROBOT_RADIUS)
        try:
            pts = self._grid.plan(start, goal)
        except (NoPathError, ValueError):
            return None
        return float(sum(math.hypot(b[0] - a[0], b[1] - a[1]) for a, b in zip([start, *pts], pts)))

    def _end_goto(self) -> None:
        g, self._goto = self._goto, None
        if g is None:
            return
        self.goto_n += 1
        if g["reached"]:
            self.goto_reached += 1
            if g["shortest"]:
                self.goto_shortest += g["shortest"]
                self.goto_driven += g["path"]
                self.goto_time += self.world.time - g["t0"]
                self.goto_optimal_time += g["shortest"] / self.max_speed

    # --------------------------------------------------------------- world
    def on_step(self, world: Any) -> None:
        rx, ry, rth = world.robot.pose
        c, s = math.cos(rth), math.sin(rth)
        step = 0.0 if self.last is None else math.hypot(rx - self.last[0], ry - self.last[1])
        self.last = (rx, ry)
        near = gap = gap_ahead = bystander = math.inf
        v = world.robot.v
        partner_pos = None
        for name, h in world.humans.items():
            if not h.present:
                continue
            hx, hy = h.position
            dx, dy = hx - rx, hy - ry
            near = min(near, math.hypot(dx, dy))
            lx, ly = abs(c * dx + s * dy), abs(-s * dx + c * dy)
            g = max(math.hypot(max(lx - HALF_LENGTH, 0.0), max(ly - HALF_WIDTH, 0.0)) - BODY, 0.0)
            gap = min(gap, g)
            if (c * dx + s * dy) * v > 0.0:
                gap_ahead = min(gap_ahead, g)
            if name == self.partner:
                partner_pos = (hx, hy)
            else:
                bystander = min(bystander, g)
        moving = abs(world.robot.v) > 0.05
        for m in self._active():
            m.time += self.dt
            m.path += step
            m.min_person = min(m.min_person, near)
            m.min_gap = min(m.min_gap, gap)
            if moving:
                m.min_gap_moving = min(m.min_gap_moving, gap_ahead)
            if gap < INTIMATE:
                m.personal += self.dt
            if bystander < PERSONAL:
                m.bystander += self.dt
        if self._goto is not None:
            self._goto["path"] += step
        if self.mode == "following" and partner_pos is not None:
            if self.partner_last is not None:
                self.partner_path += math.hypot(partner_pos[0] - self.partner_last[0], partner_pos[1] - self.partner_last[1])
                self.follow_path += step  # the robot's path over the same steps (her path's ratio)
            self.partner_last = partner_pos
        else:
            self.partner_last = None

    def summary(self) -> dict[str, Any]:
        if self.mode == "goto":
            self._end_goto()  # a go-to still under way at the end: counted, not reached
            self.mode = None
        out = self.total.as_dict()
        out.update({
            "identity_switches": self.identity_switches,
            "partner_lost_events": self.partner_lost,
            "partner_kept": self.identity_switches == 0 and self.partner_lost == 0,
            "requests": self.requests,
            "request_distance_max_m": round(self.request_distance_max, 3) if self.requests else None,
            "request_bearing_max_deg": round(self.request_bearing_max, 1) if self.requests else None,
        })
        fol = self.modes["following"].as_dict()
        fol["partner_path_length_m"] = round(self.partner_path, 3)
        # robot / partner over the same steps: the robot's path after she left the flat (searching
        # for her) is in path_length_m, not in the ratio
        fol["path_ratio"] = round(self.follow_path / self.partner_path, 3) if self.partner_path > 0.5 else None
        goto = self.modes["goto"].as_dict()
        goto.update({
            "episodes": self.goto_n,
            "success_rate": round(self.goto_reached / self.goto_n, 3) if self.goto_n else None,
            "path_ratio": round(self.goto_driven / self.goto_shortest, 3) if self.goto_shortest > 0 else None,
            "time_ratio": round(self.goto_time / self.goto_optimal_time, 3) if self.goto_optimal_time > 0 else None,
        })
        out["following"] = fol
        out["goto"] = goto
        return out


OBSERVERS = {"social": Social}
