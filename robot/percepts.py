"""The camera's percept lists as typed records (:class:`homesim.message.Typed`).

``/robot/camera/faces`` and ``/robot/camera/torsos`` go out every frame (10 Hz) to one reader,
person attention, which wants a few numbers of each item. The record keeps each item's attribute
values as the contract writes them (docs/robot-contract.md: degrees and metres with 3 decimals),
so a typed reader reads exactly what an XML reader reads (``float(row.bearing)``), and the
``<faces time pan tilt><face .../></faces>`` document is built only when somebody reads
``msg.xml`` (the trace, ``--strict``, an expectation on the channel).
"""

from __future__ import annotations

from typing import NamedTuple, Union

from lxml import etree

from homesim.message import Typed


class FaceRow(NamedTuple):
    """``<face bearing distance height/>``: the contract's texts."""

    bearing: str
    distance: str
    height: str


class TorsoRow(NamedTuple):
    """``<torso bearing r g b/>``: the contract's texts."""

    bearing: str
    r: str
    g: str
    b: str


Row = Union[FaceRow, TorsoRow]


class PerceptList(Typed):
    """One frame's percepts of one kind: the list element's template (``<faces time="" pan tilt/>``,
    kept by the camera per pan-tilt state and never changed), the frame's time as text, the item
    tag and the items."""

    __slots__ = ("template", "time", "tag", "rows")

    def __init__(self, template: etree._Element, time: str, tag: str, rows: tuple[Row, ...]) -> None:
        self.template = template
        self.time = time
        self.tag = tag
        self.rows = rows

    def to_xml(self) -> etree._Element:
        el = self.template.__copy__()
        el.set("time", self.time)  # (set in place: the attributes keep their order)
        tag = self.tag
        for row in self.rows:
            etree.SubElement(el, tag, row._asdict())
        return el
