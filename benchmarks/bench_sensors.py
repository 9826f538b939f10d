"""Sensor models' CPU: the laser, the sonar rings and the camera, per update and in the simulated home.

Run: ``python -m benchmarks.bench_sensors [--duration S] [--reps N]``. Process CPU time
(``time.process_time``), so the machine's other work counts less than on a wall clock. Prints, for
the example flat with 1, 3 and 10 people (:func:`benchmarks.bench_world.crowd_scenario`):

- a 361-beam scan (``simulate_scan``: ranges and noise) with the robot standing (the walls and
  furniture kept from the last scan, only legs cast) and moving (everything cast), and the dense
  kernel (``RayCaster``: every beam against every edge and leg, what a moving scan cost before the
  fan caster) for comparison;
- a sonar packet (``sonar_readings``: five transducers, each the nearest echo of its cone's seven
  rays, with noise and dropouts; the rings fire 2.5 per ring per 0.1 s packet), in one pass, in one
  pass with the robot standing (``SegmentRanges``: walls kept, legs cast) and ray by ray with a
  ``RayCaster`` (the same floats);
- a camera frame's detections (``detect_frame``: faces, torsos, gestures, objects, one pass of 3D
  sight lines) against the four per-kind detectors called in turn (a pass each);
- the whole simulated home (``Stage``: physics, people, every sensor and its bus messages) in CPU
  ms per simulated second, and the laser's, the sonar's, the camera's, the microphones' and the base's modules'
  share of it (each wake-up timed, as :mod:`benchmarks.bench_modules` does, their bus messages
  included).

Every figure is measured twice side by side, with the compiled kernels
(``homesim/world/_raykernels.c``) and with the pure-Python/numpy paths they replace
(``raycast._K`` set to None in this process; ``HOMESIM_PURE_PYTHON=1`` does the same for a whole
run): ``kernel`` and ``python`` columns. Where the kernel is not built both columns are the Python path.

Not a test: nothing is asserted.
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from benchmarks.bench_modules import _Account, _TimedCoroutine
from benchmarks.bench_world import crowd_scenario
from homesim.scenario.loader import load_scenario_text
from homesim.sim import Simulation
from homesim.world import raycast
from homesim.world.raycast import RayCaster
from homesim.tour.runner import ACTORS
from homesim.tour.stage import Stage
from homesim.world.world import World
from robot.hardware.camera import CameraSpec, PanTilt, detect_faces, detect_frame, detect_gestures, detect_objects, detect_torsos
from robot.hardware.laser import LaserSpec, laser_origin, simulate_scan
from robot.hardware import sonar as sonar_module
from robot.hardware.sonar import SegmentRanges, SonarSpec, sonar_readings

_clock = time.process_time


def cpu_us(fn: Callable[[], Any], reps: int) -> float:
    """Best of five rounds of ``reps`` calls, CPU microseconds per call."""
    fn()
    best = []
    for _ in range(5):
        t0 = _clock()
        for _ in range(reps):
            fn()
        best.append(1e6 * (_clock() - t0) / reps)
    return min(best)


def kernels(n_people: int, reps: int) -> dict[str, float]:
    """Per-update CPU (us) of the laser and camera models in the crowd flat, people facing the robot."""
    world = World(load_scenario_text(crowd_scenario(n_people, 10.0), source=f"crowd{n_people}"))
    pose = world.robot.pose
    cam_xy = world.robot.pose[:2]
    for h in world.humans.values():
        x, y = h.position
        h.turn_to(float(np.arctan2(cam_xy[1] - y, cam_xy[0] - x)))
        h.advance(0.0)
    spec, rng = LaserSpec(), np.random.default_rng(0)
    bearings = spec.bearings()
    poses = [(pose[0] + 1e-4 * (k % 2), pose[1], pose[2]) for k in range(2)]
    k = [0]

    def moving() -> None:
        k[0] += 1
        simulate_scan(world, poses[k[0] % 2], spec, rng, bearings=bearings)

    a, b = world._laser_segments
    c, r = world.leg_circles()
    origin, angles = laser_origin(pose, spec), bearings + pose[2]
    dense = RayCaster()
    cspec, ptu = CameraSpec(), PanTilt()
    sspec, scaster, skept = SonarSpec(), RayCaster(), SegmentRanges()

    def per_kind() -> None:
        occ = world.person_cylinders()
        detect_faces(world, pose, ptu, cspec, rng, occluders=occ)
        detect_torsos(world, pose, ptu, cspec, rng, occluders=occ)
        detect_gestures(world, pose, ptu, cspec, rng, occluders=occ)
        detect_objects(world, pose, ptu, cspec, rng, occluders=occ)

    return {
        "scan standing": compiled_and_python(lambda: cpu_us(lambda: simulate_scan(world, pose, spec, rng, bearings=bearings), reps)),
        "scan moving": compiled_and_python(lambda: cpu_us(moving, reps)),
        "dense cast": compiled_and_python(lambda: cpu_us(lambda: dense.cast(origin, angles, a, b, c, r, spec.max_range, backfaces=False), reps)),
        "sonar packet": compiled_and_python(lambda: cpu_us(lambda: sonar_readings(world, pose, sspec, (0, 8, 1, 9, 2), rng), reps)),
        "sonar standing": compiled_and_python(lambda: cpu_us(lambda: sonar_readings(world, pose, sspec, (0, 8, 1, 9, 2), rng, kept=skept), reps)),
        "sonar ray by ray": compiled_and_python(lambda: cpu_us(lambda: sonar_readings(world, pose, sspec, (0, 8, 1, 9, 2), rng, caster=scaster), reps)),
        "frame": compiled_and_python(lambda: cpu_us(lambda: detect_frame(world, pose, ptu, cspec, rng, occluders=world.person_cylinders()), reps)),
        "frame per kind": compiled_and_python(lambda: cpu_us(per_kind, reps)),
    }


def compiled_and_python(measure: Callable[[], Any]) -> tuple[Any, Any]:
    """``measure()`` with the compiled raycast kernel, then with the Python path, back to back (the sonar
    model holds its own reference to the same kernel: switched with it)."""
    kernel, sonar_kernel = raycast._K, sonar_module._K
    with_kernel = measure()
    raycast._K = sonar_module._K = None
    try:
        return with_kernel, measure()
    finally:
        raycast._K, sonar_module._K = kernel, sonar_kernel


def in_stage(n_people: int, duration: float) -> dict[str, float]:
    """CPU ms per simulated second: the whole simulated home, and its laser and camera modules."""
    account = _Account()
    spawn = Simulation.spawn

    def timed_spawn(self: Simulation, coro: Any, *, name: str) -> Any:
        return spawn(self, _TimedCoroutine(coro, name, account), name=name)

    sc = load_scenario_text(crowd_scenario(n_people, duration), source=f"crowd{n_people}")
    Simulation.spawn = timed_spawn  # type: ignore[method-assign]
    try:
        sim = Simulation(seed=1, scenario=sc.name)
        stage = Stage(sim, sc, actors=ACTORS)
        t0 = _clock()
        stage.run()
        cpu = _clock() - t0
        sim.close()
    finally:
        Simulation.spawn = spawn  # type: ignore[method-assign]
    return {"home": 1000 * cpu / duration, **{m: 1000 * account.cpu[m] / duration for m in MODULES}}


MODULES = ("laser", "sonar", "camera", "microphones", "base")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--duration", type=float, default=30.0, help="simulated seconds of each home run")
    ap.add_argument("--reps", type=int, default=300, help="calls per timing round of the kernels")
    a = ap.parse_args()
    print(f"compiled kernel {'built' if raycast._K is not None else 'NOT built (both columns: the Python path)'}; "
          "each figure: kernel / python, measured back to back")
    print(f"{'people':>6} {'scan standing us':>17} {'scan moving us':>15} {'dense cast us':>14} {'frame us':>13} {'per kind us':>13}")
    for n in (1, 3, 10):
        k = kernels(n, a.reps)
        print(f"{n:>6} " + " ".join(f"{k[name][0]:>{w - 7}.1f} / {k[name][1]:>5.1f}" for name, w in
                                   (("scan standing", 17), ("scan moving", 15), ("dense cast", 14), ("frame", 13), ("frame per kind", 13))), flush=True)
        print(f"{'':>6} sonar packet us {k['sonar packet'][0]:.1f} / {k['sonar packet'][1]:.1f} "
              f"(standing, walls kept {k['sonar standing'][0]:.1f} / {k['sonar standing'][1]:.1f}; "
              f"ray by ray {k['sonar ray by ray'][0]:.1f} / {k['sonar ray by ray'][1]:.1f})", flush=True)
    print(f"{'people':>6} {'home ms/s':>15} " + " ".join(f"{m + ' ms/s':>15}" for m in MODULES))
    for n in (1, 3, 10):
        s = compiled_and_python(lambda: in_stage(n, a.duration))
        print(f"{n:>6} {s[0]['home']:>7.2f} / {s[1]['home']:>5.2f} " + " ".join(f"{s[0][m]:>7.2f} / {s[1][m]:>5.2f}" for m in MODULES), flush=True)

if __name__ == "__main__":
    main()
