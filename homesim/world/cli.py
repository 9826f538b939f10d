"""``homesim scenario run FILE`` and ``homesim scenario plot FILE --at T -o out.png``.

``run`` loads the scenario, runs the world, the scripted people and sound
sources and the PeopleBot hardware for the scenario's duration (or
``--until``), prints what was said, the sensor traffic and one verdict line
per expectation, and exits 0 when every expectation holds, 1 otherwise.
``plot`` runs to ``--at`` and draws the top-down view of that moment with
the latest laser scan and sound directions. Loading errors print one line
naming the file and line (exit status 2, from the main CLI).
"""

from __future__ import annotations

import argparse
import math
from collections import Counter
from pathlib import Path

import numpy as np

from ..scenario.loader import load_scenario
from ..sim import Simulation
from .stage import Stage


def build_stage(path: str | Path, *, seed: int | None = None, trace: Path | None = None) -> tuple[Simulation, Stage]:
    """Load a scenario and put it on a new Simulation (seed from the file unless given)."""
    sc = load_scenario(path)
    sim = Simulation(seed=sc.seed if seed is None else seed, scenario=sc.name)
    if trace is not None:
        trace.parent.mkdir(parents=True, exist_ok=True)
        sim.record_trace(trace)
    return sim, Stage(sim, sc)


def run_scenario(path: str | Path, *, seed: int | None = None, until: float | None = None, trace: Path | None = None, quiet: bool = False) -> int:
    """Run a scenario file and print a transcript and verdicts; returns the exit status."""
    sim, stage = build_stage(path, seed=seed, trace=trace)
    with sim:
        sc = stage.scenario
        end = sc.duration if until is None else min(until, sc.duration)
        stage.run(end)
        verdicts = stage.verdicts() if end >= sc.duration else []
        print(f"scenario {sc.name}: seed {sim.seed}, {end:g} s of virtual time, {len(sc.humans)} people, {len(sc.sources)} other sound sources")
        if not quiet:
            print("transcript:")
            for u in stage.world.sound.all():
                if u.start < end:
                    print(f"  {u.start:7.2f}-{min(u.end, end):6.2f} s  {u.source:>10}: {u.text}{' [cut short]' if u.cut else ''}")
            counts = Counter(m.channel for m in stage.messages)
            print("sensor messages: " + ", ".join(f"{ch} {n}" for ch, n in sorted(counts.items())))
            if stage.world.contacts:
                print("robot contacts: " + ", ".join(f"{what} at {t:.2f} s" for t, what in stage.world.contacts))
        for v in verdicts:
            print("  " + v.line())
        ok = all(v.passed for v in verdicts)
        if until is not None and end < sc.duration:
            print(f"verdict: not checked (stopped at {end:g} s of {sc.duration:g} s)")
            return 0
        print(f"verdict: {'PASS' if ok else 'FAIL'} ({sum(v.passed for v in verdicts)}/{len(verdicts)} expectations hold)")
        return 0 if ok else 1


def plot_scenario(path: str | Path, *, at: float, out: Path, seed: int | None = None) -> int:
    """Run to time ``at`` and save the top-down view of that moment."""
    from .. import viz

    sim, stage = build_stage(path, seed=seed)
    with sim:
        sc = stage.scenario
        at = max(0.0, min(at, sc.duration))
        stage.run(at)
        scan = None
        sounds: list[float] = []
        for m in reversed(stage.messages):
            if scan is None and m.channel == "/robot/laser/scan":
                ranges = np.asarray(m.attachments["ranges"])
                start = math.radians(float(m.xml.get("min_angle")))
                step = math.radians(float(m.xml.get("resolution")))
                scan = (start + step * np.arange(ranges.shape[0]), ranges)
            if not sounds and m.channel == "/robot/audio/sources" and at - m.created < 0.2:
                sounds = [math.radians(float(s.get("bearing"))) for s in m.xml.iterfind("source")]
            if scan is not None and (sounds or at - m.created > 0.2):
                break
        fig = viz.plot_moment(stage.world, scan=scan, sound_bearings=sounds)
        out.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(out, dpi=120)
        print(f"wrote {out} ({sc.name} at t = {at:g} s)")
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``homesim scenario run|plot``."""
    p = sub.add_parser("scenario", help="run or plot a scenario file (the flat, people, robot hardware)")
    ssub = p.add_subparsers(dest="scenario_command", metavar="ACTION")
    r = ssub.add_parser("run", help="run a scenario and check its expectations")
    r.add_argument("file", type=Path)
    r.add_argument("--seed", type=int, default=None, help="override the scenario's seed")
    r.add_argument("--until", type=float, default=None, help="stop early (virtual seconds; expectations are not checked)")
    r.add_argument("--trace", type=Path, default=None, help="write the bus trace (JSON Lines)")
    r.add_argument("--quiet", action="store_true", help="verdicts only")
    r.set_defaults(func=lambda a: run_scenario(a.file, seed=a.seed, until=a.until, trace=a.trace, quiet=a.quiet))
    q = ssub.add_parser("plot", help="draw the top-down view at one moment")
    q.add_argument("file", type=Path)
    q.add_argument("--at", type=float, required=True, help="virtual time in seconds")
    q.add_argument("-o", "--output", type=Path, default=Path("out/scenario.png"))
    q.add_argument("--seed", type=int, default=None)
    q.set_defaults(func=lambda a: plot_scenario(a.file, at=a.at, out=a.output, seed=a.seed))
    p.set_defaults(func=lambda a: (p.print_help(), 2)[1])
