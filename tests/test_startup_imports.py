"""``homesim run`` reaches its first simulated step without the SciPy stack (issue 25, start-up):
scipy.ndimage pulls scipy.special and scipy.sparse.csgraph pulls scipy.linalg, ~0.25 s of CPU at
every start. The grids use homesim.ndgrid; Dijkstra, ndtri and shtab are imported where used."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

PROBE = """
import contextlib, io, sys
from homesim.cli import main
with contextlib.redirect_stdout(io.StringIO()):
    status = main(["run", "scenarios/home_tour.xml", "--until", "0.5"])
loaded = sorted(m for m in sys.modules if m == "scipy" or m.startswith("scipy.") or m == "shtab")
print(status, " ".join(loaded))
print(" ".join(m for m in ("lark", "tqdm", "multiprocessing", "homesim.tour.sweep", "homesim.tour.study") if m in sys.modules))
"""


def test_the_home_tour_starts_without_scipy_or_shtab() -> None:
    out = subprocess.run([sys.executable, "-c", PROBE], cwd=ROOT, capture_output=True, text=True, check=True)
    first, _, _ = out.stdout.strip().partition("\n")
    status, _, loaded = first.partition(" ")
    assert status == "0", out.stdout + out.stderr
    # homesim.lsap loads SciPy's LSAP extension file alone (scipy.optimize._lsap), nothing else
    assert loaded.split() in ([], ["scipy.optimize._lsap"]), loaded


def test_a_run_piped_into_a_file_loads_no_other_command_no_grammar_before_speech_and_no_progress_bar() -> None:
    """The first 0.5 s of the home tour has no utterance: the speech grammar (lark) is loaded at the first one;
    ``homesim run`` imports neither sweep/study (multiprocessing) nor tqdm when stderr is not a terminal."""
    out = subprocess.run([sys.executable, "-c", PROBE], cwd=ROOT, capture_output=True, text=True, check=True)
    assert out.stdout.strip().split("\n")[1:] in ([], [""]), out.stdout
