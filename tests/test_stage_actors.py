"""A stage puts on exactly the actors it is handed, in order, and names none itself.

The stage is the run package's, but what it puts on is BIRON's hardware and the scripted people: it takes
their ``install(stage)`` functions from whoever composes the run (:data:`homesim.tour.runner.ACTORS`) and
has no default, so no module of ``robot`` or ``humans`` is loaded by a name the import graph cannot see
(``tests/test_layers.py``).
"""

from __future__ import annotations

from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import humans.install
import robot.hardware.install
from homesim.sim import Simulation
from homesim.tour.runner import ACTORS
from homesim.tour.stage import Stage
from tests.world_helpers import scenario


def _recorder(calls: list[tuple[int, Stage, bool]], tag: int) -> Any:
    """An install that notes who called it, whether the world existed yet, and puts one actor on."""
    def install(stage: Stage) -> dict[str, int]:
        calls.append((tag, stage, stage.world is not None and stage.expectations is not None))
        stage.actors[f"a{tag}:{len(calls)}"] = tag
        return {}
    return install


@settings(max_examples=25, deadline=None)
@given(st.lists(st.integers(0, 3), max_size=6))
def test_each_install_handed_over_is_called_once_in_order_with_its_stage(tags):
    calls: list[tuple[int, Stage, bool]] = []
    pool = [_recorder(calls, t) for t in range(4)]
    stage = Stage(Simulation(seed=0, scenario="room"), scenario(), actors=[pool[t] for t in tags], truth_every=None)
    try:
        # the same function twice is called twice: the stage does what it is handed, nothing more
        assert [t for t, _, _ in calls] == tags
        assert all(s is stage and ready for _, s, ready in calls)
        assert len(stage.actors) == len(tags) and stage.hardware == {}
    finally:
        stage.sim.close()


def test_a_stage_handed_nothing_is_the_world_alone():
    sc = scenario()
    assert sc.humans  # the room has a person: nobody puts her on
    stage = Stage(Simulation(seed=0, scenario=sc.name), sc, actors=(), truth_every=None, keep_messages=True)
    try:
        stage.run(1.0)
        assert stage.actors == {} and stage.hardware == {}
        assert stage.messages == [] and stage.world.steps > 0  # the world stepped; no sensor spoke
    finally:
        stage.sim.close()


def test_a_stage_has_no_default_actors_and_refuses_a_module_name():
    sc = scenario()
    with pytest.raises(TypeError, match="actors"):
        Stage(Simulation(seed=0, scenario=sc.name), sc)  # type: ignore[call-arg]
    with pytest.raises(TypeError, match="'humans.install'"):
        Stage(Simulation(seed=0, scenario=sc.name), sc, actors=("humans.install",))  # type: ignore[arg-type]


def test_a_run_puts_the_people_on_then_the_hardware():
    assert ACTORS == (humans.install.install, robot.hardware.install.install)
    sc = scenario()
    stage = Stage(Simulation(seed=0, scenario=sc.name), sc, actors=ACTORS, truth_every=None, keep_messages=True)
    try:
        assert set(stage.actors) == {h.name for h in sc.humans} | {s.name for s in sc.sources}
        assert {"laser", "sonar", "camera", "microphones", "base", "map_server"} <= set(stage.hardware)
        stage.run(1.0)
        assert any(m.channel == "/robot/laser/scan" for m in stage.messages)
    finally:
        stage.sim.close()
