"""Bus messages: an XML document, binary attachments and metadata.

As in XCF, the XML part carries structure (extensible, XPath-addressable)
and large binary data (an image patch, a laser scan) travels beside it as
attachments. As in RSB, every message names the messages that caused it, so
a trace can be read as a causal graph.
"""

from __future__ import annotations

import hashlib
from collections.abc import Mapping
from types import MappingProxyType
from typing import Any, NamedTuple, Union

import numpy as np
from lxml import etree

from .vloop import NS_PER_S

Attachment = Union[bytes, np.ndarray]

PUBLISH = "publish"
REQUEST = "request"
REPLY = "reply"
ERROR = "error"


_NO_ATTACHMENTS: Mapping[str, Attachment] = MappingProxyType({})


class Message(NamedTuple):
    """One message on the bus. Treat ``xml`` and attachments as read-only.

    ``id`` is ``"<sender>#<n>"`` (stable, from a per-sender counter);
    ``channel`` is the channel name, or ``"<server>/<method>"`` for calls;
    ``created_ns`` is when the sender created the content (it may predate
    sending, e.g. a percept's capture time); ``sent_ns`` when it was sent.
    Immutable (a named tuple: cheap to build, which matters on the bus's hot
    path); the bus gives every receiver a payload of its own.
    """

    id: str
    kind: str
    sender: str
    channel: str
    xml: etree._Element
    created_ns: int
    sent_ns: int
    causes: tuple[str, ...] = ()
    attachments: Mapping[str, Attachment] = _NO_ATTACHMENTS

    @property
    def created(self) -> float:
        """Creation time in virtual seconds."""
        return self.created_ns / NS_PER_S

    @property
    def sent(self) -> float:
        """Send time in virtual seconds."""
        return self.sent_ns / NS_PER_S

    def xpath(self, path: str, **variables: Any) -> Any:
        """Evaluate an XPath on the payload (a convenience for receivers)."""
        return self.xml.xpath(path, **variables)

    def text(self) -> str:
        """The payload serialized as text."""
        return etree.tostring(self.xml, encoding="unicode")

    @property
    def data(self) -> Typed | None:
        """The typed record this message carries (:class:`TypedMessage`), or None: an XML-only message."""
        return None


class Typed:
    """A message's payload as an immutable typed record; its XML form is built only when asked.

    As ROS 2's intra-process communication skips serialisation, a sender may publish a record
    instead of an element: receivers that know the record read its fields (no XML built, no copy
    per receiver: they share it), and its XML (the channel's contract, what the trace holds) is
    made by :meth:`to_xml` only when somebody asks for ``msg.xml`` (the trace, ``--strict``
    validation, a module that reads XML). A subclass must be immutable and :meth:`to_xml` must
    return a new element each call, built from the record alone, byte for byte what the sender
    would have sent as XML.
    """

    __slots__ = ()

    def __setattr__(self, name: str, value: object) -> None:
        # Receivers share the record: a field one of them rebinds would reach every other receiver,
        # later messages and the trace. A subclass sets its fields with object.__setattr__.
        raise AttributeError(f"{type(self).__name__} is immutable (receivers share it)")

    def __delattr__(self, name: str) -> None:
        raise AttributeError(f"{type(self).__name__} is immutable (receivers share it)")

    def to_xml(self) -> etree._Element:
        """A new element holding this record: the channel's contract."""
        raise NotImplementedError

    def size(self) -> int:
        """``len(etree.tostring(self.to_xml()))``: the bytes its XML puts on a link.

        A link with a bandwidth asks for every message it carries; a record that knows its size
        from its fields overrides this so that sizing a message builds no XML.
        """
        return len(etree.tostring(self.to_xml()))


class Frozen(Typed):
    """A payload the sender keeps unchanged (a template per state, say) sent as a typed record.

    The record holds a copy of the element made when it is created (the sender's own element stays
    the sender's: changing it later changes no record), never hands it out (a receiver asking for
    ``msg.xml`` gets a copy of its own; lxml copies the subtree in C) and refuses new fields, so a
    receiver can change neither what another receiver reads nor the trace. Nobody asking costs
    nothing; its size is measured once, on first use.
    """

    __slots__ = ("_element", "_size")

    def __init__(self, element: etree._Element) -> None:
        object.__setattr__(self, "_element", element.__copy__())
        object.__setattr__(self, "_size", -1)

    def to_xml(self) -> etree._Element:
        return self._element.__copy__()

    def size(self) -> int:
        n = self._size
        if n < 0:
            n = len(etree.tostring(self._element))
            object.__setattr__(self, "_size", n)
        return n


class TypedMessage(Message):
    """A :class:`Message` whose payload slot holds a :class:`Typed` record; ``xml`` is built on first use.

    Each receiver gets a message object of its own sharing the record, so the element one
    receiver builds (and may change) is its own, as with XML messages. (No ``__slots__``:
    the per-object ``__dict__`` caches the built element.)
    """

    @property
    def xml(self) -> etree._Element:  # type: ignore[override]
        """The payload as XML: built from the record on first use, then this message's own."""
        d = self.__dict__
        el = d.get("_xml")
        if el is None:
            el = d["_xml"] = tuple.__getitem__(self, 4).to_xml()
        return el

    @property
    def data(self) -> Typed:
        """The record (shared by every receiver: read-only)."""
        return tuple.__getitem__(self, 4)


def describe_attachment(value: Attachment) -> dict[str, Any]:
    """Digest, dtype and shape of an attachment, for traces (never inline)."""
    if isinstance(value, np.ndarray):
        arr = np.ascontiguousarray(value)
        digest = hashlib.sha256(arr.tobytes()).hexdigest()
        return {"sha256": digest, "dtype": str(arr.dtype), "shape": list(arr.shape)}
    data = bytes(value)
    return {"sha256": hashlib.sha256(data).hexdigest(), "dtype": "bytes", "shape": [len(data)]}
