"""Re-create the run a trace recorded, checking every line, to look at what the trace does not hold.

A trace holds the bus messages (attachments only as digests) but not the
world: where the people truly were, the laser ranges. ``homesim plot`` and
``homesim export --mcap`` get those by running the trace header's scenario,
seed and options again (as ``homesim replay`` does) while comparing each new
trace line with the file's; if the run departs from the trace they stop
with an error naming the first differing line, so a picture or an export
never shows a run other than the one recorded.
"""

from __future__ import annotations

import os
import shutil
import tempfile
import weakref
from pathlib import Path
from typing import IO, Any

from ..errors import HomesimError, InputError
from .runheader import read_run_header
from .runner import Run, RunOptions, file_digest, store_digest
from ..xmlio import open_regular


#: The hint when a trace's run cannot be re-created: a recording needs no scenario file.
STANDALONE = " (a recording, 'homesim run SCENARIO --record FILE.mcap', is drawn and exported from the file alone)"


def run_options(h: dict[str, Any], *, until: float | None, trace: Any, store: Path | None = None) -> RunOptions:
    """The options of the run a checked header (:func:`read_header`) names.

    ``store``: the private copy of the header's store the run uses (:func:`store_copy`); the
    header written by the re-run still names the original.
    """
    memory = None if h["memory"] is None else Path(h["memory"])
    return RunOptions(seed=h["seed"], until=until, trace=trace,
                      memory=store if store is not None and memory is not None else memory,
                      memory_as=memory if store is not None else None, subsystems=h["subsystems"],
                      metrics=h["metrics"], profile=h.get("profile"), rates=h.get("rates"))


def store_copy(h: dict[str, Any]) -> tempfile.TemporaryDirectory[str] | None:
    """A private copy of the store directory a checked header names (its ``*.sqlite`` files and their
    journals), or None if it names none: a replay, plot or export writes what the re-run learns
    there, never to the store the (untrusted) trace names."""
    if h["memory"] is None:
        return None
    tmp = tempfile.TemporaryDirectory(prefix="homesim-replay-store-")
    try:
        for p in sorted(Path(h["memory"]).glob("*.sqlite*")):
            if p.is_file() and (p.suffix == ".sqlite" or p.name.endswith(".sqlite-journal")):
                shutil.copyfile(p, Path(tmp.name) / p.name)
    except OSError as exc:
        tmp.cleanup()
        raise InputError(f"cannot copy the store {h['memory']} named in the header: {exc.strerror}", line=1) from None
    return tmp


def read_header(trace: str | os.PathLike[str]) -> dict[str, Any]:
    """The trace's checked run header (:func:`homesim.tour.runheader.read_run_header`); one-line errors."""
    return read_run_header(trace)


def trace_lines(path: Path) -> IO[bytes]:
    """The trace file opened for line-by-line comparison (bytes: a line that is not UTF-8 is a difference, not a crash)."""
    return os.fdopen(open_regular(path, error=InputError), "rb")


def next_line(fh: IO[bytes]) -> tuple[str, bool]:
    """The next line of a trace opened by :func:`trace_lines` as text, and whether it was UTF-8.

    A line that is not UTF-8 comes back with its bad bytes replaced (U+FFFD),
    so it never equals a line a run writes and is reported where it is.
    """
    raw = fh.readline()
    try:
        return raw.decode("utf-8"), True
    except UnicodeDecodeError:
        return raw.decode("utf-8", errors="replace"), False


class TraceCheck:
    """A text stream for the run's recorder that compares each line with the trace file's."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self.fh = trace_lines(path)
        self.line = 0
        #: The departure found, if any (the loop wraps what a task raises; :meth:`reraise` gives it back plain).
        self.departed: HomesimError | None = None

    def write(self, s: str) -> int:
        self.line += 1
        want, utf8 = next_line(self.fh)
        if self.line > 1 and want != s:  # line 1, the header, names this re-run's own stop time
            why = ("the trace ends here (truncated?)" if not want.endswith("\n") else
                   "the re-run departs from the trace here" + ("" if utf8 else " (the trace's line is not UTF-8 text)"))
            if self.departed is not None:  # the first departure is the one that counts
                raise self.departed
            self.departed = HomesimError(f"{self.path}:{self.line}: {why} "
                                         f"(trace: {want.strip()[:160]!r}; re-run: {s.strip()[:160]!r})")
            raise self.departed
        return len(s)

    def reraise(self, exc: BaseException) -> None:
        """Raise the departure itself (one line: file, line, what) when ``exc`` came from it; else nothing."""
        if self.departed is not None and exc is not self.departed:
            raise self.departed from None

    def flush(self) -> None:
        pass

    def finished(self) -> None:
        """Fail unless every line of the trace was matched (a re-run that ended early is not the run)."""
        rest = next_line(self.fh)[0]
        if rest:
            raise HomesimError(f"{self.path}:{self.line + 1}: the re-run ended before the trace did (trace: {rest.strip()[:160]!r})")

    def close(self) -> None:
        self.fh.close()


def rerun(trace: str | os.PathLike[str], *, until: float | None = None) -> tuple[Run, TraceCheck]:
    """A :class:`Run` that re-creates ``trace``'s run (checked line by line), stopping at ``until``.

    Fails (``HomesimError``) when the header names no run, its scenario file
    is missing or has changed, its ``--memory`` store has changed, or ``until``
    is past the recorded run.
    """
    path = Path(trace)
    h = read_header(path)
    scen = Path(h["scenario_file"])
    if not scen.is_file():
        raise InputError(f"the scenario file {scen} named in the header does not exist{STANDALONE}", source=str(path), line=1)
    if file_digest(scen) != h["scenario_digest"]:
        raise InputError(f"{scen} has changed since the trace was written; the run cannot be re-created{STANDALONE}", source=str(path), line=1)
    if h["memory"] is not None and store_digest(h["memory"]) != h["memory_digest"]:
        raise InputError(f"the store {h['memory']} has changed since the trace was written (the run wrote "
                         "what it learned to it); the run cannot be re-created", source=str(path), line=1)
    end = h["until"]
    if until is not None and end is not None and until > end:
        raise InputError(f"t = {until:g} s is after the end of the recorded run ({end:g} s)", source=str(path))
    stop = until if until is not None else end
    check = TraceCheck(path)
    store = store_copy(h)
    try:
        opts = run_options(h, until=stop, trace=check, store=None if store is None else Path(store.name))
        run = Run.from_file(scen, opts)
    except BaseException:
        check.close()
        if store is not None:
            store.cleanup()
        raise
    if store is not None:
        weakref.finalize(run, store.cleanup)  # the copy lives as long as the run
    if until is not None and until > run.scenario.duration:
        run.close()
        check.close()
        raise InputError(f"t = {until:g} s is after the end of the scenario ({run.scenario.name}: {run.scenario.duration:g} s)", source=str(path))
    return run, check
