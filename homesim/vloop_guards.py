"""What the virtual loop adds to asyncio's around its core: failing loudly and refusing real I/O.

:class:`FailsLoudly`: a task that dies with an exception nobody takes fails
the run (asyncio would only log it when the garbage collector meets it);
a failing callback fails the run; a livelock (rounds without time moving) and
a deadlock (tasks waiting, nothing scheduled) raise errors naming the tasks.
:class:`RefusesRealIO`: threads, sockets, pipes, subprocesses, file
descriptors and signals would make a run depend on real time; they raise
:class:`~homesim.errors.RealIOError`. Both are mixins of
:class:`~homesim.vloop.VirtualEventLoop` and use its fields.
"""

from __future__ import annotations

import asyncio
import sys
from asyncio import events
from collections.abc import Coroutine
from contextvars import Context
from typing import Any, TypeVar

from .errors import DeadlockError, LivelockError, RealIOError, SimulationError, TaskFailedError
from .timers import NS_PER_S, to_ns
from .vsleep import _enter, _leave, _SleepWaiter

T = TypeVar("T")


class FailsLoudly:
    """Failures, livelocks and deadlocks of a virtual loop, raised with names (a mixin)."""

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
        # Held until done: asyncio keeps only weak references to tasks, and a pending task the
        # garbage collector finds would be closed (GeneratorExit) at a moment no run controls.
        self._spawned[task] = None
        task.add_done_callback(self._spawned_done)
        return task

    def _spawned_done(self, task: asyncio.Task[Any]) -> None:
        self._spawned.pop(task, None)
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
        for handle in list(self._ready) + self.timers.due_until(self._now_ns):
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

        def __init__(self, loop: Any) -> None:
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

    def _entered(self) -> FailsLoudly._Entered:
        return FailsLoudly._Entered(self)

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
        self.timers.clear()
        self._ready.clear()
        super().close()
        if failure is not None:
            raise TaskFailedError(f"cleanup failed while closing the simulation: {where}: {failure!r}") from failure


class RefusesRealIO:
    """asyncio's real-I/O entry points, each refused with a clear error (a mixin)."""

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
