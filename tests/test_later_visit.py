"""The later visit (scenarios/later_visit.xml) as a user runs it: first the home tour with
``--memory DIR``, then the later visit with the same ``DIR``; the robot answers "where is my
cup?" from what the tour stored. Each test builds its own store (no test order)."""

from __future__ import annotations

from pathlib import Path

from homesim.cli import main
from homesim.memory.sqlite import SqliteStore

SCENARIOS = Path(__file__).resolve().parent.parent / "scenarios"


def test_the_later_visit_answers_from_the_store_the_home_tour_wrote(tmp_path, capsys):
    store = tmp_path / "store"  # a directory that does not exist yet: the first run creates it
    # The whole tour, as a user runs it (its verdict must be PASS too).
    assert main(["run", str(SCENARIOS / "home_tour.xml"), "--memory", str(store), "--quiet"]) == 0
    capsys.readouterr()
    assert store.is_dir()
    with SqliteStore(store / "scene_model.sqlite", readonly=True) as s:
        assert "objects" in s.memories()
    # The same directory again: an existing store directory is what --memory DIR is for.
    assert main(["run", str(SCENARIOS / "later_visit.xml"), "--memory", str(store)]) == 0
    out = capsys.readouterr().out
    assert "robot: The cup is on the table in the kitchen." in out
    assert "verdict: PASS" in out


def test_without_the_tours_store_the_later_visit_is_refused_before_it_runs(tmp_path, capsys):
    assert main(["run", str(SCENARIOS / "later_visit.xml"), "--memory", str(tmp_path / "empty"), "--quiet"]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and "--memory" in captured.err and "does not exist" in captured.err
    assert not (tmp_path / "empty").exists()
