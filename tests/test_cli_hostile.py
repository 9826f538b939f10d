"""Every subcommand, fed hostile values: one error line on stderr (after the usage), exit 1 or 2, no traceback.

The subcommands and their options are discovered from the real parser, so a
command added later is covered without editing this file. Numbers get
nan/inf/huge/negative/5,000-digit values, output paths get directories and
unwritable places, input files get devices, FIFOs, directories and UTF-16.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path

import pytest

from lxml import etree

from homesim import cliargs
from homesim.cli import build_parser, main

ROOT = Path(__file__).resolve().parents[1]
VALID_INPUT = {
    "scenario": ROOT / "scenarios" / "two_people_radio.xml",
    "afsm": ROOT / "robot" / "afsm" / "biron.scxml",
}
#: Free-text options that must name something that exists (the rest, e.g. --xpath, may match nothing).
NAMING = {"--current", "--memory"}
NUMBERS = ["nan", "inf", "-inf", "-1", "1e300", "9" * 5000, "abc", "", "0x10", "1_0"]


def _store(tmp: Path) -> Path:
    """A real memory store with one document (the valid input of ``memory`` commands)."""
    from homesim.memory.core import ActiveMemory
    from homesim.memory.sqlite import SqliteStore

    path = tmp / "store.sqlite"
    if not path.exists():
        with SqliteStore(path) as store:
            ActiveMemory("objects", store=store).insert(etree.fromstring('<object name="cup"/>'))
    return path


def commands() -> list[tuple[list[str], argparse.ArgumentParser]]:
    """Every leaf (sub)command as (argv prefix, its parser)."""
    out: list[tuple[list[str], argparse.ArgumentParser]] = []

    def walk(prefix: list[str], parser: argparse.ArgumentParser) -> None:
        subs = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
        if not subs:
            out.append((prefix, parser))
            return
        for name, child in subs[0].choices.items():
            walk(prefix + [name], child)

    walk([], build_parser())
    return out


def hostile_files(tmp: Path) -> list[str]:
    fifo = tmp / "fifo.xml"
    if not fifo.exists():
        os.mkfifo(fifo)
    utf16 = tmp / "utf16.xml"
    utf16.write_bytes('<?xml version="1.0" encoding="UTF-16"?><!DOCTYPE r SYSTEM "/etc/passwd"><r/>'.encode("utf-16"))
    binary = tmp / "binary.xml"
    binary.write_bytes(bytes(range(256)) * 4)
    return ["/dev/zero", "/dev/urandom", str(fifo), str(tmp), str(tmp / "missing.xml"), str(utf16), str(binary),
            *hostile_traces(tmp)]


def hostile_traces(tmp: Path) -> list[str]:
    """Traces no command may act on: a header naming code to import or a store to create, JSON nested
    100,000 deep, bytes that are not UTF-8 (tests/test_trace_hostile.py has the full set)."""
    run = {"scenario_file": str(VALID_INPUT["scenario"]), "scenario_digest": "sha256:" + "0" * 64, "seed": 0, "until": 1.0,
           "memory": None, "memory_digest": None, "subsystems": None, "metrics": None}
    head = {"homesim_trace": 1, "scenario": "x", "seed": 0, "homesim_version": "0"}
    out = {
        "import.jsonl": json.dumps({**head, "run": {**run, "subsystems": ["this"]}}),
        "store.jsonl": json.dumps({**head, "run": {**run, "memory": str(tmp / "made-by-a-header"),
                                                      "memory_digest": "sha256:" + "0" * 64}}),
        "nested.jsonl": "[" * 100_000 + "]" * 100_000,
    }
    paths = []
    for name, text in out.items():
        (tmp / name).write_text(text + "\n", encoding="utf-8")
        paths.append(str(tmp / name))
    (tmp / "latin1.jsonl").write_bytes(b'{"homesim_trace": 1, "scenario": "caf\xe9"}\n')
    return paths + [str(tmp / "latin1.jsonl")]


def hostile_outputs(tmp: Path) -> list[str]:
    return [str(tmp), "/proc/self/nope/out.txt", "/dev/null/x", "/dev/zero", ""]


def hostile_stores(tmp: Path) -> list[str]:
    """Store directories (``--memory DIR``) no run can use: an existing file, devices, paths through files."""
    a_file = tmp / "a_file"
    a_file.write_text("not a directory", encoding="utf-8")
    return [str(a_file), "/dev/zero", "/dev/null/x", str(a_file / "store"), ""]


def _run(argv: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, str, str]:
    try:
        code = main(argv)
    except SystemExit as exc:  # argparse refusals
        code = int(exc.code or 0)
    out = capsys.readouterr()
    return code, out.out, out.err


def _error_lines(err: str) -> list[str]:
    """stderr without the usage a parser refusal starts with (``usage: ...`` and its indented continuation)."""
    lines = [line for line in err.splitlines() if line.strip()]
    if lines and lines[0].startswith("usage:"):
        lines = lines[1:]
        while lines and lines[0].startswith(" "):
            lines = lines[1:]
    return lines


def _assert_refused(argv: list[str], code: int, err: str) -> None:
    lines = _error_lines(err)
    assert code in (1, 2), (argv, code, err)
    assert "Traceback" not in err, argv
    assert len(lines) == 1, (argv, err)
    assert "error" in lines[0] or "problem" in lines[0], (argv, err)


def test_the_walk_finds_the_known_commands():
    names = {" ".join(prefix) for prefix, _ in commands()}
    assert {"demo", "scenario run", "scenario plot", "afsm show", "afsm check"} <= names


@pytest.mark.parametrize("prefix,parser", commands(), ids=lambda v: " ".join(v) if isinstance(v, list) else "")
def test_every_option_refuses_hostile_values_with_its_name(prefix, parser, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)  # default outputs (out/...) must not land in the checkout
    positionals = [a for a in parser._actions if not a.option_strings and not isinstance(a, argparse._HelpAction)]
    inputs = dict(VALID_INPUT, memory=_store(tmp_path))
    valid = [str(inputs.get(prefix[0], VALID_INPUT["scenario"]))] * len(positionals)
    required = {a.option_strings[-1]: a for a in parser._actions if a.option_strings and a.required}
    for action in parser._actions:
        if not action.option_strings or action.nargs == 0 or isinstance(action, argparse._HelpAction):
            continue
        option = action.option_strings[-1]
        values = (hostile_outputs(tmp_path) if action.type is cliargs.output_file
                  else hostile_stores(tmp_path) if action.type is cliargs.store_dir else NUMBERS)
        for value in values:
            extra: list[str] = []
            for name, req in required.items():
                if name != option:
                    extra += [name, "1" if req.type is not None else "x"]
            argv = prefix + valid + extra + [option, value]
            code, _out, err = _run(argv, capsys)
            if action.type is None and action.choices is None and option not in NAMING:
                assert "Traceback" not in err and (code == 0 or len(_error_lines(err)) == 1), (argv, err)
                continue  # free text (an XPath that matches nothing is a fine query)
            _assert_refused(argv, code, err)
            shown = [s for s in action.option_strings if s in err]
            assert shown, (argv, err)  # the refusal names the option


@pytest.mark.parametrize("prefix,parser", commands(), ids=lambda v: " ".join(v) if isinstance(v, list) else "")
def test_every_file_argument_refuses_hostile_files(prefix, parser, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    positionals = [a for a in parser._actions if not a.option_strings and not isinstance(a, argparse._HelpAction)]
    if not positionals:
        pytest.skip(f"{' '.join(prefix)} reads no file")
    required: list[str] = []
    for a in parser._actions:
        if a.option_strings and a.required:
            required += [a.option_strings[-1], "1"]
    if any(a.type is cliargs.output_file for a in parser._actions):
        required += ["-o" if "-o" in parser._option_string_actions else "--trace", str(tmp_path / "out.png")]
    for bad in hostile_files(tmp_path):
        argv = prefix + [bad] * len(positionals) + required
        code, _out, err = _run(argv, capsys)
        _assert_refused(argv, code, err)
    assert not (tmp_path / "made-by-a-header").exists() and "this" not in sys.modules


def test_cli_ranges_are_documented():
    text = (ROOT / "docs" / "running.md").read_text(encoding="utf-8")
    assert f"{cliargs.MAX_VIRTUAL_SECONDS:g}" in text or "1 000 000 s" in text
    assert "2**63 - 1" in text
