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


def describe_attachment(value: Attachment) -> dict[str, Any]:
    """Digest, dtype and shape of an attachment, for traces (never inline)."""
    if isinstance(value, np.ndarray):
        arr = np.ascontiguousarray(value)
        digest = hashlib.sha256(arr.tobytes()).hexdigest()
        return {"sha256": digest, "dtype": str(arr.dtype), "shape": list(arr.shape)}
    data = bytes(value)
    return {"sha256": hashlib.sha256(data).hexdigest(), "dtype": "bytes", "shape": [len(data)]}
