"""Real-time pacing: the one place in homesim that reads the wall clock.

A simulation normally runs as fast as it can. For live demos, a
:class:`RealtimePacer` makes virtual time follow the wall clock, scaled
(``scale=2.0`` runs twice as fast as real time). The code that runs is the
same; only the loop's clock jumps are delayed, so a paced run produces the
same trace as an unpaced one.
"""

from __future__ import annotations

import time

from .errors import ClockError
from .vloop import NS_PER_S


class RealtimePacer:
    """Sleep before each clock jump so that virtual time tracks wall time x scale."""

    def __init__(self, scale: float = 1.0) -> None:
        if not scale > 0:
            raise ClockError(f"real-time scale must be > 0, got {scale!r}")
        self.scale = scale
        self._origin_wall: float | None = None
        self._origin_ns = 0

    def before_advance(self, from_ns: int, to_ns: int) -> None:
        """Block until the wall clock has caught up with ``to_ns``."""
        now_wall = time.monotonic()
        if self._origin_wall is None:
            self._origin_wall = now_wall
            self._origin_ns = from_ns
        due = self._origin_wall + (to_ns - self._origin_ns) / NS_PER_S / self.scale
        if due > now_wall:
            time.sleep(due - now_wall)


class Stopwatch:
    """Wall-clock and CPU time since construction, for run summaries and speed reports.

    Only the run's reports read it (``wall_time_s``, simulated seconds per
    CPU second); nothing in a run's behaviour or trace depends on it.
    """

    def __init__(self) -> None:
        self._wall0 = time.perf_counter()
        self._cpu0 = time.process_time()

    def wall(self) -> float:
        """Wall-clock seconds since construction."""
        return time.perf_counter() - self._wall0

    def cpu(self) -> float:
        """CPU seconds of this process since construction."""
        return time.process_time() - self._cpu0


def peak_memory_mb() -> float:
    """The process's peak resident set size in MiB (Linux and macOS; 0.0 where unknown).

    On Linux the high-water mark of this process image (``VmHWM``): ``ru_maxrss`` also holds
    that of the image ``exec`` replaced, so a run started from a big process (a benchmark, a
    sweep's parent) would report the parent's size.
    """
    try:
        with open("/proc/self/status", encoding="ascii") as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) / 1024  # kB
    except (OSError, ValueError, IndexError):
        pass  # no /proc (macOS): the resource usage
    try:
        import resource
        import sys
    except ImportError:  # pragma: no cover - Windows
        return 0.0
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return peak / (1024 * 1024) if sys.platform == "darwin" else peak / 1024


#: Longest wall-clock watchdog accepted (seconds; one day).
MAX_WATCHDOG_S = 86_400.0


class Watchdog:
    """Opt-in wall-clock watchdog: after ``seconds`` of wall time, dump every stack and exit.

    A livelock that awaits is caught inside the simulation
    (:class:`homesim.errors.LivelockError`); a busy loop that never awaits
    cannot be seen from inside. This watchdog (``homesim --watchdog N ...``)
    uses :mod:`faulthandler`, whose C thread fires even while Python code
    spins: it writes every thread's stack to stderr and exits with status 1.
    Wall time is read here only, as the determinism rules require; the run's
    results do not depend on it (it only ends a run that would not end).
    """

    def __init__(self, seconds: float, *, stream: object = None) -> None:
        if not (0 < seconds <= MAX_WATCHDOG_S):
            raise ClockError(f"watchdog must be 0 < seconds <= {MAX_WATCHDOG_S:g}, got {seconds!r}")
        self.seconds = seconds
        self.stream = stream

    def __enter__(self) -> Watchdog:
        import faulthandler
        import sys

        stream = self.stream if self.stream is not None else sys.stderr
        stream.write(f"homesim: watchdog armed: every stack is dumped and the run ends after {self.seconds:g} s of wall time\n")  # type: ignore[attr-defined]
        faulthandler.dump_traceback_later(self.seconds, exit=True, file=stream)  # type: ignore[arg-type]
        return self

    def __exit__(self, *exc: object) -> None:
        import faulthandler

        faulthandler.cancel_dump_traceback_later()
