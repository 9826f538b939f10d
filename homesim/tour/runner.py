"""The composition root: one scenario becomes one complete run.

:class:`Run` is the only place that knows every part of a run. From a
loaded scenario it builds, in this order:

1. the :class:`~homesim.sim.Simulation` (seed, optional real-time pacing)
   and, if asked, the trace (its header names the scenario file, its
   content digest and the options, so ``homesim replay`` can re-run it);
2. the :class:`~homesim.tour.stage.Stage`: the world stepping in virtual
   time, the scripted people and sound sources and the PeopleBot's hardware
   (``ACTORS``: ``humans.install.install`` and
   ``robot.hardware.install.install``, imported here and handed to the
   stage, which names neither) and the scenario's expectations, checked as
   the run goes;
3. the execution supervisor (``robot.supervisor.ExecutionSupervisor`` with
   ``robot/afsm/biron.scxml``);
4. BIRON's modules: ``robot.install.install(run)`` with the subsystems of
   ``robot.install.SUBSYSTEMS`` (each sees ``run.sim`` and ``run.config``,
   never the world), and a heartbeat monitor on ``/system/health`` unless
   one of them monitors heartbeats itself (``monitors_heartbeats``: BIRON's
   watchdog, which also restarts failed modules);
5. the streaming metrics (:mod:`homesim.tour.metrics`), the transcript hooks
   and the scenario's faults (a module crashes or hangs at a time).

This is the run package: it imports ``robot`` and ``humans``; the kernel
never does. After :meth:`Run.run`, :meth:`Run.finish`
asks the scene model what it knows (``scene_model/request``, the contract's
RPC), evaluates the expectations and returns the summary (see
:func:`Run.summary` and docs/running.md for its fields).
"""

from __future__ import annotations

import hashlib
import os
import sqlite3
from collections.abc import Callable, Mapping, Sequence
import dataclasses
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO, Any

from lxml import etree

import humans.install as people
import robot.hardware.install as hardware
import robot.install as biron
import robot.profiles as robot_profiles
from robot.deployment import DEFAULT as ROBOT_DEPLOYMENT
from robot.deployment import MODULES as ROBOT_MODULES
from robot.knowledge.scene_model import STORE_FILE
from robot.supervisor import ExecutionSupervisor

from . import metrics as metrics_pkg
from .. import deployment as deployment_mod
from ..deployment import Deployment
from ..errors import HomesimError, InputError, ScenarioError
from ..heartbeat import HEALTH_CHANNEL, BackstopMonitor, HeartbeatMonitor
from ..message import Message
from .metrics.es import EsRecord
from ..realtime import Stopwatch, peak_memory_mb
from .runheader import RATES, check_metrics, check_rates, check_subsystems
from .expect import Verdict
from ..scenario.loader import load_scenario
from ..scenario.model import Scenario
from ..sim import FAULT_CHANNEL, Simulation
from ..trace import FileTrace, TraceRecorder
from .stage import Install, Stage

#: What a run puts on the stage, in this order: the scripted people and sound sources, then the PeopleBot's
#: hardware models (each an ``install(stage)``; the stage itself knows neither).
ACTORS: tuple[Install, ...] = (people.install, hardware.install)
#: Virtual seconds per run chunk (progress, replay's early stop); results do not depend on it.
CHUNK = 1.0
#: The verdict of a complete run of a scenario that states no expectation: nothing was checked,
#: so it neither passed nor failed.
NO_EXPECTATIONS = "no expectations"

Line = Callable[[float, str, str], None]


def file_digest(path: str | os.PathLike[str]) -> str:
    """``sha256:<hex>`` of a file's bytes (what a trace header pins)."""
    return "sha256:" + hashlib.sha256(Path(path).read_bytes()).hexdigest()


def store_digest(directory: str | os.PathLike[str]) -> str:
    """``sha256:<hex>`` of what a store directory (``--memory DIR``) holds, for a trace header.

    Each ``*.sqlite`` store counts by its content (memories, documents and
    attachments, read-only, in key order), so the same knowledge in a file laid
    out differently gives the same digest; a file SQLite cannot read counts by
    its bytes. A missing directory, or stores holding nothing, have the digest
of nothing (the first run creates an empty store). A run
    with ``--memory`` writes to its store, so replaying it needs the store as it
    was when the run started (``homesim replay`` compares this digest).
    """
    h = hashlib.sha256()
    root = Path(directory)
    files = sorted(p for p in root.glob("*.sqlite") if p.is_file()) if root.is_dir() else []
    for path in files:
        try:
            db = sqlite3.connect(f"file:{path.resolve()}?mode=ro", uri=True)
            try:
                for table, order in (("memories", "name"), ("documents", "memory, id"),
                                     ("attachments", "memory, doc_id, name")):
                    for row in db.execute(f"SELECT * FROM {table} ORDER BY {order}"):  # noqa: S608 (fixed names)
                        cells = tuple(bytes(v) if isinstance(v, memoryview) else v for v in row)
                        h.update(repr((path.name, table, cells)).encode("utf-8") + b"\n")
            finally:
                db.close()
        except sqlite3.Error:
            h.update(path.name.encode("utf-8") + b"\0" + path.read_bytes())
    return "sha256:" + h.hexdigest()


@dataclass(frozen=True)
class RunOptions:
    """How to run a scenario (the command line's options, as plain values)."""

    seed: int | None = None  # None: the scenario's
    until: float | None = None  # None: the scenario's duration
    trace: Path | IO[str] | None = None
    memory: Path | None = None  # the scene model's store; None: start empty, write nothing
    realtime: float | None = None
    subsystems: tuple[str, ...] | None = None  # None: robot.install.SUBSYSTEMS
    metrics: tuple[str, ...] | None = None  # None: every registered metric
    strict: bool | None = None  # True: validate every message on a typed channel; None: Simulation's default (homesim.bus)
    profile: str | None = None  # which robot (robot.profiles); None: the scenario's <robot profile>, else the default
    # The store the trace header names when ``memory`` is a private copy of it (a replay never writes to
    # the store a trace names: it is untrusted input, and a second replay needs the store unchanged).
    memory_as: Path | None = None
    # The sensors' rates: None keeps the scenario's <robot laser-rate camera-rate> (10 Hz each by
    # default); "hardware" runs them at BIRON's PeopleBot hardware rates (RATES: the SICK laser at
    # 37.5 Hz, the camera at 25 Hz), several times the work per simulated second.
    rates: str | None = None


@dataclass(frozen=True)
class RobotConfig:
    """``run.config``: what BIRON's modules may know of the run, as plain values (never the world)."""

    seed: int
    memory_dir: str | None  # the knowledge store (--memory DIR); None: start empty, write nothing
    max_speed: float
    max_turn: float
    laser_rate: float
    camera_rate: float
    audio_rate: float
    odometry_rate: float
    options: Mapping[str, str] = field(default_factory=dict)
    profile: str = "full"  # which robot is simulated (robot.profiles)


def _check_memory(scenario: Scenario, options: RunOptions) -> None:
    """A scenario that starts from an earlier run's knowledge (``<robot memory="required">``) needs a store:
    a directory an earlier run wrote its scene model into (a missing, mistyped or empty directory would run the
    whole scenario on no knowledge and fail only at the end)."""
    if not scenario.robot.memory_required:
        return
    if options.memory is not None:
        store = Path(options.memory)
        if not (store / STORE_FILE).is_file():
            why = "does not exist" if not store.exists() else "is not a directory" if not store.is_dir() else \
                f"holds no scene model ({STORE_FILE}): no run has written to it"
            raise ScenarioError(f"this scenario starts from what the robot learned in an earlier run (memory=\"required\"), "
                                f"but the store --memory {store} {why}; give the directory an earlier run wrote (e.g. "
                                f"homesim run scenarios/home_tour.xml --memory DIR, then this scenario with the same DIR)",
                                source=scenario.source, line=scenario.robot.line, element="robot")
    if options.memory is None:
        raise ScenarioError("this scenario starts from what the robot learned in an earlier run (memory=\"required\"): "
                            "run it with --memory DIR, the store directory of that run (e.g. a home tour: homesim run "
                            "scenarios/home_tour.xml --memory DIR, then this scenario with the same DIR)",
                            source=scenario.source, line=scenario.robot.line, element="robot")


def _check_names(options: RunOptions) -> None:
    """Refuse subsystems outside the robot's registry and unknown metrics (nothing named is imported)."""
    for what, names, check in (("subsystems", options.subsystems, check_subsystems), ("metrics", options.metrics, check_metrics)):
        if names is not None:
            try:
                check(names)
            except ValueError as exc:
                raise HomesimError(f"run option {what}: {exc}") from None


class Run:
    """One scenario on one simulation, every part wired (see the module docstring)."""

    def __init__(self, scenario: Scenario, options: RunOptions = RunOptions(), *, on_line: Line | None = None,
                 scenario_file: str | None = None, digest: str | None = None) -> None:
        self.scenario = scenario
        self.options = options
        self.on_line = on_line
        _check_names(options)  # before anything is imported or built
        _check_memory(scenario, options)
        if options.rates is not None:
            try:
                laser_rate, camera_rate = RATES[check_rates(options.rates)]
            except ValueError as exc:
                raise HomesimError(f"run option rates: {exc}") from None
            # The hardware models and the robot's config read the scenario's <robot>: run it at these rates.
            scenario = dataclasses.replace(scenario, robot=dataclasses.replace(
                scenario.robot, laser_rate=laser_rate, camera_rate=camera_rate))
        self.scenario = scenario
        seed = scenario.seed if options.seed is None else options.seed
        self.profile = resolve_profile(options.profile, scenario)
        self.sim = Simulation(seed=seed, scenario=scenario.name, realtime=options.realtime,
                              **({} if options.strict is None else {"strict": options.strict}))
        try:
            self.deployment = resolve_deployment(scenario)
            self.deployment.apply(self.sim.network)
        except BaseException:
            self.sim.close()
            raise
        self.header = {
            "scenario_file": scenario_file if scenario_file is not None else scenario.source,
            "scenario_digest": digest,
            "seed": seed,
            "until": options.until,
            "memory": None if options.memory is None else str(options.memory_as or options.memory),
            "memory_digest": None if options.memory is None else store_digest(options.memory),
            "subsystems": None if options.subsystems is None else list(options.subsystems),
            "metrics": None if options.metrics is None else list(options.metrics),
            "profile": self.profile,  # the profile that ran (the option, the scenario's, or the default)
            "deployment": self.deployment.name,
            # Where modules run and what links join the hosts (the timeline groups lanes by host
            # and marks the messages that crossed a slow link).
            "hosts": {h.name: h.link for h in self.deployment.hosts},
            "placement": {"default": self.deployment.default_host, **dict(self.deployment.placement)},
            "link_worst_ms": {lk.name: round(lk.worst_s * 1000, 3) for lk in self.deployment.links},
        }
        # A link per direction or per host pair (only when the deployment has one: other traces keep their header).
        uplinks = {h.name: h.uplink for h in self.deployment.hosts if h.uplink}
        if uplinks:
            self.header["uplinks"] = uplinks
        if self.deployment.routes:
            self.header["routes"] = {f"{r.src}->{r.dst}": r.link for r in self.deployment.routes}
        if options.rates is not None:  # (only when given: a default run's trace is as before)
            self.header["rates"] = options.rates
        try:
            self._build(scenario, options, seed)
        except BaseException:
            self.sim.close()
            raise
        self.knowledge: dict[str, list[etree._Element] | None] = {}
        self._verdicts: list[Verdict] | None = None

    def _build(self, scenario: Scenario, options: RunOptions, seed: int) -> None:
        """Steps 1-5 of the module docstring (a failure closes the half-built simulation)."""
        self.trace: TraceRecorder | None = None
        if options.trace is not None:
            if isinstance(options.trace, (str, os.PathLike)):
                self.trace = FileTrace(self.sim.bus, options.trace, scenario=scenario.name, seed=seed, header={"run": self.header})
            else:
                self.trace = TraceRecorder(self.sim.bus, options.trace, scenario=scenario.name, seed=seed, header={"run": self.header})
            self.sim.traces.append(self.trace)
        r = scenario.robot
        self.config = RobotConfig(
            seed=seed, memory_dir=None if options.memory is None else str(options.memory), max_speed=r.max_speed, max_turn=r.max_turn,
            laser_rate=r.laser_rate, camera_rate=r.camera_rate, audio_rate=r.audio_rate,
            odometry_rate=r.odometry_rate, options=dict(r.options), profile=self.profile,
        )
        self.stopwatch = Stopwatch()
        self.es = EsRecord()
        self.stage = Stage(self.sim, scenario, actors=ACTORS, truth_every=None)
        self.world = self.stage.world
        self.dispatcher = self.stage.dispatcher
        self.dispatcher.add(EsRecord.channels, self._on_es)
        self.dispatcher.add(("/robot/es/log", "/robot/es/sorted", FAULT_CHANNEL, HEALTH_CHANNEL), self._on_system)
        self._heard = 0
        self.world.add_listener(self._on_step)
        self.supervisor = ExecutionSupervisor(self.sim)
        subsystems = biron.SUBSYSTEMS if options.subsystems is None else options.subsystems
        self.modules: dict[str, Any] = biron.install(self, subsystems)
        # One heartbeat monitor reports: the robot's own (its watchdog, which also restarts modules)
        # if a subsystem brought one, else the kernel's (two would report every failure twice). Behind
        # the robot's, the kernel's stays as a backstop: silent while that one beats, it reports in its
        # place once it is silent too (every module crashed, the watchdog included).
        own = sorted(k for k, m in self.modules.items() if getattr(m, "monitors_heartbeats", False))
        participant = self.sim.bus.participant("monitor", host="robot")
        self.monitor: HeartbeatMonitor = (BackstopMonitor(participant, primary=self.modules[own[0]].name) if own
                                          else HeartbeatMonitor(participant))
        self.sim.spawn(self.monitor.run(), name="monitor")
        for f in scenario.faults:
            if f.module not in self.sim.modules:
                raise ScenarioError(f"<{f.kind} module={f.module!r}>: no such module in this run; "
                                    f"modules: {', '.join(sorted(self.sim.modules))}",
                                    source=scenario.source, line=f.line, element=f.kind)
            self.sim.inject_fault(f.module, f.kind, at=f.at)
        self.sim.start()
        self.metrics = metrics_pkg.install(self, options.metrics)

    # ------------------------------------------------------------- building
    @classmethod
    def from_file(cls, path: str | os.PathLike[str], options: RunOptions = RunOptions(), *,
                  on_line: Line | None = None) -> Run:
        """Load a scenario file (every error names file and line) and build its run."""
        scenario = load_scenario(path)
        return cls(scenario, options, on_line=on_line, scenario_file=str(path), digest=file_digest(path))

    @property
    def es_state(self) -> str | None:
        """The supervisor's state as its log and status last said."""
        return self.es.state

    @property
    def end(self) -> float:
        """Where this run stops: ``until`` if given (never past the scenario's duration)."""
        until = self.options.until
        return self.scenario.duration if until is None else max(0.0, min(until, self.scenario.duration))

    # ----------------------------------------------------------- transcript
    def _say(self, t: float, who: str, text: str) -> None:
        if self.on_line is not None:
            self.on_line(t, who, text)

    def _on_es(self, m: Message) -> None:
        change = self.es.on_message(m)
        if change is not None and change[0]:
            cause = f" ({m.xml.get('name')})" if m.channel == "/robot/es/log" else ""
            self._say(m.created, "ES", f"{change[0]} -> {change[1]}{cause}")

    def _on_system(self, m: Message) -> None:
        x = m.xml
        if m.channel == "/robot/es/log":
            if x.get("kind") == "rejected":
                detail = f": {x.get('detail')}" if x.get("detail") else ""
                self._say(m.created, "ES", f"rejected {x.get('name')} from {x.get('source')} "
                                           f"({x.get('reason')} in {x.get('state')}){detail}")
        elif m.channel == "/robot/es/sorted":
            k = int(x.get("ahead", "0"))
            self._say(m.created, "ES", f"sorted {x.get('name')} (created {x.get('created')} s) ahead of {k} queued "
                                       f"event{'s' if k != 1 else ''} ({x.get('ahead-of-name')}, created {x.get('ahead-of-created')} s)")
        elif m.channel == FAULT_CHANNEL:
            why = " (it flooded the bus)" if x.get("reason") == "flood" else ""
            self._say(m.created, "fault", f"{x.get('module')} {x.get('kind')}es{why}")
        else:
            self._say(m.created, "health", f"{x.tag} {x.get('module')}")

    def _on_step(self, world: Any) -> None:
        sound = world.sound
        if len(sound) > self._heard:
            for u in sound.since(self._heard):
                self._say(u.start, u.source, u.text)
            self._heard = len(sound)

    # ------------------------------------------------------------------ run
    def run(self, *, progress: Callable[[float, float], None] | None = None,
            stop: Callable[[], bool] | None = None) -> float:
        """Run to :attr:`end` in chunks (``progress(now, end)`` after each; ``stop()`` ends early); return the time reached."""
        end = self.end
        t = self.sim.now
        while t < end:
            t = min(end, t + CHUNK)
            self.sim.run(until=t)
            if progress is not None:
                progress(t, end)
            if stop is not None and stop():
                break
        return t

    def query_knowledge(self, timeout: float = 1.0) -> dict[str, list[etree._Element] | None]:
        """Ask the scene model for every object and place it holds (the contract's RPC); None where it cannot answer."""
        if "scene_model" not in self.sim.modules:
            self.knowledge = {"objects": None, "places": None}
            return self.knowledge
        p = self.sim.bus.participant(f"runner{len(self.knowledge)}", host="simulator")
        for kb in ("objects", "places"):
            try:
                reply = self.sim.run_until_complete(p.call("scene_model", "request", etree.Element("request", kb=kb, op="query"), timeout=timeout))
                docs = [c for c in reply.xml if isinstance(c.tag, str)]
                # The active memory wraps each document: <doc id>DOC<attachment/>*</doc>.
                self.knowledge[kb] = [next((x for x in d if isinstance(x.tag, str) and x.tag != "attachment"), d) if d.tag == "doc" else d for d in docs]
            except HomesimError:
                self.knowledge[kb] = None
        return self.knowledge

    def finish(self) -> list[Verdict]:
        """After :meth:`run`: query the scene model, evaluate every expectation (once)."""
        if self._verdicts is None:
            self.sim_time = self.sim.now
            self.query_knowledge()
            context = {"metrics": self.metric_values(), "knowledge": self.knowledge}
            self._verdicts = self.stage.verdicts(context)
        return self._verdicts

    def metric_values(self) -> dict[str, Any]:
        return {name: obs.summary() for name, obs in self.metrics.items()}

    def complete(self) -> bool:
        """Did the run reach the scenario's end (so its expectations mean something)?"""
        return getattr(self, "sim_time", self.sim.now) >= self.scenario.duration - 1e-9

    def summary(self) -> dict[str, Any]:
        """The run summary (JSON; fields in docs/running.md)."""
        verdicts = self.finish()
        sim_time = getattr(self, "sim_time", self.sim.now)
        cpu = self.stopwatch.cpu()
        return {
            "scenario": self.scenario.name,
            "scenario_file": self.header["scenario_file"],
            "seed": self.sim.seed,
            "sim_time_s": round(sim_time, 6),
            "wall_time_s": round(self.stopwatch.wall(), 3),
            "cpu_time_s": round(cpu, 3),
            "speed_sim_s_per_cpu_s": round(sim_time / cpu, 2) if cpu > 0 else None,
            "peak_memory_mb": round(peak_memory_mb(), 1),
            "verdict": self.verdict(),
            "profile": self.profile,
            "es": {**self.es.summary(), **self._es_arrivals()},
            "deployment": {**self.deployment.as_dict(), "links": {
                name: st.summary() for name, st in self.sim.network.stats().items()}},
            "utterances": [
                {"t": round(u.start, 3), "end": round(u.end, 3), "speaker": u.source, "text": u.text, **({"cut": True} if u.cut else {})}
                for u in self.world.sound.all() if u.start <= sim_time
            ],
            "learned": {kb: None if docs is None else [element_dict(d) for d in docs] for kb, docs in self.knowledge.items()},
            "expectations": [v.as_dict() for v in verdicts],
            "metrics": self.metric_values(),
        }

    def _es_arrivals(self) -> dict[str, Any]:
        """What the supervisor counted of its arrivals: events received, and how many out of creation order."""
        counts = getattr(self.supervisor, "arrivals", None)
        return dict(counts()) if callable(counts) else {}

    def verdict(self) -> str:
        """PASS, FAIL, "not checked" when the run stopped before the scenario's end, or
        "no expectations" when the scenario states none (a run that asserted nothing did not pass)."""
        if not self.complete():
            return "not checked"
        verdicts = self.finish()
        if not verdicts:
            return NO_EXPECTATIONS
        return "PASS" if all(v.passed for v in verdicts) else "FAIL"

    def close(self) -> None:
        self.sim.close()

    def __enter__(self) -> Run:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def resolve_deployment(scenario: Scenario) -> Deployment:
    """The run's deployment: the robot's default document with the scenario's ``<deployment>`` applied."""
    base_dir = Path(scenario.source).parent if scenario.source and not scenario.source.startswith("<") else None
    try:
        return deployment_mod.resolve(ROBOT_DEPLOYMENT, scenario.deployment, base_dir=base_dir, modules=ROBOT_MODULES)
    except InputError as exc:
        raise ScenarioError(exc.message, source=exc.source, line=exc.line, element=exc.element) from exc


def profiles() -> dict[str, str]:
    """The robot's profiles: name -> what it simulates."""
    return dict(robot_profiles.PROFILES)


class ProfileMismatch(ScenarioError):
    """The run asks for one robot profile, the scenario's ``<robot profile>`` says it needs another.

    Not a failure of the robot: a sweep or study reports such runs as skipped (``needs_profile``)."""

    def __init__(self, message: str, *, needs: str, asked: str, **where: Any) -> None:
        super().__init__(message, **where)
        self.needs, self.asked = needs, asked


def resolve_profile(asked: str | None, scenario: Scenario) -> str:
    """The profile a run simulates: ``asked`` (``--profile``) if given, else the scenario's
    ``<robot profile>``, else the default. Unknown names are refused with the known ones; an
    ``asked`` profile other than the one the scenario says it needs is refused
    (:class:`ProfileMismatch`): silently running a scenario's test of the full robot on the
    2005 demonstrator would report the demonstrator's missing abilities as the robot failing."""
    needs = scenario.robot.profile
    for name in (needs, asked):
        if name is not None and name not in robot_profiles.PROFILES:
            raise ScenarioError(f"unknown robot profile {name!r}; known: {', '.join(sorted(robot_profiles.PROFILES))}",
                                source=scenario.source, line=scenario.robot.line, element="robot")
    if asked is not None and needs is not None and asked != needs:
        raise ProfileMismatch(f"the scenario needs robot profile {needs!r} (<robot profile=\"{needs}\">); "
                              f"it cannot run as {asked!r} (run it without --profile, or with --profile {needs})",
                              needs=needs, asked=asked, source=scenario.source, line=scenario.robot.line, element="robot")
    name = asked if asked is not None else needs
    return str(robot_profiles.DEFAULT_PROFILE) if name is None else name


def element_dict(el: etree._Element) -> dict[str, Any]:
    """A knowledge document as JSON: its attributes, and each child element by lower-case tag
    (its ``name=``/text when that is all it says, else its own dict; repeated tags become lists)."""
    out: dict[str, Any] = {"kind": etree.QName(el).localname}
    out.update({str(k): v for k, v in el.attrib.items()})
    for c in el:
        if not isinstance(c.tag, str):
            continue
        key = etree.QName(c).localname.lower()
        value: Any
        if len(c) == 0 and set(c.attrib) <= {"name"} and (c.get("name") or not (c.text or "").strip()):
            value = c.get("name", "")
        elif len(c) == 0 and not c.attrib:
            value = (c.text or "").strip()
        else:
            value = element_dict(c)
        if key in out:
            out[key] = (out[key] if isinstance(out[key], list) else [out[key]]) + [value]
        else:
            out[key] = value
    return out


def run_file(path: str | os.PathLike[str], options: RunOptions = RunOptions(), *,
             on_line: Line | None = None) -> dict[str, Any]:
    """Build, run and summarise one scenario file (notebooks, tests)."""
    with Run.from_file(path, options, on_line=on_line) as run:
        run.run()
        return run.summary()


__all__: Sequence[str] = ("Run", "RunOptions", "RobotConfig", "run_file", "file_digest", "store_digest", "element_dict")
