"""The rear scenes (tests/scenarios/rear/, rear12): someone right behind or beside the robot, where the
laser never looks, while it backs off or turns on the spot (issue 26 items 1 and 4: never touch a
person). Every scene checks ok and says in its README what it shows; one run of the back-off scene
up to just after Mia steps toward the robot (the follower wants to back off into Jon) demands no
contact: on main 25b2ff0, before the sonar rings, the robot touched Jon at 28.5 s in that run.
``HOMESIM_REAR=1`` runs every scene for seeds 0-9 and demands no contact in any."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from homesim.scenario.loader import check_scenario_file, load_scenario
from homesim.tour.runner import Run, RunOptions

REAR = Path(__file__).resolve().parent / "scenarios" / "rear"
FILES = sorted(REAR.glob("*.xml"))
RUN_ALL = os.environ.get("HOMESIM_REAR", "") not in ("", "0")


def test_the_readme_lists_exactly_the_scenes():
    text = (REAR / "README.md").read_text(encoding="utf-8")
    assert FILES and all(f"`{f.name}`" in text for f in FILES)


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.stem)
def test_every_rear_scene_checks_ok_and_demands_no_contact(path):
    assert check_scenario_file(path) == [], path
    sc = load_scenario(path)
    assert sc.name == f"rear_{path.stem}" and sc.description
    assert "no-collision" in {e.kind for e in sc.expectations}


def test_backing_off_from_her_never_backs_into_someone_standing_behind():
    with Run.from_file(REAR / "study_backoff_behind.xml", RunOptions(seed=0, until=34)) as run:
        run.run()
        s = run.summary()
    assert s["metrics"]["social"]["collisions_people"] == 0


@pytest.mark.slow
@pytest.mark.skipif(not RUN_ALL, reason="every rear scene x seeds 0-9: set HOMESIM_REAR=1")
@pytest.mark.parametrize("seed", range(10))
@pytest.mark.parametrize("path", FILES, ids=lambda p: p.stem)
def test_no_rear_scene_touches_anyone_for_seeds_0_to_9(path, seed):
    with Run.from_file(path, RunOptions(seed=seed)) as run:
        run.run()
        s = run.summary()
    assert s["metrics"]["social"]["collisions_people"] == 0 and s["metrics"]["social"]["collisions_flat"] == 0
