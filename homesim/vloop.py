"""A virtual-time asyncio event loop with a stepping API.

Ordinary asyncio code (``asyncio.sleep``, ``wait_for``, ``asyncio.timeout``,
``Queue``, ``Event``, ``TaskGroup``, ``call_later``/``call_at``) runs on
:class:`VirtualEventLoop` unchanged, but every clock reading is virtual:
when nothing is ready to run, the clock jumps straight to the earliest timer.

Why not asyncio's own loop: its timer heap orders equal deadlines by heap
position, not by scheduling order, and it polls a selector on every round.
Here timers due at the same virtual time run in the order they were
scheduled (the timers are a :class:`~homesim.timers.TimerQueue`, whose one
``push`` the loop, the sleep and the bus use: each due time keeps its timers in
a list, in scheduling order; a heap holds the distinct due times as plain
integers, which compare several times faster than asyncio's ``(time, sequence,
handle)`` tuples), time is an integer
count of nanoseconds (no float drift over hours), and there is no selector:
a simulation does no real I/O, and asks for it (executors, sockets,
subprocesses, threads) are refused with :class:`RealIOError`.

Stepping (SimPy's ``step/peek/run(until)``, sismic's ``execute_once``) works
from plain code and from inside a running asyncio loop in the same thread
(a Jupyter kernel): each step installs this loop as the thread's running loop
for the duration of the step and puts the caller's loop back afterwards.

How it fails: an exception escaping a callback, or a task spawned with
:meth:`VirtualEventLoop.spawn`, stops the run and is re-raised from
``step``/``run`` as :class:`TaskFailedError`. When nothing is ready, no timer
is pending and tasks are still waiting, :meth:`run` raises
:class:`DeadlockError` naming the waiting tasks instead of hanging. Those
guards, the refusals of real I/O and closing live in :mod:`homesim.vloop_guards`;
this module is the clock, scheduling and the stepping loop (``_drive``).
"""

from __future__ import annotations

import asyncio
import functools
import heapq
import math
from asyncio import events
from collections.abc import Awaitable, Callable
from asyncio import futures as _futures
from contextvars import Context, copy_context
from typing import Any, Protocol, TypeVar

from .errors import ClockError
from .timers import NS_PER_S, TimerQueue, _Delivery, _Handle, _TimerHandle, to_ns  # noqa: F401 (_Delivery: the bus's)
from .vloop_guards import FailsLoudly, RefusesRealIO
from .vsleep import _MANY, _sleep_fire, _SleepWaiter

T = TypeVar("T")


#: Scheduling rounds allowed at one virtual instant before the run is called a
#: livelock (a task looping on ``await asyncio.sleep(0)``, on a sleep that
#: rounds to 0 ns, or a ``call_soon`` chain keeps the clock still for ever).
#: A real burst of same-instant work (deliveries, wake-ups) takes a few
#: hundred rounds at most; 100,000 rounds take well under a second.
MAX_ROUNDS_PER_INSTANT = 100_000

# Why the scheduling loop stopped.
_FAILED, _EMPTY, _UNTIL, _ROUNDS, _PREDICATE = range(5)


# Callbacks that asyncio itself schedules and that read no context variables:
# running them without a copied context is indistinguishable and much cheaper.
_set_result_unless_cancelled = _futures._set_result_unless_cancelled


class _Bare:
    """Marker for ``context=BARE``: run the callback without a copied context."""

    __slots__ = ()

    def __repr__(self) -> str:
        return "BARE"


#: Pass as ``context=BARE`` to :meth:`VirtualEventLoop.call_at_ns` for kernel
#: callbacks that read no context variables (bus deliveries): it saves a
#: context copy per message.
BARE: Any = _Bare()
_CONTEXT_FREE = frozenset({_set_result_unless_cancelled})


_new = object.__new__


class Pacer(Protocol):
    """Called before the clock jumps forward; real-time mode sleeps here."""

    def before_advance(self, from_ns: int, to_ns: int) -> None: ...


class VirtualEventLoop(FailsLoudly, RefusesRealIO, asyncio.BaseEventLoop):
    """An asyncio loop whose clock is virtual and whose order is deterministic.

    Timers due at the same virtual time run in the order they were scheduled.
    ``now_ns`` never decreases. Use :meth:`step`, :meth:`peek`, :meth:`run`,
    :meth:`run_until` and :meth:`run_until_complete` to drive it.
    """

    def __init__(self, *, start: float = 0.0, pacer: Pacer | None = None) -> None:
        self._inside = False
        super().__init__()
        # A C-level factory: no Python frame per future (the hottest call in asyncio.sleep).
        self.create_future = functools.partial(_futures.Future, loop=self)  # type: ignore[method-assign]
        if start < 0 or not math.isfinite(start):
            raise ClockError(f"start time must be finite and >= 0, got {start!r}")
        self._now_ns = to_ns(start)
        #: The timers (:class:`~homesim.timers.TimerQueue`): the one push every scheduler uses.
        self.timers = TimerQueue()
        self._clock_resolution = 1e-9
        self._pacer = pacer
        self._failure: BaseException | None = None
        self._failure_where: str = ""
        self._orphans: list[tuple[asyncio.Task[Any], int]] = []
        self._spawned: dict[asyncio.Task[Any], None] = {}  # top-level tasks, held until done (spawn)
        self._saved_loop: asyncio.AbstractEventLoop | None = None
        self._saved_hooks: Any = None
        self._saved_sleep: Any = None  # the loop stepping in this thread before this one (vsleep._enter)
        self.max_rounds_per_instant = MAX_ROUNDS_PER_INSTANT
        self._instant_ns = -1
        self._instant_rounds = 0

    # ------------------------------------------------------------------ clock
    def time(self) -> float:
        """Virtual time in seconds."""
        return self._now_ns / NS_PER_S

    @property
    def now(self) -> float:
        """Virtual time in seconds."""
        return self._now_ns / NS_PER_S

    @property
    def now_ns(self) -> int:
        """Virtual time in integer nanoseconds (exact)."""
        return self._now_ns

    # ------------------------------------------------------------- scheduling
    def call_soon(self, callback: Callable[..., Any], *args: Any, context: Context | None = None) -> asyncio.Handle:  # type: ignore[override]
        if self._closed:
            raise RuntimeError("Event loop is closed")
        if context is None:
            context = copy_context()
        handle = _new(_Handle)
        handle._callback = callback
        handle._args = args
        handle._context = context
        handle._cancelled = False
        handle._loop = self
        self._ready.append(handle)
        return handle

    def call_at(self, when: float, callback: Callable[..., Any], *args: Any, context: Context | None = None) -> asyncio.TimerHandle:  # type: ignore[override]
        if not math.isfinite(when):
            return self._never(when, callback, args, context)
        return self.call_at_ns(to_ns(when), callback, *args, context=context)

    def call_later(self, delay: float, callback: Callable[..., Any], *args: Any, context: Context | None = None) -> asyncio.TimerHandle:  # type: ignore[override]
        if not math.isfinite(delay):
            return self._never(delay, callback, args, context)
        return self.call_at_ns(self._now_ns + int(round(delay * NS_PER_S)), callback, *args, context=context)

    def call_at_ns(self, when_ns: int, callback: Callable[..., Any], *args: Any, context: Context | None = None) -> asyncio.TimerHandle:
        """Schedule ``callback`` at an exact virtual time in nanoseconds.

        A time in the past is treated as "now" (asyncio's rule), keeping its
        place after everything already scheduled for now.
        """
        if self._closed:
            raise RuntimeError("Event loop is closed")
        if when_ns < self._now_ns:
            when_ns = self._now_ns
        if context is None:
            if callback is not _set_result_unless_cancelled:
                context = copy_context()
        elif context is BARE:
            context = None
        handle = self._call_at_bare(when_ns, callback, args)
        handle._context = context
        return handle

    def _call_at_bare(self, when_ns: int, callback: Callable[..., Any], args: tuple[Any, ...]) -> asyncio.TimerHandle:
        """``call_at_ns(when_ns, callback, *args, context=BARE)`` for the kernel's hot paths (bus deliveries).

        The caller guarantees ``when_ns >= now`` and an open loop.
        """
        handle = _TimerHandle()
        handle._callback = callback
        handle._args = args
        handle._context = None
        handle._cancelled = False
        handle._loop = self
        handle._when = when_ns / NS_PER_S
        handle._scheduled = True
        self.timers.push(when_ns, handle)
        return handle

    def _pending_timers(self) -> int:
        """How many timers are queued, cancelled ones not yet dropped included."""
        return self.timers.pending()

    def call_later_ns(self, delay_ns: int, callback: Callable[..., Any], *args: Any, context: Context | None = None) -> asyncio.TimerHandle:
        """Schedule ``callback`` after an exact delay in nanoseconds."""
        return self.call_at_ns(self._now_ns + delay_ns, callback, *args, context=context)

    def _never(self, when: float, callback: Callable[..., Any], args: tuple[Any, ...], context: Context | None) -> asyncio.TimerHandle:
        """A timer at +inf: a valid handle that is never scheduled (``sleep(math.inf)``)."""
        if when != math.inf:
            raise ValueError(f"a timer needs a finite time or +inf, got {when!r}")
        handle = _TimerHandle()
        events.TimerHandle.__init__(handle, math.inf, callback, args, self, context)  # never scheduled
        return handle

    def _timer_handle_cancelled(self, handle: asyncio.TimerHandle) -> None:
        # Cancelled timers leave the heap lazily; _drive compacts it when
        # they become the majority (a long asyncio.timeout rescheduled often).
        self.timers.cancelled += 1

    # ------------------------------------------------------------- stepping
    def peek(self) -> float:
        """Time of the next scheduling round; ``inf`` when nothing is scheduled."""
        if self._ready:
            return self.time()
        self.timers.drop_cancelled()
        if self.timers.times:
            return self.timers.times[0] / NS_PER_S
        return math.inf

    def step(self) -> bool:
        """Run one scheduling round; return False when there was nothing to run.

        A round advances the clock to the next timer if nothing is ready, then
        runs every callback that was ready at its start (asyncio's semantics).
        """
        with self._entered():
            outcome = self._drive(None, None, 1)
        self._raise_failure()
        return outcome == _ROUNDS

    def run(self, until: float | None = None) -> None:
        """Run until virtual time ``until``, or without it until nothing is left to do.

        As in SimPy, everything scheduled strictly before ``until`` runs,
        nothing scheduled at or after it does, and the clock ends at exactly
        ``until`` (also when everything falls quiet earlier: tasks may be
        waiting for input the caller will give). Without ``until``, tasks
        still waiting when nothing can wake them raise
        :class:`DeadlockError` naming them. A failed task raises
        :class:`TaskFailedError`; ``until`` in the past :class:`ClockError`.
        """
        until_ns = None if until is None else to_ns(until)
        if until_ns is not None and until_ns < self._now_ns:
            raise ClockError(f"time can't go backwards: run(until={until}) but now is {self.now}")
        if until_ns is not None and until_ns == self._now_ns:
            return
        with self._entered():
            outcome = self._drive(until_ns, None, None)
            if outcome == _EMPTY and until_ns is None:
                self._check_deadlock()
            if until_ns is not None and outcome != _FAILED:
                self._advance_to(until_ns)
        self._raise_failure()

    def run_until(self, predicate: Callable[[], bool], *, timeout: float | None = None) -> bool:
        """Step until ``predicate()`` holds (checked after every round).

        Returns True when it held, False when ``timeout`` virtual seconds
        passed first (the clock then stands at the timeout). Without a
        timeout, :class:`DeadlockError` when nothing is left that could make
        the predicate true.
        """
        if predicate():
            return True
        deadline_ns = None if timeout is None else self._now_ns + to_ns(timeout)
        with self._entered():
            outcome = self._drive(deadline_ns, predicate, None)
            if outcome == _EMPTY and deadline_ns is None:
                self._check_deadlock(extra="the predicate")
            elif outcome in (_UNTIL, _EMPTY) and deadline_ns is not None:
                self._advance_to(deadline_ns)
        self._raise_failure()
        return outcome == _PREDICATE

    def run_until_complete(self, future: Awaitable[T]) -> T:  # type: ignore[override]
        """Run until ``future`` (a coroutine, task or future) is done; return its result."""
        fut = asyncio.ensure_future(future, loop=self)
        with self._entered():
            if not fut.done():
                outcome = self._drive(None, None, None, fut)
                if outcome == _EMPTY:
                    self._check_deadlock(extra="the awaited future")
        self._raise_failure()
        return fut.result()

    def run_forever(self) -> None:
        """Run until nothing is left to do (same as :meth:`run` with no limit)."""
        self.run()

    def _drive(self, until_ns: int | None, stop: Callable[[], bool] | None, max_rounds: int | None,
               until_done: asyncio.Future[Any] | None = None) -> int:
        """The one scheduling loop behind step/run/run_until/run_until_complete; returns why it stopped.

        A round: if nothing is ready, jump the clock to the earliest timer
        (but never to or past ``until_ns``); move every timer due now (and
        before ``until_ns``) to the ready queue in (time, sequence) order;
        run the callbacks that were ready at the round's start. Everything is
        inlined and kept in local variables: this is the simulator's hottest
        code (a sleep costs two rounds, so a round's own cost counts).

        ``until_done`` (run_until_complete's future) stops the loop after the round in which
        it became done, as a ``stop`` predicate of ``until_done.done`` would, but keeps the
        fast paths a predicate turns off: a predicate can look at anything, a future only
        becomes done in a round that runs its own code. So a round that is one bus delivery
        is followed by a look at the future; a sleep's timer round cannot finish any future
        but its own waiter (it only marks the waiter done), so it runs with its wake-up and
        the look follows both unless the awaited future is that waiter; the general round's
        inline wake-up is skipped once the future is done. Same rounds, same order, as
        through the predicate (``tests/test_vloop.py``), at ``run``'s speed.
        """
        ready = self._ready
        timers = self.timers
        times = timers.times
        due = timers.due
        pop_due = due.pop
        popleft = ready.popleft
        append = ready.append
        heappop = heapq.heappop
        pacer = self._pacer
        checks = max_rounds is not None or stop is not None
        done = until_done.done if until_done is not None else None
        last = (until_ns - 1) if until_ns is not None else None  # the last instant this call may run
        rounds = 0
        handle = lone = None
        now = self._now_ns
        instant = self._instant_ns
        instant_rounds = self._instant_rounds
        max_instant = self.max_rounds_per_instant
        try:
            while True:
                if self._failure is not None:
                    return _FAILED
                if not ready:
                    if timers.cancelled > timers.compact_above and timers.cancelled * 2 > len(times):
                        self._compact_timers()
                    if not times:
                        return _EMPTY
                    when = times[0]
                    lone = due[when]
                    if lone.__class__ is list or lone._cancelled:
                        timers.drop_cancelled()
                        if not times:
                            return _EMPTY
                        when = times[0]
                        lone = None
                    elif checks or (lone.__class__ is not _SleepWaiter and lone.__class__ is not _Delivery):
                        lone = None
                    if last is not None and when > last:
                        return _UNTIL
                    if when > now:
                        if pacer is not None:
                            pacer.before_advance(now, when)
                        self._now_ns = now = when
                else:
                    lone = None
                if now != instant:
                    instant = now
                    instant_rounds = 0
                else:
                    instant_rounds += 1
                    if instant_rounds >= max_instant:
                        instant_rounds = 0  # counting starts again if the caller goes on
                        self._livelock()
                limit = now if last is None or last > now else last
                if lone is not None:
                    # This round is one timer alone (nothing was ready, nothing else is due now:
                    # due times are distinct and none is past): run it here, as the general path
                    # below would, without the ready queue. A bus delivery is called; a sleep's
                    # timer fires and, as the next round would be its task's wake-up alone, wakes it.
                    if lone.__class__ is _Delivery:
                        pop_due(heappop(times))
                        lone._scheduled = False
                        handle = lone
                        lone = None
                        try:
                            handle._callback(*handle._args)
                        except (SystemExit, KeyboardInterrupt):
                            raise
                        except BaseException as exc:  # one failing callback fails the run
                            self._record_failure(exc, f"callback {handle!r}")
                        handle = None
                        if done is not None and done():
                            return _PREDICATE
                        continue
                    waker = lone._waker
                    if (waker is not None and waker is not _MANY and instant_rounds + 1 < max_instant
                            and lone is not until_done):
                        pop_due(heappop(times))
                        lone._scheduled = False
                        lone._done = True
                        lone._waker = None
                        instant_rounds += 1
                        handle = lone
                        lone = None
                        try:
                            handle._waker_ctx.run(waker, handle)
                        except (SystemExit, KeyboardInterrupt):
                            raise
                        except BaseException as exc:  # one failing callback fails the run
                            self._record_failure(exc, f"callback {handle!r}")
                        handle = None
                        if done is not None and done():
                            return _PREDICATE
                        continue
                    lone = None
                while times and times[0] <= limit:
                    queued = pop_due(heappop(times))
                    if queued.__class__ is list:
                        for handle in queued:
                            if handle._cancelled:
                                timers.cancelled -= 1
                            else:
                                handle._scheduled = False
                                append(handle)
                    elif queued._cancelled:
                        timers.cancelled -= 1
                    else:
                        queued._scheduled = False
                        append(queued)
                queued = None
                n = len(ready)
                try:
                    while n:
                        n -= 1
                        handle = popleft()
                        if handle._cancelled:
                            continue
                        ctx = handle._context
                        if ctx is None:
                            cb = handle._callback
                            if cb is _sleep_fire:  # our sleep's timer: set_result, reusing the object as the wake-up
                                handle._done = True
                                waker = handle._waker
                                if waker is None:
                                    pass
                                elif waker is not _MANY:
                                    handle._waker = None
                                    if (not ready and not checks and instant_rounds + 1 < max_instant
                                            and self._failure is None and (not times or times[0] > limit)
                                            and (done is None or not done())):
                                        # The wake-up would be the whole next round (nothing else is
                                        # ready or due now): run it as that round, here. Same order.
                                        instant_rounds += 1
                                        handle._waker_ctx.run(waker, handle)
                                    else:
                                        handle._callback = waker
                                        handle._context = handle._waker_ctx
                                        handle._args = (handle,)
                                        append(handle)
                                else:
                                    handle._wake_all()
                            elif cb is _set_result_unless_cancelled:  # asyncio.sleep's timer
                                fut, result = handle._args
                                if not fut.cancelled():
                                    fut.set_result(result)
                            else:
                                cb(*handle._args)
                        else:
                            ctx.run(handle._callback, *handle._args)
                except (SystemExit, KeyboardInterrupt):
                    raise
                except BaseException as exc:  # one failing callback fails the run
                    self._record_failure(exc, f"callback {handle!r}")
                handle = None
                if done is not None and done():
                    return _PREDICATE
                if checks:
                    rounds += 1
                    if max_rounds is not None and rounds >= max_rounds:
                        return _ROUNDS
                    if stop is not None and stop():
                        return _PREDICATE
        finally:
            self._instant_ns = instant
            self._instant_rounds = instant_rounds

    def _compact_timers(self) -> None:
        self.timers.compact()  # in place: _drive holds references to its lists

    # -------------------------------------------------------------- internals
    def _advance_to(self, when_ns: int) -> None:
        if when_ns < self._now_ns:
            raise ClockError(f"time can't go backwards: from {self._now_ns} ns to {when_ns} ns")
        if when_ns > self._now_ns:
            if self._pacer is not None:
                self._pacer.before_advance(self._now_ns, when_ns)
            self._now_ns = when_ns

    def _run_once(self) -> None:  # asyncio's internal entry point
        self._drive(None, None, 1)

    def is_running(self) -> bool:
        return self._inside


def new_loop(*, start: float = 0.0, pacer: Pacer | None = None) -> VirtualEventLoop:
    """Create a virtual-time loop (convenience for tests and notebooks)."""
    return VirtualEventLoop(start=start, pacer=pacer)
