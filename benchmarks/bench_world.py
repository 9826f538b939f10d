"""World benchmark: laser scans per second, physics steps per second, world cost per simulated second.

Run: ``python benchmarks/bench_world.py``. Prints

- laser scans/s: our vectorised numpy raycast (361 beams) vs one pymunk
  segment query per beam, in the example flat with two people;
- physics steps/s of the example flat (robot driving, people walking);
- wall-clock milliseconds per simulated second of a whole stage (physics
  at 50 Hz, scripted people walking and talking, laser, camera,
  microphones, base, speaker, display on the bus) with 1, 3 and 10 people.

Not a test: wall-clock numbers belong here, never in the test suite.
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import numpy as np

from homesim.scenario.loader import load_scenario, load_scenario_text
from homesim.sim import Simulation
from homesim.world.bodies import LASER_FILTER
from homesim.world.stage import Stage
from homesim.world.world import World
from robot.hardware.laser import LaserSpec, laser_origin, simulate_scan

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "scenarios" / "two_people_radio.xml"


def bench_laser(n: int) -> tuple[float, float]:
    world = World(load_scenario(EXAMPLE))
    spec = LaserSpec()
    pose = world.robot.pose
    rng = np.random.default_rng(0)
    out = np.empty(spec.n_beams)
    bearings = spec.bearings()
    t0 = time.perf_counter()
    for _ in range(n):
        simulate_scan(world, pose, spec, rng, bearings=bearings, out=out)
    ours = n / (time.perf_counter() - t0)
    origin = laser_origin(pose, spec)
    angles = bearings + pose[2]
    ends = [(origin[0] + spec.max_range * math.cos(a), origin[1] + spec.max_range * math.sin(a)) for a in angles]
    m = max(1, n // 10)
    t0 = time.perf_counter()
    for _ in range(m):
        for end in ends:
            world.space.segment_query_first(origin, end, 0.0, LASER_FILTER)
    theirs = m / (time.perf_counter() - t0)
    return ours, theirs


def bench_physics(n: int) -> float:
    world = World(load_scenario(EXAMPLE))
    world.robot.command(0.3, 0.4)
    people = list(world.humans.values())
    t0 = time.perf_counter()
    for k in range(n):
        for i, h in enumerate(people):
            a = 0.01 * k + i
            h.walk_velocity(0.5 * math.cos(a), 0.5 * math.sin(a))
        world.step()
    return n / (time.perf_counter() - t0)


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


def bench_stage(n_people: int, duration: float) -> float:
    sc = load_scenario_text(crowd_scenario(n_people, duration), source=f"crowd{n_people}")
    sim = Simulation(seed=1, scenario=sc.name)
    stage = Stage(sim, sc)
    t0 = time.perf_counter()
    stage.run()
    wall = time.perf_counter() - t0
    sim.close()
    return 1000.0 * wall / duration


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scans", type=int, default=2000)
    ap.add_argument("--steps", type=int, default=5000)
    ap.add_argument("--duration", type=float, default=30.0)
    args = ap.parse_args()
    ours, theirs = bench_laser(args.scans)
    print(f"laser (361 beams): numpy {ours:8.0f} scans/s ({1000 / ours:.3f} ms/scan); pymunk per-ray queries {theirs:6.0f} scans/s ({1000 / theirs:.3f} ms/scan); x{ours / theirs:.1f}")
    steps = bench_physics(args.steps)
    print(f"physics: {steps:8.0f} steps/s ({steps / 50:.0f}x real time at 50 Hz)")
    for n in (1, 3, 10):
        ms = bench_stage(n, args.duration)
        print(f"stage with {n:2d} people: {ms:6.1f} ms of wall clock per simulated second ({1000 / ms:.0f}x real time)")


if __name__ == "__main__":
    main()
