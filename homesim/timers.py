"""The virtual loop's timers: one queue, one push, used by the loop, the sleep and the bus.

Timers are kept by due time (integer ns): a heap of the *distinct* due times
and, per due time, the one handle due then or, once a second one comes, a list
of them in scheduling order (a list per timer would cost an allocation for the
usual lone timer). Timers due at the same time therefore run in the order they
were pushed. Cancelled timers leave lazily: :meth:`TimerQueue.drop_cancelled`
drops the earliest due times whose timers are all cancelled, and the loop calls
:meth:`TimerQueue.compact` when cancelled timers are the majority.

A handle is anything with ``_cancelled`` and ``_scheduled``: the slim
asyncio handles below, the bus's :class:`_Delivery`, the sleep's
``_SleepWaiter``. The loop's ``_drive`` pops ``times``/``due`` itself, in its
hot loop.
"""

from __future__ import annotations

import heapq
from asyncio import events
from typing import Any

_heappush = heapq.heappush

#: Nanoseconds per second: virtual time is kept in integer ns.
NS_PER_S = 1_000_000_000


def to_ns(seconds: float) -> int:
    """Convert seconds to integer nanoseconds (rounded to the nearest ns)."""
    return int(round(seconds * NS_PER_S))


class TimerQueue:
    """Timers by due time (see the module docstring)."""

    __slots__ = ("times", "due", "cancelled", "compact_above")

    def __init__(self) -> None:
        self.times: list[int] = []  # heap of distinct due times
        self.due: dict[int, Any] = {}  # due time -> handle, or [handles] in push order
        self.cancelled = 0  # cancelled timers still queued
        # Compact only past this many cancelled timers: the live timers the last compaction kept
        # (at least 64), so that a compaction's look at every timer is paid for by as many
        # cancellations (the majority test counts distinct due times, not timers).
        self.compact_above = 64

    def push(self, when_ns: int, handle: Any) -> None:
        """Queue ``handle`` at ``when_ns``, after every timer already due then."""
        due = self.due
        queued = due.get(when_ns)
        if queued is None:
            due[when_ns] = handle
            _heappush(self.times, when_ns)
        elif queued.__class__ is list:
            queued.append(handle)
        else:
            due[when_ns] = [queued, handle]

    def pending(self) -> int:
        """How many timers are queued, cancelled ones not yet dropped included."""
        return sum(len(q) if q.__class__ is list else 1 for q in self.due.values())

    def due_until(self, when_ns: int) -> list[Any]:
        """Every queued handle due at or before ``when_ns``, in run order (for diagnostics)."""
        out: list[Any] = []
        for w in sorted(self.times):
            if w > when_ns:
                break
            q = self.due[w]
            out += q if q.__class__ is list else [q]
        return out

    def needs_compacting(self) -> bool:
        return self.cancelled > self.compact_above and self.cancelled * 2 > len(self.times)

    def drop_cancelled(self) -> None:
        """Drop the earliest due times whose timers are all cancelled."""
        times, due = self.times, self.due
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
            self.cancelled -= n

    def compact(self) -> None:
        """Drop every cancelled timer, in place (the loop's ``_drive`` holds ``times`` and ``due``)."""
        kept: dict[int, Any] = {}
        n = 0
        for when, queued in self.due.items():
            live = [h for h in queued if not h._cancelled] if queued.__class__ is list else [queued] if not queued._cancelled else []
            if live:
                kept[when] = live if len(live) > 1 else live[0]
                n += len(live)
        self.compact_above = max(64, n)
        self.due.clear()
        self.due.update(kept)
        self.times[:] = kept
        heapq.heapify(self.times)
        self.cancelled = 0

    def clear(self) -> None:
        self.times.clear()
        self.due.clear()
        self.cancelled = 0


# ------------------------------------------------------------- the handles
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
    Made with ``object.__new__(_Delivery)`` by the bus, queued with the loop's ``timers.push``
    (one call per delivery).
    """

    __slots__ = ("_callback", "_args", "_scheduled")
    _cancelled = False
    _context = None

    def __repr__(self) -> str:
        cb = self._callback
        return f"<delivery {getattr(cb, '__qualname__', cb)!s}>"
