"""The attention system's messages as typed records (:class:`homesim.message.Typed`).

``/robot/attention/tracks`` goes out every scan (10 Hz) and its main readers (the run's tracking
metric, the local controllers when they drive) want a few numbers per track: the record keeps them
as the tracker had them, and its XML (docs/robot-contract.md, ``attention-tracks.xsd``) is written
only when somebody reads ``msg.xml`` (the trace, ``--strict``, a module that reads XML).

The record holds the sender's floats; the contract carries them with a fixed number of decimals
(positions, bearings and distances 3, covariances 5). A typed reader that must agree with an XML
reader rounds as the contract does: ``round(v, 3)`` is the float that parsing ``f"{v:.3f}"`` gives
(both are correctly rounded).
"""

from __future__ import annotations

import math
from typing import NamedTuple

from lxml import etree

from homesim.message import Typed
from homesim.xmlio import hardened_parser

_PARSER = hardened_parser()


def own_document(text: str) -> etree._Element:
    """A message this module wrote as text, parsed with the project's hardened parser.

    Only numbers, ``tN`` ids, names and true/false go into these texts (nothing to escape, no
    DOCTYPE, no other encoding), so the checks ``parse_bytes`` makes on documents from outside
    (size, encoding, DOCTYPE: ~10 us a message) are left out; a malformed text would still raise
    lxml's XMLSyntaxError.
    """
    return etree.fromstring(text.encode(), _PARSER)


class TrackRow(NamedTuple):
    """One track as the tracker had it when the scan was processed (odom frame; bearing in degrees)."""

    id: str  # "tN"
    x: float
    y: float
    vx: float
    vy: float
    cxx: float
    cxy: float
    cyy: float
    bearing: float  # degrees, robot frame
    distance: float  # m from the robot
    confirmed: bool
    speaking: bool
    facing: bool


def _b(v: bool) -> str:
    return "true" if v else "false"


class TracksRecord(Typed):
    """``/robot/attention/tracks``: the scan's time and every track, oldest first."""

    __slots__ = ("time", "tracks")

    def __init__(self, time: float, tracks: tuple[TrackRow, ...]) -> None:
        object.__setattr__(self, "time", time)
        object.__setattr__(self, "tracks", tracks)

    def to_xml(self) -> etree._Element:
        # Written as text and read back with the hardened parser: lxml sets an attribute given as a
        # keyword at ~1.7 us (name and value checks), so a message of four tracks cost ~100 us built
        # node by node and ~50 us this way. Every value is a number, a "tN" id or true/false:
        # nothing to escape.
        return own_document(self._text())

    def size(self) -> int:
        # The text is what lxml writes back (ASCII, nothing escaped), except that an empty list is
        # written as <tracks .../>: 8 characters fewer than <tracks ...></tracks>.
        n = len(self._text())
        return n if self.tracks else n - 8

    def _text(self) -> str:
        parts = [f'<tracks time="{self.time:.6f}" frame="odom">']
        for r in self.tracks:
            parts.append(
                f'<track id="{r.id}" x="{r.x:.3f}" y="{r.y:.3f}" vx="{r.vx:.3f}" vy="{r.vy:.3f}" cxx="{r.cxx:.5f}" cxy="{r.cxy:.5f}" cyy="{r.cyy:.5f}"'
                f' bearing="{r.bearing:.3f}" distance="{r.distance:.3f}" confirmed="{_b(r.confirmed)}"'
                f' speaking="{_b(r.speaking)}" facing="{_b(r.facing)}"/>'
            )
        parts.append("</tracks>")
        return "".join(parts)


def track_row(tid: int, x: list[float], P: list[float], bearing_rad: float, distance: float,
              confirmed: bool, speaking: bool, facing: bool) -> TrackRow:
    """A row from a tracker's state (``x`` = [x, y, vx, vy], ``P`` its 10 covariance entries)."""
    x0, x1, x2, x3 = x
    return TrackRow(f"t{tid}", x0, x1, x2, x3, P[0], P[1], P[4], math.degrees(bearing_rad), distance,
                    confirmed, speaking, facing)
