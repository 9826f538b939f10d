"""A virtual-time asyncio event loop with a stepping API.

Ordinary asyncio code (``asyncio.sleep``, ``wait_for``, ``asyncio.timeout``,
``Queue``, ``Event``, ``TaskGroup``, ``call_later``/``call_at``) runs on
:class:`VirtualEventLoop` unchanged, but every clock reading is virtual:
when nothing is ready to run, the clock jumps straight to the earliest timer.

Why not asyncio's own loop: its timer heap orders equal deadlines by heap
position, not by scheduling order, and it polls a selector on every round.
Here timers due at the same virtual time run in the order they were
scheduled (each due time keeps its timers in a list, in scheduling order; a
heap holds the distinct due times as plain integers, which compare several
times faster than asyncio's ``(time, sequence, handle)`` tuples), time is an integer
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
:class:`DeadlockError` naming the waiting tasks instead of hanging.
"""

from __future__ import annotations

import asyncio
import functools
import heapq
import math
import sys
from asyncio import events
from collections.abc import Awaitable, Callable, Coroutine
from asyncio import futures as _futures
from contextvars import Context, copy_context
from typing import Any, Protocol, TypeVar

from .errors import ClockError, DeadlockError, LivelockError, RealIOError, SimulationError, TaskFailedError
from .vsleep import _MANY, _enter, _leave, _sleep_fire, _SleepWaiter

T = TypeVar("T")

NS_PER_S = 1_000_000_000

#: Scheduling rounds allowed at one virtual instant before the run is called a
#: livelock (a task looping on ``await asyncio.sleep(0)``, on a sleep that
#: rounds to 0 ns, or a ``call_soon`` chain keeps the clock still for ever).
#: A real burst of same-instant work (deliveries, wake-ups) takes a few
#: hundred rounds at most; 100,000 rounds take well under a second.
MAX_ROUNDS_PER_INSTANT = 100_000

# Why the scheduling loop stopped.
_FAILED, _EMPTY, _UNTIL, _ROUNDS, _PREDICATE = range(5)


def to_ns(seconds: float) -> int:
    """Convert seconds to integer nanoseconds (rounded to the nearest ns)."""
    return int(round(seconds * NS_PER_S))


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


class _Handle(events.Handle):
    """A slimmer :class:`asyncio.Handle`, filled in without an ``__init__`` frame."""

    __slots__ = ()

    def __repr__(self) -> str:
        cb = self._callback
        return f"<Handle {getattr(cb, '__qualname__', cb)!s}{' cancelled' if self._cancelled else ''}>"


class _TimerHandle(events.TimerHandle):
    """A slimmer :class:`asyncio.TimerHandle`; the heap key lives outside it.

    Made with ``_TimerHandle()`` and filled in by the loop (no ``__init__`` frame).
    """

    __slots__ = ()
    __init__ = object.__init__  # type: ignore[assignment]

    def __repr__(self) -> str:
        cb = self._callback
        return f"<TimerHandle when={self._when} {getattr(cb, '__qualname__', cb)!s}>"

    def cancel(self) -> None:
        if not self._cancelled:
            if self._scheduled:
                self._loop._timer_handle_cancelled(self)
            self._cancelled = True
            self._callback = None
            self._args = None


class _Delivery:
    """A timer the kernel schedules and never cancels (a bus delivery): two fields to fill, not eight.

    The loop's scheduling code reads ``_cancelled`` and ``_context`` (class-level: never
    cancelled, no copied context), ``_callback`` and ``_args``, and sets ``_scheduled``.
    Made with ``object.__new__(_Delivery)`` by the bus, queued with the loop's ``_push_timer``
    (inlined there).
    """

    __slots__ = ("_callback", "_args", "_scheduled")
    _cancelled = False
    _context = None

    def __repr__(self) -> str:
        cb = self._callback
        return f"<delivery {getattr(cb, '__qualname__', cb)!s}>"


_new = object.__new__




class Pacer(Protocol):
    """Called before the clock jumps forward; real-time mode sleeps here."""

    def before_advance(self, from_ns: int, to_ns: int) -> None: ...


class VirtualEventLoop(asyncio.BaseEventLoop):
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
        # The timers: a heap of distinct due times (integer ns) and, per due time, the one
        # handle due then or a list of them in scheduling order (see _push_timer).
        self._times: list[int] = []
        self._due: dict[int, Any] = {}
        self._cancelled_timers = 0
        # Compact only past this many cancelled timers: the live timers the last compaction kept
        # (at least 64), so that a compaction's look at every timer is paid for by as many
        # cancellations (the majority test below counts distinct due times, not timers).
        self._compact_above = 64
        self._clock_resolution = 1e-9
        self._pacer = pacer
        self._failure: BaseException | None = None
        self._failure_where: str = ""
        self._orphans: list[tuple[asyncio.Task[Any], int]] = []
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
        due = self._due  # _push_timer, inlined
        queued = due.get(when_ns)
        if queued is None:
            due[when_ns] = handle
            heapq.heappush(self._times, when_ns)
        elif queued.__class__ is list:
            queued.append(handle)
        else:
            due[when_ns] = [queued, handle]
        return handle

    def _push_timer(self, when_ns: int, handle: Any) -> None:
        """Queue ``handle`` at ``when_ns``, after every timer already due then (same-time order = scheduling order).

        A due time holds its one handle, or a list of them once a second one comes (a list
        per timer would cost an allocation for the usual lone timer). Inlined in
        ``_call_at_bare``, the bus and the light sleep: keep them alike.
        """
        due = self._due
        queued = due.get(when_ns)
        if queued is None:
            due[when_ns] = handle
            heapq.heappush(self._times, when_ns)
        elif queued.__class__ is list:
            queued.append(handle)
        else:
            due[when_ns] = [queued, handle]

    def _pending_timers(self) -> int:
        """How many timers are queued, cancelled ones not yet dropped included."""
        return sum(len(q) if q.__class__ is list else 1 for q in self._due.values())

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
        self._cancelled_timers += 1

    # ------------------------------------------------------ failing loudly
    def create_task(self, coro: Any, *, name: str | None = None, context: Context | None = None) -> asyncio.Task[Any]:  # type: ignore[override]
        """Create a task; if it dies with an exception nobody takes, the run fails.

        asyncio only logs such an exception when the garbage collector meets
        the task (late, and at a time that depends on the collector). Here a
        task that ends with an exception is remembered; when the current
        ``step``/``run``/``run_until`` returns, any such exception that no
        awaiting task, TaskGroup, gather or done callback has taken fails the
        run, naming the task and when it died. Deterministic, and never lost.
        """
        task = super().create_task(coro, name=name, context=context)
        task.add_done_callback(self._task_done)
        return task

    def _task_done(self, task: asyncio.Task[Any]) -> None:
        if not task.cancelled() and task._log_traceback:  # type: ignore[attr-defined]
            self._orphans.append((task, self._now_ns))

    def _check_orphans(self) -> None:
        orphans, self._orphans = self._orphans, []
        for task, died_ns in orphans:
            if task._log_traceback:  # type: ignore[attr-defined]
                exc = task.exception()
                assert exc is not None
                self._record_failure(
                    exc,
                    f"task {task.get_name()!r} died at t={died_ns / NS_PER_S:.9f} s and nobody took its exception "
                    "(await it, or handle it in a done callback)",
                )

    def spawn(self, coro: Coroutine[Any, Any, T], *, name: str) -> asyncio.Task[T]:
        """Start a top-level simulated task; its failure fails the whole run."""
        task = self.create_task(coro, name=name)
        task.add_done_callback(self._spawned_done)
        return task

    def _spawned_done(self, task: asyncio.Task[Any]) -> None:
        if task.cancelled():
            return
        exc = task.exception()
        if exc is not None:
            self._record_failure(exc, f"task {task.get_name()!r}")

    def _record_failure(self, exc: BaseException, where: str) -> None:
        if self._failure is None:
            self._failure = exc
            self._failure_where = where

    def call_exception_handler(self, context: dict[str, Any]) -> None:
        """Any unhandled error in a simulated callback fails the run loudly."""
        exc = context.get("exception")
        message = context.get("message", "unhandled error")
        if exc is None:
            exc = RuntimeError(message)
        where = message
        handle = context.get("handle") or context.get("task")
        if handle is not None:
            where = f"{message} in {handle!r}"
        self._record_failure(exc, where)

    def _asyncgen_finalizer_hook(self, agen: Any) -> None:
        # asyncio's version goes through call_soon_threadsafe, which we refuse.
        self._asyncgens.discard(agen)
        if not self.is_closed():
            self.call_soon(self.create_task, agen.aclose())

    # ------------------------------------------------------------- stepping
    def peek(self) -> float:
        """Time of the next scheduling round; ``inf`` when nothing is scheduled."""
        if self._ready:
            return self.time()
        self._drop_cancelled()
        if self._times:
            return self._times[0] / NS_PER_S
        return math.inf

    def _drop_cancelled(self) -> None:
        """Drop the earliest due times whose timers are all cancelled."""
        times, due = self._times, self._due
        while times:
            queued = due[times[0]]
            if queued.__class__ is list:
                for h in queued:
                    if not h._cancelled:
                        return
                n = len(queued)
            elif not queued._cancelled:
                return
            else:
                n = 1
            del due[heapq.heappop(times)]
            self._cancelled_timers -= n

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
                outcome = self._drive(None, fut.done, None)
                if outcome == _EMPTY:
                    self._check_deadlock(extra="the awaited future")
        self._raise_failure()
        return fut.result()

    def run_forever(self) -> None:
        """Run until nothing is left to do (same as :meth:`run` with no limit)."""
        self.run()

    def _drive(self, until_ns: int | None, stop: Callable[[], bool] | None, max_rounds: int | None) -> int:
        """The one scheduling loop behind step/run/run_until; returns why it stopped.

        A round: if nothing is ready, jump the clock to the earliest timer
        (but never to or past ``until_ns``); move every timer due now (and
        before ``until_ns``) to the ready queue in (time, sequence) order;
        run the callbacks that were ready at the round's start. Everything is
        inlined and kept in local variables: this is the simulator's hottest
        code (a sleep costs two rounds, so a round's own cost counts).
        """
        ready = self._ready
        times = self._times
        due = self._due
        pop_due = due.pop
        popleft = ready.popleft
        append = ready.append
        heappop = heapq.heappop
        pacer = self._pacer
        checks = max_rounds is not None or stop is not None
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
                    if self._cancelled_timers > self._compact_above and self._cancelled_timers * 2 > len(times):
                        self._compact_timers()
                    if not times:
                        return _EMPTY
                    when = times[0]
                    lone = due[when]
                    if lone.__class__ is list or lone._cancelled:
                        self._drop_cancelled()
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
                        continue
                    waker = lone._waker
                    if waker is not None and waker is not _MANY and instant_rounds + 1 < max_instant:
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
                        continue
                    lone = None
                while times and times[0] <= limit:
                    queued = pop_due(heappop(times))
                    if queued.__class__ is list:
                        for handle in queued:
                            if handle._cancelled:
                                self._cancelled_timers -= 1
                            else:
                                handle._scheduled = False
                                append(handle)
                    elif queued._cancelled:
                        self._cancelled_timers -= 1
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
                                            and self._failure is None and (not times or times[0] > limit)):
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
        # In place: _drive holds references to both.
        kept: dict[int, Any] = {}
        n = 0
        for when, queued in self._due.items():
            live = [h for h in queued if not h._cancelled] if queued.__class__ is list else [queued] if not queued._cancelled else []
            if live:
                kept[when] = live if len(live) > 1 else live[0]
                n += len(live)
        self._compact_above = max(64, n)
        self._due.clear()
        self._due.update(kept)
        self._times[:] = kept
        heapq.heapify(self._times)
        self._cancelled_timers = 0

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

    def _raise_failure(self) -> None:
        if self._orphans:
            self._check_orphans()
        exc = self._failure
        if exc is None:
            return
        self._failure = None
        raise TaskFailedError(f"simulation failed at t={self.now:.9f} s: {self._failure_where}: {exc!r}") from exc

    def _livelock(self) -> None:
        """Raise :class:`LivelockError` naming what keeps running at this instant."""
        names: dict[str, None] = {}
        due_now = [self._due[w] for w in sorted(self._times) if w <= self._now_ns]
        for handle in list(self._ready) + [h for q in due_now for h in (q if q.__class__ is list else [q])]:
            if handle._cancelled:
                continue
            cb = handle._callback
            owners = [getattr(cb, "__self__", None)]
            if isinstance(handle, _SleepWaiter):  # a sleep's timer: the task waiting on it
                owners.append(getattr(handle._waker, "__self__", None))
            args = getattr(handle, "_args", ())
            if args and isinstance(args[0], asyncio.Future):  # asyncio's sleep timer: who waits on it
                owners += [getattr(c, "__self__", None) for c, _ctx in (args[0]._callbacks or [])]
            tasks = [o for o in owners if isinstance(o, asyncio.Task)]
            for task in tasks:
                names.setdefault(f"task {task.get_name()} ({_where(task)})", None)
            if not tasks:
                names.setdefault(f"callback {getattr(cb, '__qualname__', repr(cb))}", None)
        self._instant_rounds = 0
        raise LivelockError(
            f"livelock at t={self.now:.9f} s: {self.max_rounds_per_instant} scheduling rounds without virtual time "
            f"moving (a loop on sleep(0), a sleep shorter than 1 ns, or a call_soon chain); still running: "
            + ("; ".join(sorted(names)) or "nothing named")
        )

    def waiting_tasks(self) -> list[asyncio.Task[Any]]:
        """Tasks of this loop that are not done, sorted by name (deterministic)."""
        return sorted((t for t in asyncio.all_tasks(self) if not t.done()), key=lambda t: t.get_name())

    def _check_deadlock(self, extra: str | None = None) -> None:
        waiting = self.waiting_tasks()
        if not waiting and extra is None:
            return
        lines = [f"{t.get_name()} ({_where(t)})" for t in waiting] or [f"<{extra}>"]
        raise DeadlockError(
            f"deadlock at t={self.now:.9f} s: nothing is ready and no timer is pending, "
            f"but {len(waiting)} task(s) are still waiting: " + "; ".join(lines)
        )

    class _Entered:
        __slots__ = ("loop",)

        def __init__(self, loop: VirtualEventLoop) -> None:
            self.loop = loop

        def __enter__(self) -> None:
            loop = self.loop
            if loop._inside:
                raise SimulationError("the simulation is already running: step/run cannot be called from inside a simulated task")
            loop._check_closed()
            loop._inside = True
            loop._saved_loop = events._get_running_loop()
            loop._saved_hooks = sys.get_asyncgen_hooks()
            sys.set_asyncgen_hooks(firstiter=loop._asyncgen_firstiter_hook, finalizer=loop._asyncgen_finalizer_hook)
            events._set_running_loop(loop)
            # The lighter sleep, for code that looks asyncio.sleep up when it runs (it passes
            # every other loop on to asyncio's own, so threads with their own loops are safe).
            loop._saved_sleep = _enter(loop)

        def __exit__(self, *exc: object) -> None:
            loop = self.loop
            _leave(loop._saved_sleep)
            events._set_running_loop(loop._saved_loop)
            sys.set_asyncgen_hooks(*loop._saved_hooks)
            loop._saved_loop = None
            loop._inside = False

    def _entered(self) -> VirtualEventLoop._Entered:
        return VirtualEventLoop._Entered(self)

    def is_running(self) -> bool:
        return self._inside

    # ------------------------------------------------------- refused real I/O
    def _refuse(self, what: str) -> Any:
        raise RealIOError(
            f"{what} is not allowed inside a simulation: it would make the run depend on "
            "real time and threads. Model the work in virtual time instead (asyncio.sleep)."
        )

    def run_in_executor(self, executor: Any, func: Any, *args: Any) -> Any:  # type: ignore[override]
        return self._refuse("run_in_executor")

    def call_soon_threadsafe(self, callback: Any, *args: Any, context: Any = None) -> Any:  # type: ignore[override]
        return self._refuse("call_soon_threadsafe (threads)")

    async def getaddrinfo(self, *args: Any, **kwargs: Any) -> Any:  # type: ignore[override]
        return self._refuse("getaddrinfo (network)")

    async def getnameinfo(self, *args: Any, **kwargs: Any) -> Any:  # type: ignore[override]
        return self._refuse("getnameinfo (network)")

    async def create_connection(self, *args: Any, **kwargs: Any) -> Any:  # type: ignore[override]
        return self._refuse("create_connection (sockets)")

    async def create_server(self, *args: Any, **kwargs: Any) -> Any:  # type: ignore[override]
        return self._refuse("create_server (sockets)")

    async def create_datagram_endpoint(self, *args: Any, **kwargs: Any) -> Any:  # type: ignore[override]
        return self._refuse("create_datagram_endpoint (sockets)")

    async def create_unix_connection(self, *args: Any, **kwargs: Any) -> Any:
        return self._refuse("create_unix_connection (sockets)")

    async def create_unix_server(self, *args: Any, **kwargs: Any) -> Any:
        return self._refuse("create_unix_server (sockets)")

    async def connect_read_pipe(self, *args: Any, **kwargs: Any) -> Any:  # type: ignore[override]
        return self._refuse("connect_read_pipe (pipes)")

    async def connect_write_pipe(self, *args: Any, **kwargs: Any) -> Any:  # type: ignore[override]
        return self._refuse("connect_write_pipe (pipes)")

    async def subprocess_exec(self, *args: Any, **kwargs: Any) -> Any:  # type: ignore[override]
        return self._refuse("subprocess_exec (subprocesses)")

    async def subprocess_shell(self, *args: Any, **kwargs: Any) -> Any:  # type: ignore[override]
        return self._refuse("subprocess_shell (subprocesses)")

    async def sock_recv(self, *args: Any, **kwargs: Any) -> Any:  # type: ignore[override]
        return self._refuse("sock_recv (sockets)")

    async def sock_sendall(self, *args: Any, **kwargs: Any) -> Any:  # type: ignore[override]
        return self._refuse("sock_sendall (sockets)")

    async def sock_connect(self, *args: Any, **kwargs: Any) -> Any:  # type: ignore[override]
        return self._refuse("sock_connect (sockets)")

    async def sock_accept(self, *args: Any, **kwargs: Any) -> Any:  # type: ignore[override]
        return self._refuse("sock_accept (sockets)")

    def add_reader(self, *args: Any, **kwargs: Any) -> Any:
        return self._refuse("add_reader (file descriptors)")

    def add_writer(self, *args: Any, **kwargs: Any) -> Any:
        return self._refuse("add_writer (file descriptors)")

    def add_signal_handler(self, *args: Any, **kwargs: Any) -> Any:
        return self._refuse("add_signal_handler (signals)")

    def _process_events(self, event_list: Any) -> None:
        pass

    def _write_to_self(self) -> None:
        pass

    def close(self, *, cleanup_budget: float = 60.0) -> None:
        """Cancel every waiting task, let its cleanup run, then close the loop.

        Cleanup (``finally`` blocks, async generators' ``aclose``) runs in
        virtual time for at most ``cleanup_budget`` seconds. An exception
        raised by cleanup code is not swallowed: it is raised as
        :class:`TaskFailedError` after the loop is closed.
        """
        if self.is_closed():
            return
        if self._inside:
            raise SimulationError("cannot close the simulation from inside a simulated task")
        self._failure = None
        pending = self.waiting_tasks()
        for task in pending:
            task.cancel()
        if pending or self._asyncgens:
            deadline = self._now_ns + to_ns(cleanup_budget)
            self._instant_rounds = 0
            try:
                with self._entered():
                    self._drive(deadline, lambda: all(t.done() for t in pending), None)
                    if self._asyncgens and self._failure is None:
                        shutdown = self.create_task(self.shutdown_asyncgens())
                        self._drive(deadline, shutdown.done, None)
                    self._drive(self._now_ns + 1, None, None)  # the done callbacks of the cleanup
            except LivelockError:
                pass  # a call_soon chain that never ends: the run reported it; cleanup stops here
        self._check_orphans()
        failure, where = self._failure, self._failure_where
        self._failure = None
        self._times.clear()
        self._due.clear()
        self._ready.clear()
        super().close()
        if failure is not None:
            raise TaskFailedError(f"cleanup failed while closing the simulation: {where}: {failure!r}") from failure


def _where(task: asyncio.Task[Any]) -> str:
    """Where a waiting task is suspended: its await chain, outermost first."""
    parts = []
    coro: Any = task.get_coro()
    while coro is not None:
        frame = getattr(coro, "cr_frame", None) or getattr(coro, "gi_frame", None)
        if frame is None:
            break
        parts.append(f"{frame.f_code.co_filename.rsplit('/', 1)[-1]}:{frame.f_lineno} in {frame.f_code.co_name}")
        coro = getattr(coro, "cr_await", None) or getattr(coro, "gi_yieldfrom", None)
    return " -> ".join(parts) if parts else "not started"


def new_loop(*, start: float = 0.0, pacer: Pacer | None = None) -> VirtualEventLoop:
    """Create a virtual-time loop (convenience for tests and notebooks)."""
    return VirtualEventLoop(start=start, pacer=pacer)
