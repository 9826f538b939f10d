"""Two far-field microphones 28.1 cm apart: time difference of arrival and modelled recognition.

The microphones sit at the front of the upper platform at 1.06 m, one each
side of the robot's axis. For every active sound source the pair measures a
time difference of arrival (TDOA, with noise); the bearing computed from it
lies in the front half-plane because a pair cannot tell front from back: a
source at bearing b and one at 180 deg - b give the same TDOA. Levels fall
with distance (spherical spreading, 20 log10 d); sources below the
detection threshold go unheard.

Speech recognition is modelled, not performed: the words of an utterance
come through with errors whose rate grows with distance, with the angle off
the robot's axis (most from behind) and with competing sources (low
signal-to-noise ratio).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

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
