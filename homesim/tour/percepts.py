"""BIRON's percepts at one moment, read from its bus messages (for drawing over the truth).

:class:`PerceptCollector` keeps the latest message of each channel it reads
(one per channel: bounded) and :meth:`PerceptCollector.percepts` turns them
into :class:`~homesim.viz.percepts.Percepts` in the world frame (tracks
through the robot's true pose and its odometry: ground truth, for plots only).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from ..message import Message
from ..viz.percepts import Percepts, Track, odom_to_world

#: The channels the collector reads.
CHANNELS: tuple[str, ...] = (
    "/robot/laser/scan", "/robot/audio/sources", "/robot/attention/tracks", "/robot/attention/state",
    "/robot/attention/partner", "/robot/camera/faces", "/robot/odometry", "/robot/localisation/pose",
)

#: How recent a sound direction must be to be drawn (the microphones publish every 0.1 s).
SOUND_FRESH_S = 0.2


def _f(el: object, name: str, default: float = 0.0) -> float:
    v = el.get(name)  # type: ignore[attr-defined]
    return default if v in (None, "") else float(v)


class PerceptCollector:
    """Keeps the latest message per percept channel; call it with every message (a dispatcher callback)."""

    def __init__(self) -> None:
        self.latest: dict[str, Message] = {}

    def __call__(self, m: Message) -> None:
        self.latest[m.channel] = m

    def percepts(self, now: float, true_pose: Sequence[float]) -> Percepts:
        """The percepts at ``now`` (the robot's true pose places odom-frame tracks in the world)."""
        p = Percepts()
        m = self.latest.get("/robot/laser/scan")
        if m is not None and "ranges" in m.attachments:
            ranges = np.asarray(m.attachments["ranges"], dtype=float)
            start = math.radians(_f(m.xml, "min_angle"))
            step = math.radians(_f(m.xml, "resolution"))
            p.scan = (start + step * np.arange(len(ranges)), ranges)
        m = self.latest.get("/robot/audio/sources")
        if m is not None and now - m.created < SOUND_FRESH_S:
            p.sound_bearings = [math.radians(_f(s, "bearing")) for s in m.xml.iterfind("source")]
        m = self.latest.get("/robot/attention/state")
        if m is not None:
            p.attention = m.xml.get("state")
            p.selected = m.xml.get("selected") or None
            p.partner = m.xml.get("partner") or None
        odo = self.latest.get("/robot/odometry")
        m = self.latest.get("/robot/attention/tracks")
        if m is not None:
            odom_pose = (0.0, 0.0, 0.0) if odo is None else (_f(odo.xml, "x"), _f(odo.xml, "y"), _f(odo.xml, "theta"))
            T = odom_to_world(true_pose, odom_pose)
            R = T[:2, :2]
            for t in m.xml.iterfind("track"):
                xw, yw, _ = T @ np.array([_f(t, "x"), _f(t, "y"), 1.0])
                c = np.array([[_f(t, "cxx"), _f(t, "cxy")], [_f(t, "cxy"), _f(t, "cyy")]])
                p.tracks.append(Track(str(t.get("id")), float(xw), float(yw), R @ c @ R.T,
                                      t.get("confirmed") == "true", t.get("speaking") == "true"))
        m = self.latest.get("/robot/camera/faces")
        if m is not None and now - m.created < SOUND_FRESH_S:
            x, y, th = true_pose
            for f in m.xml.iterfind("face"):
                b, d = th + math.radians(_f(f, "bearing")), _f(f, "distance")
                p.faces.append((x + d * math.cos(b), y + d * math.sin(b)))
        m = self.latest.get("/robot/localisation/pose")
        if m is not None:
            p.estimate = (_f(m.xml, "x"), _f(m.xml, "y"), _f(m.xml, "theta"))
        return p
