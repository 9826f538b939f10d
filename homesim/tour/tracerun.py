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

import json
import os
from pathlib import Path
from typing import Any

from ..errors import HomesimError, InputError
from .runner import Run, RunOptions, file_digest, store_digest
from ..trace import TRACE_FORMAT
from ..xmlio import open_regular


def read_header(trace: str | os.PathLike[str]) -> dict[str, Any]:
    """The trace's header line (a dict); a clear error when the file is not a homesim trace."""
    try:
        with os.fdopen(open_regular(trace, error=InputError), encoding="utf-8") as fh:
            header = json.loads(fh.readline(1 << 20))
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise InputError(f"not a homesim trace ({exc})", source=str(trace), line=1) from exc
    if not isinstance(header, dict) or header.get("homesim_trace") != TRACE_FORMAT:
        raise InputError(f"not a homesim trace (no 'homesim_trace': {TRACE_FORMAT} header)", source=str(trace), line=1)
    return header


class TraceCheck:
    """A text stream for the run's recorder that compares each line with the trace file's."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self.fh = os.fdopen(open_regular(path, error=InputError), encoding="utf-8")
        self.line = 0
        #: The departure found, if any (the loop wraps what a task raises; :meth:`reraise` gives it back plain).
        self.departed: HomesimError | None = None

    def write(self, s: str) -> int:
        self.line += 1
        want = self.fh.readline()
        if self.line > 1 and want != s:  # line 1, the header, names this re-run's own stop time
            why = "the trace ends here (truncated?)" if not want.endswith("\n") else "the re-run departs from the trace here"
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
        rest = self.fh.readline()
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
    header = read_header(path)
    h = header.get("run")
    if not isinstance(h, dict):
        raise InputError("the header does not name a run (write the trace with 'homesim run --trace')", source=str(path), line=1)
    scen = Path(str(h.get("scenario_file")))
    if not scen.is_file():
        raise InputError(f"the scenario file {scen} named in the header does not exist", source=str(path), line=1)
    if file_digest(scen) != h.get("scenario_digest"):
        raise InputError(f"{scen} has changed since the trace was written; the run cannot be re-created", source=str(path), line=1)
    if h.get("memory") is not None and h.get("memory_digest") is not None and store_digest(h["memory"]) != h["memory_digest"]:
        raise InputError(f"the store {h['memory']} has changed since the trace was written (the run wrote "
                         "what it learned to it); the run cannot be re-created", source=str(path), line=1)
    end = h.get("until")
    if until is not None and end is not None and until > end:
        raise InputError(f"t = {until:g} s is after the end of the recorded run ({end:g} s)", source=str(path))
    stop = until if until is not None else end
    check = TraceCheck(path)
    try:
        opts = RunOptions(seed=h.get("seed"), until=stop, trace=check,  # type: ignore[arg-type]
                          memory=None if h.get("memory") is None else Path(h["memory"]),
                          subsystems=None if h.get("subsystems") is None else tuple(h["subsystems"]),
                          metrics=None if h.get("metrics") is None else tuple(h["metrics"]))
        run = Run.from_file(scen, opts)
    except BaseException:
        check.close()
        raise
    if until is not None and until > run.scenario.duration:
        run.close()
        check.close()
        raise InputError(f"t = {until:g} s is after the end of the scenario ({run.scenario.name}: {run.scenario.duration:g} s)", source=str(path))
    return run, check
