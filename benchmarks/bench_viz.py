"""Looking-at-a-run benchmark: the cost of the timeline, the exports and the moment plot, per unit of work.

Run: ``python benchmarks/bench_viz.py [--until 10]``. Records the home tour
to ``--until`` seconds once, then prints process CPU time

- per trace line: reading the Fig. 6 timeline (both passes), the Perfetto export;
- per MCAP message: the MCAP export (including re-creating the run, which dominates);
- per figure: the moment plot (drawing and label placement) and the timeline figure.

Not a test: timings belong here, never in the test suite.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

from homesim.cli import main

ROOT = Path(__file__).resolve().parents[1]


def cpu(fn):  # noqa: ANN001, ANN201
    t0 = time.process_time()
    out = fn()
    return time.process_time() - t0, out


def run(until: float) -> None:
    from homesim.tour.mcap_export import export_mcap
    from homesim.export.perfetto import export_perfetto
    from homesim.traceview import read_timeline
    from homesim.tour.plot_cli import plot_moment_of_trace
    from homesim.viz.timeline import plot_timeline

    with tempfile.TemporaryDirectory() as d:
        trace = Path(d) / "tour.jsonl"
        assert main(["run", str(ROOT / "scenarios/home_tour.xml"), "--until", f"{until:g}", "--quiet", "--trace", str(trace)]) == 0
        lines = sum(1 for _ in trace.open(encoding="utf-8"))
        t_tl, tl = cpu(lambda: read_timeline(trace))
        t_pf, _ = cpu(lambda: export_perfetto(trace, Path(d) / "p.json"))
        t_mc, counts = cpu(lambda: export_mcap(trace, Path(d) / "t.mcap"))
        t_mo, _ = cpu(lambda: plot_moment_of_trace(trace, until / 2))
        t_fig, _ = cpu(lambda: plot_timeline(tl))
        print(f"trace: home_tour to {until:g} s, {lines} lines")
        print(f"timeline read      {1e6 * t_tl / lines:8.1f} us per trace line ({t_tl:.2f} s)")
        print(f"perfetto export    {1e6 * t_pf / lines:8.1f} us per trace line ({t_pf:.2f} s)")
        print(f"mcap export        {1e6 * t_mc / counts['messages']:8.1f} us per MCAP message, re-run included ({t_mc:.2f} s, {counts['messages']} messages)")
        print(f"moment plot        {t_mo:8.2f} s per figure (re-run to {until / 2:g} s included)")
        print(f"timeline figure    {t_fig:8.2f} s per figure ({len(tl.messages)} arrows)")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--until", type=float, default=10.0)
    run(ap.parse_args().until)
