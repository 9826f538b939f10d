"""``python -m benchmarks``: every headline figure of issue 9 in one table, and as JSON.

Run: ``python -m benchmarks [--tiny] [--json FILE]`` (``pip install -e ".[bench]"`` for SimPy and
sismic; without them those rows say so). Prints one table and writes the same rows as JSON
(default ``benchmarks/results.json``; ``--tiny`` writes ``benchmarks/results-tiny.json``).

Rows, each a ratio or rate measured in this run, so machine load cancels out of the ratios:

- ``speed/<scenario>``: simulated seconds per CPU second (``time.process_time``) for the example
  scenario and the home tour, every robot subsystem, metrics and expectations, no trace; the
  aim is 300x (3.3 ms CPU per simulated second);
- ``speed/home_tour.xml --rates hardware``: the same at the PeopleBot's sensor rates (aim 100x);
  ``speed/home_tour.xml, whole process``: ``homesim run`` in a child process, start-up included
  (the issue's measure); ``speed/start-up``: the CPU of a child ``homesim run --until 0.01``
  (interpreter, imports, building, first step; aim < 0.4 s);
- ``stage/<n> people``: the simulated home alone (world, scripted people, all sensors and their bus
  messages, no robot modules) with 1, 3 and 10 people, CPU ms per simulated second (aims: 2 ms
  with one person, 5 ms with ten);
- ``memory/<length>``: peak RSS of the whole robot on a looping home (the example flat with a
  person pacing, so it can run for any length) for a short and a long run, each in a child
  process (:mod:`benchmarks.peak_memory`: the child's own ``VmHWM``; the Python heap's block
  count sampled along the run, and ``tracemalloc`` over the last simulated minute only, in the
  note); memory must not grow with the run's length (aims: the long run under 150 MB and within
  10 % of the short one);
- ``loop/sleep``, ``loop/sleep_gather``, ``loop/pingpong``: the virtual-time loop's events/s over SimPy's
  (``sleep_gather``: the sleep workload through ``run_until_complete(gather(...))``);
- ``supervisor/engine``, ``supervisor/bus``: the execution supervisor's events/s over sismic's;
- ``laser``: 361-beam scans/s, numpy kernel over pymunk's per-ray queries;
- ``bus/publish``, ``bus/publish --strict``: typed messages per CPU second through one publish,
  under the default validation policy (the module's element trusted) and validated (``--strict``);
- ``modules/<name>``: each module's CPU per update and per simulated second in the home tour
  (:mod:`benchmarks.bench_modules`: periodic loops and subscription handlers timed apart).

``--tiny`` runs every row with tiny sizes (a smoke test CI runs, ``tests/test_benchmarks.py``);
its figures mean nothing. Not a test: speed is measured here, never asserted.
"""

from __future__ import annotations

import argparse
import json
import platform
import sys
import time
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Callable

from homesim.tour.runner import ACTORS, Run, RunOptions
from homesim.scenario.loader import load_scenario_text

ROOT = Path(__file__).resolve().parents[1]


@dataclass(frozen=True)
class Sizes:
    """How much work each row does (full figures, or the CI smoke test's tiny ones)."""

    until: float | None  # None: each scenario's whole duration
    stage_seconds: float
    memory_short: float
    memory_long: float
    loop: tuple[int, int, int, int]  # procs, steps, pairs, msgs
    supervisor: tuple[int, int, int]  # engine, bus, sismic events
    scans: int
    publishes: int


FULL = Sizes(None, 30.0, 600.0, 3600.0, (200, 500, 100, 1000), (50_000, 20_000, 10_000), 2000, 20_000)
TINY = Sizes(2.0, 1.0, 1.0, 2.0, (5, 10, 3, 10), (50, 50, 50), 5, 50)


def cpu_run(scenario: Any, options: RunOptions) -> tuple[float, float]:
    """(simulated s, CPU s) of one whole run (``scenario`` a path or a loaded Scenario)."""
    t0 = time.process_time()
    with (Run.from_file(scenario, options) if isinstance(scenario, Path) else Run(scenario, options)) as run:
        run.run()
        run.finish()
        sim = run.sim.now
    return sim, time.process_time() - t0


def child_cpu(args: list[str]) -> float:
    """CPU seconds (user + system) of ``homesim ARGS`` in a child process: the whole
    process, interpreter start, imports and building included (what a user waits for)."""
    import os
    import subprocess

    # The console script's own entry point (homesim has no __main__ module).
    proc = subprocess.Popen([sys.executable, "-c", "import sys; from homesim.cli import main; sys.exit(main())", *args], cwd=ROOT,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode not in (0, 1):  # 1: an expectation failed (still a whole run)
        raise RuntimeError(f"homesim {' '.join(args)} exited {proc.returncode}")
    return usage.ru_utime + usage.ru_stime


def stage_ms(n_people: int, seconds: float) -> float:
    """CPU ms per simulated second of the simulated home alone with ``n_people``."""
    from homesim.sim import Simulation
    from homesim.tour.stage import Stage

    from benchmarks.bench_world import crowd_scenario

    sc = load_scenario_text(crowd_scenario(n_people, seconds), source=f"crowd{n_people}")
    sim = Simulation(seed=1, scenario=sc.name)
    stage = Stage(sim, sc, actors=ACTORS)
    t0 = time.process_time()
    stage.run()
    cpu = time.process_time() - t0
    sim.close()
    return 1000.0 * cpu / seconds


Row = dict[str, Any]


def rows(s: Sizes, only: set[str] | None = None) -> list[Row]:
    """Measure every row (or those whose group is in ``only``), printing each as it comes."""
    out: list[Row] = []

    def add(group: str, name: str, value: float | None, unit: str, aim: str = "", note: str = "") -> None:
        row = {"group": group, "name": name, "value": value, "unit": unit, "aim": aim, "note": note}
        out.append(row)
        shown = "-" if value is None else f"{value:,.2f}"
        print(f"{group + '/' + name:34} {shown:>12} {unit:22} {aim:24} {note}", flush=True)

    def want(group: str) -> bool:
        return only is None or group in only

    print(f"{'row':34} {'value':>12} {'unit':22} {'aim':24} note")
    if want("speed"):
        for name in ("two_people_radio.xml", "home_tour.xml"):
            sim, cpu = cpu_run(ROOT / "scenarios" / name, RunOptions(seed=0, until=s.until))
            add("speed", name, sim / cpu, "sim s / CPU s", ">= 300", f"{1000 * cpu / sim:.2f} ms CPU per sim s")
        sim, cpu = cpu_run(ROOT / "scenarios" / "home_tour.xml", RunOptions(seed=0, until=s.until, strict=True))
        add("speed", "home_tour.xml --strict", sim / cpu, "sim s / CPU s", "", f"{1000 * cpu / sim:.2f} ms CPU per sim s, every message validated")
        sim, cpu = cpu_run(ROOT / "scenarios" / "home_tour.xml", RunOptions(seed=0, until=s.until, rates="hardware"))
        add("speed", "home_tour.xml --rates hardware", sim / cpu, "sim s / CPU s", ">= 100",
            f"{1000 * cpu / sim:.2f} ms CPU per sim s, laser 37.5 Hz, camera 25 Hz")
        until = ["--until", f"{s.until:g}"] if s.until is not None else []
        cpu = child_cpu(["run", "scenarios/home_tour.xml", "--quiet", *until])
        sim = s.until if s.until is not None else 220.0
        add("speed", "home_tour.xml, whole process", sim / cpu, "sim s / CPU s", ">= 300 (stretch 1000)",
            f"homesim run: {cpu:.2f} s CPU, start-up included")
        cpu = child_cpu(["run", "scenarios/home_tour.xml", "--quiet", "--until", "0.01"])
        add("speed", "start-up", cpu, "CPU s", "< 0.4", "homesim run home_tour --until 0.01: start, imports, build, first step, exit")
    if want("stage"):
        for n in (1, 3, 10):
            ms = stage_ms(n, s.stage_seconds)
            add("stage", f"{n} people", ms, "CPU ms / sim s", "<= 2" if n == 1 else ("<= 5" if n == 10 else ""))
    if want("memory"):
        from benchmarks.peak_memory import describe, measure

        short = measure(s.memory_short)
        add("memory", f"{s.memory_short:g} s", short["peak_rss_mib"], "MiB peak RSS", "", describe(short))
        long = measure(s.memory_long)
        add("memory", f"{s.memory_long:g} s", long["peak_rss_mib"], "MiB peak RSS", "< 150, within 10 %",
            f"{100 * (long['peak_rss_mib'] / short['peak_rss_mib'] - 1):+.1f} % over the short run; {describe(long)}")
    if want("loop"):
        from benchmarks import bench_loop as bl

        procs, steps, pairs, msgs = s.loop
        delays = bl._delays(procs, steps, seed=1)
        for name, ours, theirs, args, aim in (("sleep", bl.sleep_homesim, bl.sleep_simpy, (delays,), ">= 0.45"),
                                              ("sleep_gather", bl.sleep_homesim_gather, bl.sleep_simpy, (delays,),
                                               "as sleep"),
                                              ("pingpong", bl.pingpong_homesim, bl.pingpong_simpy, (pairs, msgs), ">= 1.5")):
            repeat = 1 if s == TINY else 3
            t_ours, n = bl._best(ours, *args, repeat=repeat)
            try:
                t_theirs, _ = bl._best(theirs, *args, repeat=repeat)
            except ImportError:
                add("loop", name, None, "x SimPy", aim, "SimPy not installed")
                continue
            add("loop", name, t_theirs / t_ours, "x SimPy", aim, f"{n / t_ours:,.0f} events/s")
    if want("supervisor"):
        from benchmarks import bench_supervisor as bs

        n_engine, n_bus, n_sismic = s.supervisor
        engine = n_engine / bs.run_engine(bs.stream(n_engine))[0]
        total, lat, _ = bs.run_bus(bs.stream(n_bus))
        bus = n_bus / total
        p99 = float(sorted(lat)[int(0.99 * (len(lat) - 1))]) / 1000.0
        try:
            sismic = n_sismic / bs.run_sismic(bs.stream(n_sismic))[0]
        except ImportError:
            add("supervisor", "engine", None, "x sismic", "", "sismic not installed")
            add("supervisor", "bus", None, "x sismic", ">= 2", "sismic not installed")
        else:
            add("supervisor", "engine", engine / sismic, "x sismic", "", f"{engine:,.0f} events/s")
            add("supervisor", "bus", bus / sismic, "x sismic", ">= 2, p99 < 100 us", f"{bus:,.0f} events/s, p99 {p99:.0f} us")
    if want("laser"):
        from benchmarks.bench_world import bench_laser

        ours, theirs = bench_laser(s.scans)
        add("laser", "361 beams", ours / theirs, "x pymunk per-ray", "", f"{ours:,.0f} scans/s")
    if want("bus"):
        from benchmarks.bench_localisation import bare_publish_us

        us = bare_publish_us(s.publishes)
        strict_us = bare_publish_us(s.publishes, strict=True)
        add("bus", "publish", 1e6 / us, "messages / CPU s", "", f"{us:.1f} us per typed publish, no receiver (default: trusted)")
        add("bus", "publish --strict", 1e6 / strict_us, "messages / CPU s", "", f"{strict_us:.1f} us per typed publish, XSD validated")
    if want("modules"):
        from benchmarks.bench_modules import module_costs

        _, _, costs = module_costs(ROOT / "scenarios" / "home_tour.xml", seed=0, until=s.until)
        for c in costs:
            note = "" if c["us_per_update"] is None else f"{c['us_per_update']:.1f} us per update, {c['updates']} updates"
            add("modules", c["module"], c["ms_per_sim_s"], "CPU ms / sim s", "", note)
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks", description=__doc__.split("\n")[0])
    ap.add_argument("--tiny", action="store_true", help="tiny sizes: a smoke test, the figures mean nothing")
    ap.add_argument("--json", type=Path, default=None, help="where to write the rows (default benchmarks/results[-tiny].json)")
    ap.add_argument("--only", default=None, help="comma-separated groups: speed,stage,memory,loop,supervisor,laser,bus,modules")
    ap.add_argument("--memory", default=None, metavar="SHORT,LONG",
                    help="lengths (simulated s) of the two memory runs (default 600,3600)")
    a = ap.parse_args(argv)
    sizes = TINY if a.tiny else FULL
    if a.memory is not None:
        short, long = (float(v) for v in a.memory.split(","))
        sizes = replace(sizes, memory_short=short, memory_long=long)
    only = None if a.only is None else set(a.only.split(","))
    measured = rows(sizes, only)
    path = a.json or ROOT / "benchmarks" / ("results-tiny.json" if a.tiny else "results.json")
    doc = {"machine": platform.platform(), "python": sys.version.split()[0], "tiny": a.tiny,
           "date": time.strftime("%Y-%m-%d"), "rows": measured}
    path.write_text(json.dumps(doc, indent=2) + "\n", encoding="utf-8")
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
