"""Virtual-time loop vs SimPy: a sleep-heavy and a queue ping-pong workload.

Run: ``python benchmarks/bench_loop.py``. Prints events per CPU second
(``time.process_time``, so the figures hold on a loaded machine) for both
engines and the ratio (ours / SimPy; > 1 means we are faster). The two
engines alternate, best of ``--repeat``. Not a test: speed figures belong
here, never in the test suite.
"""

from __future__ import annotations

import argparse
import asyncio
import time

import numpy as np

from homesim.vloop import VirtualEventLoop


def _delays(n_procs: int, n_steps: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return rng.uniform(0.001, 0.1, size=(n_procs, n_steps)).round(6)


def sleep_homesim(delays: np.ndarray) -> int:
    loop = VirtualEventLoop()
    count = 0

    async def proc(row: list[float]) -> None:
        nonlocal count
        sleep = asyncio.sleep
        for d in row:
            await sleep(d)
            count += 1

    for i, row in enumerate(delays.tolist()):
        loop.spawn(proc(row), name=f"p{i}")
    loop.run()
    loop.close()
    return count


def sleep_homesim_gather(delays: np.ndarray) -> int:
    """The sleep workload through the entry point asyncio users reach for first:
    ``run_until_complete(gather(...))`` (the loop stops when the gathered future is done)."""
    loop = VirtualEventLoop()
    count = 0

    async def proc(row: list[float]) -> None:
        nonlocal count
        sleep = asyncio.sleep
        for d in row:
            await sleep(d)
            count += 1

    async def main() -> None:
        await asyncio.gather(*(proc(row) for row in delays.tolist()))

    loop.run_until_complete(main())
    loop.close()
    return count


def sleep_simpy(delays: np.ndarray) -> int:
    import simpy

    env = simpy.Environment()
    count = 0

    def proc(row: list[float]):
        nonlocal count
        timeout = env.timeout
        for d in row:
            yield timeout(d)
            count += 1

    for row in delays.tolist():
        env.process(proc(row))
    env.run()
    return count


def pingpong_homesim(n_pairs: int, n_msgs: int) -> int:
    loop = VirtualEventLoop()
    count = 0

    async def ping(inbox: asyncio.Queue[int], outbox: asyncio.Queue[int]) -> None:
        nonlocal count
        for i in range(n_msgs):
            await asyncio.sleep(0.001)
            outbox.put_nowait(i)
            await inbox.get()
            count += 2

    async def pong(inbox: asyncio.Queue[int], outbox: asyncio.Queue[int]) -> None:
        for _ in range(n_msgs):
            v = await inbox.get()
            outbox.put_nowait(v)

    for p in range(n_pairs):
        a: asyncio.Queue[int] = asyncio.Queue()
        b: asyncio.Queue[int] = asyncio.Queue()
        loop.spawn(ping(a, b), name=f"ping{p}")
        loop.spawn(pong(b, a), name=f"pong{p}")
    loop.run()
    loop.close()
    return count


def pingpong_simpy(n_pairs: int, n_msgs: int) -> int:
    import simpy

    env = simpy.Environment()
    count = 0

    def ping(inbox, outbox):
        nonlocal count
        for i in range(n_msgs):
            yield env.timeout(0.001)
            outbox.put(i)
            yield inbox.get()
            count += 2

    def pong(inbox, outbox):
        for _ in range(n_msgs):
            v = yield inbox.get()
            outbox.put(v)

    for _ in range(n_pairs):
        a = simpy.Store(env)
        b = simpy.Store(env)
        env.process(ping(a, b))
        env.process(pong(b, a))
    env.run()
    return count


def _once(fn, *args) -> tuple[float, int]:
    t0 = time.process_time()
    n = fn(*args)
    return time.process_time() - t0, n


def _best(fn, *args, repeat: int) -> tuple[float, int]:
    """(best CPU seconds, events) of ``repeat`` runs (``python -m benchmarks`` uses it)."""
    best = float("inf")
    n = 0
    for _ in range(repeat):
        t, n = _once(fn, *args)
        best = min(best, t)
    return best, n


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--procs", type=int, default=200)
    ap.add_argument("--steps", type=int, default=500)
    ap.add_argument("--pairs", type=int, default=100)
    ap.add_argument("--msgs", type=int, default=1000)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    delays = _delays(args.procs, args.steps, seed=1)
    rows = []
    for name, ours, theirs, a in (
        ("sleep", sleep_homesim, sleep_simpy, (delays,)),
        ("sleep_gather", sleep_homesim_gather, sleep_simpy, (delays,)),
        ("pingpong", pingpong_homesim, pingpong_simpy, (args.pairs, args.msgs)),
    ):
        t_ours = t_simpy = float("inf")
        n_ours = n_simpy = 0
        for _ in range(args.repeat):  # alternate, so both see the same load
            t, n_ours = _once(ours, *a)
            t_ours = min(t_ours, t)
            t, n_simpy = _once(theirs, *a)
            t_simpy = min(t_simpy, t)
        assert n_ours == n_simpy, (name, n_ours, n_simpy)
        rows.append((name, n_ours / t_ours, n_simpy / t_simpy))
    print(f"{'workload':<10} {'homesim ev/CPU s':>14} {'simpy ev/CPU s':>14} {'ratio':>7}")
    for name, ours_rate, simpy_rate in rows:
        print(f"{name:<10} {ours_rate:>14,.0f} {simpy_rate:>14,.0f} {ours_rate / simpy_rate:>7.2f}")


if __name__ == "__main__":
    main()
