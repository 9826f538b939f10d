"""Drive a scenario with the runner (world, hardware, supervisor, person_attention, metrics) and keep its /robot/ messages."""

from __future__ import annotations

from pathlib import Path

from homesim.tour.runner import Run, RunOptions
from homesim.world.truth import GroundTruth

HERE = Path(__file__).resolve().parent
ATTENTION_SCENARIOS = HERE.parent / "scenarios" / "attention"


def attention_run(path: Path, *, until: float | None = None, subsystems: tuple[str, ...] = ("robot.attention",)) -> Run:
    """A run of ``path`` with only the attention subsystem and the tracking metric; messages in ``run.messages``,
    ground truth frames in ``run.truth``. Call ``run.run()``; close with ``run.close()``."""
    run = Run.from_file(path, RunOptions(until=until, subsystems=subsystems, metrics=("tracking",)))
    run.messages = []
    run.dispatcher.add("/robot/", run.messages.append)
    run.truth = GroundTruth(run.world, every=5)
    return run


def channel(run: Run, name: str) -> list:
    return [m for m in run.messages if m.channel == name]


def events(run: Run) -> list[tuple[float, str]]:
    """(time, name) of every ES event the run saw."""
    return [(round(m.created, 3), m.xml.get("name")) for m in channel(run, "/robot/es/events")]
