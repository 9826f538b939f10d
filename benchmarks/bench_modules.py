"""Per-module cost: CPU per update of every module in a whole run, and per simulated second.

Run: ``python benchmarks/bench_modules.py [SCENARIO] [--until S] [--seed N] [--trace]`` (default
the home tour; ``--trace`` records the run's trace to a temporary file, as ``homesim run --trace``
does, so its cost shows in the kernel row). Every module's periodic loop (each wake-up of a task started with ``Simulation.spawn``
is one update) and every subscription handler (each message handled is one update) is timed
with ``time.process_time`` around it, attributed to its task or participant name. What runs
outside those (the loop itself, the bus's routing and delivery, the trace, metrics and
expectations) is the ``(kernel and rest)`` row, so the rows add up to the run's CPU.

The timer costs about a microsecond per update, so the figures are a little high; they rank
the modules and show which one a change made cheaper. Not a test: nothing is asserted.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from collections import defaultdict
from collections.abc import Coroutine
from pathlib import Path
from typing import Any

from homesim.bus import Participant
from homesim.tour.runner import Run, RunOptions
from homesim.sim import Simulation

ROOT = Path(__file__).resolve().parents[1]
_clock = time.process_time


class _Account:
    """CPU seconds and updates per name."""

    def __init__(self) -> None:
        self.cpu: dict[str, float] = defaultdict(float)
        self.updates: dict[str, int] = defaultdict(int)
        self.depth = 0  # nested timing (a handler run inside a timed step) is not counted twice

    def timed(self, name: str, fn: Any, *args: Any) -> Any:
        if self.depth:
            return fn(*args)
        self.depth += 1
        t = _clock()
        try:
            return fn(*args)
        finally:
            self.cpu[name] += _clock() - t
            self.updates[name] += 1
            self.depth -= 1


class _TimedCoroutine(Coroutine[Any, Any, Any]):
    """A coroutine proxy that times each step of the coroutine it wraps."""

    def __init__(self, coro: Coroutine[Any, Any, Any], name: str, account: _Account) -> None:
        self._coro, self._name, self._account = coro, name, account

    def send(self, value: Any) -> Any:
        return self._account.timed(self._name, self._coro.send, value)

    def throw(self, *exc: Any) -> Any:  # type: ignore[override]
        return self._account.timed(self._name, self._coro.throw, *exc)

    def close(self) -> None:
        self._coro.close()

    def __await__(self) -> Any:
        return self


def module_costs(scenario: Path, *, seed: int = 0, until: float | None = None,
                 trace: Path | None = None) -> tuple[float, float, list[dict[str, Any]]]:
    """(simulated s, CPU s, rows) for one run; rows per module, costliest first."""
    account = _Account()
    spawn, subscribe = Simulation.spawn, Participant.subscribe

    def timed_spawn(self: Simulation, coro: Any, *, name: str) -> Any:
        return spawn(self, _TimedCoroutine(coro, name, account), name=name)

    def timed_subscribe(self: Participant, pattern: str, handler: Any = None, **kw: Any) -> Any:
        if handler is not None:
            name, inner = self.name, handler

            def handler(msg: Any) -> Any:
                return account.timed(name, inner, msg)

        return subscribe(self, pattern, handler, **kw)

    Simulation.spawn, Participant.subscribe = timed_spawn, timed_subscribe  # type: ignore[method-assign]
    try:
        with Run.from_file(scenario, RunOptions(seed=seed, until=until, trace=trace)) as run:
            t0 = _clock()
            run.run()
            for rec in run.sim.traces:  # the trace's last gathered lines: part of its cost
                getattr(rec, "flush", rec.stream.flush)()
            cpu = _clock() - t0
            sim_s = run.sim.now
    finally:
        Simulation.spawn, Participant.subscribe = spawn, subscribe  # type: ignore[method-assign]
    rows = [
        {"module": name, "updates": account.updates[name], "us_per_update": 1e6 * c / max(1, account.updates[name]),
         "ms_per_sim_s": 1000.0 * c / sim_s}
        for name, c in account.cpu.items()
    ]
    rest = cpu - sum(account.cpu.values())
    rows.append({"module": "(kernel and rest)", "updates": 0, "us_per_update": None, "ms_per_sim_s": 1000.0 * rest / sim_s})
    rows.sort(key=lambda r: -r["ms_per_sim_s"])
    return sim_s, cpu, rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scenario", nargs="?", type=Path, default=ROOT / "scenarios" / "home_tour.xml")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--until", type=float, default=None)
    ap.add_argument("--trace", action="store_true", help="record the trace to a temporary file")
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        trace = Path(tmp) / "trace.jsonl" if a.trace else None
        sim_s, cpu, rows = module_costs(a.scenario, seed=a.seed, until=a.until, trace=trace)
    print(f"{a.scenario.name} seed {a.seed}: {sim_s:g} simulated s in {cpu:.2f} CPU s "
          f"({1000 * cpu / sim_s:.2f} ms per simulated s, {sim_s / cpu:.1f}x real time)")
    print(f"{'module':28} {'updates':>8} {'us/update':>10} {'ms/sim s':>9}")
    for r in rows:
        us = "-" if r["us_per_update"] is None else f"{r['us_per_update']:.1f}"
        print(f"{r['module']:28} {r['updates']:>8} {us:>10} {r['ms_per_sim_s']:>9.2f}")


if __name__ == "__main__":
    main()
