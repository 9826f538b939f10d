"""``homesim sweep``: scenarios x seeds on local processes or a Dask cluster, one table."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest

from homesim.cliargs import OptionError
from homesim.tour.runner import Run, RunOptions
from homesim.tour.sweep import ERROR, aggregate, parse_seeds, run_one, sweep

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "scenarios" / "two_people_radio.xml"
UNTIL = 0.5


def test_seed_ranges_are_parsed_in_order_without_repeats():
    assert parse_seeds("0-3,7,2") == [0, 1, 2, 3, 7]
    assert parse_seeds("5") == [5]
    for bad in ("3-1", "x", "1-", "-2"):
        with pytest.raises(OptionError, match="--seeds"):
            parse_seeds(bad)


def test_seeds_are_ascii_decimal_digits():
    """'²' passed str.isdigit() and then int() raised (a traceback); '٣' and '０' were taken as 3 and 0."""
    for bad in ("²", "٣", "０", "1-٩", "3-²", "1_0"):
        with pytest.raises(OptionError, match="--seeds"):
            parse_seeds(bad)


def _comparable(row):
    return {k: row[k] for k in ("scenario", "seed", "verdict", "passed", "expectations", "sim_time_s", "metrics")}


def test_a_run_in_a_sweep_is_the_run_homesim_run_makes():
    row = run_one(str(EXAMPLE), 3, UNTIL)
    with Run.from_file(EXAMPLE, RunOptions(seed=3, until=UNTIL)) as run:
        run.run()
        summary = run.summary()
    assert row["verdict"] == summary["verdict"] == "not checked"
    assert row["sim_time_s"] == summary["sim_time_s"] and row["seed"] == 3


def test_local_sweep_reports_a_broken_scenario_and_goes_on(tmp_path):
    broken = tmp_path / "broken.xml"
    broken.write_text("<scenario name='broken'><oops></scenario>", encoding="utf-8")
    lines: list[str] = []
    rows, agg = sweep([EXAMPLE, broken], [0, 1], tmp_path / "out", until=UNTIL, workers=2, progress=lines.append)
    assert [(r["scenario"], r["seed"]) for r in rows] == [("broken", 0), ("broken", 1), ("two_people_radio", 0), ("two_people_radio", 1)]
    assert all(r["verdict"] == ERROR and "broken.xml" in r["error"] for r in rows[:2])
    assert all(r["verdict"] == "not checked" for r in rows[2:])
    assert len(lines) == 4 and lines[-1].startswith("[4/4]")
    with (tmp_path / "out" / "sweep.csv").open(encoding="utf-8") as fh:
        table = list(csv.DictReader(fh))
    assert [t["verdict"] for t in table] == [r["verdict"] for r in rows]
    doc = json.loads((tmp_path / "out" / "sweep.json").read_text(encoding="utf-8"))
    assert {a["scenario"]: a["errors"] for a in doc["aggregate"]} == {"broken": 2, "two_people_radio": 0}
    assert sorted(p.name for p in (tmp_path / "out" / "summaries").iterdir()) == ["two_people_radio-0.json", "two_people_radio-1.json"]


def test_a_dask_cluster_gives_the_same_table_as_local_processes(tmp_path):
    distributed = pytest.importorskip("distributed")
    local, _ = sweep([EXAMPLE], [0, 1], tmp_path / "local", until=UNTIL, workers=1)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            remote, _ = sweep([EXAMPLE], [0, 1], tmp_path / "dask", until=UNTIL, scheduler=client)
    assert [_comparable(r) for r in remote] == [_comparable(r) for r in local]


def test_the_aggregate_counts_passes_and_spreads_metrics():
    rows = [
        {"scenario": "s", "seed": 0, "verdict": "PASS", "metrics": {"m": 1.0}},
        {"scenario": "s", "seed": 1, "verdict": "FAIL", "metrics": {"m": 3.0}},
        {"scenario": "s", "seed": 2, "verdict": ERROR, "metrics": {}},
    ]
    (a,) = aggregate(rows)
    assert (a["runs"], a["passed"], a["failed"], a["errors"]) == (3, 1, 1, 1)
    assert a["pass_rate"] == pytest.approx(1 / 3)
    assert a["metrics"]["m"] == {"mean": 2.0, "std": 1.0, "n": 2}


def test_seed_parsing_is_linear_and_bounded():
    """Parsing takes time in proportion to the seeds (0-99999 was quadratic: 56 s); a sweep has a bound.

    (No timing here: the test suite would take the old parser's 56 s.)"""
    from homesim.tour.sweep import MAX_SEEDS

    seeds = parse_seeds("0-99999")
    assert seeds == list(range(100_000))
    assert parse_seeds("5-9,0-99999,3") == [5, 6, 7, 8, 9] + [s for s in range(100_000) if not 5 <= s <= 9]
    ranges = ",".join(f"{k * 99_999}-{k * 99_999 + 99_998}" for k in range(MAX_SEEDS // 99_999 + 1))
    with pytest.raises(OptionError, match="more than"):
        parse_seeds(ranges)


def test_a_sweep_with_an_invalid_scenario_gives_error_rows_and_goes_on(tmp_path, capsys):
    from homesim.cli import main

    broken = tmp_path / "broken.xml"
    broken.write_text("<scenario name='broken'>\n<oops></scenario>", encoding="utf-8")
    code = main(["sweep", str(EXAMPLE), str(broken), "--seeds", "0-1", "--until", str(UNTIL), "--workers", "1",
                 "--out", str(tmp_path / "out")])
    captured = capsys.readouterr()
    assert code == 1, captured
    refusals = [line for line in captured.err.splitlines() if "error:" in line]
    assert len(refusals) == 1 and f"{broken}:2" in refusals[0], captured.err
    doc = json.loads((tmp_path / "out" / "sweep.json").read_text(encoding="utf-8"))
    verdicts = {(r["scenario"], r["seed"]): r["verdict"] for r in doc["runs"]}
    assert verdicts == {("broken", 0): ERROR, ("broken", 1): ERROR, ("two_people_radio", 0): "not checked",
                        ("two_people_radio", 1): "not checked"}
    assert all(f"{broken}:2" in r["error"] for r in doc["runs"] if r["scenario"] == "broken")
    # runs stopped early checked nothing: out of the pass rate, said so (not "0/2 pass")
    assert "two_people_radio: nothing checked in 2 runs" in captured.out and "broken: 0/2 pass (0 %), 0 fail, 2 error" in captured.out
