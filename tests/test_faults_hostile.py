"""Faults a module can cause must stay that module's: the run goes on and says what failed.

An RPC handler that never answers costs its caller a timeout (not the run);
a module that floods the bus is failed like a crashed one; and when every
module has crashed, the watchdog included, the kernel's monitor still says so.
"""

from __future__ import annotations

import asyncio
import gc
from pathlib import Path

import pytest
from lxml import etree

from homesim.errors import RemoteCallTimeout
from homesim.heartbeat import HEALTH_CHANNEL, HeartbeatMonitor
from homesim.module import Module
from homesim.sim import FAULT_CHANNEL, Simulation

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("kind", ["call", "subscription"])
def test_a_handler_awaiting_a_future_nobody_holds_costs_the_caller_its_timeout(kind):
    with Simulation(seed=1) as sim:
        server = sim.bus.participant("srv")
        client = sim.bus.participant("cli")

        async def forgotten(msg):
            await asyncio.get_running_loop().create_future()  # nobody else holds it: never resolved
            return etree.Element("r")

        if kind == "call":
            server.serve("m", forgotten)
        else:
            server.subscribe("/x", forgotten)
        out = []

        async def caller():
            for i in range(3):
                if kind == "subscription":
                    client.publish("/x", etree.Element("x"))
                    await asyncio.sleep(1.0)
                    out.append("published")
                    continue
                try:
                    await client.call("srv", "m", etree.Element("q"), timeout=1.0)
                    out.append("reply")
                except RemoteCallTimeout:
                    out.append("timeout")

        async def collector():  # the garbage collector at virtual times of its own
            for _ in range(40):
                gc.collect()
                await asyncio.sleep(0.1)

        sim.spawn(caller(), name="caller")
        sim.spawn(collector(), name="collector")
        sim.start()
        sim.run(until=4.0)
        assert out == (["timeout"] * 3 if kind == "call" else ["published"] * 3)


class Flooder(Module):
    """Publishes in a loop with a tiny sleep (a bug: the sleep was meant to be seconds)."""

    async def run(self):
        while True:
            self.beat()
            self.bus.publish("/flood", etree.Element("x"))
            await asyncio.sleep(1e-9)


class Looper(Module):
    async def run(self):
        while True:
            self.beat()
            self.bus.publish("/ok", etree.Element("y"))
            await asyncio.sleep(0.01)


def test_a_module_flooding_the_bus_is_failed_like_a_crashed_module():
    with Simulation(seed=2) as sim:
        faults, health = [], []
        watcher = sim.bus.participant("watcher")
        watcher.subscribe(FAULT_CHANNEL, faults.append)
        watcher.subscribe(HEALTH_CHANNEL, health.append)
        watcher.subscribe("/flood", lambda m: None)
        flooder = Flooder(sim, "flooder", heartbeat=0.1)
        Looper(sim, "steady", heartbeat=0.1)
        monitor = HeartbeatMonitor(sim.bus.participant("monitor"))
        sim.spawn(monitor.run(), name="monitor")
        sim.start()
        sim.run(until=2.0)  # the run goes on
        assert [(f.xml.get("module"), f.xml.get("kind"), f.xml.get("reason")) for f in faults] == [("flooder", "crash", "flood")]
        assert faults[0].created < 0.001  # caught within its first virtual millisecond
        assert flooder.task.cancelled() and flooder.bus.closed
        assert sim.bus._counters["flooder"][0] <= sim.bus.max_sends_per_s + 1  # nothing grows without bound
        assert [(h.xml.tag, h.xml.get("module")) for h in health] == [("module_failed", "flooder")]
        assert sim.modules["steady"].bus._count[0] > 150  # the others went on


def test_a_steady_fast_module_is_not_a_flood():
    """1,000 messages a virtual second for 3 s (far above any module of a home tour: 52) are fine."""
    class Fast(Module):
        async def run(self):
            while True:
                self.beat()
                self.bus.publish("/fast", etree.Element("x"))
                await asyncio.sleep(0.001)

    with Simulation(seed=2) as sim:
        faults = []
        sim.bus.participant("watcher").subscribe(FAULT_CHANNEL, faults.append)
        Fast(sim, "fast")
        sim.start()
        sim.run(until=3.0)
        assert faults == []
        assert sim.bus._counters["fast"][0] >= 2999


def _health(run):
    seen = []
    run.dispatcher.add((HEALTH_CHANNEL,), lambda m: seen.append((m.sender, m.xml.tag, m.xml.get("module"))))
    return seen


def test_with_every_module_crashed_the_kernels_monitor_still_reports():
    from homesim.tour.runner import Run, RunOptions

    with Run.from_file(ROOT / "scenarios" / "two_people_radio.xml", RunOptions(until=6.0)) as run:
        seen = _health(run)
        modules = sorted(run.sim.modules)
        beating = {n for n in modules if run.sim.modules[n].heartbeat is not None}
        assert "watchdog" in beating
        for name in modules:
            run.sim.inject_fault(name, "crash", at=2.0)
        run.run()
    failed = [m for s, tag, m in seen if tag == "module_failed"]
    assert ("monitor", "module_failed", "watchdog") in seen
    assert len(failed) == len(set(failed)), "a failure reported twice"
    assert set(failed) == beating  # every module that beat is reported failed


def test_the_kernels_monitor_is_silent_while_the_watchdog_reports():
    from homesim.tour.runner import Run, RunOptions

    with Run.from_file(ROOT / "scenarios" / "module_crash.xml", RunOptions(until=25.0)) as run:
        seen = _health(run)
        run.run()
    assert [(s, tag, m) for s, tag, m in seen if tag == "module_failed"] == [("watchdog", "module_failed", "scene_model")]
