"""Trace digests of the example scenarios: the check that an optimisation changed nothing.

Run: ``python benchmarks/trace_digest.py [--seeds 0,1] [--until 60] > before.txt``, optimise,
run again and ``diff`` the two outputs. Each line is ``scenario seed sha256 lines`` of the bus
trace written by :class:`homesim.tour.runner.Run` (the same trace as ``homesim run --trace``), so an
optimisation that changes any message, its order or its time shows as a different digest.
Not a benchmark and not a test (it runs whole scenarios); the suite has no short version of it
(``tests/test_trace.py`` checks that a trace is byte-identical across processes).
"""

from __future__ import annotations

import argparse
import hashlib
import io
from pathlib import Path

from homesim.tour.runner import Run, RunOptions

ROOT = Path(__file__).resolve().parents[1]
SCENARIOS = ("two_people_radio.xml", "home_tour.xml")


def trace_digest(path: Path, seed: int, until: float | None = None) -> tuple[str, int]:
    """(sha256 hex, line count) of the trace of ``path`` run with ``seed`` up to ``until``."""
    buf = io.StringIO()
    with Run.from_file(path, RunOptions(seed=seed, until=until, trace=buf)) as run:
        run.run()
        run.finish()
    text = buf.getvalue()
    # The header names the scenario file as given; digest the run, not where the checkout lives.
    text = text.replace(str(ROOT), "<root>")
    return hashlib.sha256(text.encode()).hexdigest(), text.count("\n")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seeds", default="0,1")
    ap.add_argument("--until", type=float, default=None)
    ap.add_argument("scenarios", nargs="*", default=list(SCENARIOS))
    a = ap.parse_args()
    for name in a.scenarios:
        for seed in (int(s) for s in a.seeds.split(",")):
            digest, lines = trace_digest(ROOT / "scenarios" / name, seed, a.until)
            print(f"{name} {seed} {digest} {lines}", flush=True)


if __name__ == "__main__":
    main()
