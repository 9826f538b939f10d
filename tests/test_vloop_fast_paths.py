"""The loop's fast paths do what its plain path does: same callbacks, same order, same times.

``VirtualEventLoop._drive`` has two shortcuts when it runs free (``run``): a round that is one
timer alone (a bus delivery, a sleep's wake-up) runs without the ready queue, and a sleep's
wake-up that would be the whole next round runs at once. ``step()`` takes neither (it stops after
every round), so stepping a workload to its end is the plain path; both must give the same log.
"""

from __future__ import annotations

import asyncio
import collections

from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from homesim.sim import Simulation

#: One task's script: a sequence of (sleep in ns, publish?) steps.
scripts = st.lists(
    st.lists(st.tuples(st.sampled_from([0, 1, 500, 1_000_000, 3_000_000, 10_000_000]), st.booleans()), min_size=1, max_size=8),
    min_size=1, max_size=5,
)


def _run(tasks: list[list[tuple[int, bool]]], seed: int, stepping: bool) -> list[tuple[int, str]]:
    sim = Simulation(seed=seed)
    log: list[tuple[int, str]] = []
    try:
        listener = sim.bus.participant("listener", host="laptop")
        listener.subscribe("/t/**", handler=lambda m: log.append((sim.now_ns, f"got {m.id}")))

        async def worker(i: int, script: list[tuple[int, bool]]) -> None:
            p = sim.bus.participant(f"w{i}", host="robot")
            for k, (ns, publish) in enumerate(script):
                await asyncio.sleep(ns / 1e9)
                log.append((sim.now_ns, f"w{i} woke {k}"))
                if publish:
                    p.publish(f"/t/w{i}", etree.Element("x", k=str(k)))

        for i, script in enumerate(tasks):
            sim.spawn(worker(i, script), name=f"w{i}")
        sim.loop.call_at_ns(2_000_000, lambda: log.append((sim.now_ns, "timer")))
        if stepping:
            while sim.step():
                pass
        else:
            sim.run(until=1.0)
    finally:
        sim.close()
    return log


@settings(max_examples=60, deadline=None)
@given(scripts, st.integers(0, 3))
def test_running_free_equals_stepping(tasks, seed):
    free = _run(tasks, seed, stepping=False)
    plain = _run(tasks, seed, stepping=True)
    assert free == plain
    assert sum(len(s) for s in tasks) == sum(1 for _, what in free if " woke " in what)


class _CountingReady(collections.deque):
    """The loop's ready queue, counting what goes through it."""

    appended = 0

    def append(self, handle):  # noqa: ANN001, ANN201
        self.appended += 1
        super().append(handle)


def _ready_traffic(stepping: bool) -> int:
    sim = Simulation(seed=0)
    try:
        sim.loop._ready = ready = _CountingReady(sim.loop._ready)
        p = sim.bus.participant("p", host="robot")
        p.subscribe("/t", handler=lambda m: None)
        q = sim.bus.participant("q", host="robot")

        async def sleeper() -> None:
            for _ in range(20):
                await asyncio.sleep(0.01)
                q.publish("/t", etree.Element("x"))

        sim.spawn(sleeper(), name="sleeper")
        if stepping:
            while sim.step():
                pass
        else:
            sim.run(until=1.0)
        return ready.appended
    finally:
        sim.close()


def test_running_free_takes_the_fast_paths():
    """Lone sleeps and lone deliveries skip the ready queue when the loop runs free (so the
    property above compares the fast paths, not the general path twice)."""
    assert _ready_traffic(stepping=False) < _ready_traffic(stepping=True) / 4
