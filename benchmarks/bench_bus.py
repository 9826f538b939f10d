"""The bus and the trace: CPU per typed message, sent and delivered, and per trace line.

Run: ``python benchmarks/bench_bus.py [--messages N]``. Every figure is process CPU time
(``time.process_time``), so it holds on a loaded machine; each row is the best of
``--repeat`` runs. Rows:

- a typed pose (the contract's ``/robot/localisation/pose``, nine attributes) published as an
  element the module built, to 0, 1 and 3 subscribers with handlers, the loop run until every
  copy is delivered; under the default policy (the module's element trusted) and under the
  strict one (every message XSD-validated, as in the tests and ``--strict``);
- the same published as text (a document from outside: hardened parse + XSD);
- the same with a run's two send interceptors on the bus (the metrics' dispatcher, the heartbeat backstop),
  neither watching the channel: shown only the channels they want (speed25), they cost it nothing;
- the same as a typed record (``homesim.message.Typed``, issue 25): shared by the receivers, its
  XML never built because no handler reads it (``typed``), and with every receiver reading
  ``msg.xml`` once (``typed, XML read``: each builds its own document);
- the same with the system-wide trace recorded to a file: the difference per trace line (a
  send line with its XML, and one delivery line per receiver);
- heartbeats as in a home tour: 19 modules beating at 2 Hz from their main loops (each loop
  runs at 10 Hz and calls ``beat()`` every turn) to the watchdog's monitor, which checks ten
  times a second: CPU per simulated second and per heartbeat sent.

Not a test: nothing is asserted (``tests/test_benchmarks.py`` runs it tiny as a smoke test).
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path
from typing import Any

from lxml import etree

from homesim.message import Typed
from homesim.sim import Simulation

POSE_SCHEMA = Path(__file__).resolve().parents[1] / "robot" / "schemas" / "localisation-pose.xsd"
CHANNEL = "/robot/localisation/pose"


def _pose(i: int) -> etree._Element:
    return etree.Element("pose", time=f"{i * 0.1:.6f}", x="1.0000", y="2.0000", theta="0.10000", cxx="0.000100",
                         cyy="0.000100", ctt="0.000010", frame="map")


class _PoseRecord(Typed):
    """The pose as a typed record: its nine fields, the element built only when read."""

    __slots__ = ("i",)

    def __init__(self, i: int) -> None:
        object.__setattr__(self, "i", i)  # (Typed refuses attribute assignment: records are shared)

    def to_xml(self) -> etree._Element:
        return _pose(self.i)


def run(n: int, *, receivers: int = 1, strict: bool = False, text: bool = False, trace: Path | None = None,
        typed: bool = False, read: bool = False, watched: bool = False) -> tuple[float, int]:
    """(CPU seconds, trace lines) for ``n`` publishes, each delivered to ``receivers`` handlers
    (``read``: each handler reads ``msg.xml``; ``watched``: with a run's two send interceptors, a metrics
    dispatcher and the heartbeat backstop, neither watching this channel)."""
    sim = Simulation(seed=1, scenario="bench", strict=strict)
    sim.bus.declare_channel(CHANNEL, POSE_SCHEMA)
    if watched:
        from homesim.heartbeat import BackstopMonitor
        from homesim.observe import Dispatcher

        Dispatcher(sim.bus).add("/robot/attention/", lambda m: None)
        BackstopMonitor(sim.bus.participant("backstop", host="robot"), "watchdog")
    sender = sim.bus.participant("localisation", host="robot")
    got = [0]

    def handler(msg: Any) -> None:
        got[0] += 1
        if read:
            msg.xml.get("x")

    for k in range(receivers):
        sim.bus.participant(f"r{k}", host="robot").subscribe(CHANNEL, handler)
    rec = sim.record_trace(trace) if trace is not None else None
    payloads: list[Any] = [_pose(i) for i in range(n)]
    if text:
        payloads = [etree.tostring(p) for p in payloads]
    if typed:
        payloads = [_PoseRecord(i) for i in range(n)]
    publish = sender.publish
    step = 1_000_000  # 1 ms of virtual time between messages
    t0 = time.process_time()
    for i, p in enumerate(payloads):
        publish(CHANNEL, p)
        if i % 64 == 63:
            sim.run(until=(i + 1) * step / 1e9)
    sim.run(until=n * step / 1e9 + 1.0)
    lines = rec.seq if rec is not None else 0
    sim.close()  # flushes the trace: part of its cost
    dt = time.process_time() - t0
    assert got[0] == n * receivers, (got[0], n, receivers)
    return dt, lines


def heartbeats(sim_s: float, *, modules: int = 19, strict: bool = False) -> tuple[float, int]:
    """(CPU seconds, heartbeats sent) for ``sim_s`` simulated seconds of the home tour's heartbeats."""
    import asyncio

    from homesim.heartbeat import Heartbeat, HeartbeatMonitor

    sim = Simulation(seed=1, scenario="bench", strict=strict)
    beats = [Heartbeat(sim.bus.participant(f"m{k:02d}", host="robot"), 0.5) for k in range(modules)]
    monitor = HeartbeatMonitor(sim.bus.participant("watchdog", host="robot"), misses=3, period=0.1)

    async def main_loop(hb: Heartbeat) -> None:
        while True:
            hb.beat()
            await asyncio.sleep(0.1)

    async def loop_without_beats() -> None:  # the same loops' cost without heartbeats, subtracted
        while True:
            await asyncio.sleep(0.1)

    for k, hb in enumerate(beats):
        sim.spawn(main_loop(hb), name=f"m{k:02d}")
    sim.spawn(monitor.run(), name="watchdog")
    t0 = time.process_time()
    sim.run(until=sim_s)
    dt = time.process_time() - t0
    sent = sum(hb.seq for hb in beats)
    sim.close()
    bare = Simulation(seed=1, scenario="bench", strict=strict)
    for k in range(modules):
        bare.spawn(loop_without_beats(), name=f"m{k:02d}")
    t0 = time.process_time()
    bare.run(until=sim_s)
    dt_bare = time.process_time() - t0
    bare.close()
    return dt - dt_bare, sent


def best(repeat: int, *args: Any, **kw: Any) -> tuple[float, int]:
    out = [run(*args, **kw) for _ in range(repeat)]
    return min(out)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--messages", type=int, default=20_000)
    ap.add_argument("--repeat", type=int, default=3)
    a = ap.parse_args()
    n = a.messages
    run(min(n, 500))  # warm up: schema compilation, caches
    print(f"{'case':52} {'us/message':>10}")
    base: dict[int, float] = {}
    for receivers in (0, 1, 3):
        for strict in (False, True):
            dt, _ = best(a.repeat, n, receivers=receivers, strict=strict)
            if not strict:
                base[receivers] = dt
            label = f"element, {receivers} receiver(s), {'strict (XSD every message)' if strict else 'default (trusted)'}"
            print(f"{label:52} {1e6 * dt / n:10.1f}")
    for receivers in (0, 1, 3):
        for read in (False, True):
            if read and not receivers:
                continue
            dt, _ = best(a.repeat, n, receivers=receivers, typed=True, read=read)
            label = f"typed, {receivers} receiver(s){', XML read' if read else ''}, default"
            print(f"{label:52} {1e6 * dt / n:10.1f}")
    dt, _ = best(a.repeat, n, receivers=1, watched=True)
    label = "element, 1 receiver, with the run's interceptors"
    print(f"{label:52} {1e6 * dt / n:10.1f}")
    dt, _ = best(a.repeat, n, receivers=1, text=True)
    print(f"{'text from outside (parse + XSD), 1 receiver':52} {1e6 * dt / n:10.1f}")
    with tempfile.TemporaryDirectory() as tmp:
        for receivers in (1, 3):
            dt, lines = best(a.repeat, n, receivers=receivers, trace=Path(tmp) / "t.jsonl")
            per_line = (dt - base[receivers]) / max(1, lines)
            label = f"with trace, {receivers} receiver(s)"
            print(f"{label:52} {1e6 * dt / n:10.1f}   ({1e6 * per_line:.1f} us per trace line, {lines / n:.0f} lines/message)")
    sim_s = max(10.0, n / 200)
    dt, sent = min(heartbeats(sim_s) for _ in range(a.repeat))
    print(f"{'heartbeats: 19 modules at 2 Hz, monitor at 10 Hz':52} {1e6 * dt / sent:10.1f}   "
          f"(per heartbeat; {1e3 * dt / sim_s:.3f} ms per simulated s)")


if __name__ == "__main__":
    main()
