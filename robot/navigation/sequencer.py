"""The sequencer (intermediate layer): a plan as single commands for the execution supervisor.

The ES handles single commands only (the papers' split between planner,
sequencer and ES). The sequencer takes each ``/robot/navigation/plan`` and
sends the ES one ``plan_step`` event per waypoint after the first (the
robot's own position), ``<POSE x y theta frame="map" tolerance align/>``:
heading along the next leg, the place's heading on the last step, which the
player turns to (``align``). The ES turns each into a ``move_to`` order for
the player; the player's ``/robot/player/status`` says when a step is
``reached``, and the next step goes out. After the last: ``goal_reached``
with the ``PLACE`` frame (``<PLACE beside="true">`` when the player stopped short beside
someone standing on the place: the dialog says so).

Failures, as ``navigation_failed`` with ``@reason`` and the goal's ``PLACE`` (the ES
passes both to the dialog's ``need_help``: "I cannot get to the kitchen"):

* a failed plan (``failed`` on the plan: unknown_place, no_path, ...);
* ``blocked``: the player reports ``blocked`` and is still blocked after
  ``blocked_timeout`` seconds (a person who steps aside in time lets the
  robot drive on: no failure, no help request). After ``replan_after``
  seconds of a blockage the planner is asked once for a way round it
  (``/robot/navigation/replan``: it marks what the laser sees and the map
  does not hold); a new path (``replan="true"``) replaces the plan, "no way
  round" changes nothing: the robot waits on. At most ``max_replans`` per goal and blockage (on again
  after a blockage, 0.3 m of progress, the count starts afresh);
* ``no_response``: the player did not start a step within
  ``start_timeout`` (e.g. the ES rejected the step).

The ES's ``cancel`` order drops the plan.

The way clears (issue 26 item 4: a go-to that recovers). After a ``blocked`` failure the robot
asks for help, but it keeps an eye on its way: for ``watch_time`` seconds it asks the planner
every ``watch_every`` s whether the way is clear now (``/robot/navigation/replan`` with
``watch="true"``: a path round what the laser sees that gives every person in the scan their
space, along ground the laser looks at, :meth:`robot.navigation.planner.Planner.replan`). Two
such answers in a row (the blocker has stepped aside, not just moved a moment) send the ES
``way_clear`` with the goal's ``PLACE``: asking for help, the robot goes on to its goal on its
own. At most ``max_resumes`` times per goal (each new blockage asks for help again), and
never after the ES's ``cancel`` (she stopped it, or a new plan began). A ``blocked`` failure also tells
the planner (``replan`` with ``blocked="true"``) to remember where: its next plans (the watch's, the
resumed go-to's) take another way round that spot where there is one.
"""

from __future__ import annotations

import asyncio
import math
from pathlib import Path
from typing import Any

from lxml import etree

from homesim.message import Message
from homesim.module import Module
from robot.contract import ES_EVENTS, ES_ORDERS, PLAN, PLAYER_STATUS, REPLAN

ORDERS = f"{ES_ORDERS}/sequencer"
REPLAN_SCHEMA = Path(__file__).resolve().parent.parent / "schemas" / "navigation" / "replan.xsd"


def steps_of(plan: etree._Element, *, tolerance: float = 0.25, final_tolerance: float = 0.15) -> list[dict[str, str]]:
    """The POSE attributes of each plan step (every waypoint after the start).

    Every corner of the plan is a step. A last corner a few centimetres from the place, which the
    grid's path often ends with, is dropped by the planner, which can see whether the straight leg to
    the place is free (robot.navigation.grid.without_end_corner, END_CORNER in the planner: the place's
    own arrival tolerance); a corner round a door jamb stays a step however near the place."""
    pts = [(float(w.get("x")), float(w.get("y"))) for w in plan.findall("waypoint")]
    last = plan.findall("waypoint")[-1] if pts else None
    out = []
    for i in range(1, len(pts)):
        (x0, y0), (x, y) = pts[i - 1], pts[i]
        final = i == len(pts) - 1
        if final and last is not None and last.get("theta") is not None:
            th, align = float(last.get("theta")), "true"  # type: ignore[arg-type]
        else:
            th, align = math.atan2(y - y0, x - x0), "false"
        out.append({"x": f"{x:.4f}", "y": f"{y:.4f}", "theta": f"{th:.5f}", "frame": "map",
                    "tolerance": f"{final_tolerance if final else tolerance:g}", "align": align})
    return out


class Sequencer(Module):
    """Hands the plan to the ES step by step (see the module docstring)."""

    def __init__(self, sim: Any, *, name: str = "sequencer", blocked_timeout: float = 10.0, start_timeout: float = 3.0,
                 replan_after: float = 3.0, max_replans: int = 3, watch_time: float = 60.0, watch_every: float = 1.0,
                 max_resumes: int = 2) -> None:
        super().__init__(sim, name)
        self.blocked_timeout = blocked_timeout
        self.start_timeout = start_timeout
        self.replan_after = replan_after
        self.max_replans = max_replans
        self.replans = 0  # asked for this goal
        self._asked = False  # a replan was asked during the present blockage
        self.watch_time = watch_time
        self.watch_every = watch_every
        self.max_resumes = max_resumes
        self.resumes = 0  # way_clear sent for this goal
        self.watching: float | None = None  # since when the way of a goal failed "blocked" is watched
        self._watch_asked = -math.inf  # when the last watch question went out
        self._clear = 0  # clear answers in a row
        self._resumed = False  # way_clear sent: the next plan to the goal is its resumption
        sim.bus.declare_channel(REPLAN, REPLAN_SCHEMA)
        self.goal = ""
        self.steps: list[dict[str, str]] = []
        self.index = -1
        self.sent_at = 0.0
        self.started = False
        self.blocked_since: float | None = None
        self._beside = False  # the step just reached ended beside someone standing on it (the player's ``beside``)
        self.bus.subscribe(PLAN, self._on_plan)
        self.bus.subscribe(PLAYER_STATUS, self._on_player)
        self.bus.subscribe(ORDERS, self._on_order)

    def respawn(self) -> Sequencer:
        return Sequencer(self.sim, name=self.name, blocked_timeout=self.blocked_timeout, start_timeout=self.start_timeout,
                         replan_after=self.replan_after, max_replans=self.max_replans, watch_time=self.watch_time,
                         watch_every=self.watch_every, max_resumes=self.max_resumes)

    @property
    def active(self) -> bool:
        return 0 <= self.index < len(self.steps)

    def _event(self, name: str, *, attrs: dict[str, str] | None = None, child: etree._Element | None = None) -> None:
        el = etree.Element("event", name=name, **(attrs or {}))
        if child is not None:
            el.append(child)
        self.bus.publish(ES_EVENTS, el)

    def _fail(self, reason: str) -> None:
        self.steps, self.index, self.blocked_since = [], -1, None
        self._event("navigation_failed", attrs={"reason": reason}, child=self._place())
        if reason == "blocked":  # the planner remembers where (its plans avoid that spot for a while)
            self.bus.publish(REPLAN, etree.Element("replan", goal=self.goal, blocked="true"))
        if reason == "blocked" and self.resumes < self.max_resumes:
            self.watching, self._watch_asked, self._clear = self.now, -math.inf, 0

    def _place(self) -> etree._Element:
        """The goal as a PLACE frame (``<PLACE><TITLE name/></PLACE>``), what the dialog names."""
        place = etree.Element("PLACE")
        etree.SubElement(place, "TITLE", name=self.goal)
        return place

    def _on_plan(self, msg: Message) -> None:
        plan = msg.xml
        if plan.get("watch") == "true":
            self._on_watch(plan)
            return
        if plan.get("replan") == "true":
            if not self.active or plan.get("goal", "") != self.goal or plan.get("failed"):
                return  # no way round (wait on), or an answer about a goal given up meanwhile
        else:
            if plan.get("goal", "") != self.goal or not self._resumed:
                self.resumes = 0  # a new request (the plan of a go-to resumed on way_clear keeps its count)
            self.goal = plan.get("goal", "")
            self.replans = 0
            self.watching, self._resumed = None, False
            if plan.get("failed"):
                self._fail(str(plan.get("failed")))
                return
        self.steps = steps_of(plan)
        self.index = -1
        self._next()

    def _next(self) -> None:
        self.index += 1
        self.blocked_since, self._asked = None, False
        if self.index >= len(self.steps):
            self.steps, self.index = [], -1
            place = self._place()
            if self._beside:  # the last step ended short, beside someone standing on the place: the dialog says so
                place.set("beside", "true")
            self._event("goal_reached", child=place)
            return
        self.sent_at, self.started = self.now, False
        self._event("plan_step", child=etree.Element("POSE", **self.steps[self.index]))

    def _on_player(self, msg: Message) -> None:
        if not self.active:
            return
        state = msg.xml.get("state")
        step = self.steps[self.index]
        here = msg.xml.get("x") is not None and abs(float(msg.xml.get("x")) - float(step["x"])) < 1e-3 \
            and abs(float(msg.xml.get("y")) - float(step["y"])) < 1e-3
        if state in ("moving", "blocked", "reached") and not here:
            return  # about an earlier step
        if state == "moving":
            if self.blocked_since is not None:
                # on again after a blockage (the player says so only after 0.3 m of progress): a new blockage
                # further on is another situation and gets its own replans (open_island_goto: three asked while
                # Ole stood in the bedroom door; he then stood beside the next corner and the robot, with no
                # replan left, waited 10 s and asked for help while the way round him was free)
                self.replans = 0
            self.started, self.blocked_since, self._asked = True, None, False
        elif state == "blocked":
            self.started = True
            if self.blocked_since is None:
                self.blocked_since = self.now
        elif state == "reached":
            self._beside = msg.xml.get("beside") == "true"
            self._next()
        elif state == "stopped":
            self.steps, self.index = [], -1

    def _on_order(self, msg: Message) -> None:
        if msg.xml.get("name") == "cancel":
            self.steps, self.index, self.blocked_since = [], -1, None
            self.watching = None

    def _on_watch(self, plan: etree._Element) -> None:
        """The planner's answer to a watch question: is the way of the failed goal clear now?"""
        if self.watching is None or self.active or plan.get("goal", "") != self.goal:
            return  # an answer about a watch that ended meanwhile
        self._clear = 0 if plan.get("failed") else self._clear + 1
        if self._clear >= 2:
            self.watching, self._resumed = None, True
            self.resumes += 1
            self._event("way_clear", child=self._place())

    def check(self) -> None:
        """Fail a step that stays blocked or never starts; watch a blocked way (called every 0.1 s)."""
        if self.watching is not None and not self.active:
            if self.now - self.watching >= self.watch_time:
                self.watching = None
            elif self.now - self._watch_asked >= self.watch_every - 1e-9:
                self._watch_asked = self.now
                self.bus.publish(REPLAN, etree.Element("replan", goal=self.goal, watch="true"))
        if not self.active:
            return
        if self.blocked_since is not None and self.now - self.blocked_since >= self.blocked_timeout:
            self._fail("blocked")
        elif (self.blocked_since is not None and not self._asked and self.replans < self.max_replans
              and self.now - self.blocked_since >= self.replan_after):
            self._asked = True
            self.replans += 1
            self.bus.publish(REPLAN, etree.Element("replan", goal=self.goal))
        elif not self.started and self.now - self.sent_at >= self.start_timeout:
            self._fail("no_response")

    async def run(self) -> None:
        while True:
            self.beat()
            self.check()
            await asyncio.sleep(0.1)
