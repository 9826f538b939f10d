"""The air of the flat: who says what, when, how loud.

Every utterance (a person's, the radio's, the robot's own speaker) is an
:class:`Utterance` in the :class:`SoundField`. The microphones read the
active ones (with the source positions from the world) to compute time
differences of arrival and model recognition; people's scripts read the
robot's utterances to react to it ("wait-for robot-says"). Durations come
from the word count, so a long sentence keeps the recogniser busy longer.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

#: Seconds per word and fixed onset/offset, about 150 words per minute.
SECONDS_PER_WORD = 0.4
SPEECH_OVERHEAD = 0.3


def words_of(text: str) -> tuple[str, ...]:
    """The words of an utterance: lower case, punctuation dropped."""
    return tuple(w for w in re.findall(r"[\w']+", text.lower()))


def speech_duration(text: str) -> float:
    """How long saying ``text`` takes (seconds), from its word count."""
    return SPEECH_OVERHEAD + SECONDS_PER_WORD * max(1, len(words_of(text)))


def words_spoken(text: str, duration: float, elapsed: float) -> int:
    """How many words of ``text``, said in ``duration`` seconds, are finished ``elapsed`` seconds in.

    Half the fixed overhead is the onset, then the words take equal shares
    of the rest (of the whole duration when it is shorter than the overhead).
    """
    n = len(words_of(text))
    if n == 0:
        return 0
    speech = duration - SPEECH_OVERHEAD if duration > SPEECH_OVERHEAD else duration
    onset = (duration - speech) / 2
    k = int((elapsed - onset) / (speech / n) + 1e-9) if elapsed > onset else 0
    return max(0, min(n, k))


def first_words(text: str, k: int) -> str:
    """``text`` up to the end of its ``k``-th word (as written: case and punctuation kept)."""
    if k <= 0:
        return ""
    spans = [m.end() for m in re.finditer(r"[\w']+", text)]
    return text if k >= len(spans) else text[: spans[k - 1]]


@dataclass(frozen=True)
class Utterance:
    """One thing said by one source from ``start`` to ``end`` (virtual seconds).

    ``loudness`` is dB SPL at 1 m. ``source`` is "robot", a human's or a
    radio's name. ``n`` numbers utterances in the order they started. An
    utterance cut short by its source's next one keeps only the words
    finished before the cut (``cut`` is True).
    """

    n: int
    source: str
    text: str
    start: float
    end: float
    loudness: float
    cut: bool = False  # cut short: ``text`` holds only the words said before the cut

    @property
    def words(self) -> tuple[str, ...]:
        return words_of(self.text)

    def active(self, t: float) -> bool:
        return self.start <= t < self.end


class SoundField:
    """Every utterance of a run, in start order (an append-only log)."""

    def __init__(self) -> None:
        self._log: list[Utterance] = []

    def say(self, source: str, text: str, t: float, *, loudness: float = 60.0, duration: float | None = None) -> Utterance:
        """Start an utterance at ``t``; the duration defaults to the word count's.

        A source that starts speaking while its previous utterance is still
        going cuts the previous one short (one mouth, one voice): it ends at
        ``t`` with only the words finished by then.
        """
        dur = speech_duration(text) if duration is None else float(duration)
        if dur <= 0:
            raise ValueError(f"an utterance needs a positive duration, not {dur}")
        for i in range(len(self._log) - 1, -1, -1):
            u = self._log[i]
            if u.source == source and u.end > t:
                said = first_words(u.text, words_spoken(u.text, u.end - u.start, t - u.start))
                self._log[i] = Utterance(u.n, u.source, said, u.start, max(u.start, t), u.loudness, cut=True)
                break
        u = Utterance(len(self._log), source, text, t, t + dur, loudness)
        self._log.append(u)
        return u

    def cut(self, source: str, t: float) -> Utterance | None:
        """Silence ``source`` at ``t``: what it is saying ends there with the words finished so far.

        Returns the cut utterance, or None when the source was not speaking.
        """
        for i in range(len(self._log) - 1, -1, -1):
            u = self._log[i]
            if u.source == source and u.start <= t < u.end:
                said = first_words(u.text, words_spoken(u.text, u.end - u.start, t - u.start))
                self._log[i] = Utterance(u.n, u.source, said, u.start, max(u.start, t), u.loudness, cut=True)
                return self._log[i]
        return None

    def active(self, t: float) -> list[Utterance]:
        """Utterances going on at ``t`` (start <= t < end), in start order."""
        return [u for u in self._log if u.start <= t < u.end]

    def ended(self, t0: float, t1: float) -> list[Utterance]:
        """Utterances that ended in (t0, t1], in order of their end."""
        return sorted((u for u in self._log if t0 < u.end <= t1), key=lambda u: (u.end, u.n))

    def by(self, source: str, *, since: float = float("-inf")) -> list[Utterance]:
        """Utterances of one source that started at or after ``since``."""
        return [u for u in self._log if u.source == source and u.start >= since]

    def speaking(self, source: str, t: float) -> Utterance | None:
        """What ``source`` is saying at ``t``, if anything."""
        for u in reversed(self._log):
            if u.source == source and u.start <= t < u.end:
                return u
        return None

    def __len__(self) -> int:
        return len(self._log)

    def since(self, n: int) -> list[Utterance]:
        """Utterances numbered ``n`` and later (what started since a reader's last look)."""
        return self._log[n:]

    def all(self) -> list[Utterance]:
        return list(self._log)
