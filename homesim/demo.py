"""The kernel demo: two modules, typed messages over WLAN, a crash, a monitor.

``sensor`` (on the robot, LAN) publishes a noisy ``<tick>`` every 100 ms on
a typed channel; ``peer`` (on a laptop, WLAN) answers each with an
``<ack>`` carrying a running sum. A heartbeat monitor watches both. Half-way
through, ``peer`` is crashed on purpose: its heartbeats stop, the monitor
publishes ``module_failed``, and the peer leaves the bus. The
trace is byte-identical for the same seed, in any process.
"""

from __future__ import annotations

import argparse
import asyncio
from pathlib import Path
from typing import Any

from lxml import etree

from . import cliargs
from .heartbeat import HEALTH_CHANNEL, HeartbeatMonitor
from .message import Message
from .module import Module
from .sim import Simulation

SCHEMA = Path(__file__).with_name("schemas") / "demo.xsd"
TICK = "/demo/tick"
ACK = "/demo/ack"


class Sensor(Module):
    """Publishes a noisy reading every ``period`` seconds."""

    def __init__(self, sim: Simulation, *, period: float = 0.1) -> None:
        super().__init__(sim, "sensor", host="robot", heartbeat=0.5)
        self.period = period
        self.acks = self.bus.subscribe(ACK)

    async def run(self) -> None:
        n = 0
        while True:
            self.beat()
            value = float(self.rng.normal(1.0, 0.1))
            self.bus.publish(TICK, etree.Element("tick", n=str(n), value=f"{value:.6f}"))
            n += 1
            self.acks.drain()
            await asyncio.sleep(self.period)


class Peer(Module):
    """Acknowledges every tick with a running sum; processing costs 2 ms."""

    def __init__(self, sim: Simulation) -> None:
        super().__init__(sim, "peer", host="laptop", heartbeat=0.5)
        self.ticks = self.bus.subscribe(TICK)
        self.total = 0.0

    async def run(self) -> None:
        while True:
            self.beat()
            try:
                async with asyncio.timeout(0.25):
                    msg = await self.ticks.get()
            except TimeoutError:
                continue
            await asyncio.sleep(0.002)
            self.total += float(msg.xml.get("value"))
            self.bus.publish(ACK, etree.Element("ack", n=msg.xml.get("n"), sum=f"{self.total:.6f}"), causes=(msg.id,))


def build(sim: Simulation, *, duration: float) -> dict[str, Any]:
    """Wire the demo into ``sim``; returns handles for the summary."""
    sim.network.add_host("robot", link="lan")
    sim.network.add_host("laptop", link="wlan")
    for ch, el in ((TICK, "tick"), (ACK, "ack")):
        sim.bus.declare_channel(ch, SCHEMA)
    Sensor(sim)
    Peer(sim)
    monitor_bus = sim.bus.participant("monitor", host="robot")
    monitor = HeartbeatMonitor(monitor_bus, misses=3, period=0.1)
    health: list[Message] = []
    monitor_bus.subscribe(HEALTH_CHANNEL, health.append)
    sim.spawn(monitor.run(), name="monitor")
    sim.inject_fault("peer", "crash", at=duration / 2)
    sim.start()
    return {"health": health, "monitor": monitor}


def run_demo(*, seed: int, duration: float, trace: Path | None, realtime: float | None) -> int:
    """Run the demo and print a short report; returns a process exit code."""
    with Simulation(seed=seed, scenario="kernel-demo", realtime=realtime) as sim:
        if trace is not None:
            sim.record_trace(trace)
        handles = build(sim, duration=duration)
        sim.run(until=duration)
        print(f"kernel demo: seed {seed}, {duration:g} s of virtual time")
        bus = sim.bus
        print(f"  bus: {bus.sent} messages sent, {bus.delivered} delivered, {bus.unheard} had no subscriber "
              f"(nobody listening, e.g. ticks to the crashed peer: not lost), {bus.dropped} dropped")
        for msg in handles["health"]:
            print(f"  t={msg.sent:.3f} s  {msg.xml.tag}: {msg.xml.get('module')} (last beat {msg.xml.get('last_beat')} s)")
        failed = sorted(handles["monitor"].failed)
        ok = failed == ["peer"]
        print(f"  verdict: {'PASS' if ok else 'FAIL'}: the crashed peer was detected" if ok else f"  verdict: FAIL: failed modules {failed}")
        if trace is not None:
            print(f"  trace: {trace}")
        return 0 if ok else 1


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("demo", help="kernel demo: typed messages over WLAN, heartbeats, a crash",
                       examples=["homesim demo", "homesim demo --seed 7 --duration 4 --trace out/demo.jsonl"])
    p.add_argument("--seed", type=cliargs.seed, default=1, help="seed of every random stream (link delays); same seed, same trace")
    p.add_argument("--duration", type=cliargs.seconds(positive=True), default=6.0, metavar="SECONDS", help="virtual seconds")
    p.add_argument("--trace", type=cliargs.output_file, default=Path("out/demo-trace.jsonl"),
                   metavar="FILE", help="write the bus trace here (JSON Lines)")
    p.add_argument("--realtime", type=cliargs.realtime_scale, default=None, metavar="X", help="pace the demo at X times real time")
    p.set_defaults(func=lambda a: run_demo(seed=a.seed, duration=a.duration, trace=a.trace, realtime=a.realtime))
