"""The microphone pair and the speech recogniser as a bus module (kernels in :mod:`robot.hardware.microphones`).

What two microphones and one recogniser really deliver, nothing more:

- ``/robot/audio/sources``, every frame (``rate``):
  ``<sources time><source tdoa bearing level unit_tdoa="us"/>...</sources>``,
  the *directions* the mixture shows, not the sources: every active sound
  (people, the radio, the robot's own voice after echo cancellation) is
  summed at the microphones with its level (distance, walls and closed
  furniture crossed, frame-to-frame fluctuation); sources closer than the
  pair resolves merge, a loud one masks a quiet one, at most two peaks
  (:func:`~robot.hardware.microphones.mixture_peaks`); directions appear after
  an onset delay with jitter and stay for a hangover
  (:class:`~robot.hardware.microphones.OnsetTracker`). Bearings lie in the
  front half-plane (a pair cannot tell front from back).
- ``/robot/audio/speech``: ONE recognition stream, from the beam steered at
  ``/robot/audio/steer`` (``<steer bearing="deg"/>`` or ``<steer off="true"/>``,
  sent by the person attention system). An utterance is recognised when the
  beam was on it (the utterance's direction at each moment as the pair
  measures it, its TDOA's bearing in the front half-plane (a mouth above the
  microphones close by reads nearer the axis than it stands), within
  ``beam_width`` of the steering then: the robot
  turns while people talk) for at least half its duration, or when it
  ended: the recogniser keeps the segment's two channels and beamforms the
  whole buffered segment once it decodes, so the very "Hello BIRON" that
  makes its speaker a potential partner is heard although the beam only
  turned to them during it;
  overlapping sound raises the word errors (sources outside the beam count
  ``beam_rejection_db`` less). It publishes
  ``<utterance start end tdoa bearing level confidence>words</utterance>``
  at the utterance's end (start and end as its energy segmentation found
  them, with jitter); the confidence comes from the recogniser's word
  scores, never the true error rate.
- Echo cancellation: the speaker publishes what it plays on
  ``/robot/speaker/status`` (``<speaking text start end/>``,
  ``<interrupted/>``); this module subtracts exactly that signal
  (``aec_db``) from what the microphones hear, so the robot's own voice is
  neither a sound direction nor recognised. The robot's own loudspeaker is
  cancelled from its first sample (the canceller's reference is the sound
  card's output line, not the status message, which comes after the bus's
  latency). What no loudspeaker of the robot plays is not cancelled.
"""

from __future__ import annotations

import asyncio
import math
from typing import TYPE_CHECKING

import numpy as np
from lxml import etree

from homesim.message import Message
from homesim.module import Module
from homesim.geometry import polygon_edges

from .microphones import (
    SPEED_OF_SOUND,
    MicSpec,
    OnsetTracker,
    Peak,
    bearing_from_tdoa,
    level_db,
    mixture_peaks,
    pair_geometry,
    path_loss_db,
    recognise_scored,
    snr_db,
    word_error_rate,
)
from robot.contract import SOURCES, SPEAKER_STATUS, SPEECH, STEER

if TYPE_CHECKING:
    from homesim.sim import Simulation
    from homesim.world.acoustics import Utterance
    from homesim.world.world import World



def _edges(polys: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    if not polys:
        return np.zeros((0, 2)), np.zeros((0, 2))
    pairs = [polygon_edges(p) for p in polys]
    return np.concatenate([p[0] for p in pairs]), np.concatenate([p[1] for p in pairs])


class Microphones(Module):
    """Publishes the mixture's sound directions and the steered beam's recognition results."""

    def __init__(self, sim: Simulation, world: World, spec: MicSpec | None = None, *, name: str = "microphones") -> None:
        super().__init__(sim, name, host="robot")
        self.world = world
        self.spec = spec or MicSpec()
        self._last = -math.inf
        self._onsets = OnsetTracker(self.spec)
        self._walls = _edges([o.polygon for o in world.obstacles if o.kind == "wall"])
        # Closed furniture: standing on the floor (a table's top on legs lets sound through).
        self._furniture = _edges([o.polygon for o in world.obstacles if o.kind == "furniture" and o.bottom <= 0.0 and o.top >= 0.5])
        # The beam's history: (since, bearing or None), the last few seconds only.
        self._steer: list[tuple[float, float | None]] = [(-math.inf, None)]
        # Per utterance under way: seconds with the beam on its direction at that moment (the robot
        # turns while people talk; the beam is steered in the robot frame), seconds heard so far, and
        # whether the beam was on it in the last frame.
        self._on_beam: dict[int, tuple[float, float, bool]] = {}
        # What the speaker announced it plays: (start, text) -> end (the AEC's reference).
        self._played: dict[tuple[float, str], float] = {}
        # Path loss (dB) by (source x, source y, listener): see _path_loss.
        self._losses: dict[tuple[float, float, tuple[float, float]], float] = {}
        self.bus.subscribe(STEER, self._on_steer)
        self.bus.subscribe(SPEAKER_STATUS, self._on_speaker)

    # ------------------------------------------------------------ inputs
    def _on_steer(self, msg: Message) -> None:
        el = msg.xml
        bearing: float | None = None
        if el.get("off") not in ("true", "1"):
            b = float(el.get("bearing", "nan"))
            bearing = math.radians(b) if math.isfinite(b) else None
        self._steer.append((self.now, bearing))

    def _on_speaker(self, msg: Message) -> None:
        el = msg.xml
        if el.tag == "speaking":
            self._played[(round(float(el.get("start", "0")), 6), el.get("text", ""))] = float(el.get("end", "0"))

    def _cancelled(self, u: Utterance) -> bool:
        """Whether the echo canceller has this utterance's signal: the robot's own loudspeaker
        (its reference is the output line on the same sound card, there from the first sample),
        or what the speaker announced playing.

        Why the loudspeaker itself: the status message reaches this module after the bus's
        latency (0.1-0.2 ms on one host since the deployment's links), so the frame taken at the
        instant the robot starts to talk held its own voice at 70 dB from straight ahead, at the
        partner's bearing: the dialog took it for a barge-in and cut its own question
        (tests/scenarios/lang_confirm_always.xml seed 0, "Shall I go to the living room?")."""
        if u.source == "robot":
            return True
        return (round(u.start, 6), u.text) in self._played or any(
            abs(start - u.start) < 1e-6 and u.cut and text.startswith(u.text) for (start, text) in self._played
        )

    # ------------------------------------------------------------ physics of the mixture
    def _levels(self, utterances: list[Utterance], pose: tuple[float, float, float]) -> tuple[np.ndarray, np.ndarray, list[Utterance]]:
        """TDOA (s) and level (dB, before fluctuation) at the pair of each audible utterance."""
        pts, loud, kept = [], [], []
        for u in utterances:
            p = self.world.source_point(u.source)
            if p is None:
                continue
            pts.append(p)
            loud.append(u.loudness - (self.spec.aec_db if self._cancelled(u) else 0.0))
            kept.append(u)
        if not kept:
            return np.zeros(0), np.zeros(0), []
        # mic_positions, tdoa and the distances in plain floats (a frame hears a few sources), the
        # same floats; level_db's logarithm stays numpy's.
        dts, dist, centre = pair_geometry(pts, pose, self.spec)
        levels = level_db(np.array(loud), np.array(dist)) - self._path_loss(pts, centre)
        return np.array(dts), levels, kept

    def _path_loss(self, pts: list[tuple[float, float, float]], centre: tuple[float, float]) -> np.ndarray:
        """:func:`path_loss_db` per source, remembered for the last source and listener positions:
        a person talking stands still and the robot listening mostly does too, so most
        frames ask again what the last one asked. Each source's loss is its own row of
        the computation, so computing only the new ones gives the same numbers."""
        cache = self._losses
        loss = [cache.get((float(p[0]), float(p[1]), centre)) for p in pts]
        todo = [i for i, got in enumerate(loss) if got is None]
        if todo:
            new = path_loss_db(np.array([pts[i][:2] for i in todo], dtype=float), centre, self._walls, self._furniture, self.spec).tolist()
            if len(cache) > 4 * (len(todo) + 32):  # bounded: positions long gone
                cache.clear()
            for k, i in enumerate(todo):
                loss[i] = cache[(float(pts[i][0]), float(pts[i][1]), centre)] = new[k]
        return np.array(loss, dtype=float)

    # ------------------------------------------------------------ main loop
    async def run(self) -> None:
        period = 1.0 / self.spec.rate
        spec, rng = self.spec, self.rng
        max_dt = spec.spacing / SPEED_OF_SOUND
        while True:
            self.beat()
            now = self.now
            pose = self.world.robot.pose
            dts, levels, _ = self._levels(self.world.sound.active(now), pose)
            if len(levels):
                levels = levels + rng.normal(0.0, spec.level_jitter_db, len(levels))
            peaks = []
            for pk in mixture_peaks(dts, levels, spec):
                # The peak's position is less certain when it barely stands out of the room noise.
                snr = max(pk.level - spec.noise_floor_db, 1.0)
                noise = spec.tdoa_noise * min(4.0, math.sqrt(10.0 / snr))
                peaks.append(Peak(float(np.clip(pk.tdoa + rng.normal(0.0, noise), -max_dt, max_dt)), pk.level + float(rng.normal(0.0, 1.0))))
            el = etree.Element("sources", time=f"{now:.6f}")
            for pk in self._onsets.update(peaks, rng):
                b = float(bearing_from_tdoa(pk.tdoa, spec))
                etree.SubElement(el, "source", tdoa=f"{pk.tdoa * 1e6:.2f}", bearing=f"{math.degrees(b):.3f}", level=f"{pk.level:.2f}", unit_tdoa="us")
            self.bus.publish(SOURCES, el, transfer=True)
            self._follow_beam(now, pose, period)
            for u in self.world.sound.ended(self._last, now):
                self.recognise(u, pose)
                self._on_beam.pop(u.n, None)
            self._last = now
            self._forget(now)
            await asyncio.sleep(period)

    def _forget(self, now: float) -> None:
        """Keep only the recent beam history and playback log (bounded memory)."""
        keep = now - 60.0
        if len(self._steer) > 1 and self._steer[1][0] < keep:
            i = 1
            while i < len(self._steer) and self._steer[i][0] < keep:
                i += 1
            self._steer = self._steer[i - 1 :]
        if len(self._played) > 64:
            for k in [k for k, end in self._played.items() if end < keep]:
                del self._played[k]

    def _follow_beam(self, now: float, pose: tuple[float, float, float], period: float) -> None:
        """Accumulate, per utterance under way, how long the beam pointed at its direction as it was
        at that moment (front/back folded), so a person heard while the robot turns stays in the beam."""
        beam = self._steer[-1][1]
        active = self.world.sound.active(now)
        for u in active:
            src = self.world.source_point(u.source)
            if src is None:
                continue
            # The direction the pair hears it from: its TDOA's bearing (the delay a delay-and-sum beam is
            # steered with), not the planar azimuth. A mouth above the microphones and close to the robot
            # is heard nearer the axis than it stands (1.2 m away at 95 deg, 1.74 m tall: read at 60 deg),
            # and the person attention steers the beam at that reading; with the azimuth, a person
            # greeting from the side was never in the beam she was heard from (fresh5/row_partners_hand_over
            # seed 7). ``recognise`` without this history (``_beam_share``) compares the same TDOA bearing.
            dts, _, _ = pair_geometry([src], pose, self.spec)
            front = float(bearing_from_tdoa(dts[0], self.spec))
            on, total, _ = self._on_beam.get(u.n, (0.0, 0.0, False))
            hit = beam is not None and abs(math.asin(max(-1.0, min(1.0, math.sin(beam)))) - front) <= self.spec.beam_width
            self._on_beam[u.n] = (on + (period if hit else 0.0), total + period, hit)
        if len(self._on_beam) > 4 * (len(active) + 8):  # bounded: utterances that ended unseen
            live = {u.n for u in active}
            self._on_beam = {k: v for k, v in self._on_beam.items() if k in live}

    def _beam_share(self, start: float, end: float, front_bearing: float) -> float:
        """Fraction of [start, end) during which the beam was steered at ``front_bearing``."""
        if end <= start:
            return 0.0
        on = 0.0
        hist = self._steer
        for i, (since, b) in enumerate(hist):
            until = hist[i + 1][0] if i + 1 < len(hist) else math.inf
            lo, hi = max(since, start), min(until, end)
            if hi <= lo or b is None:
                continue
            fb = math.asin(max(-1.0, min(1.0, math.sin(b))))  # the pair's beam is front/back symmetric
            if abs(fb - front_bearing) <= self.spec.beam_width:
                on += hi - lo
        return on / (end - start)

    def recognise(self, u: Utterance, pose: tuple[float, float, float]) -> None:
        """Run the recogniser on a finished utterance if the beam was on it; publish words and confidence."""
        spec, rng = self.spec, self.rng
        mid = (u.start + u.end) / 2
        others = [o for o in self.world.sound.active(mid) if o.n != u.n]
        dts, levels, kept = self._levels([u] + others, pose)
        if not kept or kept[0].n != u.n or self._cancelled(u):
            return  # the speaker left the flat, or it is the robot's own (cancelled) voice
        front = float(bearing_from_tdoa(dts[0], spec))
        heard = self._on_beam.get(u.n)
        share = heard[0] / heard[1] if heard is not None and heard[1] > 0 else self._beam_share(u.start, u.end, front)
        at_end = heard is not None and heard[2]
        if levels[0] < spec.threshold_db or (share < 0.5 and not at_end):
            return  # too quiet to segment, or the beam was elsewhere
        interference = []
        for k in range(1, len(kept)):
            ob = float(bearing_from_tdoa(dts[k], spec))
            interference.append(float(levels[k]) - (0.0 if abs(ob - front) <= spec.beam_width else spec.beam_rejection_db))
        src = self.world.source_point(u.source)
        assert src is not None
        dist = math.hypot(src[0] - pose[0], src[1] - pose[1])
        angle = math.atan2(src[1] - pose[1], src[0] - pose[0]) - pose[2]
        wer = word_error_rate(dist, angle, snr_db(float(levels[0]), interference, spec.noise_floor_db))
        words, confidence = recognise_scored(u.words, wer, rng)
        max_dt = spec.spacing / SPEED_OF_SOUND
        noisy_dt = float(np.clip(dts[0] + rng.normal(0.0, spec.tdoa_noise), -max_dt, max_dt))
        start = max(0.0, u.start + float(rng.normal(0.0, spec.boundary_jitter)))
        end = max(start, u.end + float(rng.normal(0.0, spec.boundary_jitter)))
        el = etree.Element(
            "utterance",
            start=f"{start:.6f}",
            end=f"{end:.6f}",
            tdoa=f"{noisy_dt * 1e6:.2f}",
            bearing=f"{math.degrees(float(bearing_from_tdoa(noisy_dt, spec))):.3f}",
            level=f"{float(levels[0]) + float(rng.normal(0.0, 1.0)):.2f}",
            confidence=f"{confidence:.3f}",
        )
        el.text = " ".join(words)
        self.bus.publish(SPEECH, el, created=u.end)
