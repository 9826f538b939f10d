"""Two far-field microphones 28.1 cm apart: time difference of arrival and modelled recognition.

The microphones sit at the front of the upper platform at 1.06 m, one each
side of the robot's axis. For every active sound source the pair measures a
time difference of arrival (TDOA, with noise); the bearing computed from it
lies in the front half-plane because a pair cannot tell front from back: a
source at bearing b and one at 180 deg - b give the same TDOA. Levels fall
with distance (spherical spreading, 20 log10 d); sources below the
detection threshold go unheard.

What a frame of the two channels shows is the *mixture*
(:func:`mixture_peaks`): sources whose time differences lie closer than the
cross-correlation resolves merge into one peak (power-weighted), a source
far quieter than the loudest is masked, and a frame shows at most
``max_peaks`` peaks. Levels fall with distance and lose a fixed amount per
wall and closed piece of furniture crossed (:func:`path_loss_db`).
:class:`OnsetTracker` turns frame peaks into reported directions with an
onset delay (and jitter) and an offset hangover, as an energy detector does.

Speech recognition is modelled, not performed: the words of an utterance
come through with errors whose rate grows with distance, with the angle off
the robot's axis (most from behind) and with competing sources (low
signal-to-noise ratio). The recogniser never knows its error rate; it
reports a confidence computed from its per-word scores, which are lower for
the words it got wrong (:func:`recognise_scored`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

SPEED_OF_SOUND = 343.0

#: Words a recogniser tends to produce when it gets a word wrong.
FILLERS = ("the", "a", "and", "is", "it", "this", "to", "uh", "in", "that")


@dataclass(frozen=True)
class MicSpec:
    spacing: float = 0.281
    height: float = 1.06
    offset: float = 0.10  # metres ahead of the robot's centre
    tdoa_noise: float = 2.0e-5  # seconds (about 0.7 cm of path difference)
    threshold_db: float = 35.0  # quietest level heard
    noise_floor_db: float = 30.0  # room noise for the signal-to-noise ratio
    rate: float = 10.0
    # The mixture (what one cross-correlation over two channels can tell apart):
    resolution_tdoa: float = 1.2e-4  # seconds: closer peaks merge (about 8.4 deg at broadside)
    mask_db: float = 12.0  # a source this much quieter than the loudest is masked
    max_peaks: int = 2  # peaks a frame's cross-correlation reliably shows
    level_jitter_db: float = 3.0  # frame-to-frame energy fluctuation of speech (std)
    onset_frames: int = 1  # frames above threshold before a direction is reported ...
    onset_jitter: float = 0.3  # ... plus one more with this probability
    hangover_frames: int = 2  # frames a direction is still reported after its energy fell
    track_tdoa: float = 1.0e-4  # seconds: a peak continues last frame's direction within this
    # Walls and closed furniture between source and microphones:
    wall_loss_db: float = 20.0  # per wall crossed (an open door passes the sound)
    furniture_loss_db: float = 6.0  # per closed piece (standing on the floor, reaching the line)
    # The recogniser's beam (delay-and-sum steered at /robot/audio/steer):
    beam_width: float = math.radians(15.0)  # half-width: sources within it are in the beam
    beam_rejection_db: float = 6.0  # how much a source outside the beam is suppressed
    aec_db: float = 50.0  # echo cancellation of what the robot's own speaker plays
    boundary_jitter: float = 0.05  # seconds (std) on the start/end the recogniser segments


def mic_positions(pose: tuple[float, float, float], spec: MicSpec) -> np.ndarray:
    """World positions (2, 3) of the left and right microphones."""
    x, y, th = pose
    c, s = math.cos(th), math.sin(th)
    cx, cy = x + spec.offset * c, y + spec.offset * s
    h = spec.spacing / 2
    return np.array([[cx - s * h, cy + c * h, spec.height], [cx + s * h, cy - c * h, spec.height]])


def tdoa(sources: np.ndarray, mics: np.ndarray, c: float = SPEED_OF_SOUND) -> np.ndarray:
    """Exact arrival time at the left minus at the right microphone, per source (N, 3) -> (N,).

    Negative when the source is nearer the left microphone (to the robot's left).
    """
    s = np.atleast_2d(np.asarray(sources, dtype=float))
    dl = np.linalg.norm(s - mics[0], axis=1)
    dr = np.linalg.norm(s - mics[1], axis=1)
    return (dl - dr) / c


def pair_geometry(points: list[tuple[float, float, float]], pose: tuple[float, float, float], spec: MicSpec,
                  c: float = SPEED_OF_SOUND) -> tuple[list[float], list[float], tuple[float, float]]:
    """Per source point: the TDOA (s, as :func:`tdoa`) and the distance to the pair's centre (the
    mean of :func:`mic_positions`), and that centre's (x, y); in plain floats, for the few sources
    of a frame, with exactly the numpy path's operations (the same floats)."""
    x, y, th = pose
    co, si = math.cos(th), math.sin(th)
    cx, cy = x + spec.offset * co, y + spec.offset * si
    h = spec.spacing / 2
    z = spec.height
    lx, ly, rx, ry = cx - si * h, cy + co * h, cx + si * h, cy - co * h
    mx, my, mz = (lx + rx) / 2, (ly + ry) / 2, (z + z) / 2
    dts, dists = [], []
    for px, py, pz in points:
        ax, ay, az = px - lx, py - ly, pz - z
        bx, by, bz = px - rx, py - ry, pz - z
        dl = math.sqrt(ax * ax + ay * ay + az * az)
        dr = math.sqrt(bx * bx + by * by + bz * bz)
        dts.append((dl - dr) / c)
        ex, ey, ez = px - mx, py - my, pz - mz
        dists.append(math.sqrt(ex * ex + ey * ey + ez * ez))
    return dts, dists, (mx, my)


def bearing_from_tdoa(dt: np.ndarray | float, spec: MicSpec, c: float = SPEED_OF_SOUND) -> np.ndarray:
    """The front-half-plane bearing (radians, + left) for a TDOA (far-field model).

    The true bearing is this value or ``pi - value``: the pair cannot tell.
    """
    return np.arcsin(np.clip(-np.asarray(dt, dtype=float) * c / spec.spacing, -1.0, 1.0))


def level_db(loudness: np.ndarray | float, distance: np.ndarray | float) -> np.ndarray:
    """Sound level at ``distance`` for a source of ``loudness`` dB at 1 m."""
    return np.asarray(loudness, dtype=float) - 20.0 * np.log10(np.maximum(np.asarray(distance, dtype=float), 0.3))


@dataclass(frozen=True)
class SoundPercept:
    """One active source as the microphone pair hears it."""

    tdoa: float
    bearing: float  # front half-plane, robot frame
    level: float
    truth: str  # which source it was (kept out of bus messages)


def hear(
    positions: np.ndarray,
    loudness: np.ndarray,
    names: list[str],
    pose: tuple[float, float, float],
    spec: MicSpec,
    rng: np.random.Generator | None,
) -> list[SoundPercept]:
    """TDOA, bearing and level for each source (positions (N, 3)) loud enough to hear."""
    if len(names) == 0:
        return []
    mics = mic_positions(pose, spec)
    centre = mics.mean(axis=0)
    dist = np.linalg.norm(np.atleast_2d(positions) - centre, axis=1)
    levels = level_db(loudness, dist)
    dts = tdoa(positions, mics)
    if rng is not None:
        dts = dts + rng.normal(0.0, spec.tdoa_noise, dts.shape[0])
        levels = levels + rng.normal(0.0, 1.0, levels.shape[0])
    max_dt = spec.spacing / SPEED_OF_SOUND
    dts = np.clip(dts, -max_dt, max_dt)
    bearings = bearing_from_tdoa(dts, spec)
    return [SoundPercept(float(dts[i]), float(bearings[i]), float(levels[i]), names[i]) for i in range(len(names)) if levels[i] >= spec.threshold_db]


def word_error_rate(distance: float, angle: float, snr_db: float) -> float:
    """Expected word error rate of distant speech recognition.

    About 3 % close up and straight ahead; +6 % per metre beyond 1 m; off
    the robot's axis the error grows with the angle, +12 % at 90 degrees and
    +24 % from straight behind (the microphones face forward and the robot's
    body shadows speech from behind); and up to +60 % when competing sources
    drown the speaker (low SNR). Capped at 95 %. Non-decreasing in distance
    and in the absolute (wrapped) angle.
    """
    wer = 0.03 + 0.06 * max(0.0, distance - 1.0) + 0.12 * (1.0 - math.cos(angle))
    wer += 0.6 / (1.0 + math.exp((snr_db - 5.0) / 3.0))
    return min(0.95, wer)


def snr_db(level: float, others: list[float], noise_floor_db: float) -> float:
    """Signal-to-noise ratio of one source against the others plus room noise (power sum)."""
    noise = 10.0 ** (noise_floor_db / 10.0) + sum(10.0 ** (o / 10.0) for o in others)
    return level - 10.0 * math.log10(noise)


def recognise(words: tuple[str, ...], wer: float, rng: np.random.Generator | None) -> tuple[str, ...]:
    """Words as the recogniser returns them: each wrong with probability ``wer``.

    A wrong word is substituted by a filler (two thirds) or deleted (one third).
    Exact when ``rng`` is None.
    """
    if rng is None or wer <= 0:
        return tuple(words)
    out: list[str] = []
    for w in words:
        if rng.random() >= wer:
            out.append(w)
        elif rng.random() < 2.0 / 3.0:
            out.append(FILLERS[int(rng.integers(len(FILLERS)))])
    return tuple(out)


# ------------------------------------------------------------ honest mixture
def path_loss_db(source_xy: np.ndarray, listener_xy: tuple[float, float], walls: tuple[np.ndarray, np.ndarray], furniture: tuple[np.ndarray, np.ndarray],
    spec: MicSpec) -> np.ndarray:
    """Loss (dB) per source (N, 2) from the walls and closed furniture on the straight path.

    ``walls`` and ``furniture`` are edge arrays (a, b), each (M, 2), of closed
    polygons: a straight path through one polygon crosses two of its edges,
    so each pair of crossings costs one ``wall_loss_db`` (or
    ``furniture_loss_db``). Door gaps are not walls, so sound passes them.
    """
    from homesim.geometry import segments_intersect

    src = np.atleast_2d(np.asarray(source_xy, dtype=float))
    loss = np.zeros(src.shape[0])
    q = np.asarray(listener_xy, dtype=float)
    qs = np.broadcast_to(q, src.shape)
    for (a, b), per in ((walls, spec.wall_loss_db), (furniture, spec.furniture_loss_db)):
        if a.shape[0] == 0 or per == 0 or src.shape[0] == 0:
            continue
        hits = np.count_nonzero(segments_intersect(src, qs, a, b), axis=1)
        loss += per * ((hits + 1) // 2)
    return loss


@dataclass(frozen=True)
class Peak:
    """One direction in a frame of the mixture: TDOA (s) and level (dB)."""

    tdoa: float
    level: float


def mixture_peaks(tdoas: np.ndarray, levels: np.ndarray, spec: MicSpec) -> list[Peak]:
    """The peaks one frame's cross-correlation of the summed signal shows.

    Sources loudest first: one within ``resolution_tdoa`` of a kept peak
    merges into it (TDOA power-weighted, powers summed); one more than
    ``mask_db`` under the loudest is masked; at most ``max_peaks`` peaks;
    peaks under the detection threshold are dropped. Deterministic: noise
    is added by the caller.
    """
    if len(tdoas) == 0:
        return []
    order = np.argsort(-np.asarray(levels), kind="stable")
    loudest = float(levels[order[0]])
    kept: list[list[float]] = []  # [power-weighted tdoa sum, power]
    for i in order:
        p = 10.0 ** (float(levels[i]) / 10.0)
        for k in kept:
            if abs(k[0] / k[1] - float(tdoas[i])) < spec.resolution_tdoa:
                k[0] += p * float(tdoas[i])
                k[1] += p
                break
        else:
            if float(levels[i]) < loudest - spec.mask_db or len(kept) >= spec.max_peaks:
                continue
            kept.append([p * float(tdoas[i]), p])
    peaks = [Peak(k[0] / k[1], 10.0 * math.log10(k[1])) for k in kept]
    return [pk for pk in peaks if pk.level >= spec.threshold_db]


@dataclass
class _Direction:
    tdoa: float
    level: float
    frames: int  # consecutive frames seen
    missing: int  # consecutive frames not seen
    needed: int  # frames before it is reported


@dataclass
class OnsetTracker:
    """Frame peaks -> reported sound directions, with onset delay, jitter and hangover.

    A direction is reported once its peak was present for ``needed`` frames
    in a row (``onset_frames``, one more with probability ``onset_jitter``)
    and keeps being reported (at its last TDOA) for ``hangover_frames`` after
    the peak disappears, as an energy detector with thresholds does.
    """

    spec: MicSpec
    _dirs: list[_Direction] = field(default_factory=list)

    def update(self, peaks: list[Peak], rng: np.random.Generator) -> list[Peak]:
        """Feed one frame's (noisy) peaks; returns the directions reported for it."""
        spec = self.spec
        taken = [False] * len(self._dirs)
        for pk in peaks:
            best, bd = -1, spec.track_tdoa
            for j, d in enumerate(self._dirs):
                if not taken[j] and abs(d.tdoa - pk.tdoa) < bd:
                    best, bd = j, abs(d.tdoa - pk.tdoa)
            if best >= 0:
                d = self._dirs[best]
                d.tdoa, d.level, d.frames, d.missing = pk.tdoa, pk.level, d.frames + 1, 0
                taken[best] = True
            else:
                extra = 1 if rng.random() < spec.onset_jitter else 0
                self._dirs.append(_Direction(pk.tdoa, pk.level, 1, 0, spec.onset_frames + extra))
                taken.append(True)
        for j, d in enumerate(self._dirs):
            if not taken[j]:
                d.missing += 1
        self._dirs = [d for d in self._dirs if d.missing <= spec.hangover_frames and (d.missing == 0 or d.frames >= d.needed)]
        return [Peak(d.tdoa, d.level) for d in self._dirs if d.frames >= d.needed]


def recognise_scored(words: tuple[str, ...], wer: float, rng: np.random.Generator) -> tuple[tuple[str, ...], float]:
    """Recognised words and the recogniser's confidence (0..1) for them.

    Each word is wrong with probability ``wer`` (as :func:`recognise`). The
    recogniser scores each hypothesis word: right words score high
    (Beta(8, 2), mean 0.8), wrong ones low (Beta(3, 4), mean 0.43); a deleted
    word leaves a gap the decoder scores 0.3. The confidence is the mean
    score, so it falls as errors rise, without the error rate ever being
    known to the recogniser.
    """
    out: list[str] = []
    scores: list[float] = []
    for w in words:
        if rng.random() >= wer:
            out.append(w)
            scores.append(float(rng.beta(8.0, 2.0)))
        elif rng.random() < 2.0 / 3.0:
            out.append(FILLERS[int(rng.integers(len(FILLERS)))])
            scores.append(float(rng.beta(3.0, 4.0)))
        else:
            scores.append(0.3)
    conf = float(np.mean(scores)) if scores else 0.0
    return tuple(out), conf
