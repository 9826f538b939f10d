"""Drive a scenario with the supervisor and the person attention system (until the runner lands)."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

from homesim.scenario.loader import load_scenario, load_scenario_text
from homesim.sim import Simulation
from homesim.world.stage import Stage
from robot.install import install
from robot.supervisor import ExecutionSupervisor

HERE = Path(__file__).resolve().parent
ATTENTION_SCENARIOS = HERE.parent / "scenarios" / "attention"


def attention_stage(source: Path | str, *, seed: int | None = None, text: bool = False, observers=()) -> Stage:
    """A stage of ``source`` (a path, or XML text with ``text=True``) with the ES and person_attention installed."""
    sc = load_scenario_text(source, source="test.xml") if text else load_scenario(source)
    sim = Simulation(seed=sc.seed if seed is None else seed, scenario=sc.name)
    st = Stage(sim, sc, keep_messages=True)
    for make in observers:
        make(st)
    es = ExecutionSupervisor(sim)
    es.start()
    st.supervisor = es
    st.robot = install(SimpleNamespace(sim=sim, config={}), ("robot.attention",))
    return st


def channel(st: Stage, name: str) -> list:
    return [m for m in st.messages if m.channel == name]


def events(st: Stage) -> list[tuple[float, str]]:
    """(time, name) of every ES event the stage saw."""
    return [(round(m.created, 3), m.xml.get("name")) for m in channel(st, "/robot/es/events")]
