"""The virtual-time loop: asyncio works unchanged, order is deterministic, time is exact."""

from __future__ import annotations

import asyncio
import math

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from homesim.errors import ClockError, DeadlockError, RealIOError, SimulationError, TaskFailedError
from homesim.vloop import NS_PER_S, VirtualEventLoop, to_ns

from .conftest import examples


@pytest.fixture
def loop():
    lp = VirtualEventLoop()
    yield lp
    lp.close()


def test_asyncio_primitives_run_unchanged_on_virtual_time(loop):
    seen = []

    async def worker(name, delay):
        for _ in range(2):
            await asyncio.sleep(delay)
            seen.append((name, loop.time()))

    async def main():
        async with asyncio.TaskGroup() as tg:
            tg.create_task(worker("a", 0.5))
            tg.create_task(worker("b", 0.75))
        with pytest.raises(TimeoutError):
            async with asyncio.timeout(1.0):
                await asyncio.sleep(60)
        assert loop.time() == pytest.approx(2.5)
        q: asyncio.Queue[str] = asyncio.Queue()
        loop.call_later(0.25, q.put_nowait, "x")
        assert await asyncio.wait_for(q.get(), timeout=1.0) == "x"
        ev = asyncio.Event()
        loop.call_at(loop.time() + 0.125, ev.set)
        await ev.wait()
        with pytest.raises(TimeoutError):
            await asyncio.wait_for(asyncio.Event().wait(), timeout=0.5)
        return loop.time()

    assert loop.run_until_complete(main()) == pytest.approx(3.375)
    assert seen == [("a", 0.5), ("b", 0.75), ("a", 1.0), ("b", 1.5)]


def test_same_deadline_callbacks_run_in_scheduling_order(loop):
    order = []
    for i in range(50):
        loop.call_at(1.0, order.append, i)
    loop.call_later(1.0, order.append, 50)
    loop.run()
    assert order == list(range(51))


def test_hours_of_simulated_time_do_not_drift(loop):
    async def ticker():
        for _ in range(36_000):
            await asyncio.sleep(0.1)

    loop.run_until_complete(ticker())
    assert loop.now_ns == 3600 * NS_PER_S
    assert loop.time() == 3600.0
    naive = 0.0
    for _ in range(36_000):
        naive += 0.1
    assert naive != 3600.0  # what integer nanoseconds protect us from


def test_run_until_stops_exactly_and_excludes_the_boundary(loop):
    ran = []
    for t in (0.5, 1.0, 1.5):
        loop.call_at(t, ran.append, t)
    loop.run(until=1.0)
    assert loop.now == 1.0 and ran == [0.5]
    assert loop.peek() == 1.0
    loop.run(until=10.0)
    assert ran == [0.5, 1.0, 1.5] and loop.now == 10.0
    with pytest.raises(ClockError, match="time can't go backwards"):
        loop.run(until=5.0)


def test_step_and_peek(loop):
    assert loop.peek() == math.inf
    assert loop.step() is False
    loop.call_at(2.0, lambda: None)
    assert loop.peek() == 2.0
    assert loop.step() is True
    assert loop.now == 2.0


def test_run_until_predicate_and_timeout(loop):
    box = []

    async def producer():
        for i in range(10):
            await asyncio.sleep(1.0)
            box.append(i)

    loop.spawn(producer(), name="producer")
    assert loop.run_until(lambda: len(box) == 3)
    assert loop.now == 3.0
    assert loop.run_until(lambda: len(box) == 99, timeout=2.5) is False
    assert loop.now == 5.5


def test_deadlock_names_the_waiting_tasks(loop):
    async def stuck_forever():
        await asyncio.Event().wait()

    loop.spawn(stuck_forever(), name="dialog")
    with pytest.raises(DeadlockError, match=r"dialog \(.*stuck_forever"):
        loop.run()


def test_unhandled_exception_in_a_task_fails_the_run(loop):
    async def broken():
        await asyncio.sleep(1.0)
        raise ValueError("sensor exploded")

    loop.spawn(broken(), name="laser")
    with pytest.raises(TaskFailedError, match="laser.*sensor exploded") as info:
        loop.run(until=5)
    assert isinstance(info.value.__cause__, ValueError)
    assert loop.now == 1.0


def test_unhandled_exception_in_a_callback_fails_the_run(loop):
    loop.call_later(0.5, lambda: 1 / 0)
    with pytest.raises(TaskFailedError, match="ZeroDivisionError"):
        loop.run()


@pytest.mark.parametrize(
    "action",
    [
        lambda: asyncio.get_running_loop().run_in_executor(None, print),
        lambda: asyncio.open_connection("example.org", 80),
        lambda: asyncio.create_subprocess_exec("true"),
        lambda: asyncio.to_thread(print),
    ],
    ids=["executor", "socket", "subprocess", "to_thread"],
)
def test_real_io_is_refused(loop, action):
    async def main():
        await action()

    with pytest.raises((RealIOError, TaskFailedError), match="not allowed inside a simulation"):
        loop.run_until_complete(main())


def test_stepping_works_inside_a_running_asyncio_loop():
    """A Jupyter kernel already runs a loop in the thread; stepping must still work."""

    async def notebook_cell():
        outer = asyncio.get_running_loop()
        sim_loop = VirtualEventLoop()
        hits = []

        async def module():
            while True:
                await asyncio.sleep(0.5)
                hits.append((sim_loop.time(), asyncio.get_running_loop() is sim_loop))

        sim_loop.spawn(module(), name="module")
        sim_loop.step()
        sim_loop.run(until=2.0)
        assert sim_loop.run_until(lambda: len(hits) >= 5, timeout=10)
        assert asyncio.get_running_loop() is outer  # the kernel's loop is back
        await asyncio.sleep(0)  # and it still works
        sim_loop.close()
        return hits

    hits = asyncio.run(notebook_cell())
    assert [t for t, _ in hits] == [0.5, 1.0, 1.5, 2.0, 2.5]
    assert all(ok for _, ok in hits)


def test_stepping_from_inside_the_simulation_is_refused(loop):
    async def reentrant():
        loop.step()

    with pytest.raises(SimulationError, match="already running"):
        loop.run_until_complete(reentrant())


# --------------------------------------------------------------------------
# Property: the loop's execution order equals a small reference model.
#
# A program is a forest of callbacks. Each callback, when it runs, schedules
# its children, each with call_soon, call_later(d) or call_at(absolute t).
# The reference model below states asyncio's rule directly, with lists and
# sorting: a round moves every due timer, in (time, scheduling order), behind
# the already-ready callbacks, then runs exactly the callbacks ready at the
# round's start; the clock jumps to the earliest timer only when nothing is
# ready.
# --------------------------------------------------------------------------

delays = st.sampled_from([0, 0, 1, 2, 3, 5, 8]).map(lambda k: k * 0.25)
hows = st.sampled_from(["soon", "later", "at"])
node = st.recursive(
    st.tuples(hows, delays, st.just([])),
    lambda kids: st.tuples(hows, delays, st.lists(kids, max_size=3)),
    max_leaves=20,
)
programs = st.lists(node, min_size=1, max_size=5)


def _flatten(program):
    """Number every node; return {id: (how, delay, child ids)} and the root ids."""
    table = {}

    def visit(n):
        how, d, kids = n
        nid = len(table)
        table[nid] = None
        table[nid] = (how, d, [visit(k) for k in kids])
        return nid

    roots = [visit(n) for n in program]
    return table, roots


def _reference(table, roots):
    now = 0
    seq = 0
    ready: list[int] = []
    timers: list[tuple[int, int, int]] = []
    order = []

    def schedule(nid):
        nonlocal seq
        how, d, _ = table[nid]
        if how == "soon":
            ready.append(nid)
        else:
            when = now + to_ns(d) if how == "later" else max(now, to_ns(d))
            timers.append((when, seq, nid))
        seq += 1

    for r in roots:
        schedule(r)
    while ready or timers:
        if not ready:
            now = min(timers)[0]
        due = sorted(t for t in timers if t[0] <= now)
        timers[:] = [t for t in timers if t[0] > now]
        ready.extend(nid for _, _, nid in due)
        batch, ready[:] = list(ready), []
        for nid in batch:
            order.append((now, nid))
            for kid in table[nid][2]:
                schedule(kid)
    return order


@settings(max_examples=examples(200, 500))
@given(programs)
def test_execution_order_matches_reference_model(program):
    table, roots = _flatten(program)
    loop = VirtualEventLoop()
    order = []

    def run(nid):
        order.append((loop.now_ns, nid))
        for kid in table[nid][2]:
            sched(kid)

    def sched(nid):
        how, d, _ = table[nid]
        if how == "soon":
            loop.call_soon(run, nid)
        elif how == "later":
            loop.call_later(d, run, nid)
        else:
            loop.call_at(d, run, nid)

    for r in roots:
        sched(r)
    loop.run()
    loop.close()
    assert order == _reference(table, roots)
    times = [t for t, _ in order]
    assert times == sorted(times), "virtual time went backwards"


@settings(max_examples=examples(100, 500))
@given(st.lists(st.integers(0, 40), min_size=1, max_size=30), st.integers(0, 45))
def test_run_until_is_exact(ticks, until_tick):
    loop = VirtualEventLoop()
    ran = []
    for i, k in enumerate(ticks):
        loop.call_at(k * 0.25, ran.append, i)
    until = until_tick * 0.25
    loop.run(until=until)
    assert loop.now == until
    assert sorted(ran) == sorted(i for i, k in enumerate(ticks) if k * 0.25 < until)
    loop.close()


# --------------------------------------------------------------------------
# Regressions found in review: each of these failed before its fix.
# --------------------------------------------------------------------------


def test_async_generator_cleanup_runs(loop):
    log = []

    async def gen():
        try:
            for i in range(10):
                yield i
                await asyncio.sleep(0.1)
        finally:
            log.append(("cleanup", loop.time()))

    async def main():
        async for x in gen():
            if x == 2:
                break
        await asyncio.sleep(1)

    loop.run_until_complete(main())
    assert log == [("cleanup", pytest.approx(0.2))]


def test_sleeping_forever_works_with_timeouts(loop):
    async def main():
        with pytest.raises(TimeoutError):
            async with asyncio.timeout(2):
                await asyncio.sleep(math.inf)
        with pytest.raises(TimeoutError):
            await asyncio.wait_for(asyncio.sleep(math.inf), timeout=1)
        async with asyncio.timeout(math.inf):
            await asyncio.sleep(0.5)
        return loop.time()

    assert loop.run_until_complete(main()) == 3.5
    with pytest.raises(ValueError, match="finite time or \\+inf"):
        loop.call_later(math.nan, print)


def test_sleep_forever_alone_is_a_deadlock(loop):
    loop.spawn(asyncio.sleep(math.inf), name="sleeper")
    with pytest.raises(DeadlockError, match="sleeper"):
        loop.run()


def test_unhashable_callbacks_can_be_scheduled(loop):
    class Callback:
        __hash__ = None  # type: ignore[assignment]

        def __init__(self):
            self.calls = 0

        def __eq__(self, other):
            return False

        def __call__(self):
            self.calls += 1

    cb = Callback()
    loop.call_later(1, cb)
    loop.call_soon(cb)
    loop.run()
    assert cb.calls == 2


def test_close_runs_cleanup_in_virtual_time():
    loop = VirtualEventLoop()
    done = []

    async def module():
        try:
            await asyncio.sleep(math.inf)
        finally:
            await asyncio.sleep(0.01)  # say goodbye over the bus
            done.append(loop.time())

    loop.spawn(module(), name="module")
    loop.run(until=1)
    loop.close()
    assert done == [pytest.approx(1.01)]


def test_close_reports_failing_cleanup():
    loop = VirtualEventLoop()

    async def module():
        try:
            await asyncio.sleep(math.inf)
        finally:
            raise RuntimeError("cleanup broke")

    loop.spawn(module(), name="module")
    loop.run(until=1)
    with pytest.raises(TaskFailedError, match="cleanup broke"):
        loop.close()
    assert loop.is_closed()


def test_a_spawned_task_outlives_the_garbage_collector():
    """asyncio holds tasks weakly; a spawned one waiting on nothing must still be there to clean up."""
    import gc

    loop = VirtualEventLoop()

    async def module():
        try:
            await asyncio.sleep(math.inf)
        finally:
            raise RuntimeError("cleanup broke")

    loop.spawn(module(), name="module")
    loop.run(until=1)
    gc.collect()
    with pytest.raises(TaskFailedError, match="cleanup broke"):
        loop.close()


def test_an_unawaited_task_that_dies_fails_the_run(loop):
    async def fuse():
        await asyncio.sleep(1)
        raise ValueError("helper died")

    async def module():
        helper = asyncio.get_running_loop().create_task(fuse(), name="fuse")  # kept, never awaited
        await asyncio.sleep(100)
        return helper

    loop.spawn(module(), name="module")
    with pytest.raises(TaskFailedError, match=r"'fuse' died at t=1\.000000000 s.*helper died"):
        loop.run(until=10)


def test_exceptions_taken_by_await_gather_or_taskgroup_do_not_fail_the_run(loop):
    async def boom(delay):
        await asyncio.sleep(delay)
        raise KeyError("taken")

    async def main():
        with pytest.raises(KeyError):
            await asyncio.create_task(boom(0.1))
        res = await asyncio.gather(boom(0.1), asyncio.sleep(0.2), return_exceptions=True)
        assert isinstance(res[0], KeyError)
        with pytest.raises(ExceptionGroup):
            async with asyncio.TaskGroup() as tg:
                tg.create_task(boom(0.1))
                tg.create_task(asyncio.sleep(5))
        t = asyncio.create_task(boom(0.1))
        t.add_done_callback(lambda t: t.exception())  # handled by its owner
        await asyncio.sleep(1)
        return "ok"

    assert loop.run_until_complete(main()) == "ok"


def test_run_until_never_runs_timers_at_the_boundary(loop):
    ran = []
    loop.call_at(1.0, ran.append, "timer at 1.0")
    loop.run(until=1.0)
    loop.call_soon(ran.append, "soon")
    loop.run(until=1.0)  # now == until: nothing at or after 1.0 may run
    assert ran == []
    loop.call_at(2.0, ran.append, "timer at 2.0")
    loop.run(until=2.0)
    assert ran == ["soon", "timer at 1.0"]


def test_run_until_a_time_advances_even_when_tasks_wait_for_input(loop):
    """A notebook user runs to 3 s, then publishes by hand: no deadlock error."""
    q: asyncio.Queue[str] = asyncio.Queue()
    got = []

    async def listener():
        got.append((await q.get(), loop.time()))

    loop.spawn(listener(), name="listener")
    loop.run(until=3.0)
    assert loop.now == 3.0 and got == []
    q.put_nowait("hello")
    loop.run(until=4.0)
    assert got == [("hello", 3.0)]
    assert loop.run_until(lambda: False, timeout=2.0) is False
    assert loop.now == 6.0


def test_cancelled_timers_do_not_pile_up(loop):
    async def reader():
        async with asyncio.timeout(600):
            for _ in range(6000):
                async with asyncio.timeout(300):
                    await asyncio.sleep(0.01)

    loop.run_until_complete(reader())
    assert loop._pending_timers() < 200


def test_dropping_cancelled_timers_costs_a_bounded_amount_per_cancellation(loop, monkeypatch):
    """The heap is compacted when cancelled timers are the majority: each compaction looks at every
    queued timer, so it must come after as many cancellations as there were live timers, not after a
    fixed 64. (With the timers kept per due time, the majority was counted among the distinct due
    times: 5,000 timers due at one instant made every 65th cancellation look at all 5,000.)"""
    scanned = []
    compact = VirtualEventLoop._compact_timers

    def counting(self):
        scanned.append(self._pending_timers())
        compact(self)

    monkeypatch.setattr(VirtualEventLoop, "_compact_timers", counting)
    for _ in range(5000):
        loop.call_at(1000.0, lambda: None)
    cancellations = 3000

    async def reader():
        for _ in range(cancellations):
            async with asyncio.timeout(300):  # one timer scheduled and cancelled per pass
                await asyncio.sleep(0.01)

    loop.run_until_complete(reader())
    pushed = 5000 + 2 * cancellations  # the timers, each pass's timeout and sleep
    assert sum(scanned) <= 2 * cancellations + pushed + 64
    assert loop._pending_timers() <= 2 * 5000 + 200  # and cancelled ones stay fewer than live ones


# ------------------------------------------------------------ the light sleep
# While the loop runs, asyncio.sleep is homesim.vsleep.sleep; this is asyncio's own (captured at
# import, before any loop ran): the two must give the same order of everything.
ORIGINAL_SLEEP = asyncio.sleep


def _sleep_program(sleep, plan, cancel_at):
    """Run tasks that sleep per ``plan`` (and a canceller); return what happened, in order."""
    loop = VirtualEventLoop()
    log = []

    async def worker(i, delays):
        try:
            for k, d in enumerate(delays):
                got = await sleep(d, result=(i, k))
                log.append(("woke", i, k, got, loop.now_ns))
                if k % 2:
                    loop.call_soon(log.append, ("soon", i, k, loop.now_ns))
        except asyncio.CancelledError:
            log.append(("cancelled", i, loop.now_ns))
            raise

    tasks = [loop.create_task(worker(i, delays), name=f"w{i}") for i, delays in enumerate(plan)]

    async def canceller():
        for at, victim in cancel_at:
            await ORIGINAL_SLEEP(at)
            tasks[victim % len(tasks)].cancel()
            log.append(("cancel", victim % len(tasks), loop.now_ns))

    loop.create_task(canceller(), name="canceller")
    loop.run_until_complete(asyncio.gather(*tasks, return_exceptions=True))
    loop.close()
    return log


@given(
    plan=st.lists(st.lists(st.sampled_from([0, 1e-9, 0.001, 0.002, 0.0015, 0.5]), max_size=6), min_size=1, max_size=5),
    cancel_at=st.lists(st.tuples(st.sampled_from([0.0005, 0.001, 0.002]), st.integers(0, 4)), max_size=3),
)
@settings(max_examples=examples(100, 40), deadline=None)
def test_the_light_sleep_keeps_asyncio_order_wake_ups_results_and_cancellations(plan, cancel_at):
    assert _sleep_program(lambda d, result: asyncio.sleep(d, result), plan, cancel_at) == _sleep_program(
        ORIGINAL_SLEEP, plan, cancel_at
    )


def test_asyncio_code_works_with_the_light_sleep(loop):
    async def main():
        assert asyncio.sleep is not ORIGINAL_SLEEP  # installed while the loop runs
        t = asyncio.create_task(asyncio.sleep(2.0, result="done"))  # a sleep as a task of its own
        assert await t == "done" and loop.time() == 2.0
        assert await asyncio.gather(asyncio.sleep(1.0, "a"), asyncio.sleep(0.5, "b")) == ["a", "b"]
        with pytest.raises(TimeoutError):
            await asyncio.wait_for(asyncio.sleep(10), timeout=0.25)
        with pytest.raises(TimeoutError):
            async with asyncio.timeout(0.25):
                await asyncio.sleep(10)
        sleeper = asyncio.create_task(asyncio.sleep(5))
        await asyncio.sleep(1)
        sleeper.cancel()
        with pytest.raises(asyncio.CancelledError):
            await sleeper
        return loop.time()

    assert loop.run_until_complete(main()) == pytest.approx(4.5)
    assert asyncio.sleep is ORIGINAL_SLEEP and asyncio.tasks.sleep is ORIGINAL_SLEEP  # put back


def test_another_threads_asyncio_loop_keeps_asyncios_sleep(loop):
    import threading

    seen = []

    def other_thread():
        async def nap():
            await asyncio.sleep(0.001)  # a real loop: must not land on the virtual one
            seen.append("slept")

        asyncio.run(nap())

    async def main():
        th = threading.Thread(target=other_thread)
        th.start()
        th.join()  # blocks this step: the other thread sleeps while our sleep is installed

    loop.run_until_complete(main())
    assert seen == ["slept"]


def test_the_light_sleep_is_a_coroutine_that_the_running_asyncio_takes_as_a_task(loop):
    # Python 3.12+ asyncio takes only native coroutines (``collections.abc.Coroutine``)
    # as tasks (requires-python is >= 3.11): a generator-based sleep there would make
    # ``create_task(asyncio.sleep(1))`` a TypeError. The native form is used from 3.12.
    import collections.abc
    import sys

    from homesim import vsleep

    native = vsleep._make_sleep(native=True)
    assert (vsleep.sleep is not native) or sys.version_info >= (3, 12)

    async def main():
        assert asyncio.sleep is not ORIGINAL_SLEEP
        installed, c = asyncio.sleep(0.5, "i"), native(0.5, "n")
        kinds = (asyncio.iscoroutine(installed), isinstance(c, collections.abc.Coroutine),
                 sys.version_info < (3, 12) or isinstance(installed, collections.abc.Coroutine))
        assert await installed == "i" and await c == "n"
        assert await asyncio.create_task(native(0.25, "t")) == "t"
        return kinds

    assert loop.run_until_complete(main()) == (True, True, True)
    assert loop.time() == 1.25


@given(
    plan=st.lists(st.lists(st.sampled_from([0, 1e-9, 0.001, 0.002, 0.0015, 0.5]), max_size=6), min_size=1, max_size=5),
    cancel_at=st.lists(st.tuples(st.sampled_from([0.0005, 0.001, 0.002]), st.integers(0, 4)), max_size=3),
)
@settings(max_examples=examples(60, 25), deadline=None)
def test_the_native_light_sleep_keeps_asyncio_order_wake_ups_results_and_cancellations(plan, cancel_at):
    from homesim import vsleep

    native = vsleep._make_sleep(native=True)
    assert _sleep_program(lambda d, result: native(d, result), plan, cancel_at) == _sleep_program(
        ORIGINAL_SLEEP, plan, cancel_at
    )


def test_two_threads_stepping_their_own_simulations_put_asyncios_sleep_back():
    # Thread A enters its loop, thread B enters its own, A leaves, then B leaves: each
    # loop restoring "what it saw on entry" left the light sleep installed for good, tied
    # to A's closed loop (a later asyncio.run in A's thread got a waiter of that loop).
    import threading

    a_in, b_in, a_out = threading.Event(), threading.Event(), threading.Event()
    seen = []

    def run_a():
        loop = VirtualEventLoop()

        async def main():
            a_in.set()
            assert b_in.wait(10)
            await asyncio.sleep(1)
            seen.append(("a", loop.time()))

        loop.run_until_complete(main())
        loop.close()
        a_out.set()
        seen.append(("a after", asyncio.run(asyncio.sleep(0.001, "real"))))  # this thread's real loop

    def run_b():
        assert a_in.wait(10)
        loop = VirtualEventLoop()

        async def main():
            b_in.set()
            assert a_out.wait(10)  # A left while B runs
            await asyncio.sleep(2)
            seen.append(("b", loop.time()))

        loop.run_until_complete(main())
        loop.close()

    ta, tb = threading.Thread(target=run_a), threading.Thread(target=run_b)
    ta.start()
    tb.start()
    ta.join()
    tb.join()
    assert sorted(seen) == [("a", 1.0), ("a after", "real"), ("b", 2.0)]
    assert asyncio.sleep is ORIGINAL_SLEEP and asyncio.tasks.sleep is ORIGINAL_SLEEP
    assert asyncio.run(asyncio.sleep(0.001, "main")) == "main"


@settings(max_examples=examples(100, 300), deadline=None)
@given(
    st.lists(st.tuples(st.integers(0, 6), st.booleans(), st.booleans()), min_size=1, max_size=200),
    st.integers(0, 7),
)
def test_timers_due_together_run_in_scheduling_order_whatever_was_cancelled(timers, until_tick):
    """Timers at equal times (many share a due time) run in the order they were scheduled; cancelled
    ones never run, whether cancelled before the run or by the first timer of their instant; the
    heap's compaction (over 64 cancelled) changes nothing; run(until) stops before ``until``."""
    loop = VirtualEventLoop()
    ran = []
    handles = []
    firsts: dict[int, int] = {}  # tick -> the first timer of that instant not cancelled early
    for i, (tick, early, _) in enumerate(timers):
        if not early:
            firsts.setdefault(tick, i)
    victims = {first: [j for j, (t, early, by_first) in enumerate(timers) if t == tick and j > first and by_first and not early]
               for tick, first in firsts.items()}

    def fire(i):
        ran.append(i)
        for j in victims.get(i, ()):
            handles[j].cancel()

    for i, (tick, _, _) in enumerate(timers):
        handles.append(loop.call_at(tick * 0.001, fire, i))
    for i, (_, early, _) in enumerate(timers):
        if early:
            handles[i].cancel()
    loop.run(until=until_tick * 0.001)
    expected = []
    for tick in sorted(firsts):
        if tick < until_tick:
            first = firsts[tick]
            expected += [first] + [i for i, (t, early, by_first) in enumerate(timers)
                                   if t == tick and i > first and not early and not by_first]
    assert ran == expected
    loop.close()


@settings(max_examples=examples(100, 400))
@given(
    st.lists(st.lists(st.integers(0, 6), min_size=1, max_size=8), min_size=1, max_size=6),
    st.lists(st.integers(0, 6), min_size=0, max_size=8),
    st.lists(st.tuples(st.integers(0, 30), st.booleans()), max_size=8),
    st.none() | st.integers(0, 30),
)
@example(workers=[[0]], main_sleeps=[1], callbacks=[], plain_at=1)  # a wake-up due with the future's timer
def test_run_until_complete_stops_where_a_done_predicate_would(workers, main_sleeps, callbacks, plain_at):
    """run_until_complete skips the per-round predicate (a fast path) but stops after the same round:
    the same steps ran, at the same times, and the same ones were left, as ``run_until(fut.done)``,
    for a task and for a plain future a timer completes (no done callback: no round of its own)."""

    def play(use_complete: bool) -> tuple[list[tuple[int, str]], int]:
        loop = VirtualEventLoop()
        log: list[tuple[int, str]] = []

        async def worker(i: int, sleeps: list[int]) -> None:
            for k, d in enumerate(sleeps):
                log.append((loop.now_ns, f"w{i}.{k}"))
                await asyncio.sleep(d / 10)

        async def main() -> str:
            tasks = [loop.create_task(worker(i, s)) for i, s in enumerate(workers)]
            for k, d in enumerate(main_sleeps):
                log.append((loop.now_ns, f"main.{k}"))
                await asyncio.sleep(d / 10)
            log.append((loop.now_ns, "main.end"))
            del tasks
            return "done"

        for j, (tick, soon) in enumerate(callbacks):
            if soon:
                loop.call_soon(lambda j=j: log.append((loop.now_ns, f"soon{j}")))
            loop.call_later(tick / 10, lambda j=j: log.append((loop.now_ns, f"cb{j}")))
        if plain_at is not None:
            target: asyncio.Future[str] = loop.create_future()
            loop.create_task(main())
            loop.call_later(plain_at / 10, target.set_result, "done")
        if use_complete:
            assert loop.run_until_complete(main() if plain_at is None else target) == "done"
        else:
            task = loop.create_task(main()) if plain_at is None else target
            assert loop.run_until(task.done)
        seen = (list(log), loop.now_ns)
        loop.run()  # the workers still sleeping finish
        loop.close()
        return seen

    assert play(True) == play(False)
