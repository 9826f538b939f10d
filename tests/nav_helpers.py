"""Test stand-ins for the modules the navigation is built against, and a run harness.

Runs are real runs (:class:`homesim.tour.runner.Run`: world, people, hardware with the map
server, the supervisor with BIRON's AFSM, the localiser, the scene model, the watchdog,
the navigation modules and the player, the metrics). Until the person attention is on
main, :class:`Oracle` stands in for it with the contract's messages (docs/robot-contract.md)
made from ground truth, here in the tests (never in ``robot/``): ``/robot/attention/state``,
``/robot/attention/partner`` and ``/robot/attention/tracks`` for scripted people (each person
one track id). The
dialog is stood in for by a participant named ``dialog`` that sends the ES the events the
dialog would send and records the conditions it gets.
"""

from __future__ import annotations

import asyncio
import math
from pathlib import Path
from typing import Any

from lxml import etree

from homesim.tour.runner import Run, RunOptions
from homesim.scenario.loader import load_scenario, load_scenario_text
from robot.supervisor import event_xml

HERE = Path(__file__).resolve().parent / "scenarios"
#: What the navigation runs install (no attention or dialog yet: the oracle and the test stand in for them).
SUBSYSTEMS = ("robot.localisation", "robot.knowledge", "robot.watchdog", "robot.navigation", "robot.navigation.player")


class Oracle:
    """Ground truth in the contract's formats (see the module docstring)."""

    def __init__(self, stage: Any, *, tracks: dict[str, str] | None = None, rate: float = 10.0, pose: bool = False) -> None:
        self.stage = stage
        self.world = stage.world
        self.tracks = tracks or {}  # person -> track id published on /robot/attention/partner
        self.state = "Interaction"
        self.partner: str | None = None  # the track id of the partner
        self.hidden: set[str] = set()  # people the attention does not see now
        self._lost: dict[str, float] = {}
        self._prev: dict[str, tuple[float, float, float]] = {}
        self.bus = stage.sim.bus.participant("oracle", host="robot")
        self.period = 1.0 / rate
        self.pose = pose  # publish the true pose as the localiser would (when no localiser runs)
        stage.sim.spawn(self._run(), name="oracle")

    def follow(self, partner: str) -> None:
        self.state, self.partner = "Follow", partner
        self._publish_state()

    def interact(self) -> None:
        self.state = "Interaction"
        self._publish_state()

    def _publish_state(self) -> None:
        self.bus.publish("/robot/attention/state", etree.Element("attention", state=self.state, selected=self.partner or "",
                                                                 partner=self.partner or ""))

    async def _run(self) -> None:
        n = 0
        while True:
            self._tick()
            if n % int(1 / self.period) == 0:
                self._publish_state()
            n += 1
            await asyncio.sleep(self.period)

    def _tick(self) -> None:
        w = self.world
        rx, ry, rth = w.robot.pose
        if self.pose:
            self.bus.publish("/robot/localisation/pose", etree.Element(
                "pose", time=f"{w.time:.3f}", x=f"{rx:.4f}", y=f"{ry:.4f}", theta=f"{rth:.5f}", cxx="0.0001", cyy="0.0001",
                ctt="0.0001", frame="map"))
        base = self.stage.hardware.get("base")
        if base is None:
            return
        ox, oy, oth = base.odometry
        t = w.time
        tracks = etree.Element("tracks", time=f"{t:.6f}", frame="odom")
        for name, tid in sorted(self.tracks.items()):
            h = w.humans[name]
            hx, hy = h.position
            c, s = math.cos(rth), math.sin(rth)
            lx, ly = c * (hx - rx) + s * (hy - ry), -s * (hx - rx) + c * (hy - ry)
            co, so = math.cos(oth), math.sin(oth)
            px, py = ox + co * lx - so * ly, oy + so * lx + co * ly
            prev = self._prev.get(name)
            vx = vy = 0.0
            if prev is not None and t > prev[0]:
                vx, vy = (px - prev[1]) / (t - prev[0]), (py - prev[2]) / (t - prev[0])
            self._prev[name] = (t, px, py)
            visible = h.present and name not in self.hidden
            if visible:
                self._lost.pop(name, None)
            else:
                self._lost.setdefault(name, t)
            if visible:
                etree.SubElement(tracks, "track", id=tid, x=f"{px:.3f}", y=f"{py:.3f}", vx=f"{vx:.3f}", vy=f"{vy:.3f}",
                                 cxx="0.01", cxy="0", cyy="0.01", bearing=f"{math.degrees(math.atan2(ly, lx)):.3f}",
                                 distance=f"{math.hypot(lx, ly):.3f}", confirmed="true", speaking="false", facing="false")
            self.bus.publish("/robot/attention/partner", etree.Element(
                "partner", id=tid, bearing=f"{math.degrees(math.atan2(ly, lx)):.3f}", distance=f"{math.hypot(lx, ly):.4f}",
                x=f"{px:.4f}", y=f"{py:.4f}", vx=f"{vx:.4f}", vy=f"{vy:.4f}", visible="true" if visible else "false",
                lost_for=f"{t - self._lost.get(name, t):.3f}"))
        if self.tracks:
            self.bus.publish("/robot/attention/tracks", tracks)


def _param_value(p: etree._Element) -> str | None:
    """A condition's param as text: its text, or the name in a copied frame's TITLE."""
    title = p.find(".//TITLE")
    return title.get("name") if title is not None else p.text


class NavRun:
    """A :class:`Run` of ``tests/scenarios/<name>.xml`` with the oracle and a dialog stand-in."""

    def __init__(self, name: str, *, tracks: dict[str, str] | None = None, text: str | None = None) -> None:
        sc = load_scenario_text(text, source=f"{name}.xml") if text is not None else load_scenario(HERE / f"{name}.xml")
        self.run = Run(sc, RunOptions(subsystems=SUBSYSTEMS))
        self.sim = self.run.sim
        self.stage = self.run.stage
        self.world = self.run.world
        self.es = self.run.supervisor
        self.modules = self.run.modules
        self.oracle = Oracle(self.stage, tracks=tracks)
        self.events: list[tuple[float, str, dict[str, str]]] = []
        self.conditions: list[tuple[float, str, dict[str, str | None]]] = []
        self.user = self.sim.bus.participant("dialog", host="robot")
        self.user.subscribe("/robot/es/conditions/dialog", lambda m: self.conditions.append(
            (m.created, m.xml.get("name"), {p.get("name"): _param_value(p) for p in m.xml.findall("param")})))
        self.sim.bus.participant("event_watch", host="robot").subscribe(
            "/robot/es/events", lambda m: self.events.append((m.created, m.xml.get("name"), dict(m.xml.attrib))))

    def metric(self, name: str) -> dict[str, Any]:
        return self.run.metrics[name].summary()

    def at(self, t: float, fn: Any) -> None:
        self.sim.call_at(t, fn)

    def until(self, t: float) -> None:
        self.sim.run(until=t)

    def close(self) -> None:
        self.run.close()

    def say(self, name: str, *children: etree._Element, extra: tuple[etree._Element, ...] = ()) -> None:
        """The dialog's event ``name`` (a SPEECH frame with ``children``, then ``extra``) to the ES."""
        speech = etree.Element("SPEECH")
        for c in children:
            speech.append(c)
        self.user.publish("/robot/es/events", event_xml(name, children=(speech, *extra)))

    def engage(self) -> None:
        """A potential partner and a greeting: the ES goes to Interacting."""
        person = etree.Element("PERSON", id="t1", bearing="0", distance="1.5", speaking="true", facing="true")
        self.oracle.bus.publish("/robot/es/events", event_xml("potential_partner", children=(person,)))
        self.say("greeting", etree.Element("GREETING"))

    def teach_place(self, place: str, x: float, y: float, theta: float = 0.0) -> None:
        """"This is the <place>" as the dialog sends it (the pose it gives is the localised one)."""
        p = etree.Element("PLACE")
        etree.SubElement(p, "TITLE", name=place)
        self.say("place_teaching", p, extra=(etree.Element("POSE", x=f"{x:.4f}", y=f"{y:.4f}", theta=f"{theta:.4f}", frame="map"),))

    def goto(self, place: str) -> None:
        p = etree.Element("PLACE")
        etree.SubElement(p, "TITLE", name=place)
        self.say("goto", p)

    def condition_names(self) -> list[str]:
        return [c[1] for c in self.conditions]


def start_run(name: str, *, tracks: dict[str, str] | None = None, text: str | None = None) -> NavRun:
    """The run of ``tests/scenarios/<name>.xml`` (or of ``text``), built, not yet run."""
    return NavRun(name, tracks=tracks, text=text)
