"""The camera's percept lists as typed records (:class:`homesim.message.Typed`).

``/robot/camera/faces`` and ``/robot/camera/torsos`` go out every frame (10 Hz) to one reader,
person attention, which wants a few numbers of each item. The record keeps each item's attribute
values as the contract writes them (docs/robot-contract.md: degrees and metres with 3 decimals),
so a typed reader reads exactly what an XML reader reads (``float(row.bearing)``), and the
``<faces time pan tilt><face .../></faces>`` document is built only when somebody reads
``msg.xml`` (the trace, ``--strict``, an expectation on the channel).
"""

from __future__ import annotations

import re
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


def attr_len(value: str) -> int:
    """Length of ``value`` as lxml writes it in an attribute (ASCII output, libxml2's escapes)."""
    if value.isascii():
        if not _SPECIAL.search(value):
            return len(value)
        return len("".join(_ESCAPES.get(c, c) for c in value))
    # (Not in any message the robot sends: its texts are numbers. Measured, not guessed.)
    return len(etree.tostring(etree.Element("a", a=value))) - len('<a a=""/>')


_ESCAPES = {"&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;", "\n": "&#10;", "\r": "&#13;", "\t": "&#9;"}
_SPECIAL = re.compile("[&<>\"\n\r\t]")
#: Per row class: the characters of ``<tag`` + `` name=""`` per field + ``/>`` but the tag.
_ROW_FIXED: dict[type, int] = {}


class PerceptForm:
    """What a list's frames share while the pan-tilt unit holds still: ``<faces time="" pan tilt/>``.

    The camera makes one per kind and pan-tilt state; the form builds its element itself and never
    hands it out (a :class:`PerceptList`'s XML is a copy), and is immutable, so no receiver can
    change what the next frame or the trace says. ``time`` comes first; ``item`` is the items' tag.
    """

    __slots__ = ("tag", "item", "_template", "_sizes")

    def __init__(self, tag: str, item: str, attrs: dict[str, str]) -> None:
        set_ = object.__setattr__
        set_(self, "tag", tag)
        set_(self, "item", item)
        set_(self, "_template", etree.Element(tag, {"time": "", **attrs}))
        set_(self, "_sizes", None)

    def __setattr__(self, name: str, value: object) -> None:
        raise AttributeError("PerceptForm is immutable (every frame in its pan-tilt state shares it)")

    def __delattr__(self, name: str) -> None:
        raise AttributeError("PerceptForm is immutable (every frame in its pan-tilt state shares it)")

    def sizes(self) -> tuple[int, int]:
        """(bytes of the list with ``time=""`` and no items, bytes more when it has items), measured once."""
        sz = self._sizes
        if sz is None:
            el = self._template.__copy__()
            empty = len(etree.tostring(el))
            etree.SubElement(el, "x")
            sz = (empty, len(etree.tostring(el)) - len("<x/>") - empty)
            object.__setattr__(self, "_sizes", sz)
        return sz


class PerceptList(Typed):
    """One frame's percepts of one kind: its :class:`PerceptForm`, the frame's time as text and the items.

    Immutable: receivers share it (rows are named tuples of strings)."""

    __slots__ = ("form", "time", "rows")

    def __init__(self, form: PerceptForm, time: str, rows: tuple[Row, ...]) -> None:
        set_ = object.__setattr__
        set_(self, "form", form)
        set_(self, "time", time)
        set_(self, "rows", rows if rows.__class__ is tuple else tuple(rows))

    @property
    def tag(self) -> str:
        """The items' tag (``face``, ``torso``)."""
        return self.form.item

    def to_xml(self) -> etree._Element:
        el = self.form._template.__copy__()
        el.set("time", self.time)  # (set in place: the attributes keep their order)
        tag = self.form.item
        for row in self.rows:
            etree.SubElement(el, tag, row._asdict())
        return el

    def size(self) -> int:
        """``len(etree.tostring(self.to_xml()))`` from the fields: no XML built."""
        empty, more = self.form.sizes()
        n = empty + attr_len(self.time)
        rows = self.rows
        if rows:
            n += more
            item = len(self.form.item)
            for row in rows:
                cls = row.__class__
                fixed = _ROW_FIXED.get(cls)
                if fixed is None:
                    fixed = _ROW_FIXED[cls] = 3 + sum(len(f) + 4 for f in cls._fields)
                n += fixed + item
                for v in row:
                    n += attr_len(v)
        return n
