"""A recorded run as MCAP for Foxglove: every bus channel, poses, laser scans, tracks and the map.

The trace keeps only a digest of each laser scan's ranges and nothing of the
world, so the export re-creates the run (:func:`homesim.tour.tracerun.rerun`,
every trace line compared; a run that departs from the trace stops the
export with ``file:line``) and writes, with virtual time as log and publish
time:

* one channel per bus channel (topic = the channel, schema
  ``homesim.BusMessage``: kind, sender, id, receivers, causes, created, xml,
  attachment digests), each send in bus order;
* ``/tf`` (``foxglove.FrameTransforms``): ``map -> base_link`` (the robot's
  true pose), ``base_link -> laser`` and ``map -> odom`` (where the robot's
  odometry frame truly lies, from its true pose and its odometry) at each
  odometry message, and ``map -> estimate`` (the localiser's pose);
* ``/laser`` (``foxglove.LaserScan`` in ``laser``): every scan with its ranges;
* ``/scene/map`` (``foxglove.SceneUpdate``, once): walls and furniture outlines, room names;
* ``/scene/people`` (10 Hz): each present person as a cylinder with name and words being said
  (ground truth, for viewing only);
* ``/scene/robot`` (once): the robot's footprint, locked to ``base_link``;
* ``/scene/tracks`` (every tracks message, in ``odom``): the robot's person tracks as
  2-sigma spheres with their ids.

All JSON is canonical (sorted keys) and chunks are zstd-compressed, so the
same trace gives a byte-identical file.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from lxml import etree
from mcap.writer import CompressionType, Writer

from .. import __version__
from ..bus import SEND, Observation
from ..message import Message, describe_attachment
from .tracerun import rerun
from ..viz.percepts import odom_to_world
from ..world.bodies import HUMAN_RADIUS, LASER_OFFSET, ROBOT_LENGTH, ROBOT_WIDTH
from ..export import foxglove as fg

#: How often the people are written (Hz of virtual time).
PEOPLE_RATE = 10.0
LASER_HEIGHT = 0.30


class _Mcap:
    """Channels registered on first use; messages written in call order."""

    def __init__(self, fh: Any) -> None:
        self.w = Writer(fh, compression=CompressionType.ZSTD)
        self.w.start(profile="", library=f"homesim {__version__}")
        self.schemas: dict[str, int] = {}
        self.channels: dict[str, int] = {}
        self.seq: dict[int, int] = {}
        self.count = 0

    def channel(self, topic: str, schema: str) -> int:
        if topic not in self.channels:
            if schema not in self.schemas:
                self.schemas[schema] = self.w.register_schema(schema, "jsonschema", fg.dumps(fg.SCHEMAS[schema]))
            self.channels[topic] = self.w.register_channel(topic, "json", self.schemas[schema])
        return self.channels[topic]

    def write(self, topic: str, schema: str, t_ns: int, obj: Any) -> None:
        cid = self.channel(topic, schema)
        n = self.seq.get(cid, 0)
        self.seq[cid] = n + 1
        self.w.add_message(cid, log_time=t_ns, data=fg.dumps(obj), publish_time=t_ns, sequence=n)
        self.count += 1

    def finish(self) -> None:
        self.w.finish()


def _f(el: etree._Element, name: str) -> float:
    return float(el.get(name) or 0.0)


class _Exporter:
    """Watches the re-created run (bus interceptor + world listener) and writes the MCAP as it goes."""

    observes = (SEND,)  # the bus spares it deliveries and drops

    def __init__(self, out: _Mcap, run: Any) -> None:
        self.out = out
        self.run = run
        self.world = run.world
        self.next_people = 0
        self.scans = 0
        self.frames = 0

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
        self.out.write(m.channel, "homesim.BusMessage", t, rec)
        if m.channel == "/robot/laser/scan" and "ranges" in m.attachments:
            self.laser(t, m)
        elif m.channel == "/robot/odometry":
            self.frames_at(t, m)
        elif m.channel == "/robot/localisation/pose":
            x = m.xml
            self.out.write("/tf", "foxglove.FrameTransforms", t, {"transforms": [fg.transform(t, "map", "estimate", _f(x, "x"), _f(x, "y"), _f(x, "theta"))]})
        elif m.channel == "/robot/attention/tracks":
            self.tracks(t, m)

    def laser(self, t: int, m: Message) -> None:
        ranges = np.asarray(m.attachments["ranges"], dtype=float)
        start = math.radians(_f(m.xml, "min_angle"))
        step = math.radians(_f(m.xml, "resolution"))
        self.out.write("/laser", "foxglove.LaserScan", t, {
            "timestamp": fg.stamp(t), "frame_id": "laser", "pose": fg.pose(0.0, 0.0), "start_angle": start,
            "end_angle": start + step * (len(ranges) - 1), "ranges": [float(r) for r in ranges], "intensities": []})
        self.scans += 1

    def frames_at(self, t: int, odo: Message) -> None:
        x, y, th = self.world.robot.pose
        T = odom_to_world((x, y, th), (_f(odo.xml, "x"), _f(odo.xml, "y"), _f(odo.xml, "theta")))
        self.out.write("/tf", "foxglove.FrameTransforms", t, {"transforms": [
            fg.transform(t, "map", "base_link", x, y, th),
            fg.transform(t, "base_link", "laser", LASER_OFFSET, 0.0, 0.0, LASER_HEIGHT),
            fg.transform(t, "map", "odom", float(T[0, 2]), float(T[1, 2]), math.atan2(T[1, 0], T[0, 0])),
        ]})
        self.frames += 1

    def tracks(self, t: int, m: Message) -> None:
        spheres, texts = [], []
        for tr in m.xml.iterfind("track"):
            cov = np.array([[_f(tr, "cxx"), _f(tr, "cxy")], [_f(tr, "cxy"), _f(tr, "cyy")]])
            vals, vecs = np.linalg.eigh(cov)
            vals = np.clip(vals, 1e-6, None)
            ang = math.atan2(vecs[1, 1], vecs[0, 1])
            tx, ty = _f(tr, "x"), _f(tr, "y")
            confirmed = tr.get("confirmed") == "true"
            spheres.append({"pose": fg.pose(tx, ty, 0.05, ang), "size": fg.vec(4 * math.sqrt(vals[1]), 4 * math.sqrt(vals[0]), 0.1),
                            "color": fg.color(0.09, 0.75, 0.81, 0.6 if confirmed else 0.25)})
            texts.append(fg.text(tx, ty, 0.4, str(tr.get("id")) + ("" if confirmed else " (unconfirmed)")))
        self.out.write("/scene/tracks", "foxglove.SceneUpdate", t, {
            "deletions": [{"timestamp": fg.stamp(t), "type": 1, "id": ""}],
            "entities": [fg.entity(t, "odom", "tracks", spheres=spheres, texts=texts)] if spheres else []})

    # ----------------------------------------------------------- the world
    def on_step(self, world: Any) -> None:
        t = int(round(world.time * 1e9))
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
            ents.append(fg.entity(t, "map", f"person/{name}",
                                  cylinders=[{"pose": fg.pose(x, y, h.height / 2, h.heading), "size": fg.vec(2 * HUMAN_RADIUS, 2 * HUMAN_RADIUS, h.height),
                                              "bottom_scale": 1.0, "top_scale": 1.0, "color": fg.color(r, g, b, 0.7)}],
                                  arrows=[{"pose": fg.pose(x, y, h.height * 0.9, h.gaze), "shaft_length": 0.5, "shaft_diameter": 0.03,
                                           "head_length": 0.12, "head_diameter": 0.08, "color": fg.color(1.0, 0.5, 0.05)}],
                                  texts=[fg.text(x, y, h.height + 0.2, label)]))
        self.out.write("/scene/people", "foxglove.SceneUpdate", t, {"deletions": [{"timestamp": fg.stamp(t), "type": 1, "id": ""}], "entities": ents})

    def static(self) -> None:
        """The map (walls, furniture, rooms, objects) and the robot's body, once at t = 0."""
        w = self.world
        lines, texts = [], []
        for ob in w.obstacles:
            pts = [fg.vec(px, py, ob.top if ob.kind != "wall" else 0.0) for px, py in np.asarray(ob.polygon)]
            rgb = (0.2, 0.2, 0.2) if ob.kind == "wall" else (0.55, 0.45, 0.3)
            lines.append({"type": 1, "pose": fg.pose(0, 0), "thickness": 0.03, "scale_invariant": False, "points": pts, "color": fg.color(*rgb)})
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
        self.out.write("/scene/map", "foxglove.SceneUpdate", 0, {"entities": [fg.entity(0, "map", "map", lines=lines, texts=texts, cubes=cubes)]})
        self.out.write("/scene/robot", "foxglove.SceneUpdate", 0, {"entities": [fg.entity(0, "base_link", "robot", cubes=[
            {"pose": fg.pose(0, 0, 0.5), "size": fg.vec(ROBOT_LENGTH, ROBOT_WIDTH, 1.0), "color": fg.color(0.12, 0.37, 0.75, 0.8)}],
            arrows=[{"pose": fg.pose(0, 0, 1.05), "shaft_length": 0.4, "shaft_diameter": 0.04, "head_length": 0.1, "head_diameter": 0.1,
                     "color": fg.color(1, 1, 1)}])]})


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
            mc = _Mcap(fh)
            ex = _Exporter(mc, run)
            ex.static()
            run.sim.bus.add_interceptor(ex)
            run.world.add_listener(ex.on_step)
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
