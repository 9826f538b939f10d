"""Traces are untrusted input: every command that reads one, fed hostile headers and lines.

``homesim replay``, ``plot`` and ``export`` re-create the run a trace header
names. A header must never import code or touch the file system: names of
subsystems and metrics only from the registries, a store only where one
already is, every field checked by one schema (homesim.tour.runheader). Each
refusal is one line on stderr naming ``TRACE:LINE``, exit 2 (1 only for a
replay that differs), no traceback, and nothing created.
"""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path

import pytest

from homesim.cli import main

ROOT = Path(__file__).resolve().parents[1]
SCENARIO = ROOT / "scenarios" / "two_people_radio.xml"
#: Every command that reads a trace (argv after the trace's path is filled in).
READERS = {
    "replay": lambda t, tmp: ["replay", str(t)],
    "plot": lambda t, tmp: ["plot", str(t), "--out", str(tmp / "out.png")],
    "timeline": lambda t, tmp: ["plot", str(t), "--timeline", "--out", str(tmp / "tl.png")],
    "export-mcap": lambda t, tmp: ["export", str(t), "--mcap", str(tmp / "out.mcap")],
    "export-perfetto": lambda t, tmp: ["export", str(t), "--perfetto", str(tmp / "out.json")],
}
#: Readers that use the header (the timeline and the Perfetto export read the lines alone).
HEADER_READERS = ("replay", "plot", "export-mcap")


@pytest.fixture(scope="module")
def good_trace(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("trace") / "good.jsonl"
    assert main(["run", str(SCENARIO), "--until", "1", "--quiet", "--trace", str(out)]) == 0
    return out


def _lines(trace: Path) -> list[str]:
    return trace.read_text(encoding="utf-8").split("\n")


def _with_header(good: Path, tmp: Path, edit) -> Path:  # noqa: ANN001 (a function of the header dict)
    lines = _lines(good)
    header = json.loads(lines[0])
    edit(header)
    out = tmp / "hostile.jsonl"
    out.write_text("\n".join([json.dumps(header)] + lines[1:]), encoding="utf-8")
    return out


def _refused(argv: list[str], capsys: pytest.CaptureFixture[str], where: str) -> str:
    code = main(argv)
    err = capsys.readouterr().err
    assert code == 2, (argv, err)
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    assert where in lines[0], lines[0]
    return lines[0]


def _evil_module(tmp: Path, name: str) -> Path:
    """A module next to the trace that leaves a mark when imported (the current directory on sys.path)."""
    mark = tmp / f"{name}.imported"
    (tmp / f"{name}.py").write_text(f"open({str(mark)!r}, 'w').write('ran')\n", encoding="utf-8")
    return mark


@pytest.mark.parametrize("reader", HEADER_READERS)
@pytest.mark.parametrize("field", ["subsystems", "metrics"])
def test_a_header_never_imports_a_module_it_names(good_trace, tmp_path, capsys, monkeypatch, reader, field):
    name = f"evil_{field}_{reader.replace('-', '_')}"
    mark = _evil_module(tmp_path, name)
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.chdir(tmp_path)
    for names in ([name], ["this"], ["robot.localisation", "os"], [f"{name}.sub"]):
        trace = _with_header(good_trace, tmp_path, lambda h: h["run"].__setitem__(field, names))
        line = _refused(READERS[reader](trace, tmp_path), capsys, f"{trace}:1:")
        assert f"run.{field}" in line and "unknown" in line
    assert not mark.exists()
    assert name not in sys.modules and "this" not in sys.modules


def test_the_run_options_refuse_subsystems_outside_the_registry(tmp_path, monkeypatch):
    from homesim.errors import HomesimError
    from homesim.tour.runner import Run, RunOptions

    mark = _evil_module(tmp_path, "evil_api")
    monkeypatch.syspath_prepend(str(tmp_path))
    with pytest.raises(HomesimError, match="unknown subsystem"):
        Run.from_file(SCENARIO, RunOptions(until=1, subsystems=("evil_api",)))
    with pytest.raises(HomesimError, match="unknown metric"):
        Run.from_file(SCENARIO, RunOptions(until=1, metrics=("evil_api",)))
    assert not mark.exists()


@pytest.mark.parametrize("reader", HEADER_READERS)
def test_a_header_store_path_creates_nothing(good_trace, tmp_path, capsys, reader):
    from homesim.tour.runner import store_digest

    where = tmp_path / "made" / "by" / "header"
    empty = tmp_path / "empty"
    empty.mkdir()
    for memory in (where, empty):
        trace = _with_header(good_trace, tmp_path, lambda h: h["run"].update(memory=str(memory), memory_digest=store_digest(memory)))
        line = _refused(READERS[reader](trace, tmp_path), capsys, f"{trace}:1:")
        assert "holds no store" in line
    assert not (tmp_path / "made").exists()
    assert list(empty.iterdir()) == []
    # A store path without the digest it started from is refused too (nothing to compare the store with).
    trace = _with_header(good_trace, tmp_path, lambda h: h["run"].update(memory=str(empty)))
    _refused(READERS[reader](trace, tmp_path), capsys, "memory_digest")


BAD_HEADERS = {
    "until NaN": lambda h: h["run"].__setitem__("until", float("nan")),
    "until inf": lambda h: h["run"].__setitem__("until", float("inf")),
    "until negative": lambda h: h["run"].__setitem__("until", -1),
    "until a string": lambda h: h["run"].__setitem__("until", "10"),
    "subsystems a number": lambda h: h["run"].__setitem__("subsystems", 5),
    "subsystems a string": lambda h: h["run"].__setitem__("subsystems", "robot.speech"),
    "metrics of non-strings": lambda h: h["run"].__setitem__("metrics", [1, {}]),
    "seed a string": lambda h: h["run"].__setitem__("seed", "0"),
    "seed a bool": lambda h: h["run"].__setitem__("seed", True),
    "seed negative": lambda h: h["run"].__setitem__("seed", -1),
    "seed huge": lambda h: h["run"].__setitem__("seed", 2**80),
    "seed a float": lambda h: h["run"].__setitem__("seed", 1.5),
    "scenario_file a number": lambda h: h["run"].__setitem__("scenario_file", 5),
    "scenario_file a list": lambda h: h["run"].__setitem__("scenario_file", ["a"]),
    "scenario_file with NUL": lambda h: h["run"].__setitem__("scenario_file", "a\0b"),
    "scenario_digest garbage": lambda h: h["run"].__setitem__("scenario_digest", {"x": 1}),
    "memory a number": lambda h: h["run"].__setitem__("memory", 7),
    "memory_digest garbage": lambda h: h["run"].update(memory_digest="md5:0"),
    "an unknown run field": lambda h: h["run"].__setitem__("exec", "rm -rf /"),
    "an unknown header field": lambda h: h.__setitem__("plugin", "this"),
    "run a list": lambda h: h.__setitem__("run", []),
    "no run": lambda h: h.pop("run"),
    "no seed": lambda h: h["run"].pop("seed"),
    "format 2": lambda h: h.__setitem__("homesim_trace", 2),
    "top seed a dict": lambda h: h.__setitem__("seed", {}),
    "version a number": lambda h: h.__setitem__("homesim_version", 1),
}


@pytest.mark.parametrize("case", sorted(BAD_HEADERS))
def test_every_header_field_is_checked(good_trace, tmp_path, capsys, case):
    trace = _with_header(good_trace, tmp_path, BAD_HEADERS[case])
    for reader in HEADER_READERS:
        _refused(READERS[reader](trace, tmp_path), capsys, f"{trace}:1:")
        assert not (tmp_path / "out.png").exists() and not (tmp_path / "out.mcap").exists()


def test_a_header_integer_too_long_for_int_is_refused_in_one_line(good_trace, tmp_path, capsys):
    """json.loads raised a bare ValueError (Python's 4300-digit limit) for a 5000-digit seed: a traceback."""
    lines = _lines(good_trace)
    trace = tmp_path / "hostile.jsonl"
    trace.write_text("\n".join([re.sub(r'"seed":\s*[0-9]+', '"seed":' + "9" * 5000, lines[0], count=1)] + lines[1:]), encoding="utf-8")
    assert "9" * 5000 in trace.read_text(encoding="utf-8")
    for reader in HEADER_READERS:
        _refused(READERS[reader](trace, tmp_path), capsys, f"{trace}:1:")


def test_the_runs_own_header_passes_the_schema(tmp_path):
    """Every header a run writes (all options set) is one the readers accept."""
    from homesim.tour.runheader import read_run_header
    from homesim.tour.runner import Run, RunOptions

    trace = tmp_path / "t.jsonl"
    opts = RunOptions(seed=3, until=0.5, trace=trace, memory=tmp_path / "store", subsystems=("robot.knowledge",),
                      metrics=("tracking",))
    with Run.from_file(SCENARIO, opts) as run:
        run.run()
    h = read_run_header(trace)
    assert (h["seed"], h["until"], h["subsystems"], h["metrics"]) == (3, 0.5, ("robot.knowledge",), ("tracking",))
    assert h["memory"] == str(tmp_path / "store")


#: A trace line replaced by something no recorder writes (bytes).
HOSTILE_LINES = {
    "deep nesting": b"[" * 100_000 + b"]" * 100_000,
    "deep nesting in a record": b'{"t":1.0,"seq":1,"kind":"deliver","id":' + b"[" * 100_000 + b"]" * 100_000 + b"}",
    "a byte that is not UTF-8": b'{"t":0.5,"seq":4,"kind":"deliver","id":"m\xff","receivers":["x"]}',
    "a lone surrogate": b'{"t":0.5,"seq":4,"kind":"publish","sender":"a","channel":"/x","receivers":[],"id":"\\ud800","causes":[],"created":0.5,"xml":"<x/>"}',
    "NUL": b"\x00" * 64,
    "not an object": b"[1, 2, 3]",
    "not JSON": b"{'t': 1}",
    "a huge number": b'{"t":1e999,"seq":4,"kind":"deliver","id":"m","receivers":["x"]}',
    "an integer of 5000 digits": b'{"t":0.5,"seq":' + b"9" * 5000 + b',"kind":"deliver","id":"m","receivers":["x"]}',
    "a send without fields": b'{"t":0.5,"seq":4,"kind":"publish"}',
    "receivers not a list": b'{"t":0.5,"seq":4,"kind":"deliver","id":"m","receivers":{"a":1}}',
}
LINE = 5


def _with_line(good: Path, tmp: Path, raw: bytes) -> Path:
    lines = good.read_bytes().split(b"\n")
    lines[LINE - 1] = raw
    out = tmp / "hostile-line.jsonl"
    out.write_bytes(b"\n".join(lines))
    return out


@pytest.mark.parametrize("reader", sorted(READERS))
@pytest.mark.parametrize("case", sorted(HOSTILE_LINES))
def test_a_hostile_line_gives_one_line_naming_it(good_trace, tmp_path, capsys, reader, case):
    trace = _with_line(good_trace, tmp_path, HOSTILE_LINES[case])
    argv = READERS[reader](trace, tmp_path)
    code = main(argv)
    captured = capsys.readouterr()
    if reader == "replay":  # a replay reports the first line that differs (exit 1)
        assert code == 1, captured
        assert captured.out.startswith(f"replay: {trace}:{LINE} differs"), captured.out
        assert captured.err == ""
        return
    err = captured.err.strip()
    assert code == 2, (code, captured)
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    assert f"{trace}:{LINE}" in err, err
    assert not any(p.name.startswith(("out.", "tl.")) for p in tmp_path.iterdir())


# ---------------------------------------------------------------- properties
from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from .conftest import examples  # noqa: E402

JSON = st.recursive(st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=20),
                    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=10), inner, max_size=4),
                    max_leaves=12)


@settings(max_examples=examples(100, 1000), deadline=None)
@given(st.lists(st.binary(max_size=200) | JSON.map(lambda v: json.dumps(v).encode()), min_size=1, max_size=6))
def test_reading_any_bytes_as_a_trace_gives_records_or_one_input_error(tmp_path_factory, lines):
    from homesim.errors import InputError
    from homesim.trace import read_trace

    path = tmp_path_factory.mktemp("fuzz") / "t.jsonl"
    path.write_bytes(b"\n".join(lines))
    try:
        for rec in read_trace(path):
            assert isinstance(rec, dict)
    except InputError as exc:
        assert str(exc).startswith(f"{path}:") and "\n" not in str(exc)


@settings(max_examples=examples(100, 1000), deadline=None)
@given(st.dictionaries(st.sampled_from(["scenario_file", "scenario_digest", "seed", "until", "memory", "memory_digest",
                                        "subsystems", "metrics", "other"]), JSON, max_size=9),
       st.dictionaries(st.sampled_from(["scenario", "seed", "homesim_version", "x"]), JSON, max_size=3))
def test_any_header_is_accepted_checked_or_refused_in_one_line(run, top):
    """Whatever a header holds: a checked run (every value of its type) or a HeaderError naming line 1."""
    from homesim.tour.runheader import RUN_FIELDS, HeaderError, check_header

    try:
        h = check_header({"homesim_trace": 1, **top, "run": run}, source="t.jsonl")
    except HeaderError as exc:
        assert str(exc).startswith("t.jsonl:1: ") and "\n" not in str(exc)
        return
    assert set(h) == set(RUN_FIELDS)
    assert isinstance(h["scenario_file"], str) and isinstance(h["seed"], int) and h["seed"] >= 0
    assert h["until"] is None or (isinstance(h["until"], float) and h["until"] >= 0)
    assert h["subsystems"] is None or isinstance(h["subsystems"], tuple)
