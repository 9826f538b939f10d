"""A recorded run as MCAP for Foxglove: every bus channel, poses, laser scans, tracks and the map.

The trace keeps only a digest of each laser scan's ranges and nothing of the
world, so the export re-creates the run (:func:`homesim.tour.tracerun.rerun`,
every trace line compared; a run that departs from the trace stops the
export with ``file:line``) and writes, with virtual time as log and publish
time:

* one channel per bus channel (topic = the channel with a leading slash,
  schema ``homesim.BusMessage``: kind, sender, id, receivers, causes,
  created, xml, attachment digests), each send in bus order;
* ``/tf`` (``foxglove.FrameTransforms``): ``map -> base_link`` (the robot's
  true pose), ``base_link -> laser`` and ``map -> odom`` (where the robot's
  odometry frame truly lies, from its true pose and its odometry) at each
  odometry message, and ``map -> estimate`` (the localiser's pose);
* the same poses as ``foxglove.PoseInFrame`` (for plots and the pose panels):
  ``/poses/truth`` (``map``), ``/poses/odometry`` (``odom``),
  ``/poses/estimate`` (``map``);
* ``/laser`` (``foxglove.LaserScan`` in ``laser``): every scan with its ranges;
* ``/transcript`` (``foxglove.Log``): every utterance as it starts, named by
  its speaker (the robot, a person, a radio), for the Log panel, logged and
  stamped at its start (as every stamped message: timestamp = log time);
* ``/scene/map`` (``foxglove.SceneUpdate``, once): walls and furniture outlines, room names, objects;
* ``/scene/people`` (10 Hz): each present person as a cylinder with a gaze
  arrow, her name and the words being said (ground truth, for viewing only),
  one entity per person, deleted when she leaves;
* ``/scene/robot`` (once): the robot's footprint, locked to ``base_link``;
* ``/scene/tracks`` (every tracks message, in ``odom``): the robot's person tracks as
  2-sigma ellipsoids with their ids, one entity per track, deleted when the track ends.

A metadata record ``homesim`` says where the file came from: the trace's
header (scenario, seed, profile, deployment, scenario file and digest,
homesim version of the run) and the exporter's version.

Every ``foxglove.*`` message satisfies Foxglove's official JSON Schema of
its name (:mod:`homesim.export.foxglove`, checked in the tests).
All JSON is canonical (sorted keys) and chunks are zstd-compressed, so the
same trace gives a byte-identical file.
"""

from __future__ import annotations

import heapq
import json
import math
import os
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import numpy as np
from lxml import etree
from mcap.writer import CompressionType, Writer

from .. import __version__
from ..bus import SEND, Observation
from ..message import Message, describe_attachment
from ..trace import read_trace
from .tracerun import rerun
from ..viz.percepts import odom_to_world
from ..world.bodies import HUMAN_RADIUS, LASER_OFFSET, ROBOT_LENGTH, ROBOT_WIDTH
from ..export import foxglove as fg

#: How often the people are written (Hz of virtual time).
PEOPLE_RATE = 10.0
LASER_HEIGHT = 0.30


class McapFile:
    """An MCAP file of JSON channels: channels registered on first use, messages written in log-time order.

    The public interface the recorder (:mod:`homesim.tour.recording`) builds on too: ``schemas``
    names extra JSON Schemas (name -> schema bytes) beside Foxglove's and ``homesim.BusMessage``.
    A transcript line is known only at the end of the world step in which the utterance started,
    up to one step after its start; it is stamped with the start (log time = publish time =
    ``Log.timestamp``). Messages wait up to ``hold_ns`` (the world's step) so that the file stays
    in log-time order; with ``hold_ns=0`` they are written in call order.
    """

    def __init__(self, fh: Any, schemas: Mapping[str, bytes] | None = None, hold_ns: int = 0) -> None:
        self.w = Writer(fh, compression=CompressionType.ZSTD)
        self.w.start(profile="", library=f"homesim {__version__}")
        self.extra = dict(schemas or {})
        self.schemas: dict[str, int] = {}
        self.channels: dict[str, int] = {}
        self.seq: dict[int, int] = {}
        self.count = 0
        self.hold_ns = hold_ns
        self.pending: list[tuple[int, int, int, int, bytes]] = []  # (log time, order, channel, sequence, data)
        self.latest = 0
        self.written = 0  # log time of the last message written

    def channel(self, topic: str, schema: str) -> int:
        """The channel id of ``topic`` (registered with ``schema`` on first use)."""
        if topic not in self.channels:
            if schema not in self.schemas:
                data = self.extra[schema] if schema in self.extra else fg.schema_bytes(schema)
                self.schemas[schema] = self.w.register_schema(schema, "jsonschema", data)
            self.channels[topic] = self.w.register_channel(topic, "json", self.schemas[schema])
        return self.channels[topic]

    def write(self, topic: str, schema: str, t_ns: int, obj: Any) -> None:
        """One message: ``obj`` as canonical JSON, at virtual time ``t_ns`` (log and publish time)."""
        self.write_json(topic, schema, t_ns, fg.dumps(obj))

    def write_json(self, topic: str, schema: str, t_ns: int, data: bytes) -> None:
        """One message already encoded as one JSON document (``data``)."""
        cid = self.channels.get(topic)
        if cid is None:
            cid = self.channel(topic, schema)
        n = self.seq.get(cid, 0)
        self.seq[cid] = n + 1
        if t_ns < self.written:  # later than one step (not seen in the runs measured): written at its time, out of file order
            self.w.add_message(cid, log_time=t_ns, data=data, publish_time=t_ns, sequence=n)
            self.count += 1
            return
        heapq.heappush(self.pending, (t_ns, self.count, cid, n, data))
        self.count += 1
        self.latest = max(self.latest, t_ns)
        self._flush(self.latest - self.hold_ns)

    def _flush(self, upto: int) -> None:
        while self.pending and self.pending[0][0] <= upto:
            t_ns, _, cid, n, data = heapq.heappop(self.pending)
            self.w.add_message(cid, log_time=t_ns, data=data, publish_time=t_ns, sequence=n)
            self.written = t_ns

    def metadata(self, name: str, values: dict[str, str]) -> None:
        """A metadata record (strings only)."""
        self.w.add_metadata(name, values)

    def finish(self) -> None:
        self._flush(self.latest)
        self.w.finish()


_json_str = json.encoder.encode_basestring  # type: ignore[attr-defined]
_float_repr = float.__repr__


def _json_list(items: Any) -> str:
    return "[" + ",".join(map(_json_str, items)) + "]"


def bus_message_json(obj: dict[str, Any]) -> bytes:
    """``fg.dumps(obj)`` of a bus message without attachments, formatted directly (sorted keys, no spaces;
    the same bytes, a third of the time)."""
    return (f'{{"causes":{_json_list(obj["causes"])},"created":{_float_repr(obj["created"])},"id":{_json_str(obj["id"])},'
            f'"kind":{_json_str(obj["kind"])},"receivers":{_json_list(obj["receivers"])},"sender":{_json_str(obj["sender"])},'
            f'"xml":{_json_str(obj["xml"])}}}').encode("utf-8")


def _f(el: etree._Element, name: str) -> float:
    return float(el.get(name) or 0.0)


class FoxgloveViews:
    """Watches a run (bus interceptor + world listener) and writes the Foxglove channels as it goes.

    The public interface the export and the recorder share (so the two write the same channels with
    the same schemas): ``FoxgloveViews(out, run, ranges_decimals=None)``, :meth:`attach` (the map
    and the robot at t = 0, then every send and world step), :meth:`detach`, and the counts
    ``scans`` and ``frames``. ``ranges_decimals``: the laser's ranges rounded to that many decimals
    of a metre (None: as measured).
    """

    observes = (SEND,)  # the bus spares it deliveries and drops

    def __init__(self, out: McapFile, run: Any, *, ranges_decimals: int | None = None) -> None:
        self.out = out
        self.run = run
        self.ranges_decimals = ranges_decimals
        self.world = run.world
        self.next_people = 0
        self.scans = 0
        self.frames = 0
        self.people: set[str] = set()  # entity ids on /scene/people now
        self.track_ids: set[str] = set()  # entity ids on /scene/tracks now
        self.said = 0  # utterances written to /transcript so far

    def attach(self) -> None:
        """Write the static scene and start watching the run's bus and world."""
        self.static()
        self.run.sim.bus.add_interceptor(self)
        self.world.add_listener(self.on_step)

    def detach(self) -> None:
        """Stop watching (the file can then be finished)."""
        bus = self.run.sim.bus
        if self in bus._interceptors:
            bus.remove_interceptor(self)
        self.world.remove_listener(self.on_step)

    # ------------------------------------------------------------- the bus
    def __call__(self, obs: Observation) -> None:
        if obs.event != SEND:
            return
        m = obs.message
        t = obs.t_ns
        rec: dict[str, Any] = {"kind": m.kind, "sender": m.sender, "id": m.id, "receivers": list(obs.receivers), "causes": list(m.causes),
                               "created": m.created_ns / 1e9, "xml": etree.tostring(m.xml, encoding="unicode")}
        if m.attachments:
            rec["attachments"] = {k: describe_attachment(v) for k, v in sorted(m.attachments.items())}
            self.out.write(fg.topic(m.channel), "homesim.BusMessage", t, rec)
        else:
            self.out.write_json(fg.topic(m.channel), "homesim.BusMessage", t, bus_message_json(rec))
        if m.channel == "/robot/laser/scan" and "ranges" in m.attachments:
            self.laser(t, m)
        elif m.channel == "/robot/odometry":
            self.frames_at(t, m)
        elif m.channel == "/robot/localisation/pose":
            x, y, th = _f(m.xml, "x"), _f(m.xml, "y"), _f(m.xml, "theta")
            self.out.write("/tf", "foxglove.FrameTransforms", t, {"transforms": [fg.transform(t, "map", "estimate", x, y, th)]})
            self.out.write("/poses/estimate", "foxglove.PoseInFrame", t, fg.pose_in_frame(t, "map", x, y, th))
        elif m.channel == "/robot/attention/tracks":
            self.tracks(t, m)

    def laser(self, t: int, m: Message) -> None:
        ranges = np.asarray(m.attachments["ranges"], dtype=float)
        start = math.radians(_f(m.xml, "min_angle"))
        step = math.radians(_f(m.xml, "resolution"))
        self.out.write("/laser", "foxglove.LaserScan", t, {
            "timestamp": fg.stamp(t), "frame_id": "laser", "pose": fg.pose(0.0, 0.0), "start_angle": start,
            "end_angle": start + step * (len(ranges) - 1),
            "ranges": [float(r) for r in ranges] if self.ranges_decimals is None else np.round(ranges, self.ranges_decimals).tolist(),
            "intensities": []})
        self.scans += 1

    def frames_at(self, t: int, odo: Message) -> None:
        x, y, th = self.world.robot.pose
        ox, oy, oth = _f(odo.xml, "x"), _f(odo.xml, "y"), _f(odo.xml, "theta")
        T = odom_to_world((x, y, th), (ox, oy, oth))
        self.out.write("/tf", "foxglove.FrameTransforms", t, {"transforms": [
            fg.transform(t, "map", "base_link", x, y, th),
            fg.transform(t, "base_link", "laser", LASER_OFFSET, 0.0, 0.0, LASER_HEIGHT),
            fg.transform(t, "map", "odom", float(T[0, 2]), float(T[1, 2]), math.atan2(T[1, 0], T[0, 0])),
        ]})
        self.out.write("/poses/truth", "foxglove.PoseInFrame", t, fg.pose_in_frame(t, "map", x, y, th))
        self.out.write("/poses/odometry", "foxglove.PoseInFrame", t, fg.pose_in_frame(t, "odom", ox, oy, oth))
        self.frames += 1

    def tracks(self, t: int, m: Message) -> None:
        ents = []
        for tr in m.xml.iterfind("track"):
            cov = np.array([[_f(tr, "cxx"), _f(tr, "cxy")], [_f(tr, "cxy"), _f(tr, "cyy")]])
            vals, vecs = np.linalg.eigh(cov)
            vals = np.clip(vals, 1e-6, None)
            ang = math.atan2(vecs[1, 1], vecs[0, 1])
            tx, ty = _f(tr, "x"), _f(tr, "y")
            confirmed = tr.get("confirmed") == "true"
            tid = str(tr.get("id"))
            ents.append(fg.entity(t, "odom", f"track/{tid}", frame_locked=False,
                                  metadata={"track": tid, "confirmed": str(confirmed).lower(),
                                            "sigma_major_m": f"{math.sqrt(vals[1]):.3f}", "sigma_minor_m": f"{math.sqrt(vals[0]):.3f}"},
                                  spheres=[{"pose": fg.pose(tx, ty, 0.05, ang), "size": fg.vec(4 * math.sqrt(vals[1]), 4 * math.sqrt(vals[0]), 0.1),
                                            "color": fg.color(0.09, 0.75, 0.81, 0.6 if confirmed else 0.25)}],
                                  texts=[fg.text(tx, ty, 0.4, tid + ("" if confirmed else " (unconfirmed)"))]))
        self.track_ids = self._replace("/scene/tracks", t, ents, self.track_ids)

    def _replace(self, topic: str, t: int, ents: list[dict[str, Any]], shown: set[str]) -> set[str]:
        """Write ``ents`` on ``topic``, deleting the entities shown before that are gone now; return the ids shown."""
        now = {e["id"] for e in ents}
        self.out.write(topic, "foxglove.SceneUpdate", t, fg.scene_update(ents, [fg.deletion(t, eid) for eid in sorted(shown - now)]))
        return now

    # ----------------------------------------------------------- the world
    def on_step(self, world: Any) -> None:
        t = int(round(world.time * 1e9))
        for u in world.sound.since(self.said):
            # seen when the step that started it ends; logged at its start (McapFile keeps the file in time order)
            start = int(round(u.start * 1e9))
            self.out.write("/transcript", "foxglove.Log", start, fg.log(start, u.source, u.text))
            self.said = u.n + 1
        if t < self.next_people:
            return
        self.next_people = t + int(1e9 / PEOPLE_RATE)
        ents = []
        for name, h in world.humans.items():
            if not h.present:
                continue
            x, y = h.position
            r, g, b = h.torso
            u = world.sound.speaking(name, world.time)
            label = name + (f': "{u.text}"' if u is not None else "")
            ents.append(fg.entity(t, "map", f"person/{name}", frame_locked=False,
                                  metadata={"name": name, "saying": u.text if u is not None else ""},
                                  cylinders=[{"pose": fg.pose(x, y, h.height / 2, h.heading), "size": fg.vec(2 * HUMAN_RADIUS, 2 * HUMAN_RADIUS, h.height),
                                              "bottom_scale": 1.0, "top_scale": 1.0, "color": fg.color(r, g, b, 0.7)}],
                                  arrows=[{"pose": fg.pose(x, y, h.height * 0.9, h.gaze), "shaft_length": 0.5, "shaft_diameter": 0.03,
                                           "head_length": 0.12, "head_diameter": 0.08, "color": fg.color(1.0, 0.5, 0.05)}],
                                  texts=[fg.text(x, y, h.height + 0.2, label)]))
        self.people = self._replace("/scene/people", t, ents, self.people)

    def static(self) -> None:
        """The map (walls, furniture, rooms, objects) and the robot's body, once at t = 0."""
        w = self.world
        lines, texts = [], []
        for ob in w.obstacles:
            pts = [fg.vec(px, py, ob.top if ob.kind != "wall" else 0.0) for px, py in np.asarray(ob.polygon)]
            rgb = (0.2, 0.2, 0.2) if ob.kind == "wall" else (0.55, 0.45, 0.3)
            lines.append(fg.line(pts, fg.color(*rgb), kind=fg.LINE_LOOP))
            if ob.kind == "furniture":
                c = np.asarray(ob.polygon).mean(axis=0)
                texts.append(fg.text(float(c[0]), float(c[1]), ob.top + 0.05, ob.name, size=11))
        for room in w.scenario.rooms:
            c = np.asarray(room.polygon, dtype=float).mean(axis=0)
            texts.append(fg.text(float(c[0]), float(c[1]), 0.05, room.name))
        cubes, labels = [], []
        for name, o in w.objects.items():
            ox, oy, oz = w.object_point(name)
            side = max(o.size, 0.08)
            cubes.append({"pose": fg.pose(ox, oy, oz), "size": fg.vec(side, side, side), "color": fg.color(*o.colour)})
            labels.append(fg.text(ox, oy, oz + 0.15, name, size=10))
        texts += labels
        meta = {"scenario": w.scenario.name, "rooms": ", ".join(r.name for r in w.scenario.rooms), "objects": ", ".join(w.objects)}
        self.out.write("/scene/map", "foxglove.SceneUpdate", 0,
                       fg.scene_update([fg.entity(0, "map", "map", frame_locked=False, metadata=meta, lines=lines, texts=texts, cubes=cubes)]))
        self.out.write("/scene/robot", "foxglove.SceneUpdate", 0, fg.scene_update([fg.entity(
            0, "base_link", "robot", metadata={"length_m": f"{ROBOT_LENGTH:g}", "width_m": f"{ROBOT_WIDTH:g}"},
            cubes=[{"pose": fg.pose(0, 0, 0.5), "size": fg.vec(ROBOT_LENGTH, ROBOT_WIDTH, 1.0), "color": fg.color(0.12, 0.37, 0.75, 0.8)}],
            arrows=[{"pose": fg.pose(0, 0, 1.05), "shaft_length": 0.4, "shaft_diameter": 0.04, "head_length": 0.1, "head_diameter": 0.1,
                     "color": fg.color(1, 1, 1)}])]))


def run_metadata(trace: str | os.PathLike[str]) -> dict[str, str]:
    """Where an export came from, as an MCAP metadata record: the trace's header (scenario, seed, profile,
    deployment, versions ...; non-string values as canonical JSON) and the exporter's version."""
    header = next(read_trace(trace))
    meta = {"trace": Path(trace).name, "exporter": f"homesim {__version__}"}
    for key, value in header.items():
        if key == "run" and isinstance(value, dict):
            for k, v in value.items():
                meta[f"run.{k}"] = v if isinstance(v, str) else json.dumps(v, sort_keys=True, separators=(",", ":"))
        else:
            meta[key] = value if isinstance(value, str) else json.dumps(value, sort_keys=True, separators=(",", ":"))
    return dict(sorted(meta.items()))


def export_mcap(trace: str | os.PathLike[str], out: str | os.PathLike[str], *,
                progress: Callable[[float, float], None] | None = None) -> dict[str, int]:
    """Re-create ``trace``'s run and write it as MCAP to ``out``; return counts (channels, messages, scans, frames).

    ``progress(now, end)``: told the virtual time the re-created run has reached.
    The file appears only when the whole run has been re-created and matched
    the trace (a partial export is removed).
    """
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = out.with_name(out.name + ".part")
    run, check = rerun(trace)
    try:
        with open(tmp, "wb") as fh, run:
            mc = McapFile(fh, hold_ns=math.ceil(run.world.dt * 1e9) + 1)
            mc.metadata("homesim", run_metadata(trace))  # the scenario, seed, profile and versions it came from
            ex = FoxgloveViews(mc, run)
            ex.attach()
            run.run(progress=progress)
            run.finish()  # the closing questions to the scene model are in the trace too
            check.finished()
            mc.finish()
        os.replace(tmp, out)
    except BaseException as exc:
        tmp.unlink(missing_ok=True)
        check.reraise(exc)
        raise
    finally:
        check.close()
    return {"channels": len(mc.channels), "messages": mc.count, "scans": ex.scans, "frames": ex.frames}
