"""Module failures from the scenario file: detected by the watchdog, restarted where possible.

``tests/scenarios/nav_faults.xml`` crashes the player at 2 s. A module the watchdog can
restart comes back and the tour goes on (here: a go-to after the recovery arrives); the
laser cannot be restarted, so the robot stays in TechnicalFailure and the dialog is told
to ask for technical support (``restarting`` false).
"""

from __future__ import annotations

import pytest

from homesim.errors import ScenarioError
from homesim.scenario.loader import load_scenario_text
from tests.nav_helpers import HERE, start_run

BASE = (HERE / "nav_faults.xml").read_text(encoding="utf-8")
FAULT = '<crash module="player" at="2"/>'


def _faulty(fault: str) -> str:
    assert FAULT in BASE
    return BASE.replace(FAULT, fault)


def _health(run):
    return [(m.xml.tag, m.xml.get("module"), m.xml.get("restarting")) for m in run.health]


def _start(text: str):
    run = start_run("nav_faults", text=text)
    run.health = []
    run.sim.bus.participant("health_watch").subscribe("/system/health", lambda m: run.health.append(m))
    run.at(0.5, run.engage)
    return run


@pytest.mark.parametrize("kind", ["crash", "hang"])
def test_a_restartable_module_comes_back_and_the_tour_goes_on(kind):
    run = _start(_faulty(f'<{kind} module="player" at="2"/>'))
    old = run.sim.modules["player"]
    states = []
    run.sim.bus.participant("es_watch").subscribe("/robot/es/status", lambda m: states.append(m.xml.get("state")))
    run.at(5.5, run.engage)
    run.at(5.8, lambda: run.teach_place("kitchen", 8.2, 1.2))
    run.at(6.0, lambda: run.goto("kitchen"))
    run.until(30.0)
    assert _health(run) == [("module_failed", "player", "true"), ("module_recovered", "player", None)]
    failed, recovered = run.health
    assert 1.0 < failed.created - 2.0 <= 1.7  # three missed 0.5 s beats after the last one
    i = states.index("TechnicalFailure")
    assert states[i - 1] == "Interacting" and states[i + 1] == "LookingAround"
    tf = [c for c in run.conditions if c[1] == "technical_failure"]
    assert tf and tf[0][2] == {"module": "player", "still_failed": "1", "restarting": "true"}
    assert "recovered" in run.condition_names()
    assert run.sim.modules["player"] is not old  # a fresh instance took over
    # the tour goes on: engaged again, it drives to the kitchen with the new player
    assert "goal_reached" in [e[1] for e in run.events]
    f = run.metric("failures")
    assert f["faults"] == 1 and f["detected"] == 1 and f["recovered"] == 1 and f["restarting"] == 1
    assert f["time_to_detect_max"] == pytest.approx(failed.created - 2.0)
    run.close()


def test_a_module_that_cannot_be_restarted_needs_technical_support():
    run = _start(_faulty('<crash module="laser" at="2"/>'))
    run.until(8.0)
    assert _health(run) == [("module_failed", "laser", "false")]
    assert run.es.state == "TechnicalFailure"
    tf = [c for c in run.conditions if c[1] == "technical_failure"]
    assert tf == [(tf[0][0], "technical_failure", {"module": "laser", "still_failed": "1", "restarting": "false"})]
    assert "recovered" not in run.condition_names()
    f = run.metric("failures")
    assert f["detected"] == 1 and f["recovered"] == 0 and f["restarting"] == 0
    run.close()


def test_restarts_are_limited_per_module():
    faults = "".join(f'<crash module="sequencer" at="{t}"/>' for t in (2, 6, 10))
    run = _start(_faulty(faults))
    run.until(15.0)
    assert _health(run) == [
        ("module_failed", "sequencer", "true"), ("module_recovered", "sequencer", None),
        ("module_failed", "sequencer", "true"), ("module_recovered", "sequencer", None),
        ("module_failed", "sequencer", "false"),
    ]
    assert run.es.state == "TechnicalFailure"
    run.close()


def test_a_fault_for_an_unknown_module_is_refused_naming_the_line():
    with pytest.raises(ScenarioError, match=r"nav_faults\.xml:\d+.*teleporter"):
        start_run("nav_faults", text=_faulty('<crash module="teleporter" at="1"/>'))


def test_the_loader_refuses_an_unknown_fault_kind_with_file_and_line():
    with pytest.raises(ScenarioError, match=r"bad\.xml:\d+"):
        load_scenario_text(_faulty('<explode module="player" at="1"/>'), source="bad.xml")
