"""The memory row measures the run's own process, not the process that started it."""

from __future__ import annotations

import sys

import numpy as np
import pytest

from benchmarks.peak_memory import measure


def _rss_mib() -> float | None:
    """This process's resident set size now (Linux /proc; None elsewhere)."""
    try:
        with open("/proc/self/status", encoding="ascii") as f:
            return next(int(line.split()[1]) / 1024 for line in f if line.startswith("VmRSS:"))
    except (OSError, StopIteration, ValueError):
        return None


@pytest.mark.skipif(not sys.platform.startswith("linux") or _rss_mib() is None, reason="reads /proc")
def test_the_peak_rss_is_the_runs_own_and_not_its_parents():
    """Linux carries the high-water mark of the image an exec replaces into the new one's
    ru_maxrss: a child started from a big parent (python -m benchmarks after its speed rows,
    the test suite) read the parent's size. With 400 MiB more in this process the row must
    still be the run's own (about a hundred MiB)."""
    ballast = np.ones(400 * 2**20 // 8)  # resident: written by ones()
    parent = _rss_mib()
    assert parent is not None and parent > 400
    report = measure(1.0)
    del ballast
    assert 0 < report["peak_rss_mib"] < parent - 300


@pytest.mark.skipif(not sys.platform.startswith("linux") or _rss_mib() is None, reason="reads /proc")
def test_a_runs_summary_reports_its_own_peak_memory_not_its_parents():
    """The summary's peak_memory_mb (homesim.realtime.peak_memory_mb) in a process started
    from one holding 400 MiB more: its own size, not the parent's carried over exec."""
    import subprocess

    ballast = np.ones(400 * 2**20 // 8)
    parent = _rss_mib()
    out = subprocess.run([sys.executable, "-c", "from homesim.realtime import peak_memory_mb; print(peak_memory_mb())"],
                         capture_output=True, text=True, check=True).stdout
    del ballast
    assert parent is not None and parent > 400
    assert 0 < float(out) < parent - 300
