"""One participant's bad message never kills the run; the project's own bugs still do.

Class: a message another participant sends that a receiver cannot use. Typed
channels refuse it at the sender (the kernel types every heartbeat channel
from the start); a receiver that still gets something it cannot handle
raises :class:`BadMessageError`, which the bus reports as a drop with the
reason (in the trace) and the run goes on. Any other exception in a handler
is a bug and fails the run loudly.
"""

from __future__ import annotations

import asyncio

import pytest
from hypothesis import given
from hypothesis import strategies as st
from lxml import etree

from homesim.errors import BadMessageError, MessageValidationError, TaskFailedError
from homesim.heartbeat import HEALTH_CHANNEL, MAX_INTERVAL_S, HeartbeatMonitor
from homesim.module import Module
from homesim.sim import Simulation


class Looper(Module):
    async def run(self):
        while True:
            self.beat()
            await asyncio.sleep(0.05)


def _monitored(sim):
    Looper(sim, "laser", heartbeat=0.2)
    mon_bus = sim.bus.participant("monitor")
    monitor = HeartbeatMonitor(mon_bus, misses=3, period=0.05)
    health = []
    mon_bus.subscribe(HEALTH_CHANNEL, health.append)
    sim.spawn(monitor.run(), name="monitor")
    sim.start()
    return monitor, health


@given(
    channel=st.sampled_from(["/system/heartbeat/evil", "/system/heartbeat/laser", "/system/heartbeat/a/b"]),
    interval=st.sampled_from(["abc", "", "nan", "inf", "-1", "0", "1e299", "1e-9", "1" + "0" * 400]),
)
def test_a_bad_heartbeat_is_refused_at_the_sender_on_every_heartbeat_channel(channel, interval):
    with Simulation(seed=1) as sim:
        evil = sim.bus.participant("evil")
        got = []
        sim.bus.participant("listener").subscribe("/system/heartbeat/**", got.append)
        with pytest.raises(MessageValidationError, match="refused \\(nothing delivered\\)"):
            evil.publish(channel, etree.Element("heartbeat", module="evil", seq="1", interval=interval))
        sim.run(until=0.5)
        assert got == []


def test_a_message_the_monitor_cannot_use_is_reported_and_the_run_goes_on():
    with Simulation(seed=1) as sim:
        rec = sim.record_trace()
        monitor, health = _monitored(sim)
        evil = sim.bus.participant("evil")
        # valid for system.xsd, but not a heartbeat: the monitor refuses it
        sim.call_at(1.0, lambda: evil.publish("/system/heartbeat/evil", etree.Element("fault", module="x", kind="crash")))
        sim.inject_fault("laser", "crash", at=3.0)
        sim.run(until=5.0)
        drops = [r for r in rec.records() if r.get("kind") == "drop"]
        assert any("not a heartbeat" in r["reason"] and r["receivers"] == ["monitor"] for r in drops)
        # the monitor kept working: the real failure is still reported
        assert [(m.xml.tag, m.xml.get("module")) for m in health] == [("module_failed", "laser")]


@pytest.mark.parametrize("is_async", [False, True])
def test_bad_message_error_from_any_handler_is_a_reported_drop(is_async):
    with Simulation(seed=1) as sim:
        rec = sim.record_trace()
        seen = []

        def handler(msg):
            seen.append(msg.xml.get("n"))
            if msg.xml.get("n") == "2":
                raise BadMessageError("n=2 is not something I handle")

        async def ahandler(msg):
            await asyncio.sleep(0.01)
            handler(msg)

        sim.bus.participant("rx").subscribe("/x", ahandler if is_async else handler)
        tx = sim.bus.participant("tx")
        for n in range(4):
            sim.call_at(0.1 * (n + 1), lambda n=n: tx.publish("/x", etree.Element("m", n=str(n))))
        sim.run(until=1.0)
        assert seen == ["0", "1", "2", "3"]
        drops = [r for r in rec.records() if r.get("kind") == "drop"]
        assert len(drops) == 1 and "n=2 is not something I handle" in drops[0]["reason"]


def test_a_handler_bug_still_fails_the_run_loudly():
    with Simulation(seed=1) as sim:
        sim.bus.participant("rx").subscribe("/x", lambda msg: 1 / 0)
        sim.call_at(0.1, lambda: sim.bus.participant("tx").publish("/x", etree.Element("m")))
        with pytest.raises(TaskFailedError, match="ZeroDivisionError"):
            sim.run(until=1.0)


@pytest.mark.parametrize("interval", [1e299, float("inf"), float("nan"), -1.0, 1e-6, MAX_INTERVAL_S * 2])
def test_absurd_heartbeat_intervals_are_refused_by_the_module(interval):
    with Simulation(seed=1) as sim:
        with pytest.raises(ValueError, match="heartbeat interval must be"):
            Looper(sim, "m", heartbeat=interval)


def test_subtree_types_apply_to_channels_without_their_own_and_the_longest_wins():
    from homesim.xmlio import schema_from_text

    def xsd(name):
        return schema_from_text(
            name, f'<xs:schema xmlns:xs="http://www.w3.org/2001/XMLSchema"><xs:element name="{name}"/></xs:schema>'
        )

    with Simulation(seed=1) as sim:
        sim.bus.declare_channel("/a/**", xsd("outer"))
        sim.bus.declare_channel("/a/b/**", xsd("inner"))
        sim.bus.declare_channel("/a/b/own", xsd("own"))
        assert sim.bus.channel_schema("/a/x").name == "outer"
        assert sim.bus.channel_schema("/a/b/c/d").name == "inner"
        assert sim.bus.channel_schema("/a/b/own").name == "own"
        assert sim.bus.channel_schema("/ab") is None
        p = sim.bus.participant("p")
        with pytest.raises(MessageValidationError):
            p.publish("/a/b/c", etree.Element("outer"))
        p.publish("/a/b/c", etree.Element("inner"))
