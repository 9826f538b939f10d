"""World benchmark: laser scans per second, physics steps per second, world cost per simulated second.

Run: ``python benchmarks/bench_world.py``. Prints

- laser scans/s: our raycast (361 beams; the fan caster, with its compiled kernel and, back to
  back, its pure-Python/numpy path) vs one pymunk segment query per beam, in the example flat
  with two people;
- physics steps/s of the example flat (robot driving, people walking);
- CPU milliseconds (process time) per simulated second of a whole stage (physics
  at 50 Hz, scripted people walking and talking, laser, camera,
  microphones, base, speaker, display on the bus) with 1, 3 and 10 people,
  and its parts: ``physics`` (the ``world`` task: stepping, holding people
  back, contacts, step listeners, minus ground truth), ``ground truth``
  (the stage's :class:`~homesim.world.truth.GroundTruth` frames, 10 a second),
  ``people`` (the scripted people's tasks: scripts, walking, path planning)
  and the rest (sensors and their messages, the kernel). Each part is timed
  around its task as ``bench_modules.py`` does (about a microsecond per update
  of timer overhead).

Not a test: CPU times belong here, never in the test suite.
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path
from typing import Any

import numpy as np

from homesim.scenario.loader import load_scenario, load_scenario_text
from homesim.sim import Simulation
from homesim.world.bodies import LASER_FILTER
from homesim.tour.runner import ACTORS
from homesim.tour.stage import Stage
from homesim.world.world import World
from robot.hardware.laser import LaserSpec, laser_origin, simulate_scan

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "scenarios" / "two_people_radio.xml"


_clock = time.process_time


def bench_laser(n: int) -> tuple[float, float]:
    world = World(load_scenario(EXAMPLE))
    spec = LaserSpec()
    pose = world.robot.pose
    rng = np.random.default_rng(0)
    out = np.empty(spec.n_beams)
    bearings = spec.bearings()
    t0 = _clock()
    for _ in range(n):
        simulate_scan(world, pose, spec, rng, bearings=bearings, out=out)
    ours = n / (_clock() - t0)
    origin = laser_origin(pose, spec)
    angles = bearings + pose[2]
    ends = [(origin[0] + spec.max_range * math.cos(a), origin[1] + spec.max_range * math.sin(a)) for a in angles]
    m = max(1, n // 10)
    t0 = _clock()
    for _ in range(m):
        for end in ends:
            world.space.segment_query_first(origin, end, 0.0, LASER_FILTER)
    theirs = m / (_clock() - t0)
    return ours, theirs


def bench_physics(n: int) -> float:
    world = World(load_scenario(EXAMPLE))
    world.robot.command(0.3, 0.4)
    people = list(world.humans.values())
    t0 = _clock()
    for k in range(n):
        for i, h in enumerate(people):
            a = 0.01 * k + i
            h.walk_velocity(0.5 * math.cos(a), 0.5 * math.sin(a))
        world.step()
    return n / (_clock() - t0)


def crowd_scenario(n_people: int, duration: float) -> str:
    """The example flat with ``n_people`` people pacing and talking (no radio)."""
    text = EXAMPLE.read_text(encoding="utf-8")
    head, rest = text.split("<humans>", 1)
    _, tail = rest.split("</humans>", 1)
    tail = tail.split("<expect>", 1)[0] + "</scenario>\n"
    tail = tail.replace(tail[tail.index("<sources>") : tail.index("</sources>") + len("</sources>")], "")
    spots = [(2.9 + 0.55 * (i % 5), 1.6 + 0.8 * (i // 5)) for i in range(n_people)]
    humans = []
    for i, (x, y) in enumerate(spots):
        humans.append(
            f'<human name="p{i}" x="{x:.2f}" y="{y:.2f}" heading="180"><script><repeat>'
            f'<walk-to point="{7.5 - 0.2 * (i % 5):.2f} {1.2 + 0.3 * (i % 4):.2f}"/><say text="hello there number {i}"/>'
            f'<walk-to point="{x:.2f} {y:.2f}"/><face robot="true"/><wait for="1"/></repeat></script></human>'
        )
    text = head + "<humans>" + "".join(humans) + "</humans>" + tail
    return text.replace('duration="40"', f'duration="{duration:g}"')


def looping_home(duration: float) -> Any:
    """The example flat with one person pacing and talking forever (any length; no radio)."""
    return load_scenario_text(crowd_scenario(1, duration), source=f"looping home ({duration:g} s)")


def bench_stage(n_people: int, duration: float) -> float:
    """CPU ms per simulated second of the whole stage with ``n_people``."""
    return stage_parts(n_people, duration, parts=False)["stage"]


def stage_parts(n_people: int, duration: float, *, parts: bool = True) -> dict[str, float]:
    """CPU ms per simulated second of the whole stage and (``parts``) of physics, ground truth and people."""
    try:
        from benchmarks.bench_modules import _Account, _TimedCoroutine
    except ImportError:  # run as a script: benchmarks/ is on the path, its package is not
        from bench_modules import _Account, _TimedCoroutine  # type: ignore[no-redef]
    from homesim.world.truth import GroundTruth

    account = _Account()
    spawn, capture = Simulation.spawn, GroundTruth.capture
    truth = [0.0]

    def timed_spawn(self: Simulation, coro: Any, *, name: str) -> Any:
        return spawn(self, _TimedCoroutine(coro, name, account), name=name)

    def timed_capture(self: GroundTruth) -> Any:
        t = _clock()
        try:
            return capture(self)
        finally:
            truth[0] += _clock() - t

    sc = load_scenario_text(crowd_scenario(n_people, duration), source=f"crowd{n_people}")
    sim = Simulation(seed=1, scenario=sc.name)
    if parts:
        Simulation.spawn, GroundTruth.capture = timed_spawn, timed_capture  # type: ignore[method-assign]
    try:
        stage = Stage(sim, sc, actors=ACTORS)
        t0 = _clock()
        stage.run()
        cpu = _clock() - t0
    finally:
        Simulation.spawn, GroundTruth.capture = spawn, capture  # type: ignore[method-assign]
        sim.close()
    out = {"stage": 1000.0 * cpu / duration}
    if parts:
        people = sum(c for name, c in account.cpu.items() if name.startswith("human:"))
        out.update(physics=1000.0 * (account.cpu["world"] - truth[0]) / duration, truth=1000.0 * truth[0] / duration,
                   people=1000.0 * people / duration)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scans", type=int, default=2000)
    ap.add_argument("--steps", type=int, default=5000)
    ap.add_argument("--duration", type=float, default=30.0)
    args = ap.parse_args()
    from homesim.world import raycast

    kernel = raycast._K
    ours, theirs = bench_laser(args.scans)
    raycast._K = None  # the same scans on the compiled kernel's Python path, back to back
    python, _ = bench_laser(args.scans)
    raycast._K = kernel
    built = "compiled kernel" if kernel is not None else "kernel NOT built"
    print(f"laser (361 beams): {built} {ours:8.0f} scans/s ({1000 / ours:.3f} ms/scan), its Python path {python:8.0f} scans/s "
          f"({1000 / python:.3f} ms/scan); pymunk per-ray queries {theirs:6.0f} scans/s ({1000 / theirs:.3f} ms/scan); x{ours / theirs:.1f}")
    steps = bench_physics(args.steps)
    print(f"physics: {steps:8.0f} steps/s ({steps / 50:.0f}x real time at 50 Hz)")
    for n in (1, 3, 10):
        p = stage_parts(n, args.duration)
        print(f"stage with {n:2d} people: {p['stage']:6.1f} ms CPU per simulated second ({1000 / p['stage']:.0f}x real time): "
              f"physics {p['physics']:.2f}, ground truth {p['truth']:.2f}, people {p['people']:.2f}, "
              f"the rest (sensors, kernel) {p['stage'] - p['physics'] - p['truth'] - p['people']:.2f}")


if __name__ == "__main__":
    main()
