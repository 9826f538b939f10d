"""``homesim study``: scenarios x seeds x conditions -> per-capability rates with intervals, failure causes.

``homesim study (FILES... | --generated K --seed S) [--seeds 0-9] [--workers N | --scheduler ADDR]
[--condition NAME=OPTIONS ...] --out DIR``

Every run is one ``homesim run SCENARIO --seed N`` (the same :class:`~homesim.tour.runner.Run`
as ``homesim sweep``'s :func:`~homesim.tour.sweep.run_one`), on local processes or a Dask
cluster. ``--generated K --seed S`` first writes ``homesim generate --seed S --count K``
into ``DIR/scenarios/``. A condition changes how the runs are made, one study table
column each (e.g. two robot profiles): ``NAME=key=value,key=value`` where a key is

* a run option (a field of :class:`~homesim.tour.runner.RunOptions`, e.g. ``strict=true``, and the
  robot profile or deployment once the run takes them);
* ``robot.ATTRIBUTE`` -- an attribute of the scenario's ``<robot>`` (``robot.max-speed=0.3``);
* ``option.NAME`` -- a ``<robot><option>`` for BIRON's modules (``option.follow-distance=1.2``).

Scenario changes are written as derived scenario files into ``DIR/conditions/NAME/`` (and
checked like any scenario) so every run stays reproducible from a file.

Output: ``DIR/study.json`` (``runs``: one row per run with its first failed expectation
and that expectation's kind and capability; ``capabilities``: per capability runs, passed,
rate and Wilson ``ci95``, overall and by condition; ``failures``: failed expectations grouped
by cause; ``throughput``), ``DIR/study.md`` (the tables), ``DIR/study.png`` and ``.svg``
(rates with intervals), ``DIR/summaries/`` (each run's summary). ``--resume`` reuses the runs
whose summaries are already there (an interrupted study, or one extended by more seeds,
scenarios or conditions; only runs made from the same scenario file content, seed, run
options and code (homesim's version and a digest of the homesim, robot and humans packages'
files), stamped in ``summaries/*.key``) and makes only the others; runs made by other code are
made again, and the study says how many. Exit status 0 when the
study ran (failed runs are results, not errors), 2 for bad input.
"""

from __future__ import annotations

import argparse
import dataclasses
import functools
import hashlib
import json
import os
import sys
from collections.abc import Callable, Iterator
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path
from typing import IO, Any

from .. import cliargs
from ..cliargs import OptionError
from ..realtime import Stopwatch
from .sweep import ERROR, FAIL, PASS, SKIPPED, dask_client, _scheduler, _workers, parse_seeds, run_one
from .capabilities import CAPABILITIES, capability_of, cause_of, rate
from .socialtable import social_navigation, social_table

Row = dict[str, Any]
DEFAULT = "default"
#: Run options a condition may not set (the study sets them, or they write files per run).
RESERVED = {"seed", "until", "trace", "memory", "realtime"}


# ------------------------------------------------------------------ conditions
@dataclasses.dataclass(frozen=True)
class Condition:
    name: str
    run: tuple[tuple[str, Any], ...] = ()  # RunOptions fields
    robot: tuple[tuple[str, str], ...] = ()  # <robot> attributes
    options: tuple[tuple[str, str], ...] = ()  # <robot><option>s
    users: tuple[tuple[str, float], ...] = ()  # the user profiles' mix (usergen.parse_mix)

    def text(self) -> str:
        parts = [f"{k}={v}" for k, v in self.run] + [f"robot.{k}={v}" for k, v in self.robot] + [f"option.{k}={v}" for k, v in self.options]
        if self.users:
            parts.append("users=" + "+".join(f"{n}:{w:g}" for n, w in self.users))
        return ",".join(parts) or "(as written)"


def parse_condition(text: str) -> Condition:
    """``NAME=key=value,key=value`` (or just ``NAME``: the scenarios as written)."""
    from .runner import RunOptions

    name, _, rest = text.partition("=")
    name = name.strip()
    if not name or not name.replace("-", "").replace("_", "").isalnum() or len(name) > 40:
        raise OptionError("--condition", f"{text[:40]!r}: a condition is NAME=key=value,... with a short name of letters, digits, - or _")
    fields = {f.name: f for f in dataclasses.fields(RunOptions)}
    run, robot, opts = [], [], []
    users: tuple[tuple[str, float], ...] = ()
    for item in filter(None, (s.strip() for s in rest.split(","))):
        key, eq, value = item.partition("=")
        key, value = key.strip(), value.strip()
        if not eq or not key:
            raise OptionError("--condition", f"{name}: {item!r} is not key=value")
        if key.startswith("robot."):
            robot.append((key[6:], value))
        elif key.startswith("option."):
            opts.append((key[7:], value))
        elif key == "users":  # user profiles: users=cooperative, users=typical:3+silent:1
            from .usergen import MixError, parse_mix

            try:
                users = parse_mix(value)
            except MixError as exc:
                raise OptionError("--condition", f"{name}: users={value}: {exc}") from None
        elif key == "profile":  # refused here, not as an error row in every run
            from .runner import profiles

            if value not in profiles():
                raise OptionError("--condition", f"{name}: unknown robot profile {value!r} (known: {', '.join(sorted(profiles()))})")
            run.append((key, value))
        elif key in fields and key not in RESERVED:
            run.append((key, _value(fields[key], value, name)))
        else:
            known = ", ".join(sorted(set(fields) - RESERVED))
            raise OptionError("--condition", f"{name}: unknown key {key!r} (run options: {known}; or robot.ATTRIBUTE, option.NAME, users=PROFILES)")
    return Condition(name, tuple(run), tuple(robot), tuple(opts), users)


def _value(f: dataclasses.Field, text: str, name: str) -> Any:  # type: ignore[type-arg]
    kind = str(f.type)
    if "bool" in kind:
        if text.lower() not in ("true", "false", "1", "0", "yes", "no"):
            raise OptionError("--condition", f"{name}: {f.name} takes true or false, not {text!r}")
        return text.lower() in ("true", "1", "yes")
    if "tuple" in kind:
        return tuple(s for s in text.split("+") if s)
    if "float" in kind and "str" not in kind:
        try:
            return float(text)
        except ValueError:
            raise OptionError("--condition", f"{name}: {f.name} takes a number, not {text!r}") from None
    return text


def derive(files: list[str], cond: Condition, out: Path, generated: tuple[int, int] | None = None) -> list[str]:
    """The scenario files of a condition: the originals, or copies with its robot and user changes.

    ``users=`` with generated tours (``generated``: the generator's seed and count) generates
    the same tours with the condition's users (the same flats and scripts, each user drawn from
    the condition's mix, the run long enough for her patience); with scenario files it sets the
    profile of each user: every person with a profile, or, when nobody has one, every person
    who waits for the robot's answers (bystanders do not).
    """
    if cond.users and generated is not None:
        from .generate import generate

        seed, count = generated
        where = out / "conditions" / cond.name / "scenarios"
        made = generate(seed, count, where, cond.users)
        files = [str((where / f"{g.name}.xml").resolve()) for g in made]
        if not cond.robot and not cond.options:
            return files
    elif not cond.robot and not cond.options and not cond.users:
        return files
    from lxml import etree

    from ..scenario.loader import load_scenario
    from ..xmlio import parse_file

    where = out / "conditions" / cond.name
    where.mkdir(parents=True, exist_ok=True)
    made = []
    for f in files:
        root = parse_file(f)
        robot = root.find("robot")
        for k, v in cond.robot:
            robot.set(k, v)
        for k, v in cond.options:
            for old in robot.findall("option"):
                if old.get("name") == k:
                    robot.remove(old)
            etree.SubElement(robot, "option", name=k, value=v)
        if cond.users and generated is None:
            _set_users(root, cond, f)
        target = where / Path(f).name
        target.write_bytes(etree.tostring(root, xml_declaration=True, encoding="UTF-8"))
        load_scenario(target)  # a condition that makes a bad scenario is refused before any run
        made.append(str(target))
    return made


def _set_users(root: Any, cond: Condition, file: str) -> None:
    """Give each user of the scenario a profile drawn from the condition's mix (in document order)."""
    from .usergen import draw_user

    humans = root.findall("humans/human")
    users = [h for h in humans if h.get("profile") is not None] or [h for h in humans if h.find("script/wait-for") is not None]
    if not users:
        raise OptionError("--condition", f"{cond.name}: users= but {file} has no user (no person with a profile or a wait-for)")
    import zlib

    digest = zlib.crc32(Path(file).name.encode())  # the same file name, the same users
    for i, h in enumerate(users):
        h.set("profile", draw_user(digest, i, cond.users))


# ------------------------------------------------------------------ running
def study_run(file: str, seed: int, condition: str, options: dict[str, Any], summaries: str) -> Row:
    """One run of one condition (``homesim sweep``'s run, with the condition's run options)."""
    row = run_one(file, seed, None, summaries or None, options, f"-{condition}")
    row["condition"] = condition
    if summaries:  # what the summary was made from, so --resume never reuses it for another scenario or condition
        stamp_path((file, seed, condition, options, summaries)).write_text(run_key((file, seed, condition, options, summaries)) + "\n", encoding="utf-8")
    return row


Job = tuple[str, int, str, dict[str, Any], str]


def summary_path(job: Job) -> Path:
    """Where a job's run summary goes (as ``sweep.run_one`` names it)."""
    file, seed, condition, _, summaries = job
    return Path(summaries) / f"{Path(file).stem}-{seed}-{condition}.json"


def stamp_path(job: Job) -> Path:
    """The file beside a run's summary that says what the run was made from."""
    return summary_path(job).with_suffix(".key")


#: The packages whose code and data make a run's result: the simulator, the robot (its modules,
#: configuration, grammar, corpus, AFSM) and the simulated people (scripts, phrasing bank).
CODE_PACKAGES = ("homesim", "robot", "humans")


@functools.lru_cache(maxsize=1)
def code_digest() -> str:
    """A digest of the code that makes runs: homesim's version and every source and data file of
    :data:`CODE_PACKAGES` (compiled files left out: they follow their sources), ~250 files, ~10 ms.

    A researcher who fixes the robot and resumes a study expects the runs made by the old robot
    to be made again, not mixed into the new rates; a commit id would also change on a docs-only
    commit and is missing outside a git checkout, so the content is what is hashed."""
    import importlib

    from .. import __version__

    h = hashlib.sha256(f"homesim {__version__}\n".encode())
    for name in CODE_PACKAGES:
        root = Path(importlib.import_module(name).__file__ or "").parent
        for f in sorted(root.rglob("*")):
            rel = f.relative_to(root.parent)
            if (not f.is_file() or f.suffix in (".pyc", ".pyo", ".so", ".pyd")
                    or any(part == "__pycache__" or part.startswith(".") for part in rel.parts)):
                continue
            h.update(f"{rel.as_posix()}\0{f.stat().st_size}\0".encode())
            h.update(f.read_bytes())
    return f"{__version__}+sha256:{h.hexdigest()[:16]}"


def run_key(job: Job) -> str:
    """A run's identity for ``--resume``: the scenario file's content digest, the seed, the
    condition's run options and the code that made it (:func:`code_digest`)."""
    from .runner import file_digest

    file, seed, _, options, _ = job
    return json.dumps({"scenario": file_digest(file), "seed": seed, "options": {k: options[k] for k in sorted(options)},
                       "code": code_digest()}, default=str)


def stale_by_code(job: Job) -> bool:
    """Whether a run's summary is there for the same scenario, seed and options but was made by other code."""
    try:
        old = json.loads(stamp_path(job).read_text(encoding="utf-8"))
        new = json.loads(run_key(job))
    except (OSError, ValueError):
        return False
    return isinstance(old, dict) and old.get("code") != new["code"] and all(old.get(k) == new[k] for k in ("scenario", "seed", "options"))


def row_from_summary(job: Job) -> Row | None:
    """The row of a run already made (``--resume``), from its summary; None when it cannot be read
    or was made from another scenario version or other run options (then the run is made again)."""
    from .sweep import _flat

    try:
        if stamp_path(job).read_text(encoding="utf-8").strip() != run_key(job):
            return None
        d = json.loads(summary_path(job).read_text(encoding="utf-8"))
        verdicts = d["expectations"]
        metrics: dict[str, float] = {}
        for name, value in (d.get("metrics") or {}).items():
            _flat(name, value, metrics)
        return {"scenario": Path(job[0]).stem, "file": job[0], "seed": job[1], "condition": job[2], "verdict": d["verdict"],
                "passed": sum(bool(v["passed"]) for v in verdicts), "expectations": len(verdicts), "sim_time_s": d["sim_time_s"],
                "cpu_time_s": d["cpu_time_s"], "error": "", "metrics": metrics, "failed": [v for v in verdicts if not v["passed"]],
                "resumed": True}
    except (OSError, ValueError, KeyError, TypeError):
        return None


def _local(jobs: list[Job], workers: int) -> Iterator[Row]:
    if workers == 1:  # in this process: no pool to start (and what a profiler sees)
        for job in jobs:
            yield study_run(*job)
        return
    with ProcessPoolExecutor(max_workers=workers) as pool:
        futures = {pool.submit(study_run, *job): job for job in jobs}
        for fut in as_completed(futures):
            yield _result(fut, futures[fut])


def _dask(jobs: list[Job], scheduler: Any) -> Iterator[Row]:
    client, dask_completed = dask_client(scheduler)
    try:
        futures = [client.submit(study_run, *job, pure=False, key=f"homesim-study-{Path(job[0]).stem}-{job[1]}-{job[2]}") for job in jobs]
        where = {f.key: job for f, job in zip(futures, jobs)}
        for fut in dask_completed(futures):
            yield _result(fut, where[fut.key])
    finally:
        if client is not scheduler:
            client.close()


def _result(fut: Any, job: Job) -> Row:
    try:
        return fut.result()
    except Exception as exc:  # the worker died: still a row
        return {"scenario": Path(job[0]).stem, "file": job[0], "seed": job[1], "condition": job[2], "verdict": ERROR,
                "passed": 0, "expectations": 0, "sim_time_s": None, "cpu_time_s": None, "metrics": {}, "failed": [],
                "error": f"worker lost: {type(exc).__name__}: {exc}"[:2000]}


class Progress:
    """A progress bar (tqdm) on a terminal, with the runs that passed; a line for each run that could not run."""

    def __init__(self, total: int, out: IO[str]) -> None:
        from ..progress import bar

        self.out, self.passed = out, 0
        self.bar = bar(total, desc="study", unit="run", file=out)

    def __call__(self, row: Row) -> None:
        from ..progress import write

        self.passed += row["verdict"] == PASS
        self.bar.set_postfix_str(f"{self.passed} pass", refresh=False)
        self.bar.update(1)
        if row["verdict"] == ERROR:
            write(f"{row['scenario']} seed {row['seed']} {row['condition']}: {ERROR} ({row['error'][:120]})", file=self.out)

    def close(self) -> None:
        self.bar.close()


# ------------------------------------------------------------------ analysis
def _user_wrong(metrics: dict[str, Any]) -> bool:
    """Whether a user confirmed a wrong guess of the robot's or left a misnaming of hers uncorrected."""
    return bool(metrics.get("users.confirmed_wrongly")) or (metrics.get("users.misnamed") or 0) > (metrics.get("users.self_corrected") or 0)


def analyse(rows: list[Row], expectations: dict[str, list[Any]], names: dict[str, list[str]], conditions: list[str]) -> dict[str, Any]:
    """Capabilities (overall and by condition) and failures grouped by cause, from the run rows.

    ``expectations``: each scenario file's expectations (the loaded model's); ``names``: its names
    (rooms, objects, people) to take out of failure details."""
    caps: dict[str, dict[str, list[int]]] = {}  # capability -> condition -> [runs, passed]
    overall: dict[str, list[int]] = {c: [0, 0] for c in conditions}
    nothing: dict[str, int] = {c: 0 for c in conditions}  # runs that checked nothing ("no expectations", "not checked")
    groups: dict[str, dict[str, Any]] = {}
    for r in rows:
        if r["verdict"] == SKIPPED:  # the scenario needs another robot profile: not run, neither passed nor failed
            _add(groups, "skipped", "skipped", r.get("error", "skipped"), r)
            continue
        exps = expectations.get(r["file"], [])
        failed_lines = _failed_lines(r)
        cond = r["condition"]
        if r["verdict"] not in (PASS, FAIL, ERROR):  # neither passed nor failed: counted apart, out of every rate
            nothing[cond] += 1
            continue
        overall[cond][0] += 1
        overall[cond][1] += r["verdict"] == PASS
        by_cap: dict[str, bool] = {}
        first = None
        for e in exps:
            cap = capability_of(e, exps)
            ok = r["verdict"] != ERROR and e.line not in failed_lines
            by_cap[cap] = by_cap.get(cap, True) and ok
            if not ok and first is None:
                first = (e, cap)
        for cap, ok in by_cap.items():
            cell = caps.setdefault(cap, {}).setdefault(cond, [0, 0])
            cell[0] += 1
            cell[1] += ok
        if first is not None:
            e, cap = first
            r["first_failed"] = e.describe()
            r["first_failed_kind"] = e.kind
            r["first_failed_capability"] = cap
        if r["verdict"] == ERROR:
            _add(groups, "error", "error", f"error: {cause_of('run', r.get('error', ''), names.get(r['file'], []))}", r)
            continue
        for f in r.get("failed", []):
            line = _line_of(f)
            e = next((x for x in exps if x.line == line), None)
            kind = e.kind if e is not None else f["name"].split()[0].lstrip("<").rstrip("/>")
            cap = capability_of(e, exps) if e is not None else "other"
            cause = cause_of(kind, f.get("detail", ""), names.get(r["file"], []))
            if r.get("metrics", {}).get("users.stopped"):  # not the robot's doing alone: she stopped or left
                cause = f"{cause} (the user gave up)"
            elif r.get("metrics", {}).get("users.blocked"):  # she gave up a walk the robot stood in the way of
                cause = f"{cause} (the robot blocked her way)"
            elif _user_wrong(r.get("metrics", {})):  # she said yes to a wrong guess, or misnamed and let it stand
                cause = f"{cause} (the user got it wrong)"
            _add(groups, cap, kind, cause, r)
    order = [c for c in CAPABILITIES if c in caps] + sorted(set(caps) - set(CAPABILITIES))
    capabilities = {}
    for cap in order:
        per = caps[cap]
        runs, passed = sum(v[0] for v in per.values()), sum(v[1] for v in per.values())
        capabilities[cap] = {**rate(passed, runs), "by_condition": {c: rate(per.get(c, [0, 0])[1], per.get(c, [0, 0])[0]) for c in conditions}}
    runs_all, pass_all = sum(v[0] for v in overall.values()), sum(v[1] for v in overall.values())
    failures = sorted(groups.values(), key=lambda g: (-g["runs"], g["cause"]))
    for g in failures:
        g["examples"] = g["examples"][:3]
    return {"overall": {**rate(pass_all, runs_all), "by_condition": {c: rate(overall[c][1], overall[c][0]) for c in conditions}},
            "nothing_checked": {"runs": sum(nothing.values()), "by_condition": nothing},
            "capabilities": capabilities, "failures": failures}


def _failed_lines(r: Row) -> set[int]:
    return {ln for ln in (_line_of(f) for f in r.get("failed", [])) if ln is not None}


def _line_of(f: dict[str, Any]) -> int | None:
    where = str(f.get("where", ""))
    tail = where.rsplit(":", 1)[-1].replace("line ", "")
    return int(tail) if tail.isdigit() else None


def _add(groups: dict[str, dict[str, Any]], cap: str, kind: str, cause: str, r: Row) -> None:
    g = groups.setdefault(f"{cap}|{cause}", {"cause": cause, "capability": cap, "kind": kind, "runs": 0, "by_condition": {}, "examples": [], "_seen": set()})
    key = (r["file"], r["seed"], r["condition"])
    if key in g["_seen"]:
        return
    g["_seen"].add(key)
    g["runs"] += 1
    g["by_condition"][r["condition"]] = g["by_condition"].get(r["condition"], 0) + 1
    g["examples"].append(f"{r['scenario']} seed {r['seed']} ({r['condition']})")


def table(result: dict[str, Any], conditions: list[str]) -> str:
    """The capability table (one rate and interval column per condition) and the failure table, in Markdown."""
    def cell(c: dict[str, Any]) -> str:
        if not c["runs"]:
            return "-"
        lo, hi = c["ci95"]
        return f"{100 * c['rate']:.0f} % ({c['passed']}/{c['runs']}) [{100 * lo:.0f}, {100 * hi:.0f}]"

    head = "| capability | " + " | ".join(conditions) + " |"
    lines = [head, "|" + "---|" * (len(conditions) + 1)]
    lines.append("| **every expectation** | " + " | ".join(cell(result["overall"]["by_condition"][c]) for c in conditions) + " |")
    for cap, c in result["capabilities"].items():
        lines.append(f"| {cap} | " + " | ".join(cell(c["by_condition"][k]) for k in conditions) + " |")
    nothing = result.get("nothing_checked", {"runs": 0})
    if nothing["runs"]:  # runs without expectations (or stopped early): in no rate above
        lines.append("| nothing checked (runs, in no rate) | " + " | ".join(str(nothing["by_condition"].get(c, 0)) for c in conditions) + " |")
    lines += ["", "rate (passed/runs) [95 % Wilson interval], in %", ""]
    if result["failures"]:
        lines += ["| runs | capability | cause | " + " | ".join(conditions) + " |", "|" + "---|" * (len(conditions) + 3)]
        for g in result["failures"]:
            cause = g["cause"].replace("|", "\\|")
            lines.append(f"| {g['runs']} | {g['capability']} | {cause} | " + " | ".join(str(g["by_condition"].get(c, 0)) for c in conditions) + " |")
    return "\n".join(lines) + "\n"


# ------------------------------------------------------------------ the study
def study(files: list[str], seeds: list[int], conditions: list[Condition], out: Path, *, workers: int | None = None,
          scheduler: Any = None, progress: Callable[[Row], None] | None = None, resume: bool = False,
          generated: tuple[int, int] | None = None) -> dict[str, Any]:
    """Run the study, write study.json / study.md / study.png / study.svg into ``out``, return study.json's content."""
    from ..scenario.loader import load_scenario

    out.mkdir(parents=True, exist_ok=True)
    summaries = out / "summaries"
    summaries.mkdir(exist_ok=True)
    if len({c.name for c in conditions}) != len(conditions):
        raise OptionError("--condition", "two conditions have the same name")
    stems: dict[str, str] = {}
    for f in files:  # a run's summary is named by the file's stem: two files of one name would overwrite each other's
        if stems.setdefault(Path(f).stem, f) != f:
            raise OptionError("SCENARIO", f"{stems[Path(f).stem]} and {f} have the same name; a study needs distinct scenario file names")
    expectations: dict[str, list[Any]] = {}
    names: dict[str, list[str]] = {}
    jobs: list[Job] = []
    for cond in conditions:
        cfiles = derive(files, cond, out, generated)
        for f in cfiles:
            sc = load_scenario(f)
            expectations[f] = list(sc.expectations)
            names[f] = [x.name for group in (sc.rooms, sc.objects, sc.humans, sc.places, sc.furniture, sc.sources) for x in group] + [
                d.name for w in sc.walls for d in w.doors if d.name]
        jobs += [(f, n, cond.name, dict(cond.run), str(summaries)) for f in cfiles for n in seeds]
    rows: list[Row] = []
    if resume:  # runs made before (an interrupted study): their summaries, not the runs again
        todo = []
        recode = 0
        for job in jobs:
            old = row_from_summary(job)
            if old is None:
                todo.append(job)
                recode += stale_by_code(job)
            else:
                rows.append(old)
                if progress is not None:
                    progress(old)
        jobs = todo
        if recode:  # said, not silent: the researcher may have expected these to be reused
            print(f"homesim study: {recode} run{'s' * (recode != 1)} in {summaries} were made by other code "
                  f"(homesim/robot/humans changed since): made again with this code ({code_digest()})", file=sys.stderr)
    watch = Stopwatch()  # the study's report only (homesim.realtime: the one place that reads the clock)
    start_cpu = _cpu_used()
    workers = workers or os.cpu_count() or 1
    results = _dask(jobs, scheduler) if scheduler is not None else _local(jobs, workers)
    for row in results:
        rows.append(row)
        if progress is not None:
            progress(row)
    wall = watch.wall()
    everything = _cpu_used() - start_cpu if scheduler is None else None
    order = {c.name: i for i, c in enumerate(conditions)}
    rows.sort(key=lambda r: (order[r["condition"]], r["scenario"], r["seed"]))
    cnames = [c.name for c in conditions]
    result = analyse(rows, expectations, names, cnames)
    made = [r for r in rows if not r.get("resumed")]  # throughput of the runs made now
    cpu = sum(r["cpu_time_s"] or 0.0 for r in made)
    sim = sum(r["sim_time_s"] or 0.0 for r in made)
    doc = {
        "study": {"scenarios": len(files), "seeds": seeds, "runs": len(rows), "code": code_digest(),
                  "conditions": {c.name: c.text() for c in conditions}},
        "overall": result["overall"],
        "nothing_checked": result["nothing_checked"],
        "capabilities": result["capabilities"],
        "failures": [{k: v for k, v in g.items() if k != "_seen"} for g in result["failures"]],
        "social_navigation": social_navigation(rows, cnames),
        "throughput": {"runs": len(made), "cpu_s": round(cpu, 3), "simulated_s": round(sim, 3), "wall_s": round(wall, 3),
                       "workers": "dask" if scheduler is not None else workers,
                       "runs_per_cpu_minute": round(60 * len(made) / cpu, 3) if cpu else None,
                       # local studies: all the CPU the study's processes used (worker start-up, imports, loading, set-up)
                       "cpu_s_all": round(everything, 3) if everything is not None else None,
                       "runs_per_cpu_minute_all": round(60 * len(made) / everything, 3) if everything else None,
                       "runs_per_wall_minute": round(60 * len(made) / wall, 3) if wall and made else None},
        "runs": [_public(r) for r in rows],
    }
    (out / "study.json").write_text(json.dumps(doc, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")
    (out / "study.md").write_text(table(result, cnames) + "\n" + social_table(doc["social_navigation"], cnames), encoding="utf-8")
    from ..viz.study import plot_rates

    for suffix in ("png", "svg"):
        plot_rates(doc, out / f"study.{suffix}")
    return doc


def _cpu_used() -> float:
    """CPU seconds of this process and of its children that have ended (the pool's workers, once shut down)."""
    import resource

    me, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return me.ru_utime + me.ru_stime + kids.ru_utime + kids.ru_stime


def _public(r: Row) -> Row:
    keep = ("scenario", "file", "seed", "condition", "verdict", "passed", "expectations", "first_failed", "first_failed_kind",
            "first_failed_capability", "sim_time_s", "cpu_time_s", "error")
    row = {k: r.get(k) for k in keep}
    row["failed"] = r.get("failed", [])
    return row


def study_command(a: argparse.Namespace) -> int:
    from ..scenario.loader import load_scenario

    out = Path(a.out)
    if bool(a.scenarios) == (a.generated is not None):
        raise OptionError("SCENARIO", "give scenario files or --generated K --seed S (not both)")
    conditions = [parse_condition(c) for c in a.condition] or [Condition(DEFAULT)]  # refused before anything is written
    seeds = parse_seeds(a.seeds)
    if a.generated is not None:
        if a.seed is None:
            raise OptionError("--generated", "needs --seed S (the generator's seed)")
        from .generate import generate

        made = generate(a.seed, a.generated, out / "scenarios")
        files = [str((out / "scenarios" / f"{g.name}.xml").resolve()) for g in made]
    else:
        files = []
        for p in a.scenarios:
            if not Path(p).is_file():
                raise OptionError("SCENARIO", f"{p}: no such file")
            load_scenario(p)  # bad input is refused before any run (file, line, what)
            files.append(str(Path(p).resolve()))
    shown = Progress(len(files) * len(seeds) * len(conditions), sys.stderr)
    try:
        doc = study(files, seeds, conditions, out, workers=a.workers, scheduler=a.scheduler, progress=shown, resume=a.resume,
                    generated=(a.seed, a.generated) if a.generated is not None else None)
    finally:
        shown.close()
    print((out / "study.md").read_text(encoding="utf-8"))
    t = doc["throughput"]
    print(throughput_line(t))
    print(f"wrote {out / 'study.json'}, {out / 'study.md'}, {out / 'study.png'} and {out / 'study.svg'}")
    return 0


def throughput_line(t: dict[str, Any]) -> str:
    """The closing line on throughput; a fully resumed study made no run, so it has no rate to give."""
    if not t["runs"]:
        return f"no run made (every run resumed from an earlier summary), so no throughput; {t['wall_s']:.0f} s wall"
    rate = f"{t['runs_per_cpu_minute']} runs per CPU minute" if t["runs_per_cpu_minute"] is not None else "no CPU time measured"
    allcpu = (f"; {t['cpu_s_all']:.0f} CPU s with start-up and set-up: {t['runs_per_cpu_minute_all']} runs per CPU minute"
              if t.get("cpu_s_all") else "")
    return f"{t['runs']} runs made, {t['cpu_s']:.0f} CPU s in the runs ({rate}){allcpu}, {t['wall_s']:.0f} s wall"


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``homesim study``."""
    p = sub.add_parser("study", help="scenarios (or generated tours) x seeds x conditions: per-capability rates with 95 %% intervals, failure causes, a plot",
                       examples=["homesim study --generated 20 --seed 1000 --seeds 0 -o out/study",
                                 "homesim study scenarios/home_tour.xml --seeds 0-9 --condition slow=robot.max-speed=0.15 -o out/study"])
    p.add_argument("scenarios", type=Path, nargs="*", metavar="SCENARIO", help="scenario files, e.g. scenarios/home_tour.xml")
    p.add_argument("--generated", type=_count, default=None, metavar="K", help="generate K tours (with --seed S) into OUT/scenarios and study them")
    p.add_argument("--seed", type=cliargs.seed, default=None, help="the generator's seed for --generated")
    p.add_argument("--seeds", default="0", help="run seeds: 0-9, or 0,3,7")
    p.add_argument("--condition", action="append", default=[], metavar="NAME=OPTIONS",
                   help="a condition to compare (repeatable): NAME=key=value,... with run options, robot.ATTRIBUTE, option.NAME "
                        "or users=PROFILES (cooperative, or typical:3+silent:1: the same homes with these users)")
    p.add_argument("--workers", type=_workers, default=None, help="local processes (default: the CPU count)")
    p.add_argument("--scheduler", type=_scheduler, default=None, metavar="ADDRESS", help="run on this Dask distributed scheduler (tcp://host:8786)")
    p.add_argument("-o", "--out", required=True, metavar="DIR", help="directory for study.json, study.md, study.png/.svg, summaries/")
    p.add_argument("--resume", action="store_true", help="reuse the runs whose summaries OUT/summaries/ already holds (an interrupted or extended study)")
    p.set_defaults(func=study_command)


def _count(text: str) -> int:
    from .generate import _count as count

    return count(text)
