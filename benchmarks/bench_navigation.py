"""Navigation benchmark: CPU cost per control step of the follower and the player, and of planning.

Run: ``python benchmarks/bench_navigation.py``. Prints, on this machine:

- the dynamic window alone (:func:`robot.navigation.local.dwa`) on a real 361-beam scan
  (a room with two people), and the scan to points conversion (legs inflated to bodies);
- one whole control step of the follower and of the player (``control_step``: their
  inputs already delivered; the bus publish of the velocity and the status included);
- the planner: building the inflated grid from the map once, one path across the flat, and
  one replan (a copy of the grid with a person's echoes marked, and a path on it);
- the metrics' per-physics-step observers;

and what each means per simulated second at 10 Hz control (the tour's budget is 3.3 ms
of CPU per simulated second for everything). Not a test: wall-clock numbers belong here.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np
from lxml import etree

from homesim.tour.metrics.following import Following
from homesim.tour.metrics.navigation import Navigation
from homesim.scenario.loader import load_scenario
from homesim.sim import Simulation
from homesim.tour.runner import ACTORS
from homesim.tour.stage import Stage
from robot.hardware.laser import LaserSpec, simulate_scan
from robot.hardware.map_server import floor_plan, map_element
from robot.navigation.config import Limits
from robot.navigation.giveway import back_out_spot, give_way_spot
from robot.navigation.grid import NoPathError, OccupancyGrid, parse_map
from robot.navigation.local import dwa, scan_points

ROOT = Path(__file__).resolve().parents[1]
DOOR = ROOT / "tests" / "scenarios" / "follow_door.xml"
GOTO = ROOT / "tests" / "scenarios" / "nav_goto.xml"


def per_call(fn, n: int) -> float:
    """Mean CPU microseconds (process time) of ``fn()`` over ``n`` calls (after one warm-up call)."""
    fn()
    t0 = time.process_time()
    for _ in range(n):
        fn()
    return (time.process_time() - t0) / n * 1e6


async def _next_scan(run):  # type: ignore[no-untyped-def]
    sub = run.sim.bus.participant(f"bench{run.sim.now_ns}").subscribe("/robot/laser/scan")
    return await sub.get()


def _replan(grid: OccupancyGrid, marked: np.ndarray) -> None:
    """One replan: the grid with the marked echoes, and a path on it (none through a blocked door is fine)."""
    try:
        grid.with_obstacles(marked).plan((1.5, 1.0), (8.2, 1.2))
    except NoPathError:
        pass


def main() -> None:
    import sys

    sys.path.insert(0, str(ROOT))
    from tests.nav_helpers import start_run

    sc = load_scenario(GOTO)
    sim = Simulation(seed=1)
    stage = Stage(sim, sc, actors=ACTORS)
    sim.run(until=0.1)
    spec = LaserSpec()
    ranges = simulate_scan(stage.world, stage.world.robot.pose, spec, np.random.default_rng(0))
    lim = Limits()
    pts = scan_points(ranges, -spec.fov / 2, spec.resolution, spec.max_range, spec.offset)
    r = {}
    r["scan -> points (legs as bodies)"] = per_call(lambda: scan_points(ranges, -spec.fov / 2, spec.resolution, spec.max_range, spec.offset), 2000)
    r["dwa (one decision)"] = per_call(lambda: dwa(0.3, 0.0, (2.0, 0.5), pts, lim, v_pref=0.4), 1000)
    from robot.navigation.seen import SeenGround

    seen = SeenGround()
    x0, y0, th0 = stage.world.robot.pose
    r["follower: seen ground, one scan (2/s while following)"] = per_call(
        lambda: seen.add(ranges, -spec.fov / 2, spec.resolution, spec.max_range, (x0, y0, th0)), 2000)

    run = start_run("follow_door", tracks={"anna": "t1"})
    run.at(0.3, lambda: run.oracle.follow("t1"))
    run.until(6.0)
    fol = run.modules["follower"]
    scan = run.sim.run_until_complete(_next_scan(run))

    def follow_step() -> None:
        fol.scan.update(scan)  # a fresh scan each step, as at 10 Hz
        fol.control_step()

    r["follower control step"] = per_call(follow_step, 1000)
    run.close()

    run = start_run("nav_goto", text=GOTO.read_text(encoding="utf-8").replace('x="6.0" y="2.0"', 'x="1.0" y="3.2"'))
    run.at(0.5, run.engage)
    run.at(1.0, lambda: run.teach_place("kitchen", 8.2, 1.2))
    run.at(1.5, lambda: run.goto("kitchen"))
    run.until(4.0)
    pl = run.modules["player"]
    goal = pl.goal
    scan = run.sim.run_until_complete(_next_scan(run))

    def step() -> None:
        pl.goal = goal
        pl.scan.update(scan)
        pl.control_step()
    r["player control step (move_to)"] = per_call(step, 1000)
    run.close()

    m = map_element(floor_plan(sc))
    plan = parse_map(m)
    t0 = time.process_time()
    grid = OccupancyGrid(plan, radius=lim.radius)
    build = (time.process_time() - t0) * 1e3
    grid.plan((1.5, 1.0), (8.2, 1.2))
    # (the grid keeps its latest searches and paths: ``_forget`` first measures a whole search)
    r["planner: one path across the flat"] = per_call(lambda: (grid._forget(), grid.plan((1.5, 1.0), (8.2, 1.2))), 50)
    r["planner: the same path asked again (kept)"] = per_call(lambda: grid.plan((1.5, 1.0), (8.2, 1.2)), 500)
    # the follower's search for a place to give way, then to back out (robot.navigation.giveway), with the
    # robot in the door and the partner in front of it: afresh (a new place), and asked again from where it
    # stands (wedged: the follower asks about every second; fresh23 defect F)
    here, her = (6.0, 2.0), (5.3, 2.0)

    def give_way() -> None:
        if give_way_spot(grid, here, her, keep=0.8) is None:
            back_out_spot(grid, here, her, keep=0.8, came=(7.0, 2.0))
    r["follower: give-way + back-out search (afresh)"] = per_call(lambda: (grid._forget(), give_way()), 10)
    r["follower: give-way + back-out search (asked again)"] = per_call(give_way, 50)
    person = np.array([[6.0 + 0.25 * math.cos(a), 2.0 + 0.25 * math.sin(a)] for a in np.linspace(0, 2 * math.pi, 10)])
    r["planner: replan (local costmap copy + path)"] = per_call(
        lambda: _replan(grid, person), 20)

    class _Run:
        world = stage.world
        config = None
        es_state = "Following"

    fm = Following(_Run())
    fm.partner = "tom"
    nm = Navigation(_Run())
    nm.active, nm.last = True, (1.5, 1.0)
    r["metrics per physics step (following + go-to)"] = per_call(lambda: (fm.on_step(stage.world), nm.on_step(stage.world)), 5000)

    print(f"{'what':48s} {'us/call':>10s} {'ms per simulated s':>20s}")
    for k, v in r.items():
        rate = 50.0 if "physics" in k else 2.0 if "seen ground" in k else 10.0 if "step" in k or "dwa" in k or "scan" in k else 0.0
        per_s = (f"{v * rate / 1000:.3f} (x{rate:g}/s)" if rate else "once per blockage" if "replan" in k
                 else "about 1/s while wedged" if "give-way" in k else "once per go-to")
        print(f"{k:48s} {v:10.1f} {per_s:>20s}")
    print(f"{'planner: grid build from the map (once per run)':48s} {build * 1000:10.1f} {'once per run':>20s}")
    print(f"grid: {grid.nx} x {grid.ny} cells of {grid.cell} m")
    sim.close()


if __name__ == "__main__":
    main()
