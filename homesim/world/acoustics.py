"""The air of the flat: who says what, when, how loud.

Every utterance (a person's, the radio's, the robot's own speaker) is an
:class:`Utterance` in the :class:`SoundField`. The microphones read the
active ones (with the source positions from the world) to compute time
differences of arrival and model recognition; people's scripts read the
robot's utterances to react to it ("wait-for robot-says"). Durations come
from the word count, so a long sentence keeps the recogniser busy longer.
"""

from __future__ import annotations

import json
import math
import re
import tempfile
import weakref
from collections.abc import Iterable
from dataclasses import astuple, dataclass

#: Seconds per word and fixed onset/offset, about 150 words per minute.
SECONDS_PER_WORD = 0.4
SPEECH_OVERHEAD = 0.3
#: Characters of transcript a sound field keeps in memory; the rest of a long run's goes to a temporary file.
SPOOL_CHARS = 256 * 1024
#: Loudest sound level a source may have (dB SPL at 1 m; homesim/schemas/scenario.xsd has the same bound).
MAX_LOUDNESS_DB = 140.0


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
    """The utterances of a run: the few a listener can still hear or ask about, indexed.

    Listeners ask about the present and the recent past only: what is being
    said now (:meth:`active`, :meth:`speaking`), what ended since their last
    look (:meth:`ended`, a cursor 0.1 s back), what overlapped the middle of
    an utterance that just ended (the recogniser), what someone said in the
    last seconds (:meth:`by` with ``since``). So the live window holds only
    utterances still going or ended less than ``horizon`` seconds (or, if
    longer, the longest utterance so far) before the latest time it was
    told; older ones are dropped when a new utterance starts. Queries about
    the live window cost what it holds (a few dozen utterances), not the
    run's length.

    ``history=True`` (the default) also keeps the run's transcript, one
    record per utterance (its final text after a cut), for :meth:`all`,
    :meth:`by` and :meth:`ended` further back and the run summary; with
    ``history=False`` asking further back than the window raises ValueError.
    The transcript holds the utterances that left the window (final by then:
    only a live utterance is ever cut) as lines of JSON, in memory up to
    :data:`SPOOL_CHARS` and in a temporary file beyond, so a long run's memory
    does not grow with what was said; questions about the forgotten past read
    it back (the summary at the end, asking further back than the window).
    """

    def __init__(self, *, horizon: float = 30.0, history: bool = True) -> None:
        self.horizon = float(horizon)
        self._count = 0
        self._live: list[Utterance] = []  # in start (= n) order
        self._history: _Transcript | None = _Transcript() if history else None
        self._floor = -math.inf  # every utterance that ended at or after this is live
        self._longest = 0.0
        self._said: dict[str, int] = {}

    # ------------------------------------------------------------ changes
    def say(self, source: str, text: str, t: float, *, loudness: float = 60.0, duration: float | None = None) -> Utterance:
        """Start an utterance at ``t``; the duration defaults to the word count's.

        A source that starts speaking while its previous utterance is still
        going cuts the previous one short (one mouth, one voice): it ends at
        ``t`` with only the words finished by then.
        """
        if not 0.0 <= loudness <= MAX_LOUDNESS_DB:  # also NaN; a louder level overflows the microphones' sums
            raise ValueError(f"loudness {loudness!r} dB SPL is outside 0 to {MAX_LOUDNESS_DB:g}")
        dur = speech_duration(text) if duration is None else float(duration)
        if dur <= 0:
            raise ValueError(f"an utterance needs a positive duration, not {dur}")
        live = self._live
        for i in range(len(live) - 1, -1, -1):
            u = live[i]
            if u.source == source and u.end > t:
                said = first_words(u.text, words_spoken(u.text, u.end - u.start, t - u.start))
                self._replace(i, Utterance(u.n, u.source, said, u.start, max(u.start, t), u.loudness, cut=True))
                break
        self._forget(t)
        u = Utterance(self._count, source, text, t, t + dur, loudness)
        self._count += 1
        self._longest = max(self._longest, dur)
        self._said[source] = self._said.get(source, 0) + 1
        self._live.append(u)
        return u

    def cut(self, source: str, t: float) -> Utterance | None:
        """Silence ``source`` at ``t``: what it is saying ends there with the words finished so far.

        Returns the cut utterance, or None when the source was not speaking.
        """
        live = self._live
        for i in range(len(live) - 1, -1, -1):
            u = live[i]
            if u.source == source and u.start <= t < u.end:
                said = first_words(u.text, words_spoken(u.text, u.end - u.start, t - u.start))
                return self._replace(i, Utterance(u.n, u.source, said, u.start, max(u.start, t), u.loudness, cut=True))
        return None

    def _replace(self, i: int, u: Utterance) -> Utterance:
        self._live[i] = u
        return u

    def _forget(self, t: float) -> None:
        """Drop what ended longer ago than the window (bounded memory, bounded queries); the transcript keeps it."""
        floor = t - max(self.horizon, self._longest)
        if floor > self._floor:
            live = self._live
            if any(u.end < floor for u in live):
                if self._history is not None:
                    self._history.add(u for u in live if u.end < floor)
                self._live = [u for u in live if u.end >= floor]
            self._floor = floor

    def _window(self, t: float, what: str) -> list[Utterance]:
        """The utterances to search for a question about times after ``t``."""
        if t >= self._floor:
            return self._live
        if self._history is None:
            raise ValueError(f"{what}: {t:g} s is before the sound field's window (from {self._floor:g} s) and it keeps no history")
        return self.all()

    # ------------------------------------------------------------ questions
    def active(self, t: float) -> list[Utterance]:
        """Utterances going on at ``t`` (start <= t < end), in start order."""
        return [u for u in self._window(t, "active") if u.start <= t < u.end]

    def ended(self, t0: float, t1: float, *, closed: bool = False) -> list[Utterance]:
        """Utterances that ended in (t0, t1] ([t0, t1] with ``closed``), in order of their end."""
        if closed:
            got = [u for u in self._window(t0, "ended") if t0 <= u.end <= t1]
        else:
            got = [u for u in self._window(t0, "ended") if t0 < u.end <= t1]
        if len(got) > 1:
            got.sort(key=lambda u: (u.end, u.n))
        return got

    def by(self, source: str, *, since: float = -math.inf) -> list[Utterance]:
        """Utterances of one source that started at or after ``since``."""
        return [u for u in self._window(since, "by") if u.source == source and u.start >= since]

    def speaking(self, source: str, t: float) -> Utterance | None:
        """What ``source`` is saying at ``t``, if anything."""
        for u in reversed(self._window(t, "speaking")):
            if u.source == source and u.start <= t < u.end:
                return u
        return None

    def __len__(self) -> int:
        """How many utterances started so far (the next one's ``n``)."""
        return self._count

    def since(self, n: int) -> list[Utterance]:
        """Utterances numbered ``n`` and later (what started since a reader's last look)."""
        if n >= self._count:
            return []
        got: list[Utterance] = []
        for u in reversed(self._live):
            if u.n < n:
                break
            got.append(u)
        if len(got) == self._count - n:
            got.reverse()
            return got
        if self._history is None:
            raise ValueError(f"since({n}): utterance {n} is no longer in the sound field's window and it keeps no history")
        return self.all()[n:]

    def said_by(self) -> dict[str, int]:
        """How many utterances each source started (all of the run, history or not)."""
        return dict(self._said)

    def all(self) -> list[Utterance]:
        """Every utterance of the run (the transcript), in start (``n``) order; ValueError without ``history``."""
        if self._history is None:
            raise ValueError("the sound field keeps no history (history=False)")
        got = self._history.read() + self._live
        got.sort(key=lambda u: u.n)  # an utterance leaves the window when it ends, not in start order
        return got


class _Transcript:
    """Final utterances as lines of JSON: in memory up to :data:`SPOOL_CHARS`, then in a
    temporary file (closed with the sound field). Floats are written as ``repr`` writes
    them, so they read back exactly."""

    def __init__(self) -> None:
        self._file = tempfile.SpooledTemporaryFile(max_size=SPOOL_CHARS, mode="w+", encoding="utf-8")
        self._close = weakref.finalize(self, self._file.close)

    def add(self, us: Iterable[Utterance]) -> None:
        f = self._file
        f.seek(0, 2)
        f.write("".join(json.dumps(astuple(u)) + "\n" for u in us))

    def read(self) -> list[Utterance]:
        f = self._file
        f.seek(0)
        return [Utterance(*json.loads(line)) for line in f]
