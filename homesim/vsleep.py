"""The virtual loop's ``asyncio.sleep``: one object per sleep instead of five.

asyncio's own sleep costs a coroutine, a Future, a TimerHandle, the
``call_later`` chain, a Handle to wake the task and a ``cancel()`` on the way
out: about twice what a SimPy timeout costs. While a
:class:`homesim.vloop.VirtualEventLoop` steps or runs, ``asyncio.sleep`` is
:func:`sleep` (the loop installs it and puts asyncio's back), which yields
one :class:`_SleepWaiter`: the loop's timer and the future-like object the
task waits on at once. The loop's scheduling code (``VirtualEventLoop._drive``)
knows the waiter (``_sleep_fire``) and wakes the task exactly where asyncio's
``set_result`` would have: the order of every callback is asyncio's, so
traces do not change.

How it fails: it does not; in any other thread or loop, and for ``delay <= 0``
or an infinite delay, it is asyncio's own sleep.
"""

from __future__ import annotations

import asyncio
import math
import sys
import threading
import types
from collections.abc import Callable
from contextvars import Context, copy_context
from typing import Any

NS_PER_S = 1_000_000_000


#: A sleep waiter's ``_waker`` when several callbacks wait on it (they are in ``_more``).
_MANY: Any = object()

#: Always empty: its ``clear`` is a waiter's ``result`` (returns None).
_NOTHING: dict[str, Any] = {}


class _SleepWaiter:
    """What a task waits on in :func:`sleep`: a timer and a future in one object.

    asyncio's own sleep costs a coroutine, a Future, a TimerHandle, the
    ``call_later`` chain, a Handle to wake the task and a ``cancel()`` on the
    way out. This object is the timer in the loop's heap *and* the
    future-like object the task waits on (asyncio's Task accepts any object
    with ``_asyncio_future_blocking``, ``_loop``, ``add_done_callback``,
    ``result`` and ``cancel``). When its time comes, the loop moves it to the
    ready queue exactly where ``set_result`` would have put the task's
    wake-up, and runs the wake-up in the next round: the same order as
    asyncio's sleep, with one object instead of five.

    Defaults live on the class (a sleep sets three attributes); ``result`` is
    a C callable (no frame); a cancelled waiter gets one that raises
    :class:`asyncio.CancelledError`.
    """

    __slots__ = (
        "_cancelled", "_scheduled", "_context", "_callback", "_args", "_done", "_waker", "_waker_ctx", "_more",
        "result", "_loop", "_when", "_asyncio_future_blocking", "__weakref__",
    )

    def __repr__(self) -> str:
        state = "cancelled" if self._cancelled else "done" if self._done else "pending"
        return f"<sleep until {self._when / NS_PER_S:.9f} s {state}>"

    def done(self) -> bool:
        return self._done

    def cancelled(self) -> bool:
        return self._cancelled

    def exception(self) -> BaseException | None:
        self.result()
        return None

    def add_done_callback(self, fn: Callable[[Any], Any], *, context: Context | None = None) -> None:
        if context is None:
            context = copy_context()
        if self._done:
            self._loop.call_soon(fn, self, context=context)
        elif self._waker is None:  # the usual case: the one task that sleeps
            self._waker = fn
            self._waker_ctx = context
        else:
            if self._waker is not _MANY:
                self._more = [(self._waker, self._waker_ctx)]
                self._waker = _MANY
            self._more.append((fn, context))

    def remove_done_callback(self, fn: Callable[[Any], Any]) -> int:
        if self._waker is None:
            return 0
        if self._waker is not _MANY:
            if self._waker != fn:
                return 0
            self._waker = self._waker_ctx = None
            return 1
        keep = [(f, c) for f, c in self._more if f != fn]
        n = len(self._more) - len(keep)
        self._more = keep
        if not keep:
            self._waker = self._more = None
        return n

    def cancel(self, msg: Any = None) -> bool:
        """Cancel the sleep: the timer leaves the heap, the waiting task is woken with CancelledError."""
        if self._done:
            return False
        self._done = True
        self._cancelled = True
        if self._scheduled:
            self._scheduled = False
            self._loop.timers.cancelled += 1
        exc = asyncio.CancelledError() if msg is None else asyncio.CancelledError(msg)

        def raise_cancelled() -> None:
            raise exc

        self.result = raise_cancelled
        self._wake_all()
        return True

    def _wake_all(self) -> None:
        # asyncio's order: a future's callbacks are scheduled in the order they were added.
        waker = self._waker
        if waker is None:
            return
        callbacks = self._more if waker is _MANY else [(waker, self._waker_ctx)]
        self._waker = self._waker_ctx = self._more = None
        for fn, ctx in callbacks:
            self._loop.call_soon(fn, self, context=ctx)

    def _fire(self) -> None:
        """The timer is due: what ``set_result`` does, reusing this object as the wake-up's handle.

        (The loop's scheduling code has this inlined; keep the two alike.)
        """
        self._done = True
        waker = self._waker
        if waker is None:
            return
        if waker is _MANY:
            self._wake_all()
            return
        self._callback = waker
        self._context = self._waker_ctx
        self._args = (self,)
        self._waker = None
        self._loop._ready.append(self)

    def __await__(self) -> Any:
        if not self._done:
            self._asyncio_future_blocking = True
            yield self
        return self.result()

    __iter__ = __await__


def _sleep_fire(waiter: _SleepWaiter) -> None:
    waiter._fire()




def _make_sleep(*, native: bool) -> Callable[..., Any]:
    """The light sleep: a native coroutine (``native``), or one generator (cheaper).

    Python 3.12+ asyncio takes only native coroutines (``collections.abc.Coroutine``)
    as tasks, so ``create_task(asyncio.sleep(1))`` needs the native form there; 3.11's
    asyncio still takes a generator-based coroutine, which saves a generator per sleep.
    """
    # A closure, so that the hot path reads cells rather than module globals.
    asyncio_sleep = asyncio.sleep
    get_ident = threading.get_ident
    waiter = _SleepWaiter
    inf = math.inf
    fire = _sleep_fire
    nothing = _NOTHING.clear  # result(): a C method that returns None (no frame; cheaper to call than NoneType)
    running = _running.get

    def _waiter(loop: Any, delay: float) -> _SleepWaiter:
        w = waiter()
        w._asyncio_future_blocking = False  # (set by __await__ when the task gets it)
        w._loop = loop
        w._cancelled = w._done = False
        w._scheduled = True
        w._context = w._waker = None
        w._callback = fire
        w.result = nothing
        w._when = when = loop._now_ns + round(delay * NS_PER_S)
        loop.timers.push(when, w)
        return w

    if native:
        async def sleep(delay: float, result: Any = None) -> Any:
            loop = running(get_ident())
            if loop is None or not delay > 0 or delay == inf:
                return await asyncio_sleep(delay, result)
            await _waiter(loop, delay)
            return result
    else:
        @types.coroutine
        def sleep(delay: float, result: Any = None) -> Any:  # type: ignore[misc]
            loop = running(get_ident())
            if loop is None or not delay > 0 or delay == inf:
                return (yield from asyncio_sleep(delay, result).__await__())
            # _waiter, inlined (one frame less per sleep: this is the simulator's commonest await)
            w = waiter()
            w._asyncio_future_blocking = True
            w._loop = loop
            w._cancelled = w._done = False
            w._scheduled = True
            w._context = w._waker = None
            w._callback = fire
            w.result = nothing
            w._when = when = loop._now_ns + round(delay * NS_PER_S)
            loop.timers.push(when, w)
            yield w
            return result

        sleep._is_coroutine = asyncio.coroutines._is_coroutine  # type: ignore[attr-defined]

    sleep.__doc__ = """``asyncio.sleep`` for the virtual loop, with fewer objects (installed while the loop runs).

    Same semantics and order as asyncio's: a coroutine, so ``create_task``,
    ``wait_for``, ``gather`` and cancellation work as before. In a thread
    whose running loop is not a :class:`VirtualEventLoop`, and for
    ``delay <= 0`` or an infinite delay, it is asyncio's own sleep.
    """
    return sleep


#: The VirtualEventLoop stepping in each thread (by thread id), for :func:`sleep`.
_running: dict[int, Any] = {}
_installed = 0  # how many loops are stepping, in all threads (the light sleep is installed while > 0)
_saved: tuple[Any, Any] = (None, None)  # asyncio's own sleep, put back when the last loop stops
_lock = threading.Lock()


def _enter(loop: Any) -> Any:
    """``loop`` starts stepping in this thread: install the light sleep; return what to give :func:`_leave`.

    Counted over all threads: asyncio's sleep is put back when the last loop stops,
    whatever order loops in different threads start and stop in.
    """
    global _installed, _saved
    tid = threading.get_ident()
    with _lock:
        outer = _running.get(tid)
        _running[tid] = loop
        if _installed == 0:
            _saved = (asyncio.sleep, asyncio.tasks.sleep)
            asyncio.sleep = asyncio.tasks.sleep = sleep
        _installed += 1
    return outer


def _leave(outer: Any) -> None:
    """The loop that :func:`_enter` gave ``outer`` stops stepping in this thread."""
    global _installed
    tid = threading.get_ident()
    with _lock:
        if outer is None:
            _running.pop(tid, None)
        else:
            _running[tid] = outer
        _installed -= 1
        if _installed == 0:
            asyncio.sleep, asyncio.tasks.sleep = _saved
sleep = _make_sleep(native=sys.version_info >= (3, 12))
