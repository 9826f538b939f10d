"""A built wheel installs and runs a scenario on its own: every schema and default document ships inside it.

The test builds homesim's wheel from a copy of the sources (the files the
build reads: pyproject.toml, setup.py, README.md and the three packages), installs
it into a fresh virtual environment and runs the home tour for 3 s from
another directory, with a copy of the scenario file beside it and nothing of the
source tree on the path. It needs no network: the wheel is built with this
environment's setuptools and wheel (``--no-build-isolation``, both in the test
extra), installed with ``--no-deps --no-index``, and the fresh environment finds
homesim's dependencies (numpy, lxml, ...) through a ``.pth`` line naming this
environment's site-packages (a plain path: the editable install's own ``.pth``
hook there is not run, so ``homesim`` can only come from the wheel).
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import sysconfig
import venv
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: What the build reads.
SOURCES = ("pyproject.toml", "setup.py", "README.md", "homesim", "robot", "humans")
_JUNK = shutil.ignore_patterns("__pycache__", "*.pyc", "*.so", "*.egg-info", "build")


def _run(args: list[str], cwd: Path, env: dict[str, str] | None = None) -> subprocess.CompletedProcess[str]:
    done = subprocess.run(args, cwd=cwd, env=env, capture_output=True, text=True, stdin=subprocess.DEVNULL)
    assert done.returncode == 0, f"{args} failed ({done.returncode}):\n{done.stdout[-3000:]}\n{done.stderr[-3000:]}"
    return done


@pytest.fixture(scope="module")
def installed(tmp_path_factory) -> Path:
    """A fresh venv with homesim installed from a wheel built from a copy of the sources; returns its python."""
    base = tmp_path_factory.mktemp("wheel")
    src = base / "src"
    src.mkdir()
    for name in SOURCES:
        p = ROOT / name
        if p.is_dir():
            shutil.copytree(p, src / name, ignore=_JUNK)
        else:
            shutil.copy2(p, src / name)
    dist = base / "dist"
    _run([sys.executable, "-m", "pip", "wheel", ".", "--no-deps", "--no-build-isolation", "--no-index", "-q", "-w", str(dist)], src)
    (wheel,) = dist.glob("homesim-*.whl")
    env_dir = base / "venv"
    venv.create(env_dir, with_pip=False)
    python = env_dir / ("Scripts/python.exe" if os.name == "nt" else "bin/python")
    purelib = Path(_run([str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"], base).stdout.strip())
    deps = {sysconfig.get_paths()["purelib"], sysconfig.get_paths()["platlib"]}
    (purelib / "zz_homesim_test_deps.pth").write_text("".join(f"{d}\n" for d in sorted(deps)), encoding="utf-8")
    _run([sys.executable, "-m", "pip", "--python", str(python), "install", "--no-deps", "--no-index", "-q", str(wheel)], base)
    shutil.rmtree(src)  # nothing of a source tree is left to find
    return python


@pytest.mark.slow
def test_a_wheel_installed_elsewhere_loads_and_runs_a_scenario(installed, tmp_path):
    python = installed
    here = tmp_path / "elsewhere"
    here.mkdir()
    shutil.copy2(ROOT / "scenarios" / "home_tour.xml", here / "tour.xml")
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    where = _run([str(python), "-c", "import homesim, robot, humans; print(homesim.__file__, robot.__file__, humans.__file__)"], here, env)
    venv_root = python.parent.parent.resolve()
    assert all(Path(f).resolve().is_relative_to(venv_root) for f in where.stdout.split()), where.stdout
    homesim_exe = python.parent / ("homesim.exe" if os.name == "nt" else "homesim")
    _run([str(homesim_exe), "check", "tour.xml"], here, env)
    done = _run([str(homesim_exe), "run", "tour.xml", "--until", "3", "--trace", "t.jsonl"], here, env)
    assert "robot: Hello, I am BIRON" in done.stdout  # the greeting ran: scenario schema, dialogs, grammar, AFSM all found
    assert (here / "t.jsonl").stat().st_size > 0
