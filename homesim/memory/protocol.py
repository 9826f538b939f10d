"""Active memories on the bus: XML requests, replies and subscription notifications.

A server module routes each request to one of its memories and answers with
:func:`apply_request`. Requests (the routing attribute, e.g. ``kb``, is the
server's business)::

    <request op="insert">DOC</request>              (attachments: the bus message's)
    <request op="update" id="7">DOC</request>       (new attachments replace the old when any are sent)
    <request op="remove" id="7"/>   or   <request op="remove" xpath="..."/>
    <request op="query" [xpath="..."] [limit="n"] [attachments="inline"]><where index="type" value="cup"/>*</request>
    <request op="subscribe" xpath="..." [actions="insert update remove"] channel="/x/y"/>
    <request op="unsubscribe" subscription="3"/>

Reply: ``<reply ok="true" count="n"><doc id="7">DOC<attachment name dtype shape
sha256/>*</doc>*</reply>`` (query and remove list documents; insert and update
the id only; attachments inline as base64 on request, since bus replies carry
no binary attachments). A request that cannot be carried out is answered
``<reply ok="false" count="0" reason="..."/>`` and changes nothing.

Notifications of a subscription are published on its channel:
``<memory_event memory action id subscription matches>DOC</memory_event>`` with
the document's attachments as the message's attachments.
"""

from __future__ import annotations

import base64
import hashlib
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np
from lxml import etree

from ..bus import _check_channel_name
from ..errors import BusError, MemoryQueryError
from .core import ACTIONS, ActiveMemory, Attachment, MemoryEvent, Record
from .sqlite import decode_attachment, encode_attachment

#: What a server does with a subscription's notifications: publish them somewhere.
Publisher = Callable[[str, etree._Element, Mapping[str, Attachment]], Any]


def reply(ok: bool, *, count: int = 0, reason: str | None = None, **attrs: str) -> etree._Element:
    """A ``<reply>`` element."""
    el = etree.Element("reply", ok="true" if ok else "false", count=str(count))
    if reason is not None:
        el.set("reason", reason)
    for k, v in attrs.items():
        el.set(k, v)
    return el


def attachment_element(name: str, value: Attachment, *, inline: bool) -> etree._Element:
    """Describe an attachment (dtype, shape, sha256), with its data as base64 when ``inline``."""
    dtype, shape, data = encode_attachment(value)
    el = etree.Element("attachment", name=name, dtype=dtype, shape=" ".join(str(s) for s in np.asarray(value).shape) if dtype != "bytes" else str(len(data)),
                       sha256=hashlib.sha256(data).hexdigest())
    if inline:
        el.set("encoding", "base64")
        el.text = base64.b64encode(data).decode("ascii")
    return el


def decode_inline(el: etree._Element) -> Attachment:
    """Inverse of :func:`attachment_element` with ``inline=True``; :class:`MemoryQueryError` if it does not decode."""
    try:
        data = base64.b64decode((el.text or "").strip(), validate=True)
        dtype = el.get("dtype", "bytes")
        shape = "[]" if dtype == "bytes" else "[" + ",".join((el.get("shape") or "").split()) + "]"
        return decode_attachment(dtype, shape, data)
    except (ValueError, TypeError) as exc:
        raise MemoryQueryError(f"attachment {el.get('name')!r} does not decode: {exc}", source="<memory request>") from exc


def doc_element(rec: Record, *, with_xml: bool = True, inline: bool = False) -> etree._Element:
    """``<doc id>`` holding a record's document and its attachments' descriptions."""
    el = etree.Element("doc", id=str(rec.id))
    if with_xml:
        el.append(rec.xml)
        for name in sorted(rec.attachments):
            el.append(attachment_element(name, rec.attachments[name], inline=inline))
    return el


def event_element(ev: MemoryEvent) -> etree._Element:
    """The ``<memory_event>`` payload of a notification."""
    el = etree.Element("memory_event", memory=ev.memory, action=ev.action, id=str(ev.id),
                       subscription=str(ev.subscription), matches="true" if ev.matches else "false")
    el.append(ev.xml)
    return el


def _int(req: etree._Element, attr: str) -> int:
    text = req.get(attr)
    try:
        return int(text)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise MemoryQueryError(f"<request op={req.get('op')!r}> needs an integer {attr}=, got {text!r}", source="<memory request>") from None


def _document(req: etree._Element) -> etree._Element:
    children = [c for c in req if isinstance(c.tag, str)]
    if len(children) != 1:
        raise MemoryQueryError(f"<request op={req.get('op')!r}> needs exactly one document child, got {len(children)}", source="<memory request>")
    return children[0]


def apply_request(memory: ActiveMemory, req: etree._Element, attachments: Mapping[str, Attachment],
                  publish: Publisher | None = None) -> etree._Element:
    """Carry out one request on ``memory``; the reply says what happened (see the module docstring).

    ``publish(channel, xml, attachments)`` sends a subscription's notifications;
    without it, ``subscribe`` is refused. A request that fails is answered
    ``ok="false"`` with the reason, and nothing changed.
    """
    try:
        return _apply(memory, req, attachments, publish)
    except (MemoryQueryError, BusError) as exc:
        return reply(False, reason=getattr(exc, "message", str(exc)))


def _apply(memory: ActiveMemory, req: etree._Element, attachments: Mapping[str, Attachment], publish: Publisher | None) -> etree._Element:
    op = req.get("op")
    if op == "insert":
        doc_id = memory.insert(_document(req), attachments)
        out = reply(True, count=1)
        out.append(etree.Element("doc", id=str(doc_id)))
        return out
    if op == "update":
        doc_id = _int(req, "id")
        memory.update(doc_id, _document(req), attachments if attachments else None)
        out = reply(True, count=1)
        out.append(etree.Element("doc", id=str(doc_id)))
        return out
    if op == "remove":
        if req.get("id") is not None:
            ids = [_int(req, "id")]
            if ids[0] not in memory:
                raise MemoryQueryError(f"memory {memory.name!r} has no document {ids[0]}", source="<memory request>")
        elif req.get("xpath") is not None:
            ids = memory.query_ids(req.get("xpath"))
        else:
            raise MemoryQueryError("<request op='remove'> needs id= or xpath=", source="<memory request>")
        out = reply(True, count=len(ids))
        for i in ids:
            out.append(doc_element(memory.remove(i)))
        return out
    if op == "query":
        where = {w.get("index", ""): w.get("value", "") for w in req.iterchildren("where")}
        limit = _int(req, "limit") if req.get("limit") is not None else None
        recs = memory.query(req.get("xpath"), where=where or None, limit=limit)
        inline = req.get("attachments") == "inline"
        out = reply(True, count=len(recs))
        for rec in recs:
            out.append(doc_element(rec, inline=inline))
        return out
    if op == "subscribe":
        if publish is None:
            raise MemoryQueryError("this server offers no subscriptions", source="<memory request>")
        channel = req.get("channel")
        if not channel:
            raise MemoryQueryError("<request op='subscribe'> needs channel=", source="<memory request>")
        _check_channel_name(channel)
        actions = (req.get("actions") or " ".join(ACTIONS)).split()
        xpath = req.get("xpath") or "/*"

        def notify(ev: MemoryEvent, channel: str = channel) -> None:
            publish(channel, event_element(ev), ev.attachments)

        sub_id = memory.subscribe(xpath, notify, actions=actions)
        return reply(True, subscription=str(sub_id), channel=channel)
    if op == "unsubscribe":
        memory.unsubscribe(_int(req, "subscription"))
        return reply(True)
    raise MemoryQueryError(f"unknown op {op!r} (use insert, update, remove, query, subscribe, unsubscribe)", source="<memory request>")
