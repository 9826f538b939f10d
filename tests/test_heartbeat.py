"""Heartbeats: a silent module is reported failed, a healthy one never is."""

from __future__ import annotations

import asyncio

import pytest

from homesim.heartbeat import HEALTH_CHANNEL, HeartbeatMonitor
from homesim.module import Module
from homesim.sim import Simulation


class Looper(Module):
    async def run(self):
        while True:
            self.beat()
            await asyncio.sleep(0.05)


def _setup(seed=0, *, misses=3):
    sim = Simulation(seed=seed)
    sim.network.add_host("laptop", link="wlan")
    Looper(sim, "dialog", host="laptop", heartbeat=0.5)
    Looper(sim, "laser", heartbeat=0.2)
    mon_bus = sim.bus.participant("monitor")
    monitor = HeartbeatMonitor(mon_bus, misses=misses, period=0.05)
    health = []
    mon_bus.subscribe(HEALTH_CHANNEL, health.append)
    sim.spawn(monitor.run(), name="monitor")
    sim.start()
    return sim, monitor, health


def test_healthy_modules_are_never_reported_even_over_wlan():
    sim, monitor, health = _setup()
    sim.run(until=60.0)
    assert health == [] and monitor.failed == {}
    sim.close()


@pytest.mark.parametrize("fault", ["crash", "hang"])
def test_silent_module_is_reported_within_its_miss_budget(fault):
    sim, monitor, health = _setup()
    sim.inject_fault("laser", fault, at=3.0)
    sim.run(until=10.0)
    assert [(m.xml.tag, m.xml.get("module")) for m in health] == [("module_failed", "laser")]
    last_beat = float(health[0].xml.get("last_beat"))
    assert 2.8 <= last_beat <= 3.0
    # reported after 3 missed 0.2 s beats (+ slack), within one check period
    assert last_beat + 0.6 < health[0].sent <= last_beat + 0.6 + 0.05 + 0.05 + 1e-9
    sim.close()


def test_recovery_is_reported_when_beats_come_back():
    sim = Simulation(seed=0)
    p = sim.bus.participant("flaky")
    mon_bus = sim.bus.participant("monitor")
    monitor = HeartbeatMonitor(mon_bus, misses=2, period=0.1)
    health = []
    mon_bus.subscribe(HEALTH_CHANNEL, health.append)
    from homesim.heartbeat import Heartbeat

    hb = Heartbeat(p, 0.1)

    async def flaky():
        for t in range(100):
            if not (20 <= t < 40):
                hb.beat()
            await asyncio.sleep(0.1)

    sim.spawn(flaky(), name="flaky")
    sim.spawn(monitor.run(), name="monitor")
    sim.run(until=10.0)
    assert [m.xml.tag for m in health] == ["module_failed", "module_recovered"]
    sim.close()
