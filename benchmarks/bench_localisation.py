"""Localisation benchmark: the localiser's CPU per simulated second, per update, per correction.

Run: ``python benchmarks/bench_localisation.py [--seconds 60]``. The example flat,
the robot driving circles at 0.3 m/s (people walking about), odometry and laser at
10 Hz. The localiser's two handlers are timed with ``time.process_time`` (CPU, this
process) around each call:

- odometry handler: compose the last estimate with the odometry since, publish the
  typed ``/robot/localisation/pose`` (XSD validation and delivery included);
- scan handler: when the robot moved 10 cm / 0.1 rad since the last correction,
  predict + likelihood-field correction (120 particles x 30 beams) + estimate;
  otherwise it returns at once.

Also: the same tour standing still (corrections stop after the first three scans),
the localisation error of the run (homesim.tour.metrics.localisation) and the likelihood
field's construction time. Budget (the performance aim: 3.3 ms CPU per simulated second for the
whole tour): the localiser aims under 0.5 ms per simulated second. Not counted: the
bus's own cost of delivering scans and odometry to one more receiver, and the
metric's scoring of each pose (timed apart and subtracted).

Not a test: CPU numbers belong here, never in the test suite.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from homesim.tour.metrics.localisation import LocalisationMetric
from homesim.scenario.loader import load_scenario
from homesim.sim import Simulation
from homesim.tour.runner import ACTORS
from homesim.tour.stage import Stage
from robot.hardware.map_server import floor_plan
from robot.localisation import install
from robot.localisation.mcl import LikelihoodField, MCLParams

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "scenarios" / "two_people_radio.xml"


class _Run:
    def __init__(self, sim: Simulation) -> None:
        self.sim = sim
        self.config = None


def _timed(fn, acc: list[float], corrections: list[float] | None = None, mcl_of=None):  # type: ignore[no-untyped-def]
    def wrapper(msg):  # type: ignore[no-untyped-def]
        before = mcl_of().updates if mcl_of and mcl_of() else 0
        t0 = time.process_time()
        fn(msg)
        dt = time.process_time() - t0
        acc.append(dt)
        if corrections is not None and mcl_of and mcl_of() and mcl_of().updates > before:
            corrections.append(dt)

    return wrapper


def tour(seconds: float, *, drive: bool) -> dict[str, float]:
    from lxml import etree

    sc = load_scenario(EXAMPLE)
    sim = Simulation(seed=sc.seed, scenario=sc.name)
    stage = Stage(sim, sc, actors=ACTORS)
    loc = install(_Run(sim))["localiser"]
    odo_t: list[float] = []
    scan_t: list[float] = []
    corr_t: list[float] = []
    # Re-route the localiser's subscriptions through timers (same handlers, same order).
    for sub in loc.bus.subscriptions:
        if sub.pattern == "/robot/odometry":
            sub.handler = _timed(loc._on_odometry, odo_t)
        elif sub.pattern == "/robot/laser/scan":
            sub.handler = _timed(loc._on_scan, scan_t, corr_t, lambda: loc.mcl)
    metric = LocalisationMetric(None)
    metric_t: list[float] = []
    # The metric scores each pose as it is sent (inside the localiser's publish): timed apart
    # and subtracted, it is the run's scoring, not the robot's cost.
    stage.dispatcher.add(metric.channels, _timed(metric.on_message, metric_t))
    stage.world.add_listener(metric.on_step)
    if drive:
        driver = sim.bus.participant("driver", host="robot")

        async def go() -> None:
            import asyncio

            while True:
                driver.publish("/robot/base/cmd", etree.Element("velocity", v="0.3", w="0.25"))
                await asyncio.sleep(0.2)

        sim.spawn(go(), name="driver")
    stage.run(until=seconds)
    sim.close()
    total = sum(odo_t) + sum(scan_t) - sum(metric_t)
    return {
        "ms_per_sim_s": 1000 * total / seconds,
        "odometry_us": 1e6 * (sum(odo_t) - sum(metric_t)) / max(1, len(odo_t)),
        "scan_us": 1e6 * sum(scan_t) / max(1, len(scan_t)),
        "correction_us": 1e6 * sum(corr_t) / max(1, len(corr_t)),
        "corrections_per_s": len(corr_t) / seconds,
        **{f"err_{k}": v for k, v in metric.summary().items() if k in ("mean_m", "max_m")},
    }


def bare_publish_us(n: int = 2000, *, strict: bool = False) -> float:
    """The kernel's cost of one typed pose publish with no receiver (a yardstick for this machine).

    ``strict``: under the validating policy (tests, ``--strict``), else the default (the
    module's own element is trusted; see :mod:`homesim.bus`).
    """
    from lxml import etree

    from robot.localisation import POSE_SCHEMA

    sim = Simulation(seed=1, scenario="bench", strict=strict)
    sim.bus.declare_channel("/robot/localisation/pose", POSE_SCHEMA)
    p = sim.bus.participant("p", host="robot")
    t0 = time.process_time()
    for i in range(n):
        p.publish("/robot/localisation/pose", etree.Element("pose", time=f"{i * 0.1:.6f}", x="1.0000", y="2.0000", theta="0.10000", cxx="0.000100", cyy="0.000100",
            ctt="0.000010", frame="map"))
    dt = time.process_time() - t0
    sim.close()
    return 1e6 * dt / n


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seconds", type=float, default=60.0)
    args = ap.parse_args()
    plan = floor_plan(load_scenario(EXAMPLE))
    t0 = time.process_time()
    for _ in range(5):
        LikelihoodField(plan, resolution=MCLParams().resolution)
    print(f"likelihood field ({MCLParams().resolution * 100:.0f} cm cells): {1000 * (time.process_time() - t0) / 5:.1f} ms to build")
    print(f"yardstick: one typed pose publish with no receiver costs {bare_publish_us():.0f} us on this machine now")
    for drive in (True, False):
        r = tour(args.seconds, drive=drive)
        what = "driving 0.3 m/s" if drive else "standing      "
        print(
            f"{what}: {r['ms_per_sim_s']:.3f} ms CPU per simulated s | odometry+publish {r['odometry_us']:.0f} us"
            f" | scan handler {r['scan_us']:.0f} us mean, correction {r['correction_us']:.0f} us x {r['corrections_per_s']:.1f}/s"
            f" | error mean {r['err_mean_m']} m, max {r['err_max_m']} m"
        )


if __name__ == "__main__":
    main()
