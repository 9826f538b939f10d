"""The simulated people walking among people: what keeping clear of each other costs (process CPU time).

``python -m benchmarks.bench_people [--duration S]``: the example flat of ``bench_world`` with 2, 4 and 10
people pacing between their places and the far wall (their ways cross, they meet head-on), the people alone on
the stage (no robot modules). Per update, each timed by wrapping the method:

- ``leg``: a walk's per-leg look at the people (``Person._someone_ahead`` + ``Person._give_way``, every leg of
  every walk, 2 per walking second);
- ``plan``: a path plan (``Person.plan``, with the people's discs: at a walk's start, after someone was
  ahead or held her back);
- ``hold``: the world's per-step check that no step brings two bodies together (``World._crowded``, every
  physics step of every walking person);

and the whole stage's CPU ms per simulated second, the people's share of it. Run on a tree without the change
(``PYTHONPATH=<main's tree>``) it times only ``plan`` and the stage: the before figures.
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable
from typing import Any

from homesim.scenario.loader import load_scenario_text
from homesim.sim import Simulation
from homesim.tour.stage import Stage
from homesim.world.world import World
from humans.install import install as install_people
from humans.person import Person

try:
    from benchmarks.bench_world import crowd_scenario
except ImportError:  # run as a script
    from bench_world import crowd_scenario  # type: ignore[no-redef]


def _clock() -> float:
    return time.process_time()


class _Timed:
    """Wraps a method: its calls and CPU seconds."""

    def __init__(self, owner: type, name: str) -> None:
        self.owner, self.name = owner, name
        self.fn: Callable[..., Any] | None = getattr(owner, name, None)  # None: not in this version (main's)
        self.calls, self.cpu = 0, 0.0

    def __enter__(self) -> _Timed:
        fn, timed = self.fn, self
        if fn is None:
            return self

        def wrapper(*args: Any, **kwargs: Any) -> Any:
            t = _clock()
            try:
                return fn(*args, **kwargs)
            finally:
                timed.cpu += _clock() - t
                timed.calls += 1

        setattr(self.owner, self.name, wrapper)
        return self

    def __exit__(self, *exc: object) -> None:
        if self.fn is not None:
            setattr(self.owner, self.name, self.fn)

    def per_call_us(self) -> float:
        return 1e6 * self.cpu / self.calls if self.calls else 0.0


def bench(n_people: int, duration: float) -> dict[str, float]:
    sc = load_scenario_text(crowd_scenario(n_people, duration), source=f"crowd{n_people}")
    sim = Simulation(seed=1, scenario=sc.name)
    with _Timed(Person, "_someone_ahead") as ahead, _Timed(Person, "_give_way") as way, _Timed(Person, "plan") as plan, \
            _Timed(World, "_crowded") as hold:
        stage = Stage(sim, sc, actors=(install_people,))
        t0 = _clock()
        stage.run()
        cpu = _clock() - t0
    sim.close()
    legs = max(ahead.calls, 1)
    return {
        "stage_ms_per_s": 1000.0 * cpu / duration,
        "leg_us": 1e6 * (ahead.cpu + way.cpu) / legs, "legs": ahead.calls,
        "plan_us": plan.per_call_us(), "plans": plan.calls,
        "hold_us": hold.per_call_us(), "holds": hold.calls,
        "people_ms_per_s": 1000.0 * (ahead.cpu + way.cpu + plan.cpu + hold.cpu) / duration,
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=60.0)
    args = ap.parse_args()
    for n in (2, 4, 10):
        r = bench(n, args.duration)
        print(f"{n:2d} people: leg look {r['leg_us']:6.1f} us ({r['legs']} legs), plan {r['plan_us']:7.1f} us ({r['plans']} plans), "
              f"hold {r['hold_us']:5.2f} us ({r['holds']} checks); keeping clear {r['people_ms_per_s']:.2f} ms CPU per simulated s "
              f"of the stage's {r['stage_ms_per_s']:.1f} (people only, no robot modules)")


if __name__ == "__main__":
    main()
