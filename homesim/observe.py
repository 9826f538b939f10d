"""Streaming observation of a run: one bus interceptor, handlers by channel prefix.

Expectations and metrics watch a run as it goes instead of keeping every
message for the end (a run's memory must not grow with its length). A
:class:`Dispatcher` is one interceptor on the bus; each handler registers
the channel prefixes it cares about (``"/system/health"``, ``"/system/"``,
``"scene_model/"`` for calls to that server) and is called with every
message *sent* on a matching channel, in send order. The routing of a
channel is computed once and cached, so a message no one watches costs one
dictionary look-up. Handlers observe; they must not change the message or
publish (an exception in one fails the run, like any callback).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

from .bus import SEND, Bus, Observation
from .message import Message

Handler = Callable[[Message], None]


class Dispatcher:
    """Routes every sent message to the handlers whose prefixes match its channel."""

    #: Sends only: the bus does not call it for deliveries and drops.
    observes = (SEND,)

    def __init__(self, bus: Bus) -> None:
        self.bus = bus
        self._handlers: list[tuple[tuple[str, ...], Handler]] = []
        self._routes: dict[str, tuple[Handler, ...]] = {}
        bus.add_interceptor(self)

    def add(self, prefixes: Sequence[str] | str, handler: Handler) -> None:
        """Call ``handler(message)`` for each message sent on a channel starting with one of ``prefixes``."""
        if isinstance(prefixes, str):
            prefixes = (prefixes,)
        self._handlers.append((tuple(prefixes), handler))
        self._routes.clear()
        self.bus.interceptors_changed()  # (the bus shows it only the channels it wants)

    def _route(self, channel: str) -> tuple[Handler, ...]:
        route = tuple(h for prefixes, h in self._handlers if channel.startswith(prefixes))
        self._routes[channel] = route
        return route

    def wants(self, channel: str) -> bool:
        """Whether a message sent on ``channel`` reaches a handler (the bus builds lazy payloads only then)."""
        route = self._routes.get(channel)
        if route is None:
            route = self._route(channel)
        return bool(route)

    def __call__(self, obs: Observation) -> None:
        if obs.event != SEND:
            return
        msg = obs.message
        route = self._routes.get(msg.channel)
        if route is None:
            route = self._route(msg.channel)
        for handler in route:
            handler(msg)

    def close(self) -> None:
        """Stop observing the bus."""
        if self in self.bus._interceptors:
            self.bus.remove_interceptor(self)
