"""``homesim sweep``: every scenario x seed, in parallel, into one table of verdicts and metrics.

Each run is exactly ``homesim run SCENARIO --seed N`` (the same :class:`~homesim.tour.runner.Run`,
so the same trace and summary); its summary is written to ``OUT/summaries/`` and one row per
run goes into ``OUT/sweep.csv`` and ``OUT/sweep.json``, with an aggregate per scenario (runs,
pass rate, crashes, and the mean and standard deviation of every numeric metric).

Where the runs happen: by default on local processes (``--workers N``, default the CPU count);
with ``--scheduler ADDRESS`` on a Dask distributed cluster (the engine users already run for
sweeps; ``pip install "dask[distributed]"``). How it fails: a run that fails its expectations
is a ``FAIL`` row; a run that raises (a bad scenario, a module crash that fails the run) or
whose worker dies is an ``ERROR`` row with the error, and the sweep goes on. Progress goes to
stderr, one line per finished run.
"""

from __future__ import annotations

import argparse
import csv
import io
import json
import math
import os
import re
import sys
import traceback
from collections import Counter
from collections.abc import Callable, Iterable, Iterator, Mapping
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path
from typing import Any

from .. import cliargs
from ..cliargs import OptionError
from ..errors import HomesimError

Row = dict[str, Any]
PASS, FAIL, ERROR = "PASS", "FAIL", "ERROR"
#: a run not made: the scenario needs another robot profile than the sweep's --profile (not a robot failure)
SKIPPED = "SKIPPED"


#: Most seeds one sweep takes (ranges together).
MAX_SEEDS = 1_000_000


def parse_seeds(text: str) -> list[int]:
    """``"0-99"``, ``"3"``, ``"0-4,10,20-22"`` -> the seeds, in order, without repeats (time linear in the seeds)."""
    out: dict[int, None] = {}
    for part in text.split(","):
        lo, sep, hi = part.strip().partition("-")
        try:
            a = cliargs.seed(lo.strip())
            b = cliargs.seed(hi.strip()) if sep else a
        except argparse.ArgumentTypeError as exc:
            raise OptionError("--seeds", f"{part.strip()!r}: {exc}") from None
        if b < a:
            raise OptionError("--seeds", f"{part.strip()!r}: the range is empty (write low-high)")
        if b - a >= 100_000:
            raise OptionError("--seeds", f"{part.strip()!r}: more than 100000 seeds in one range")
        out.update(dict.fromkeys(range(a, b + 1)))
        if len(out) > MAX_SEEDS:
            raise OptionError("--seeds", f"more than {MAX_SEEDS} seeds in one sweep")
    return list(out)


def _flat(prefix: str, value: Any, into: dict[str, float]) -> None:
    if isinstance(value, bool):
        into[prefix] = float(value)
    elif isinstance(value, (int, float)):
        if math.isfinite(value):
            into[prefix] = float(value)
    elif isinstance(value, dict):
        for k, v in value.items():
            _flat(f"{prefix}.{k}", v, into)


def run_one(scenario: str, seed: int, until: float | None = None, summaries: str | None = None,
            options: dict[str, Any] | None = None, tag: str = "", profile: str | None = None) -> Row:
    """One run, as ``homesim run`` does it; never raises (an error becomes an ``ERROR`` row).

    ``options``: further :class:`~homesim.tour.runner.RunOptions` fields (a study's condition);
    ``tag``: appended to the summary's file name; ``profile``: the robot profile (None: the
    scenario's own, else the default; a condition's ``profile`` option wins)."""
    from .runner import ProfileMismatch, Run, RunOptions

    row: Row = {"scenario": Path(scenario).stem, "file": scenario, "seed": seed, "verdict": ERROR,
                "passed": 0, "expectations": 0, "sim_time_s": None, "cpu_time_s": None, "error": "", "metrics": {}}
    try:
        opts = {"profile": profile, **(options or {})}
        with Run.from_file(Path(scenario), RunOptions(seed=seed, until=until, **opts)) as run:
            run.run()
            verdicts = run.finish()
            summary = run.summary()
    except ProfileMismatch as exc:  # the scenario tests another robot: skipped, said why, not counted as failing
        row.update(verdict=SKIPPED, error=f"needs profile {exc.needs}, skipped (run as {exc.asked})", needs_profile=exc.needs)
        return row
    except Exception as exc:  # a failing run is a row, never the end of the sweep
        row["error"] = f"{type(exc).__name__}: {exc}"[:2000]
        row["traceback"] = traceback.format_exc(limit=8)[-4000:]
        return row
    metrics: dict[str, float] = {}
    for name, value in (summary.get("metrics") or {}).items():
        _flat(name, value, metrics)
    row.update(verdict=summary["verdict"], passed=sum(v.passed for v in verdicts), expectations=len(verdicts),
               sim_time_s=summary["sim_time_s"], cpu_time_s=summary["cpu_time_s"], metrics=metrics,
               failed=[v.as_dict() for v in verdicts if not v.passed])
    if summaries is not None:
        path = Path(summaries) / f"{row['scenario']}-{seed}{tag}.json"
        path.write_text(json.dumps(summary, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")
    return row


def aggregate(rows: list[Row]) -> list[Row]:
    """Per scenario: runs, passes, pass rate, errors, and each metric's mean and spread (std)."""
    out: list[Row] = []
    for name in sorted({r["scenario"] for r in rows}):
        mine = [r for r in rows if r["scenario"] == name]
        keys = sorted({k for r in mine for k in r["metrics"]})
        metrics = {}
        for k in keys:
            vals = [r["metrics"][k] for r in mine if k in r["metrics"]]
            mean = sum(vals) / len(vals)
            std = math.sqrt(sum((v - mean) ** 2 for v in vals) / len(vals))
            metrics[k] = {"mean": mean, "std": std, "n": len(vals)}
        passed = sum(r["verdict"] == PASS for r in mine)
        # A run that checked nothing ("no expectations", or stopped early: "not checked") neither
        # passed nor failed: it is counted apart and left out of the pass rate (None: none checked).
        unchecked = sum(r["verdict"] not in (PASS, FAIL, ERROR) for r in mine)
        checked = len(mine) - unchecked
        out.append({"scenario": name, "runs": len(mine), "checked": checked, "passed": passed,
                    "pass_rate": passed / checked if checked else None,
                    "failed": sum(r["verdict"] == FAIL for r in mine), "errors": sum(r["verdict"] == ERROR for r in mine),
                    "unchecked": unchecked, "metrics": metrics})
    return out


def _local(jobs: list[tuple[str, int]], until: float | None, summaries: str, workers: int,
           profile: str | None = None) -> Iterator[Row]:
    with ProcessPoolExecutor(max_workers=workers) as pool:
        futures = {pool.submit(run_one, s, n, until, summaries, profile=profile): (s, n) for s, n in jobs}
        for fut in as_completed(futures):
            yield _result(fut, futures[fut])


def dask_client(scheduler: Any) -> tuple[Any, Any]:
    """(client, distributed.as_completed) for ``scheduler`` (an address or a ``distributed.Client``).

    The caller closes the client when it is not ``scheduler`` itself. A missing Dask or an
    unreachable scheduler is an :class:`OptionError` on ``--scheduler``.
    """
    try:
        from distributed import Client, as_completed
    except ImportError:
        raise OptionError("--scheduler", 'needs Dask: pip install "dask[distributed]"') from None
    if isinstance(scheduler, Client):
        return scheduler, as_completed
    try:
        return Client(scheduler, timeout=20), as_completed
    except (OSError, ValueError, TimeoutError) as exc:
        raise OptionError("--scheduler", f"cannot reach the Dask scheduler {scheduler!r}: {exc}") from None


def _dask(jobs: list[tuple[str, int]], until: float | None, summaries: str, scheduler: Any,
          profile: str | None = None) -> Iterator[Row]:
    client, dask_completed = dask_client(scheduler)
    try:
        futures = [client.submit(run_one, s, n, until, summaries, profile=profile, pure=False, key=f"homesim-{Path(s).stem}-{n}") for s, n in jobs]
        where = {f.key: job for f, job in zip(futures, jobs)}
        for fut in dask_completed(futures):
            yield _result(fut, where[fut.key])
    finally:
        if client is not scheduler:
            client.close()


def error_row(file: str, seed: int, error: str) -> Row:
    """The row of a run that could not be made (its scenario does not load, its worker died)."""
    return {"scenario": Path(file).stem, "file": file, "seed": seed, "verdict": ERROR, "passed": 0,
            "expectations": 0, "sim_time_s": None, "cpu_time_s": None, "error": error[:2000], "metrics": {}}


def _result(fut: Any, job: tuple[str, int]) -> Row:
    try:
        return fut.result()
    except Exception as exc:  # the worker died (killed, out of memory): still a row
        return error_row(job[0], job[1], f"worker lost: {type(exc).__name__}: {exc}")


def sweep(scenarios: Iterable[Path], seeds: Iterable[int], out: Path, *, until: float | None = None, workers: int | None = None,
          scheduler: Any = None, progress: Callable[[str], None] | None = None,
          refused: Mapping[str, str] | None = None, profile: str | None = None) -> tuple[list[Row], list[Row]]:
    """Run every scenario with every seed; write the table; return (rows, aggregate).

    ``scheduler``: a Dask scheduler address or ``distributed.Client``; None runs on local
    processes (``workers`` of them, default the CPU count). ``refused``: scenario file ->
    why it cannot be run (found before the sweep): its runs are ``ERROR`` rows, not started.
    ``profile``: the robot profile of every run (None: each scenario's own, else the default).
    """
    seeds = list(seeds)
    files = [str(Path(s).resolve()) for s in scenarios]
    bad = {str(Path(f).resolve()): why for f, why in (refused or {}).items()}
    for f in files:
        if f not in bad and not Path(f).is_file():
            raise OptionError("SCENARIO", f"{f}: no such file")
    jobs = [(f, n) for f in files if f not in bad for n in seeds]
    summaries = out / "summaries"
    summaries.mkdir(parents=True, exist_ok=True)
    results = (_dask(jobs, until, str(summaries), scheduler, profile) if scheduler is not None
               else _local(jobs, until, str(summaries), workers or os.cpu_count() or 1, profile))
    rows: list[Row] = [error_row(f, n, bad[f]) for f in files if f in bad for n in seeds]
    ran = 0
    for row in results:
        ran += 1
        rows.append(row)
        if progress is not None:
            extra = f" ({row['error']})" if row["verdict"] == ERROR else ""
            progress(f"[{ran}/{len(jobs)}] {row['scenario']} seed {row['seed']}: {row['verdict']}{extra}")
    rows.sort(key=lambda r: (r["scenario"], r["seed"]))
    agg = aggregate(rows)
    write_table(out, rows, agg)
    return rows, agg


def write_table(out: Path, rows: list[Row], agg: list[Row]) -> None:
    """``sweep.json`` (rows and aggregate) and ``sweep.csv`` (one line per run, a column per metric)."""
    out.mkdir(parents=True, exist_ok=True)
    (out / "sweep.json").write_text(json.dumps({"runs": rows, "aggregate": agg}, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")
    keys = sorted({k for r in rows for k in r["metrics"]})
    buf = io.StringIO()
    w = csv.writer(buf)
    w.writerow(["scenario", "seed", "verdict", "passed", "expectations", "sim_time_s", "cpu_time_s", "error", *keys])
    for r in rows:
        w.writerow([r["scenario"], r["seed"], r["verdict"], r["passed"], r["expectations"], r["sim_time_s"], r["cpu_time_s"],
                    r["error"], *(r["metrics"].get(k, "") for k in keys)])
    (out / "sweep.csv").write_text(buf.getvalue(), encoding="utf-8")


def sweep_command(a: argparse.Namespace) -> int:
    """``homesim sweep``: the table, and one line per scenario; exit 1 if any run failed or errored."""
    seeds = parse_seeds(a.seeds)
    out = Path(a.out)
    from ..scenario.loader import load_scenario

    refused: dict[str, str] = {}
    for path in a.scenarios:  # a scenario that does not load: one line (file, line, what), its runs are ERROR rows
        try:
            load_scenario(path)
        except HomesimError as exc:
            refused[str(path)] = f"{type(exc).__name__}: {exc}"
            print(f"homesim sweep: error: {exc} (its runs are ERROR rows; the sweep goes on)", file=sys.stderr, flush=True)
    from ..progress import bar, write

    runs = sum(str(p) not in refused for p in a.scenarios) * len(seeds)
    with bar(runs, desc="sweep", unit="run") as shown:
        def progress(line: str) -> None:
            shown.update(1)
            if f": {ERROR} (" in line:  # why a run failed to run is worth a line, terminal or not
                write(line, file=sys.stderr)

        rows, agg = sweep(a.scenarios, seeds, out, until=a.until, workers=a.workers, scheduler=a.scheduler,
                          progress=progress, refused=refused, profile=a.profile)
    for g in agg:
        unchecked = "".join(f", {n} {v}" for v, n in sorted(Counter(r["verdict"] for r in rows if r["scenario"] == g["scenario"]
                                                                  and r["verdict"] not in (PASS, FAIL, ERROR)).items()))
        skipped = [r for r in rows if r["scenario"] == g["scenario"] and r["verdict"] == SKIPPED]
        if skipped and len(skipped) == g["runs"]:
            print(f"{g['scenario']}: {skipped[0]['error']} ({len(skipped)} run{'s' if len(skipped) > 1 else ''})")
            continue
        if g["checked"]:
            rate = f"{g['passed']}/{g['checked']} pass ({100 * g['pass_rate']:.0f} %)"
        else:
            rate = f"nothing checked in {g['runs']} run{'s' * (g['runs'] != 1)}"
        print(f"{g['scenario']}: {rate}, {g['failed']} fail, {g['errors']} error{unchecked}")
    print(f"wrote {out / 'sweep.csv'} and {out / 'sweep.json'}")
    return 1 if any(r["verdict"] in (FAIL, ERROR) for r in rows) else 0


def _scheduler(text: str) -> str:
    """A type for --scheduler: a Dask address, ``tcp://host:port`` (or ``tls://``, or ``host:port``)."""
    if len(text) > 300 or not re.fullmatch(r"((tcp|tls)://)?[A-Za-z0-9_.\-\[\]:]+:[0-9]{1,5}", text):
        raise argparse.ArgumentTypeError(f"{text[:25]!r} is not a Dask scheduler address (tcp://host:port)")
    return text


def _workers(text: str) -> int:
    """A type for --workers: 1 to 256 local processes."""
    if not (text.strip().isascii() and text.strip().isdigit()) or not 1 <= int(text) <= 256:
        raise argparse.ArgumentTypeError(f"{text[:25]!r} is not a number of workers (1 to 256)")
    return int(text)


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``homesim sweep``."""
    p = sub.add_parser("sweep", help="run scenarios x seeds in parallel (local processes or a Dask cluster); one table",
                       examples=["homesim sweep scenarios/*.xml --seeds 0-9 -o out/sweep",
                                 "homesim sweep scenarios/home_tour.xml --seeds 0,3,7 --workers 1 -o out/sweep"])
    p.add_argument("scenarios", type=Path, nargs="+", metavar="SCENARIO", help="scenario files, e.g. scenarios/home_tour.xml")
    p.add_argument("--seeds", default="0", help="seeds: 0-99, or 0,3,7, or 0-9,20-29")
    p.add_argument("--until", type=cliargs.seconds(), default=None, metavar="SECONDS",
                   help="stop each run early, at this virtual time in seconds (verdicts are then 'not checked')")
    p.add_argument("--workers", type=_workers, default=None, help="local processes (default: the CPU count)")
    p.add_argument("--scheduler", type=_scheduler, default=None, metavar="ADDRESS", help="run on this Dask distributed scheduler (tcp://host:8786)")
    p.add_argument("-o", "--out", required=True, metavar="DIR", help="directory for sweep.csv, sweep.json and summaries/")
    from robot.profiles import PROFILES

    p.add_argument("--profile", default=None, choices=sorted(PROFILES), help="robot profile of every run (default: each scenario's)")
    p.set_defaults(func=sweep_command)
