"""Runner benchmark: the whole home tour, its speed and its memory.

Run: ``python benchmarks/bench_runner.py [--scenario scenarios/home_tour.xml] [--seed 0]``.
Prints, for the scenario run end to end by :class:`homesim.tour.runner.Run`
(world, people, hardware, supervisor, every installed robot subsystem,
streaming expectations and metrics, no trace):

- simulated seconds per CPU second and CPU milliseconds per simulated second
  (the project's aim: 300x, 3.3 ms), for the full run and for the same run
  without robot subsystems and without metrics (what each layer costs);
- the Python heap's peak (tracemalloc) for the first half and for the
  whole run: a run that kept every message would peak about twice as high
  for twice the length; streaming expectations and metrics keep it flat;
- the process's peak resident set size.

Not a test: wall-clock and CPU figures belong here, never in the test suite.
"""

from __future__ import annotations

import argparse
import time
import tracemalloc
from pathlib import Path

from homesim.realtime import peak_memory_mb
from homesim.tour.runner import Run, RunOptions

ROOT = Path(__file__).resolve().parents[1]


def timed(path: Path, options: RunOptions) -> tuple[float, float]:
    """(simulated seconds, CPU seconds) of one run."""
    t0 = time.process_time()
    with Run.from_file(path, options) as run:
        run.run()
        run.finish()
        sim = run.sim.now
    return sim, time.process_time() - t0


def heap_peak(path: Path, options: RunOptions) -> float:
    """Peak traced Python heap (MiB) of one run."""
    tracemalloc.start()
    with Run.from_file(path, options) as run:
        run.run()
        run.finish()
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return peak / 2**20


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scenario", type=Path, default=ROOT / "scenarios" / "home_tour.xml")
    ap.add_argument("--seed", type=int, default=0)
    a = ap.parse_args()
    rows = [
        ("full run", RunOptions(seed=a.seed)),
        ("no metrics", RunOptions(seed=a.seed, metrics=())),
        ("no robot subsystems, no metrics", RunOptions(seed=a.seed, subsystems=(), metrics=())),
    ]
    print(f"{a.scenario.name}, seed {a.seed}")
    print(f"{'configuration':34} {'sim s':>7} {'CPU s':>7} {'x real':>7} {'ms CPU/sim s':>13}")
    for label, opts in rows:
        sim, cpu = timed(a.scenario, opts)
        print(f"{label:34} {sim:7.1f} {cpu:7.2f} {sim / cpu:7.1f} {1000 * cpu / sim:13.2f}")
    with Run.from_file(a.scenario, RunOptions(seed=a.seed)) as run:
        half = run.scenario.duration / 2
    first = heap_peak(a.scenario, RunOptions(seed=a.seed, until=half))
    whole = heap_peak(a.scenario, RunOptions(seed=a.seed))
    print(f"Python heap peak: {first:.1f} MiB to {half:g} s, {whole:.1f} MiB to the end")
    print(f"process peak RSS: {peak_memory_mb():.0f} MiB")


if __name__ == "__main__":
    main()
