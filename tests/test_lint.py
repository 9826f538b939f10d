"""The tree passes ``ruff check`` with the project's configuration (pyproject.toml, [tool.ruff])."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def test_ruff_finds_nothing():
    pytest.importorskip("ruff", reason="ruff is in the test extras: pip install -e '.[test]'")
    done = subprocess.run([sys.executable, "-m", "ruff", "check", "--no-cache", "--output-format", "concise", "."],
                          cwd=ROOT, capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stdout + done.stderr


def test_ruff_sees_a_line_too_long_and_an_undefined_name(tmp_path):
    """The same configuration on a bad file fails (the check above can fail)."""
    pytest.importorskip("ruff", reason="ruff is in the test extras: pip install -e '.[test]'")
    bad = tmp_path / "bad.py"
    bad.write_text("x = undefined_name\ny = '" + "a" * 200 + "' + 'b'\n", encoding="utf-8")
    done = subprocess.run([sys.executable, "-m", "ruff", "check", "--no-cache", "--config", str(ROOT / "pyproject.toml"),
                           "--output-format", "concise", str(bad)], capture_output=True, text=True, check=False)
    assert done.returncode == 1
    assert "F821" in done.stdout and "E501" in done.stdout
