"""Heartbeats: a silent module is reported failed, a healthy one never is."""

from __future__ import annotations

import asyncio

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from homesim.heartbeat import HEALTH_CHANNEL, HeartbeatMonitor
from homesim.module import Module
from homesim.sim import Simulation

from .conftest import examples


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


class _AlwaysLooks(HeartbeatMonitor):
    """The monitor without its shortcut: every check looks at every module."""

    def check(self):
        self._quiet_until = -1
        return super().check()


monitor_events = st.lists(
    st.one_of(
        st.tuples(st.just("beat"), st.sampled_from(["a", "b", "c"]), st.sampled_from([0.05, 0.1, 0.5]), st.integers(0, 3)),
        st.tuples(st.just("watch"), st.sampled_from(["c", "d"]), st.sampled_from([0.05, 0.5]), st.just(0)),
        st.tuples(st.just("misses"), st.just(""), st.sampled_from([1, 2, 3]), st.just(0)),
        st.tuples(st.just("wait"), st.just(""), st.sampled_from([0.01, 0.1, 0.3, 1.0]), st.just(0)),
    ),
    max_size=60,
)


@settings(max_examples=examples(100, 300), deadline=None)
@given(monitor_events)
def test_the_monitor_reports_the_same_failures_as_one_that_always_looks(events):
    """check() skips looking at the modules while no deadline can have passed: it must report
    the same modules at the same times as a monitor that looks every time, whatever beats come
    (new modules, shorter intervals, a beat created earlier than the last) and whatever changes."""
    from lxml import etree

    from homesim.message import PUBLISH, Message

    with Simulation(seed=0) as sim:
        fast = HeartbeatMonitor(sim.bus.participant("fast"), misses=3, period=0.1)
        slow = _AlwaysLooks(sim.bus.participant("slow"), misses=3, period=0.1)
        reports = []
        for kind, name, value, back in events:
            now = sim.loop.now_ns
            if kind == "beat":  # delivered directly, created up to 0.3 s before now
                el = etree.Element("heartbeat", module=name, seq="1", interval=repr(value))
                created = max(0, now - back * 100_000_000)
                msg = Message(f"{name}#1", PUBLISH, name, f"/system/heartbeat/{name}", el, created, now)
                fast._on_beat(msg)
                slow._on_beat(msg)
            elif kind == "watch":
                fast.watch(name, value)
                slow.watch(name, value)
            elif kind == "misses":
                fast.misses = slow.misses = value
            else:
                sim.run(until=sim.now + value)
            reports.append((fast.check(), dict(fast.failed)))
            assert reports[-1] == (slow.check(), dict(slow.failed))


class _Stops(Module):
    """Beats for a while, then its main loop stops beating (hangs)."""

    async def run(self):
        for _ in range(5):
            self.beat()
            await asyncio.sleep(0.1)
        await asyncio.sleep(1000)


def test_a_numpy_interval_is_a_number_in_the_beat_and_the_silence_is_reported():
    """numpy 2 writes repr(np.float64(0.5)) as 'np.float64(0.5)': a beat carrying that was refused
    by the monitor, so the module was never watched and its silence never reported."""
    np = pytest.importorskip("numpy")
    with Simulation(seed=0) as sim:
        mon_bus = sim.bus.participant("monitor")
        monitor = HeartbeatMonitor(mon_bus, misses=3, period=0.1)
        health = []
        mon_bus.subscribe(HEALTH_CHANNEL, health.append)
        sim.spawn(monitor.run(), name="monitor")
        mod = _Stops(sim, "laser", heartbeat=np.float64(0.5))
        mod.start()
        sim.run(until=5.0)
        assert mod.heartbeat.interval == 0.5 and type(mod.heartbeat.interval) is float
        assert sim.bus.dropped == 0
        assert [(m.xml.tag, m.xml.get("module")) for m in health] == [("module_failed", "laser")]


@pytest.mark.parametrize("interval", [True, float("nan"), "0.5"])
def test_a_heartbeat_interval_that_is_not_a_number_of_seconds_is_refused(interval):
    """True is an int in Python (1 s) but its beats would read interval="True": refused up front."""
    from homesim.heartbeat import Heartbeat

    with Simulation(seed=0) as sim:
        with pytest.raises(ValueError, match="heartbeat interval"):
            Heartbeat(sim.bus.participant("m"), interval)


def test_an_int_interval_keeps_its_spelling_in_the_beat():
    from homesim.heartbeat import Heartbeat

    with Simulation(seed=0) as sim:
        got = []
        sim.bus.participant("obs").subscribe("/system/heartbeat/**", got.append)
        Heartbeat(sim.bus.participant("m"), 1).beat()
        sim.run()
        assert [m.xml.get("interval") for m in got] == ["1"]


@pytest.mark.parametrize("interval", [float("nan"), float("inf"), -1.0, 0.0, True])
def test_watch_refuses_an_interval_no_heartbeat_could_have(interval):
    """A bad interval given to watch() used to be taken, and failed the whole run later, from inside
    the monitor's periodic check (to_ns(nan)), far from the call that caused it."""
    with Simulation(seed=0) as sim:
        monitor = HeartbeatMonitor(sim.bus.participant("monitor"))
        with pytest.raises(ValueError, match="interval"):
            monitor.watch("laser", interval)
        assert monitor.check() == []
