"""The microphone pair as a bus module (kernels in :mod:`robot.hardware.microphones`).

At its rate it publishes every audible active source on
``/robot/audio/sources`` as ``<sources time><source tdoa bearing level/>...</sources>``
(bearing in degrees, front half-plane: the pair cannot tell front from
back). When an utterance ends it publishes what the recogniser would make
of it on ``/robot/audio/speech``:
``<utterance start end tdoa bearing level wer>recognised words</utterance>``
(TDOA, bearing and level measured with the same noise as the sources).
The robot's own voice is heard too (as a real robot hears itself); its
utterances carry ``self="true"`` so the speech module can ignore them.
"""

from __future__ import annotations

import asyncio
import dataclasses
import math
from typing import TYPE_CHECKING

import numpy as np
from lxml import etree

from homesim.module import Module

from .microphones import MicSpec, hear, recognise, snr_db, word_error_rate

if TYPE_CHECKING:
    from homesim.sim import Simulation
    from homesim.world.acoustics import Utterance
    from homesim.world.world import World

SOURCES = "/robot/audio/sources"
SPEECH = "/robot/audio/speech"


class Microphones(Module):
    """Publishes sound directions and modelled recognition results."""

    def __init__(self, sim: Simulation, world: World, spec: MicSpec | None = None, *, name: str = "microphones") -> None:
        super().__init__(sim, name, host="robot")
        self.world = world
        self.spec = spec or MicSpec()
        self._unthresholded = dataclasses.replace(self.spec, threshold_db=-math.inf)
        self._last = -math.inf

    def _positions(self, utterances: list[Utterance]) -> tuple[np.ndarray, np.ndarray, list[str], list[Utterance]]:
        pts, loud, names, kept = [], [], [], []
        for u in utterances:
            p = self.world.source_point(u.source)
            if p is None:
                continue
            pts.append(p)
            loud.append(u.loudness)
            names.append(u.source)
            kept.append(u)
        return np.array(pts, dtype=float).reshape(-1, 3), np.array(loud, dtype=float), names, kept

    async def run(self) -> None:
        period = 1.0 / self.spec.rate
        while True:
            self.beat()
            now = self.now
            pose = self.world.robot.pose
            active = self.world.sound.active(now)
            pts, loud, names, _ = self._positions(active)
            el = etree.Element("sources", time=f"{now:.6f}")
            for p in hear(pts, loud, names, pose, self.spec, self.rng):
                etree.SubElement(el, "source", tdoa=f"{p.tdoa * 1e6:.2f}", bearing=f"{math.degrees(p.bearing):.3f}", level=f"{p.level:.2f}", unit_tdoa="us")
            self.bus.publish(SOURCES, el)
            for u in self.world.sound.ended(self._last, now):
                self.publish_utterance(u, pose)
            self._last = now
            await asyncio.sleep(period)

    def publish_utterance(self, u: Utterance, pose: tuple[float, float, float]) -> None:
        """Model recognition of a finished utterance against what else was audible."""
        mid = (u.start + u.end) / 2
        pts, loud, names, kept = self._positions([u] + [o for o in self.world.sound.active(mid) if o.n != u.n])
        if not names or names[0] != u.source:
            return  # the speaker left the flat
        heard = {p.truth: p for p in hear(pts, loud, names, pose, self.spec, None)}
        me = heard.get(u.source)
        if me is None:
            return  # too quiet to hear at all
        others = [p.level for n, p in heard.items() if n != u.source]
        centre = pts[0]
        dist = math.hypot(centre[0] - pose[0], centre[1] - pose[1])
        angle = math.atan2(centre[1] - pose[1], centre[0] - pose[0]) - pose[2]
        wer = word_error_rate(dist, angle, snr_db(me.level, others, self.spec.noise_floor_db))
        words = recognise(u.words, wer, self.rng)
        # What goes on the bus is measured, with noise, like every other percept
        # (the noise-free values above only drive the recognition model).
        (noisy,) = hear(pts[:1], loud[:1], names[:1], pose, self._unthresholded, self.rng)
        el = etree.Element(
            "utterance",
            start=f"{u.start:.6f}",
            end=f"{u.end:.6f}",
            tdoa=f"{noisy.tdoa * 1e6:.2f}",
            bearing=f"{math.degrees(noisy.bearing):.3f}",
            level=f"{noisy.level:.2f}",
            wer=f"{wer:.3f}",
        )
        if u.source == "robot":
            el.set("self", "true")
        el.text = " ".join(words)
        self.bus.publish(SPEECH, el, created=u.end)
