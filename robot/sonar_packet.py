"""The sonar rings' packet (``/robot/sonar``) as a typed record (:class:`homesim.message.Typed`).

The sonar sends ten packets a second to up to three readers (person attention always, the follower
while following, the player while driving), each of which wants every echo's five numbers. As XML
each packet was an element built, copied per receiver and read back attribute by attribute by each
of them. The record keeps the texts the contract writes (docs/robot-contract.md: metres and degrees
with 3 decimals, ranges with 4), so a typed reader reads exactly what an XML reader reads, and
:meth:`SonarPacket.echoes` reads them once for every receiver (the record is shared and immutable).
The ``<sonar seq time min_range max_range cone height><echo id x y bearing range/>...</sonar>``
document is built only when somebody reads ``msg.xml`` (the trace, ``--strict``, an expectation).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, NamedTuple

from lxml import etree

from homesim.message import Typed

__all__ = ["Echo", "SonarPacket", "echoes_of"]


class Echo(NamedTuple):
    """One reading as a receiver uses it: transducer ``id``, its place (m) and bearing (rad, ``math.radians``
    of the degrees the message carries) in the robot frame, and the ``range`` (m) it read."""

    id: int
    x: float
    y: float
    bearing: float
    range: float


def _echo(ident: str, x: str, y: str, bearing: str, rng: str) -> Echo:
    return Echo(int(ident), float(x), float(y), math.radians(float(bearing)), float(rng))


def echoes_of(xml: etree._Element) -> tuple[Echo, ...]:
    """The echoes of a ``<sonar>`` element (a packet that came as XML): :meth:`SonarPacket.echoes`' values."""
    return tuple(_echo(e.get("id"), e.get("x"), e.get("y"), e.get("bearing"), e.get("range")) for e in xml.iter("echo"))


class SonarPacket(Typed):
    """One packet: the packet's attribute texts (``seq``, ``time``, then ``head``: min_range, max_range, cone,
    height) and one (id, x, y, bearing, range) row of texts per reading. Immutable: receivers share it."""

    __slots__ = ("seq", "time", "head", "rows", "_echoes", "_size", "_derived")

    def __init__(self, seq: str, time: str, head: tuple[str, str, str, str], rows: tuple[tuple[str, str, str, str, str], ...]) -> None:
        set_ = object.__setattr__
        set_(self, "seq", seq)
        set_(self, "time", time)
        set_(self, "head", head)
        set_(self, "rows", rows)
        set_(self, "_echoes", None)
        set_(self, "_size", -1)
        set_(self, "_derived", None)

    def get(self, name: str, default: str | None = None) -> str | None:
        """A packet attribute's text as the XML carries it (``max_range``, ``cone``, ...)."""
        i = _HEAD.get(name)
        if i is not None:
            return self.head[i]
        return self.seq if name == "seq" else self.time if name == "time" else default

    def echoes(self) -> tuple[Echo, ...]:
        """Every reading read from its texts (what :func:`echoes_of` reads from the XML), once for all receivers."""
        got = self._echoes
        if got is None:
            got = tuple(_echo(*row) for row in self.rows)
            object.__setattr__(self, "_echoes", got)
        return got

    def derived(self, key: str, make: Callable[[SonarPacket], Any]) -> Any:
        """``make(self)``, worked out once for all the packet's receivers and kept on the packet (it dies with
        it): a value that is a function of the packet alone (the blind side's arcs, :func:`robot.blindside.near_arcs`)."""
        got = self._derived
        if got is None:
            got = {}
            object.__setattr__(self, "_derived", got)
        if key not in got:
            got[key] = make(self)
        return got[key]

    def to_xml(self) -> etree._Element:
        lo, hi, cone, height = self.head
        el = etree.Element("sonar", seq=self.seq, time=self.time, min_range=lo, max_range=hi, cone=cone, height=height)
        sub = etree.SubElement
        for ident, x, y, bearing, rng in self.rows:
            sub(el, "echo", id=ident, x=x, y=y, bearing=bearing, range=rng)
        return el

    def size(self) -> int:
        """The XML's length, measured once (a link with a bandwidth asks for it)."""
        n = self._size
        if n < 0:
            n = len(etree.tostring(self.to_xml()))
            object.__setattr__(self, "_size", n)
        return n


_HEAD = {"min_range": 0, "max_range": 1, "cone": 2, "height": 3}
