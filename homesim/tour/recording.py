"""A run recorded to MCAP while it runs: a file that stands alone, like a rosbag.

``homesim run SCENARIO --record out.mcap`` writes, as the run goes:

* everything :mod:`homesim.tour.mcap_export` writes for Foxglove: one channel per bus channel
  (``homesim.BusMessage``), ``/tf``, ``/laser`` (every scan with its ranges), ``/scene/map``,
  ``/scene/robot``, ``/scene/people`` and ``/scene/tracks``;
* ``/homesim/map`` (``homesim.Map``, once at t = 0): rooms, walls, furniture and objects as
  polygons and points, what a top-down plot needs;
* ``/homesim/world`` (``homesim.WorldState``, :data:`WORLD_RATE` Hz): the robot's true pose and
  camera pan, every person (position, heading, gaze, legs, torso colour, pointing target, words
  being said) and the other sound sources (ground truth, for viewing and scoring only);
* ``/homesim/trace`` (``homesim.TraceRecords``): every line of the JSON Lines trace
  (:mod:`homesim.trace`) byte for byte, sends, deliveries and drops, in batches (each message one
  JSON document ``{"lines": [line, ...]}``, a batch within 0.1 s of virtual time, logged at its
  last line's time); the trace header is the ``homesim.trace``
  metadata record. So ``homesim trace``, ``plot --timeline`` and
  ``export --perfetto`` read a recording as they read a trace.
* metadata ``homesim.run``: scenario name, file and digest, seed, robot profile, deployment,
  the homesim, Python, numpy and mcap versions; ``homesim.scenario``: the scenario file's text.

Why MCAP and not more lines in the JSON Lines trace: the trace is what ``homesim replay`` checks
byte for byte and what ``benchmarks/trace_digest.py`` digests; it records the bus (what the robot
saw), never the world. Putting ground truth and the laser's ranges into it would make every trace
several times larger (the ranges are most of a recording) for every run, change every digest, and
mix the truth into the robot's log. The recording is asked for (``--record``) and holds both.

The file is written to ``out.mcap.part`` and renamed when the run is closed, so a file named
``out.mcap`` is always a finished MCAP file; a run stopped early (Ctrl-C, an error) keeps what it
recorded, with ``homesim.stopped`` metadata (reason, virtual time) saying it is partial. Same scenario, seed and options give a byte-identical recording
(virtual time only; canonical JSON; no wall time in the metadata).
"""

from __future__ import annotations

import os
import platform
from json.encoder import encode_basestring as _json_str
from pathlib import Path
from typing import Any

import numpy as np

from .. import __version__
from ..bus import Observation
from ..export import foxglove as fg
from ..trace import header_line, observation_line
from .mcap_export import PEOPLE_RATE, FoxgloveViews, McapFile

#: How often the world's truth is written (Hz of virtual time; the people of ``/scene/people`` too).
WORLD_RATE = PEOPLE_RATE
TRACE_CHANNEL = "/homesim/trace"
#: The trace's lines are written in batches of at most this much virtual time and this many lines.
TRACE_BATCH_S = 0.1
TRACE_BATCH_NS = 100_000_000
TRACE_BATCH_LINES = 1024
WORLD_CHANNEL = "/homesim/world"
MAP_CHANNEL = "/homesim/map"

_ANY = {"type": "object"}
#: The recording's own schemas (JSON Schema; the fields are described in docs/running.md).
SCHEMAS: dict[str, dict[str, Any]] = {
    "homesim.TraceRecords": {"title": "homesim.TraceRecords", "type": "object", "required": ["lines"],
                             "description": "consecutive lines of the homesim JSON Lines trace, each as a string, byte for byte",
                             "properties": {"lines": {"type": "array", "items": {"type": "string"}}}},
    "homesim.WorldState": {"title": "homesim.WorldState", "type": "object", "required": ["t", "robot", "people", "sources"],
                           "properties": {"t": {"type": "number"}, "robot": _ANY, "people": {"type": "array"}, "sources": {"type": "array"}}},
    "homesim.Map": {"title": "homesim.Map", "type": "object", "required": ["scenario", "bounds", "rooms", "obstacles", "objects"],
                    "properties": {"scenario": {"type": "string"}, "bounds": {"type": "array"}, "rooms": {"type": "array"},
                                   "obstacles": {"type": "array"}, "objects": {"type": "array"}}},
}


def _r(v: float) -> float:
    """Truth rounded to 0.1 mm / 0.1 mrad: plenty for a plot, and a third of the bytes."""
    return round(float(v), 4)


def world_map(world: Any) -> dict[str, Any]:
    """The flat as plain data: rooms, obstacles (walls, furniture, table legs), objects, bounds."""
    return {
        "scenario": world.scenario.name,
        "bounds": [float(b) for b in world.bounds()],
        "rooms": [{"name": r.name, "polygon": np.asarray(r.polygon, dtype=float).round(4).tolist()} for r in world.scenario.rooms],
        "obstacles": [{"name": o.name, "kind": o.kind, "polygon": np.asarray(o.polygon, dtype=float).round(4).tolist(),
                       "bottom": float(o.bottom), "top": float(o.top)} for o in world.obstacles],
        "objects": [{"name": name, "x": _r(o.x), "y": _r(o.y), "size": float(o.size), "colour": [float(c) for c in o.colour]}
                    for name, o in world.objects.items()],
    }


def world_state(world: Any) -> dict[str, Any]:
    """The truth at this moment: robot pose and camera pan, people, other sound sources."""
    t = world.time
    people = []
    for name, h in world.humans.items():
        u = world.sound.speaking(name, t)
        point = h.pointing.target if h.pointing is not None and h.hand_point() is not None else None
        people.append({"name": name, "present": bool(h.present), "x": _r(h.position[0]), "y": _r(h.position[1]),
                       "heading": _r(h.heading), "gaze": _r(h.gaze), "height": float(h.height),
                       "torso": [float(c) for c in h.torso], "legs": np.asarray(h.leg_centres(), dtype=float).round(4).tolist(),
                       "pointing": None if point is None else [_r(point[0]), _r(point[1]), _r(point[2])],
                       "saying": None if u is None else u.text})
    sources = []
    for name, (sx, sy, sz) in world.sources.items():
        u = world.sound.speaking(name, t)
        sources.append({"name": name, "x": float(sx), "y": float(sy), "z": float(sz), "saying": None if u is None else u.text})
    x, y, th = world.robot.pose
    return {"t": t, "robot": {"x": _r(x), "y": _r(y), "theta": _r(th), "pan": _r(world.ptu[0]), "tilt": _r(world.ptu[1])},
            "people": people, "sources": sources}


def versions() -> dict[str, str]:
    """The versions a recording names (no wall time, no host name: the file stays reproducible)."""
    import mcap

    return {"homesim": __version__, "python": platform.python_version(), "numpy": np.__version__,
            "mcap": getattr(mcap, "__version__", "unknown")}


class _TraceLines:
    """The JSON Lines trace, line for line, on ``/homesim/trace`` (an interceptor).

    Lines are written in batches, one MCAP message per batch (a message per line cost more than
    the rest of the recording): a batch holds the lines of at most :data:`TRACE_BATCH_S` of virtual
    time and at most :data:`TRACE_BATCH_LINES` lines, as one JSON document ``{"lines": [...]}`` (so
    any MCAP reader decodes it); its log time is its last line's, so every line at or after ``t``
    is in a batch logged at or after ``t``, and the recording ends when the trace does.
    """

    def __init__(self, out: McapFile) -> None:
        self.out = out
        self.seq = 0
        self.lines: list[str] = []
        self.first = 0
        self.last = 0

    def __call__(self, obs: Observation) -> None:
        if self.lines and (obs.t_ns - self.first >= TRACE_BATCH_NS or len(self.lines) >= TRACE_BATCH_LINES):
            self.flush()
        if not self.lines:
            self.first = obs.t_ns
        self.seq += 1
        self.last = obs.t_ns
        self.lines.append(observation_line(obs, self.seq))

    def flush(self) -> None:
        if self.lines:
            data = '{"lines":[' + ",".join(map(_json_str, self.lines)) + "]}"
            self.out.write_json(TRACE_CHANNEL, "homesim.TraceRecords", self.last, data.encode("utf-8"))
            self.lines.clear()


class Recorder:
    """Writes a live run to MCAP (attach before :meth:`Run.run`; :meth:`close` after :meth:`Run.finish`).

    The Foxglove channels come from the export's :class:`~homesim.tour.mcap_export.FoxgloveViews`
    (its public interface, the same schemas), so a recording and an export cannot drift apart;
    this class adds homesim's own channels and metadata.
    """

    def __init__(self, run: Any, path: str | os.PathLike[str]) -> None:
        self.run = run
        self.world = run.world
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.tmp = self.path.with_name(self.path.name + ".part")
        self.fh = open(self.tmp, "wb")
        self.out = mc = McapFile(self.fh, {name: fg.dumps(schema) for name, schema in SCHEMAS.items()})
        self.next_world = 0
        self.closed = False
        h = run.header
        scen = h.get("scenario_file")
        info = {"scenario": run.scenario.name, "scenario_file": str(scen or ""), "scenario_digest": str(h.get("scenario_digest") or ""),
                "seed": str(run.sim.seed), "profile": str(run.profile), "deployment": str(run.deployment.name),
                "until": "" if h.get("until") is None else repr(float(h["until"])), "duration": repr(float(run.scenario.duration)),
                **{f"version.{k}": v for k, v in versions().items()}}
        mc.metadata("homesim.run", info)
        mc.metadata("homesim.trace", {"header": header_line(run.scenario.name, run.sim.seed, {"run": h})})
        if scen and Path(scen).is_file():
            mc.metadata("homesim.scenario", {"file": Path(scen).name, "xml": Path(scen).read_text(encoding="utf-8")})
        # The laser's ranges rounded to 0.1 mm (a real scanner's are mm; a third of the bytes and of the encoding time).
        self.views = FoxgloveViews(mc, run, ranges_decimals=4)
        self.views.attach()
        mc.write(MAP_CHANNEL, "homesim.Map", 0, world_map(self.world))
        self.lines = _TraceLines(mc)
        run.sim.bus.add_interceptor(self.lines)
        self.world.add_listener(self.on_world)
        self.on_world(self.world)  # the truth at the start (the world's first step comes later)

    @property
    def scans(self) -> int:
        return self.views.scans

    def on_world(self, world: Any) -> None:
        t = int(round(world.time * 1e9))
        if t < self.next_world:
            return
        period = int(1e9 / WORLD_RATE)
        self.next_world = (t // period + 1) * period  # on the grid of whole periods (a plot at 10 s finds the state at 10 s)
        self.out.write(WORLD_CHANNEL, "homesim.WorldState", t, world_state(world))

    def close(self, stopped: str | None = None) -> dict[str, int]:
        """Finish the file and give it its name; return counts (channels, messages, scans).

        ``stopped``: why the run ended early (Ctrl-C, an error); the partial recording is kept, like
        ``ros2 bag record``'s, with the ``homesim.stopped`` metadata saying why and at what virtual time.
        """
        if not self.closed:
            self.closed = True
            self.views.detach()
            if self.lines in self.run.sim.bus._interceptors:
                self.run.sim.bus.remove_interceptor(self.lines)
            self.world.remove_listener(self.on_world)
            self.lines.flush()
            if stopped is not None:
                self.out.metadata("homesim.stopped", {"reason": stopped, "t": repr(float(self.run.sim.now))})
            self.out.finish()
            self.fh.close()
            os.replace(self.tmp, self.path)
        return {"channels": len(self.out.channels), "messages": self.out.count, "scans": self.views.scans}

    def abandon(self) -> None:
        """Remove the partial file (the recorder itself failed: nothing whole can be written)."""
        if not self.closed:
            self.closed = True
            self.fh.close()
            self.tmp.unlink(missing_ok=True)


def record(run: Any, path: str | os.PathLike[str]) -> Recorder:
    """Start recording ``run`` to ``path`` (MCAP); needs the mcap library (``homesim[export]``)."""
    return Recorder(run, path)
