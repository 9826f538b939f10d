"""Livelocks: work that keeps virtual time still for ever fails with a report, not a hang.

Class: any schedule where rounds keep running at one virtual instant (a task
looping on ``sleep(0)``, on a sleep that rounds to 0 ns, a ``call_soon``
chain, two tasks waking each other). The loop counts rounds per instant and
raises :class:`LivelockError` naming what still runs. A busy loop that never
awaits cannot be seen from inside; the wall-clock watchdog (the only wall
clock, in ``homesim/realtime.py``) dumps every stack and ends the process.
"""

from __future__ import annotations

import asyncio
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from homesim.errors import DeadlockError, LivelockError
from homesim.sim import Simulation
from homesim.vloop import MAX_ROUNDS_PER_INSTANT

from .conftest import examples

ROOT = Path(__file__).resolve().parents[1]


async def sleep_zero():
    while True:
        await asyncio.sleep(0)


async def sleep_tiny():
    while True:
        await asyncio.sleep(1e-12)  # rounds to 0 ns


async def ping(me: asyncio.Event, other: asyncio.Event):
    while True:
        other.set()
        await me.wait()
        me.clear()


def chain(loop):
    loop.call_soon(chain, loop)


def _install(sim: Simulation, kind: str, start: float) -> str:
    """Start a livelock of ``kind`` at virtual time ``start``; return the name the report must give."""
    if kind == "chain":
        sim.call_at(start, lambda: sim.loop.call_soon(chain, sim.loop))
        return "callback chain"

    async def later(coro):
        await asyncio.sleep(start)
        await coro

    if kind == "ping":
        a, b = asyncio.Event(), asyncio.Event()
        sim.spawn(later(ping(a, b)), name="pinger")
        sim.spawn(later(ping(b, a)), name="ponger")
        return "task pinger"
    sim.spawn(later(sleep_zero() if kind == "zero" else sleep_tiny()), name=f"busy-{kind}")
    return f"task busy-{kind}"


@settings(max_examples=examples(12, 40))
@given(kind=st.sampled_from(["zero", "tiny", "chain", "ping"]), start=st.sampled_from([0.0, 0.25, 2.5]),
       driver=st.sampled_from(["run_until", "run_forever", "run_until_pred", "step"]))
def test_every_livelock_fails_with_a_report_naming_what_runs(kind, start, driver):
    with Simulation(seed=1) as sim:
        sim.loop.max_rounds_per_instant = 500  # the default (100,000) is tested once below
        name = _install(sim, kind, start)

        async def ticker():  # honest work alongside, so the loop is not otherwise empty
            while True:
                await asyncio.sleep(0.1)

        sim.spawn(ticker(), name="ticker")
        with pytest.raises(LivelockError) as info:
            if driver == "run_until":
                sim.run(until=10.0)
            elif driver == "run_forever":
                sim.run()
            elif driver == "run_until_pred":
                sim.run_until(lambda: False, timeout=10.0)
            else:
                for _ in range(10_000):
                    sim.step()
        msg = str(info.value)
        assert f"livelock at t={start:.9f} s" in msg
        assert name in msg
        assert isinstance(info.value, DeadlockError)  # callers handling deadlocks see livelocks too


def test_the_default_limit_catches_a_sleep_zero_loop():
    with Simulation(seed=1) as sim:
        sim.spawn(sleep_zero(), name="spinner")
        with pytest.raises(LivelockError, match=f"{MAX_ROUNDS_PER_INSTANT} scheduling rounds.*task spinner"):
            sim.run(until=1.0)


@pytest.mark.parametrize("depth", [10, 400])
def test_a_finite_same_instant_burst_is_not_a_livelock(depth):
    with Simulation(seed=1) as sim:
        sim.loop.max_rounds_per_instant = 500
        done = []

        def step(n):
            if n:
                sim.loop.call_soon(step, n - 1)
            else:
                done.append(sim.now)

        for t in (0.5, 1.0):  # the count starts again at every instant
            sim.call_at(t, step, depth)
        sim.run(until=2.0)
        assert done == [0.5, 1.0]


def test_the_wall_clock_watchdog_dumps_every_stack_of_a_busy_loop(tmp_path):
    script = tmp_path / "busy.py"
    script.write_text(textwrap.dedent(
        """
        from homesim.realtime import Watchdog

        def spin_without_awaiting():
            while True:
                pass

        with Watchdog(0.5):
            spin_without_awaiting()
        """
    ))
    proc = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert proc.returncode == 1
    assert "watchdog armed" in proc.stderr
    assert "in spin_without_awaiting" in proc.stderr  # the stack of the spinning code


def test_the_watchdog_option_is_refused_out_of_range(capsys):
    from homesim.cli import main

    for bad in ("0", "-1", "nan", "1e9"):
        assert main(["--watchdog", bad, "demo"]) == 2
        assert "argument --watchdog" in capsys.readouterr().err
