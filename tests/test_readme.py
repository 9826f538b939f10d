"""The README's examples work as written: its Python snippets run, its commands exist and parse."""

from __future__ import annotations

import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from homesim.cli import build_parser

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")
BLOCKS = re.findall(r"```(\w+)\n(.*?)```", README, re.S)
PYTHON = [code for lang, code in BLOCKS if lang == "python"]
COMMANDS = [
    part.strip()
    for lang, code in BLOCKS if lang == "bash"
    for line in code.splitlines() if line.strip() and not line.lstrip().startswith("#")
    for part in line.split("#", 1)[0].split("&&")
]


def test_the_readme_has_python_snippets_and_commands():
    assert PYTHON and COMMANDS


@pytest.mark.parametrize("code", PYTHON, ids=[f"snippet{i}" for i in range(len(PYTHON))])
def test_every_python_snippet_runs_as_written(code):
    """Nothing elided (no '...' placeholders): each snippet is a whole program."""
    assert "# ..." not in code
    done = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr


def test_the_stepping_snippet_reaches_the_interaction():
    (code,) = [c for c in PYTHON if "sim.step()" in c]
    done = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=120)
    lines = done.stdout.splitlines()
    assert lines[1].split() == ["1.2", "LookingAround"]  # the greeting waits for a partner
    assert lines[2].split()[1] == "Interacting" and 1.5 < float(lines[2].split()[0]) < 1.6


@pytest.mark.parametrize("command", [c for c in COMMANDS if c.startswith(".venv/bin/homesim")])
def test_every_homesim_command_exists_and_its_files_too(command):
    args = shlex.split(command)[1:]
    parsed = build_parser().parse_args(args)  # SystemExit on an unknown command or option
    assert getattr(parsed, "func", None) is not None
    for a in args:
        if a.endswith((".xml", ".scxml")):
            # A file the README has the reader make first (the tutorial's out/...) must be made before it is used.
            made = README.find(f"> {a}") if a.startswith("out/") else -1
            if made < 0:
                made = README.find(f"Save it as `{a}`") if a.startswith("out/") else -1
            if made < 0 and a.startswith("out/"):  # written by an earlier `homesim generate ... --out DIR`
                made = README.find(f"--out {Path(a).parent}\n")
            assert (ROOT / a).is_file() or 0 <= made < README.find(command), a


def test_commands_use_the_venv_and_the_benchmarks_install_their_extra():
    for c in COMMANDS:
        assert not re.match(r"(python|pip|pytest|homesim)\b", c), f"{c!r}: outside the venv"
    bench = [i for i, c in enumerate(COMMANDS) if "benchmarks/" in c]
    extra = [i for i, c in enumerate(COMMANDS) if '".[bench]"' in c]
    assert bench and extra and min(extra) < min(bench)
    for i in bench:
        script = next(t for t in shlex.split(COMMANDS[i]) if t.startswith("benchmarks/"))
        assert (ROOT / script).is_file()


def test_the_afsm_and_check_commands_are_documented():
    assert any(c.startswith(".venv/bin/homesim afsm show") for c in COMMANDS)
    assert any(c.startswith(".venv/bin/homesim afsm check") for c in COMMANDS)
    assert any(c.startswith(".venv/bin/homesim check") for c in COMMANDS)
