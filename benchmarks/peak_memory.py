"""Peak memory of the whole robot on a long run, measured in a child process.

Run: ``python -m benchmarks.peak_memory SECONDS [SECONDS ...]`` (default 600 3600). Each length
runs in a fresh Python process (``python -m benchmarks.peak_memory --child SECONDS``) exactly as
``homesim run`` would run it (every robot subsystem, metrics and expectations, the summary at
the end), on the looping home (the example flat with one person pacing and talking for ever, so
it can run for any length). What is measured, all of it real and cheap enough for an hour:

- peak RSS of the child: the high-water mark of its own memory since it started Python
  (``VmHWM`` in ``/proc/self/status``, read by the child at the end), the figure the issue's
  "peak memory" asks for (everything: Python heap, numpy, lxml, pymunk). Not ``ru_maxrss``:
  Linux carries the high-water mark of the process image an ``exec`` replaces into it, so a
  child started from a big parent (``python -m benchmarks`` after the speed rows, the test
  suite) reports the parent's size; ``os.wait4``'s ``ru_maxrss`` is the fallback where
  ``/proc`` is missing;
- the Python heap as it goes: ``sys.getallocatedblocks()`` (a counter CPython keeps, no tracing)
  and the RSS now (``/proc/self/statm``) every 60 simulated s, so growth shows as a slope;
- what the last simulated minute left behind: ``tracemalloc`` runs for that minute only (tracing
  the whole hour would cost several times the run) and reports the bytes allocated in it that
  are still held at the end of the run, with the three biggest allocation sites. A run that does
  not grow holds only what replaced older things (the live sound window, the latest readings).

Not a test: nothing is asserted. ``python -m benchmarks --only memory`` prints the same as rows.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
import tracemalloc
from pathlib import Path
from typing import Any

from homesim.realtime import peak_memory_mb

ROOT = Path(__file__).resolve().parents[1]
#: Simulated seconds between samples of the heap and RSS.
SAMPLE_EVERY = 60.0
#: The traced window at the end of the run (simulated seconds).
TRACED = 60.0


def _rss_mib() -> float | None:
    """Resident set size now (Linux ``/proc``; None elsewhere)."""
    try:
        with open("/proc/self/statm", encoding="ascii") as f:
            pages = int(f.read().split()[1])
    except (OSError, ValueError, IndexError):
        return None
    return pages * os.sysconf("SC_PAGE_SIZE") / 2**20


def child(seconds: float) -> dict[str, Any]:
    """Run the looping home for ``seconds`` in this process, sampling as it goes (see the module docstring)."""
    from homesim.tour.runner import Run, RunOptions

    from benchmarks.bench_world import looping_home

    samples: list[tuple[float, int, float | None]] = []
    traced: dict[str, Any] = {}
    t0 = time.process_time()
    with Run(looping_home(seconds), RunOptions(seed=0)) as run:
        trace_from = max(0.0, seconds - TRACED)
        next_sample = 0.0

        def progress(now: float, end: float) -> None:
            nonlocal next_sample
            if now >= next_sample - 1e-9:
                samples.append((now, sys.getallocatedblocks(), _rss_mib()))
                next_sample += SAMPLE_EVERY
            if not tracemalloc.is_tracing() and now >= trace_from - 1e-9 and now < end:
                tracemalloc.start()
                traced["from"] = now

        run.run(progress=progress)
        run.summary()  # the end of a run as `homesim run` ends it (expectations, transcript)
        sim_s = run.sim.now
    if tracemalloc.is_tracing():
        snap = tracemalloc.take_snapshot()
        held, _ = tracemalloc.get_traced_memory()
        tracemalloc.stop()
        top = snap.statistics("lineno")[:3]
        traced.update(held_kib=held / 1024, top=[f"{s.traceback[0].filename.replace(str(ROOT) + os.sep, '')}:"
                                                  f"{s.traceback[0].lineno} {s.size / 1024:.0f} KiB" for s in top])
    samples.append((sim_s, sys.getallocatedblocks(), _rss_mib()))
    return {"seconds": sim_s, "cpu_s": time.process_time() - t0, "samples": samples, "traced": traced,
            "own_peak_rss_mib": peak_memory_mb() or None}


def measure(seconds: float) -> dict[str, Any]:
    """Run :func:`child` in a fresh process; its report plus ``peak_rss_mib``: the child's own
    high-water mark (``os.wait4``'s ``ru_maxrss`` without ``/proc``; see the module docstring)."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")])))
    proc = subprocess.Popen([sys.executable, "-m", "benchmarks.peak_memory", "--child", f"{seconds:g}"],
                            stdout=subprocess.PIPE, cwd=ROOT, env=env)
    assert proc.stdout is not None
    with proc.stdout:
        out = proc.stdout.read()
    _, status, usage = os.wait4(proc.pid, 0)  # this child's own resource usage (Popen.wait would not give it)
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode != 0:
        raise RuntimeError(f"the {seconds:g} s memory run failed (exit {proc.returncode})")
    report: dict[str, Any] = json.loads(out.decode().strip().splitlines()[-1])
    own = report.pop("own_peak_rss_mib", None)
    report["peak_rss_mib"] = own if own is not None else usage.ru_maxrss / 1024  # KiB on Linux
    return report


def describe(r: dict[str, Any]) -> str:
    """One line: peak RSS, the heap's blocks and RSS at the first and last samples, the traced minute."""
    samples = r["samples"]
    # From a sixth of the way (600 s of an hour: what a ten-minute run reaches) to the end.
    first = next(s for s in samples if s[0] >= r["seconds"] / 6 - 1e-9)
    (t_a, b_a, m_a), (t_b, b_b, m_b) = first, samples[-1]
    rss = "" if m_a is None or m_b is None else f", RSS {m_a:.1f} -> {m_b:.1f} MiB"
    tr = r["traced"]
    held = f"; the last {r['seconds'] - tr['from']:g} s left {tr['held_kib']:.0f} KiB held ({', '.join(tr['top'])})" if "held_kib" in tr else ""
    return (f"peak RSS {r['peak_rss_mib']:.1f} MiB; Python heap blocks {b_a:,} at {t_a:g} s -> {b_b:,} at {t_b:g} s"
            f" ({100 * (b_b / b_a - 1):+.1f} %){rss}{held}; {r['cpu_s']:.0f} CPU s")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("seconds", nargs="*", type=float, default=[600.0, 3600.0])
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    a = ap.parse_args(argv)
    if a.child:
        print(json.dumps(child(a.seconds[0])), flush=True)
        return 0
    for s in a.seconds:
        print(f"{s:g} s: {describe(measure(s))}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
