"""The active memory: XML documents with insert, update, remove, XPath query,
indexes and subscriptions (as XCF's active memory).

A memory holds documents, each one XML element that is the root of a tree of
its own, with optional binary attachments (``bytes`` or numpy arrays, e.g. an
object's colour histogram). Documents get integer ids from a counter, so a
run's ids are reproducible. Queries are XPath 1.0 expressions evaluated with
each document as the context (``/OBJECT[@type='cup']`` or ``self::*[@x > 2]``);
a document matches when the result, converted as XPath's ``boolean()``, is
true. Compiled XPath objects are cached, so a free query compiles once.

Indexes keep common look-ups fast as the memory grows: an index is a name and
an XPath that gives a document's key strings (``@type``, ``OWNER/@name``);
``query(where={"type": "cup"})`` intersects index entries without touching
the other documents, and an ``xpath`` given beside it only filters those.

Subscriptions (an XPath and the actions ``insert``/``update``/``remove``) call
back after each change that concerns them: an insert or a remove of a
matching document, an update where the old or the new version matches
(``MemoryEvent.matches`` says whether the new one does). The kernel's bus
glue (:mod:`homesim.memory.protocol`) turns the call-backs into messages.

Persistence is a separate object (:class:`homesim.memory.sqlite.SqliteStore`):
given one, each change is written and committed before the memory changes, so
memory and disk never disagree; without one the memory lives only in memory.

How it fails: a bad XPath, an unknown id, a document with a DOCTYPE or entity
references, or an attachment that is not bytes or a plain numpy array raise
:class:`MemoryQueryError` and change nothing.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Union

import numpy as np
from lxml import etree

from ..errors import InputError, MemoryQueryError, MemoryStoreError, XMLInputError
from ..xmlio import parse_bytes

if TYPE_CHECKING:
    from .sqlite import SqliteStore

Attachment = Union[bytes, np.ndarray]
DocLike = Union[etree._Element, str, bytes]

INSERT = "insert"
UPDATE = "update"
REMOVE = "remove"
ACTIONS = (INSERT, UPDATE, REMOVE)

_XPATH_CACHE_SIZE = 512
_xpath_cache: dict[str, etree.XPath] = {}


def compile_xpath(expr: str) -> etree.XPath:
    """A compiled XPath for ``expr`` (cached per process); raises :class:`MemoryQueryError` if malformed."""
    xp = _xpath_cache.get(expr)
    if xp is None:
        if not isinstance(expr, str) or not expr.strip():
            raise MemoryQueryError(f"an XPath must be a non-empty string, not {expr!r}", source="<memory>")
        try:
            xp = etree.XPath(expr, smart_strings=False)
        except etree.XPathSyntaxError as exc:
            raise MemoryQueryError(f"bad XPath {expr!r}: {exc}", source="<memory>") from exc
        if len(_xpath_cache) >= _XPATH_CACHE_SIZE:
            _xpath_cache.pop(next(iter(_xpath_cache)))
        _xpath_cache[expr] = xp
    return xp


def _evaluate(xp: etree.XPath, doc: etree._Element) -> Any:
    try:
        return xp(doc)
    except etree.XPathError as exc:
        raise MemoryQueryError(f"XPath {xp.path!r} cannot be evaluated: {exc}", source="<memory>") from exc


def xpath_true(result: Any) -> bool:
    """XPath 1.0 ``boolean()`` of an lxml XPath result."""
    if isinstance(result, bool):
        return result
    if isinstance(result, float):
        return not math.isnan(result) and result != 0.0
    if isinstance(result, (list, str)):
        return len(result) > 0
    return bool(result)


def own_document(doc: DocLike, *, source: str = "<memory>") -> etree._Element:
    """``doc`` as the root element of a tree of its own (text parsed by the hardened parser).

    An element is deep-copied (no parent, siblings or tail come along); one
    carrying a DOCTYPE or entity references is refused, as text with a DOCTYPE is.
    """
    if isinstance(doc, (str, bytes)):
        try:
            return parse_bytes(doc, source=source)
        except XMLInputError as exc:
            raise MemoryQueryError(f"document refused: {exc.message}", source=source, line=exc.line) from exc
    if not isinstance(doc, etree._Element) or not isinstance(doc.tag, str):
        raise MemoryQueryError(f"a document must be an XML element or XML text, not {type(doc).__name__}", source=source)
    info = doc.getroottree().docinfo
    if info.doctype or info.internalDTD is not None:
        raise MemoryQueryError("elements from documents with a DOCTYPE are refused", source=source)
    own = doc.__copy__()
    own.tail = None
    for _ in own.iter(etree.Entity):
        raise MemoryQueryError("entity references are refused in documents", source=source)
    return own


def own_attachments(attachments: Mapping[str, Attachment] | None, *, source: str = "<memory>") -> dict[str, Attachment]:
    """Read-only copies of attachments; refuse anything but bytes and plain numpy arrays."""
    out: dict[str, Attachment] = {}
    for name, value in (attachments or {}).items():
        if not isinstance(name, str) or not name or "/" in name:
            raise MemoryQueryError(f"attachment name {name!r}: a non-empty string without '/'", source=source)
        if isinstance(value, np.ndarray):
            if value.dtype.hasobject or value.dtype.fields is not None:
                raise MemoryQueryError(f"attachment {name!r}: only plain numeric arrays are stored, not {value.dtype}", source=source)
            value = np.array(value, copy=True)
            value.flags.writeable = False
        elif isinstance(value, (bytes, bytearray, memoryview)):
            value = bytes(value)
        else:
            raise MemoryQueryError(f"attachment {name!r}: bytes or a numpy array, not {type(value).__name__}", source=source)
        out[name] = value
    return out


@dataclass(frozen=True, slots=True)
class Record:
    """One document as the memory returns it: a private copy, with its id and attachments."""

    id: int
    xml: etree._Element
    attachments: Mapping[str, Attachment] = field(default_factory=dict)


@dataclass(frozen=True, slots=True)
class MemoryEvent:
    """What a subscriber hears: ``action`` on document ``id`` of memory ``memory``.

    ``xml`` is the document after the change (before it, for a remove);
    ``matches`` whether that version matches the subscription's XPath (an
    update can move a document out of a subscription's selection).
    """

    memory: str
    subscription: int
    action: str
    id: int
    xml: etree._Element
    attachments: Mapping[str, Attachment]
    matches: bool


Callback = Callable[[MemoryEvent], None]


@dataclass(slots=True)
class _Subscription:
    id: int
    xpath: etree.XPath
    actions: frozenset[str]
    callback: Callback


class _Index:
    __slots__ = ("name", "xpath", "entries", "keys")

    def __init__(self, name: str, xpath: etree.XPath) -> None:
        self.name = name
        self.xpath = xpath
        self.entries: dict[str, dict[int, None]] = {}
        self.keys: dict[int, tuple[str, ...]] = {}

    def values_of(self, doc: etree._Element) -> tuple[str, ...]:
        res = _evaluate(self.xpath, doc)
        if isinstance(res, list):
            vals = [v if isinstance(v, str) else (v.text or "") if isinstance(v, etree._Element) else str(v) for v in res]
        elif isinstance(res, str):
            vals = [res] if res else []
        else:
            raise MemoryQueryError(f"index {self.name!r}: its XPath {self.xpath.path!r} must give strings or nodes, not {type(res).__name__}", source="<memory>")
        return tuple(dict.fromkeys(vals))

    def add(self, doc_id: int, values: tuple[str, ...]) -> None:
        self.keys[doc_id] = values
        for v in values:
            self.entries.setdefault(v, {})[doc_id] = None

    def discard(self, doc_id: int) -> None:
        for v in self.keys.pop(doc_id, ()):
            ids = self.entries.get(v)
            if ids is not None:
                ids.pop(doc_id, None)
                if not ids:
                    del self.entries[v]


class ActiveMemory:
    """One named memory of XML documents (see the module docstring).

    ``store`` (optional) persists every change before it is applied; the
    memory's documents are loaded from it at construction. ``indexes`` maps
    index names to key XPaths.
    """

    def __init__(self, name: str, *, store: SqliteStore | None = None, indexes: Mapping[str, str] | None = None) -> None:
        if not name or not isinstance(name, str):
            raise MemoryQueryError(f"a memory needs a non-empty name, not {name!r}", source="<memory>")
        self.name = name
        self.store = store
        self._docs: dict[int, tuple[etree._Element, dict[str, Attachment]]] = {}
        self._indexes: dict[str, _Index] = {}
        self._subs: dict[int, _Subscription] = {}
        self._next_sub = 1
        self._next_id = 1
        if store is not None:
            docs, next_id = store.load(name)
            self._docs = docs
            self._next_id = next_id
        for iname, expr in (indexes or {}).items():
            self.add_index(iname, expr)

    def check_loaded(self, check: Callable[[etree._Element], None]) -> None:
        """Check every document loaded from the store with ``check`` (raising :class:`~homesim.errors.InputError`).

        A stored document is input like any other (the file may have been
        edited or written by another program): the first that fails stops the
        run before anything uses it, with :class:`MemoryStoreError` naming the
        store file, the memory, the document and what is wrong; nothing is
        changed (the store is left as it is).
        """
        for doc_id in sorted(self._docs):
            try:
                check(self._docs[doc_id][0])
            except InputError as exc:
                where = self.store.path if self.store is not None else "<memory>"
                raise MemoryStoreError(f"memory {self.name!r} document {doc_id} is not a valid stored document: {exc.message} "
                                       "(the store was left as it is; correct or remove the document, or use another store)",
                                       source=str(where)) from None

    # ------------------------------------------------------------ reading
    def __len__(self) -> int:
        return len(self._docs)

    def __contains__(self, doc_id: object) -> bool:
        return doc_id in self._docs

    def ids(self) -> list[int]:
        """Every document id, ascending."""
        return sorted(self._docs)

    def get(self, doc_id: int) -> Record:
        """A copy of document ``doc_id``; :class:`MemoryQueryError` if there is none."""
        entry = self._docs.get(doc_id)
        if entry is None:
            raise MemoryQueryError(f"memory {self.name!r} has no document {doc_id!r}", source="<memory>")
        return Record(doc_id, entry[0].__copy__(), dict(entry[1]))

    def query(self, xpath: str | None = None, *, where: Mapping[str, str] | None = None, limit: int | None = None) -> list[Record]:
        """Copies of the documents that match, in id order.

        ``where`` (index name -> value) narrows the candidates through the
        indexes first; ``xpath`` then filters them (or every document). With
        neither, every document is returned.
        """
        return [Record(i, d.__copy__(), dict(a)) for i, d, a in self._select(xpath, where, limit)]

    def query_ids(self, xpath: str | None = None, *, where: Mapping[str, str] | None = None, limit: int | None = None) -> list[int]:
        """The ids :meth:`query` would return (no copies: the cheapest look-up)."""
        return [i for i, _, _ in self._select(xpath, where, limit)]

    def _candidates(self, where: Mapping[str, str] | None) -> Iterable[int]:
        if not where:
            return sorted(self._docs)
        sets = []
        for iname, value in where.items():
            index = self._indexes.get(iname)
            if index is None:
                raise MemoryQueryError(f"memory {self.name!r} has no index {iname!r} (it has {sorted(self._indexes)})", source="<memory>")
            ids = index.entries.get(value)
            if not ids:
                return ()
            sets.append(ids)
        if len(sets) == 1:
            return sorted(sets[0])
        sets.sort(key=len)
        common = sets[0].keys() & sets[1].keys()  # set operations on dict views run in C
        for s in sets[2:]:
            common &= s.keys()
        return sorted(common)

    def _select(self, xpath: str | None, where: Mapping[str, str] | None, limit: int | None) -> list[tuple[int, etree._Element, dict[str, Attachment]]]:
        xp = compile_xpath(xpath) if xpath is not None else None
        out = []
        docs = self._docs
        for i in self._candidates(where):
            doc, att = docs[i]
            if xp is None or xpath_true(_evaluate(xp, doc)):
                out.append((i, doc, att))
                if limit is not None and len(out) >= limit:
                    break
        return out

    def index_names(self) -> list[str]:
        return sorted(self._indexes)

    # ------------------------------------------------------------ changing
    def insert(self, doc: DocLike, attachments: Mapping[str, Attachment] | None = None) -> int:
        """Store a new document; return its id."""
        own = own_document(doc, source=f"<memory {self.name}>")
        att = own_attachments(attachments, source=f"<memory {self.name}>")
        keys = self._keys(own)
        doc_id = self._next_id
        if self.store is not None:  # the store allocates the id in its write transaction (another process may share it)
            doc_id = self.store.insert(self.name, own, att, at_least=doc_id)
        self._next_id = doc_id + 1
        self._docs[doc_id] = (own, att)
        self._index(doc_id, keys)
        self._notify(INSERT, doc_id, own, att, None)
        return doc_id

    def update(self, doc_id: int, doc: DocLike, attachments: Mapping[str, Attachment] | None = None) -> None:
        """Replace document ``doc_id`` (and, when given, its attachments; otherwise they are kept)."""
        old = self._docs.get(doc_id)
        if old is None:
            raise MemoryQueryError(f"memory {self.name!r} has no document {doc_id!r} to update", source="<memory>")
        own = own_document(doc, source=f"<memory {self.name}>")
        att = own_attachments(attachments, source=f"<memory {self.name}>") if attachments is not None else old[1]
        keys = self._keys(own)
        if self.store is not None:
            self.store.put(self.name, doc_id, own, att, next_id=self._next_id)
        self._unindex(doc_id)
        self._docs[doc_id] = (own, att)
        self._index(doc_id, keys)
        self._notify(UPDATE, doc_id, own, att, old[0])

    def remove(self, doc_id: int) -> Record:
        """Remove document ``doc_id``; return what it was."""
        old = self._docs.get(doc_id)
        if old is None:
            raise MemoryQueryError(f"memory {self.name!r} has no document {doc_id!r} to remove", source="<memory>")
        if self.store is not None:
            self.store.delete(self.name, doc_id)
        self._unindex(doc_id)
        del self._docs[doc_id]
        self._notify(REMOVE, doc_id, old[0], old[1], None)
        return Record(doc_id, old[0], dict(old[1]))

    # ------------------------------------------------------------ indexes
    def add_index(self, name: str, expr: str) -> None:
        """Index every document (present and future) by the strings ``expr`` gives."""
        if name in self._indexes:
            raise MemoryQueryError(f"memory {self.name!r} already has an index {name!r}", source="<memory>")
        index = _Index(name, compile_xpath(expr))
        for doc_id in sorted(self._docs):
            index.add(doc_id, index.values_of(self._docs[doc_id][0]))
        self._indexes[name] = index

    def _keys(self, doc: etree._Element) -> list[tuple[str, ...]]:
        # Computed before anything changes, so a failing index XPath changes nothing.
        return [ix.values_of(doc) for ix in self._indexes.values()]

    def _index(self, doc_id: int, keys: list[tuple[str, ...]]) -> None:
        for ix, values in zip(self._indexes.values(), keys):
            ix.add(doc_id, values)

    def _unindex(self, doc_id: int) -> None:
        for ix in self._indexes.values():
            ix.discard(doc_id)

    # ------------------------------------------------------- subscriptions
    def subscribe(self, xpath: str, callback: Callback, *, actions: Iterable[str] = ACTIONS) -> int:
        """Call ``callback`` after every change concerning documents that match ``xpath``; return the id."""
        acts = frozenset(actions)
        bad = sorted(acts - set(ACTIONS))
        if bad or not acts:
            raise MemoryQueryError(f"subscription actions must be among {list(ACTIONS)} (at least one), got {sorted(acts)}", source="<memory>")
        sub = _Subscription(self._next_sub, compile_xpath(xpath), acts, callback)
        self._next_sub += 1
        self._subs[sub.id] = sub
        return sub.id

    def unsubscribe(self, sub_id: int) -> None:
        """Stop a subscription; :class:`MemoryQueryError` if there is none with this id."""
        if self._subs.pop(sub_id, None) is None:
            raise MemoryQueryError(f"memory {self.name!r} has no subscription {sub_id!r}", source="<memory>")

    def _notify(self, action: str, doc_id: int, doc: etree._Element, att: dict[str, Attachment], old: etree._Element | None) -> None:
        for sub in list(self._subs.values()):
            if action not in sub.actions or sub.id not in self._subs:
                continue
            matches = xpath_true(_evaluate(sub.xpath, doc))
            if matches or (old is not None and xpath_true(_evaluate(sub.xpath, old))):
                sub.callback(MemoryEvent(self.name, sub.id, action, doc_id, doc.__copy__(), dict(att), matches))
