"""Persistence of active memories on SQLite (the standard library's sqlite3).

One store file holds any number of named memories. Every change is its own
transaction (``BEGIN IMMEDIATE`` ... ``COMMIT``, rollback journal,
``synchronous=FULL``): a document and its attachments are written together
or not at all, and what was committed survives a killed process (SQLite
rolls a hot journal back at the next open). A new document's id is allocated
inside its write transaction from the counter on disk, so two processes
writing to one store (two runs on one ``--memory`` directory) never replace
each other's documents.

The schema is versioned (``PRAGMA user_version``; ``application_id`` marks
the file as a homesim memory store). An older store is migrated step by step
(:data:`MIGRATIONS`) inside one transaction, so a failed migration leaves the
file as it was. Opening refuses, with :class:`MemoryStoreError`:

* a corrupt file (not SQLite, failing ``quick_check``, a foreign
  application id, or a document that does not parse with the hardened
  parser): the file is **moved aside** to ``<name>.corrupt-<n>`` (the first
  free ``n``; never overwriting anything), so the next run starts a fresh
  store and the broken one stays for inspection;
* a store written by a newer homesim (``user_version`` above
  :data:`SCHEMA_VERSION`): the file is **left where it is, untouched** (it
  belongs to that newer homesim, which must still find it); the run stops.

Everything is read and checked at open, before any memory sees it, so a
refused store leaves nothing half-loaded.
"""

from __future__ import annotations

import json
import os
import sqlite3
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import TypeVar

import numpy as np
from lxml import etree

from ..errors import MemoryStoreError, XMLInputError
from ..xmlio import parse_bytes, serialize

#: The schema this code writes. Bump it with a new entry in MIGRATIONS.
SCHEMA_VERSION = 2
#: ``PRAGMA application_id`` of homesim memory stores ("hmem").
APPLICATION_ID = 0x686D656D

Attachment = bytes | np.ndarray

_V1 = (
    "CREATE TABLE meta (key TEXT PRIMARY KEY, value TEXT NOT NULL)",
    "CREATE TABLE documents (memory TEXT NOT NULL, id INTEGER NOT NULL, xml BLOB NOT NULL, PRIMARY KEY (memory, id))",
)


def _migrate_1_to_2(db: sqlite3.Connection) -> None:
    """Version 2 adds attachments and a per-memory id counter (ids are never reused)."""
    db.execute("CREATE TABLE memories (name TEXT PRIMARY KEY, next_id INTEGER NOT NULL)")
    db.execute("INSERT INTO memories (name, next_id) SELECT memory, MAX(id) + 1 FROM documents GROUP BY memory")
    db.execute(
        "CREATE TABLE attachments (memory TEXT NOT NULL, doc_id INTEGER NOT NULL, name TEXT NOT NULL, "
        "dtype TEXT NOT NULL, shape TEXT NOT NULL, data BLOB NOT NULL, PRIMARY KEY (memory, doc_id, name))"
    )


#: from_version -> step to from_version + 1
MIGRATIONS: dict[int, Callable[[sqlite3.Connection], None]] = {1: _migrate_1_to_2}


def create_v1(path: str | os.PathLike[str], documents: Mapping[str, Mapping[int, bytes]]) -> None:
    """Write a version-1 store (tests of the migration path; the old layout as it was)."""
    db = sqlite3.connect(os.fspath(path), isolation_level=None)
    try:
        db.execute("BEGIN")
        for stmt in _V1:
            db.execute(stmt)
        db.execute(f"PRAGMA application_id = {APPLICATION_ID}")
        for memory, docs in documents.items():
            db.executemany("INSERT INTO documents VALUES (?, ?, ?)", [(memory, i, x) for i, x in docs.items()])
        db.execute("PRAGMA user_version = 1")
        db.execute("COMMIT")
    finally:
        db.close()


def _free_aside(path: Path, tag: str) -> Path:
    n = 1
    while True:
        cand = path.with_name(f"{path.name}.{tag}-{n}")
        if not cand.exists() and not cand.is_symlink():
            return cand
        n += 1


def _move_aside(path: Path, tag: str) -> Path:
    """Move ``path`` (and its rollback journal) to a free ``<name>.<tag>-<n>``; never overwrites."""
    while True:
        dest = _free_aside(path, tag)
        try:
            os.link(path, dest)  # fails if dest exists: no overwrite even in a race
        except FileExistsError:
            continue
        os.unlink(path)
        journal = path.with_name(path.name + "-journal")
        if journal.exists():
            jdest = dest.with_name(dest.name + "-journal")
            if not jdest.exists():
                os.link(journal, jdest)
                os.unlink(journal)
        return dest


def encode_attachment(value: Attachment) -> tuple[str, str, bytes]:
    """(dtype, shape, data) for a row: numpy arrays as dtype string, shape JSON, C-order bytes."""
    if isinstance(value, np.ndarray):
        # tobytes() is C order whatever the layout (ascontiguousarray would turn a 0-d array into 1-d)
        return value.dtype.str, json.dumps(list(value.shape)), value.tobytes(order="C")
    return "bytes", "[]", bytes(value)


def decode_attachment(dtype: str, shape: str, data: bytes) -> Attachment:
    """Inverse of :func:`encode_attachment` (arrays come back read-only)."""
    if dtype == "bytes":
        return bytes(data)
    arr = np.frombuffer(data, dtype=np.dtype(dtype)).reshape(tuple(json.loads(shape))).copy()
    arr.flags.writeable = False
    return arr


_T = TypeVar("_T")
#: Raise a memory's id counter to at least the given value (never lower it: another process may have raised it).
_BUMP = ("INSERT INTO memories (name, next_id) VALUES (?, ?) "
         "ON CONFLICT (name) DO UPDATE SET next_id = MAX(next_id, excluded.next_id)")

LoadedDocs = dict[int, tuple[etree._Element, dict[str, Attachment]]]


class SqliteStore:
    """A memory store file; see the module docstring for what it guarantees and refuses.

    ``SqliteStore(path)`` opens (creating the file and its directory if
    needed), migrates an older schema, and reads every memory in it.
    :meth:`load` hands a memory its documents; :meth:`put` and
    :meth:`delete` commit one change each.
    """

    def __init__(self, path: str | os.PathLike[str], *, readonly: bool = False) -> None:
        self.path = Path(path)
        self.readonly = readonly
        self.migrated_from: int | None = None
        self._db: sqlite3.Connection | None = None
        self._loaded: dict[str, tuple[LoadedDocs, int]] = {}
        self._claimed: set[str] = set()
        if readonly:
            self._open_readonly()
            return
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise MemoryStoreError(f"cannot create the store's directory: {exc.strerror}", source=str(self.path)) from exc
        self._check_writable()
        self._open()

    def _check_writable(self) -> None:
        """Refuse, before anything is read, a store this process could not write to (not at its first write, mid-run)."""
        if self.path.exists():
            try:
                os.close(os.open(self.path, os.O_RDWR | getattr(os, "O_CLOEXEC", 0)))
            except OSError as exc:
                raise MemoryStoreError(
                    f"the store file cannot be written ({exc.strerror}); a run writes what it learns to its store: "
                    "make the file writable or use another directory (the file was left as it is)",
                    source=str(self.path), kept_at=str(self.path)) from None
        if not os.access(self.path.parent, os.W_OK | os.X_OK):
            raise MemoryStoreError("the store's directory is not writable (SQLite writes its journal beside the store); "
                                   "nothing was changed", source=str(self.path), kept_at=str(self.path))

    def _open_readonly(self) -> None:
        """Inspection (``homesim memory``): read, never write, move or migrate; refusals leave the file as it is."""
        def refuse(why: str) -> MemoryStoreError:
            if self._db is not None:
                self._db.close()
                self._db = None
            return MemoryStoreError(f"cannot read the memory store: {why} (left as it is)", source=str(self.path), kept_at=str(self.path))

        if not self.path.is_file():
            raise refuse("no such file")
        try:
            self._db = sqlite3.connect(f"file:{self.path.resolve()}?mode=ro", uri=True, isolation_level=None)
            db = self._db
            if db.execute("PRAGMA quick_check").fetchall() != [("ok",)]:
                raise refuse("it fails SQLite's integrity check")
            app = db.execute("PRAGMA application_id").fetchone()[0]
            version = db.execute("PRAGMA user_version").fetchone()[0]
        except sqlite3.DatabaseError as exc:
            raise refuse(f"not a readable SQLite database ({exc})") from exc
        if app != APPLICATION_ID:
            raise refuse(f"not a homesim memory store (application id {app:#x})")
        if version != SCHEMA_VERSION:
            raise refuse(f"schema version {version}; this homesim reads {SCHEMA_VERSION} (a run migrates older stores)")
        try:
            self._read_all(refuse=refuse)
        except sqlite3.DatabaseError as exc:
            raise refuse(f"cannot read its rows ({exc})") from exc

    # ------------------------------------------------------------ opening
    def _refuse_corrupt(self, why: str, exc: BaseException | None = None) -> MemoryStoreError:
        if self._db is not None:
            self._db.close()
            self._db = None
        kept = _move_aside(self.path, "corrupt")
        err = MemoryStoreError(
            f"corrupt memory store ({why}); it was moved aside to {kept} and nothing was loaded from it",
            source=str(self.path), kept_at=str(kept),
        )
        if exc is not None:
            err.__cause__ = exc
        return err

    def _open(self) -> None:
        fresh = not self.path.exists() or self.path.stat().st_size == 0
        try:
            self._db = sqlite3.connect(os.fspath(self.path), isolation_level=None)
        except sqlite3.Error as exc:
            raise MemoryStoreError(f"cannot open the memory store: {exc}", source=str(self.path)) from exc
        db = self._db
        try:
            if not fresh:
                check = db.execute("PRAGMA quick_check").fetchall()
                if check != [("ok",)]:
                    raise self._refuse_corrupt(f"SQLite integrity check: {'; '.join(str(r[0]) for r in check[:3])}")
            app = db.execute("PRAGMA application_id").fetchone()[0]
            version = db.execute("PRAGMA user_version").fetchone()[0]
            tables = {r[0] for r in db.execute("SELECT name FROM sqlite_master WHERE type = 'table'")}
        except sqlite3.DatabaseError as exc:
            raise self._refuse_corrupt(f"not a readable SQLite database: {exc}", exc) from exc
        if app == 0 and version == 0 and not tables:
            self._create()
        elif app != APPLICATION_ID:
            raise self._refuse_corrupt(f"not a homesim memory store (application id {app:#x})")
        elif version > SCHEMA_VERSION:
            db.close()
            self._db = None
            raise MemoryStoreError(
                f"memory store written by a newer homesim (schema version {version}; this one reads up to "
                f"{SCHEMA_VERSION}); the file was left untouched where it is, use a newer homesim or another store",
                source=str(self.path), kept_at=str(self.path),
            )
        elif version < SCHEMA_VERSION:
            self._migrate(version)
        try:
            self._read_all()
        except sqlite3.DatabaseError as exc:
            raise self._refuse_corrupt(f"cannot read its rows: {exc}", exc) from exc

    def _pragmas(self) -> None:
        assert self._db is not None
        self._db.execute("PRAGMA journal_mode = DELETE")
        self._db.execute("PRAGMA synchronous = FULL")

    def _create(self) -> None:
        db = self._db
        assert db is not None
        self._pragmas()
        db.execute("BEGIN IMMEDIATE")
        try:
            for stmt in _V1:
                db.execute(stmt)
            _migrate_1_to_2(db)
            db.execute(f"PRAGMA application_id = {APPLICATION_ID}")
            db.execute(f"PRAGMA user_version = {SCHEMA_VERSION}")
            db.execute("COMMIT")
        except BaseException:
            db.execute("ROLLBACK")
            raise

    def _migrate(self, version: int) -> None:
        db = self._db
        assert db is not None
        self._pragmas()
        if version < 1 or any(v not in MIGRATIONS for v in range(version, SCHEMA_VERSION)):
            raise self._refuse_corrupt(f"schema version {version} has no migration path")
        db.execute("BEGIN IMMEDIATE")
        try:
            for v in range(version, SCHEMA_VERSION):
                MIGRATIONS[v](db)
            db.execute(f"PRAGMA user_version = {SCHEMA_VERSION}")
            db.execute("COMMIT")
        except sqlite3.DatabaseError as exc:
            db.execute("ROLLBACK")
            raise self._refuse_corrupt(f"migration from version {version} failed: {exc}", exc) from exc
        self.migrated_from = version

    def _read_all(self, refuse: Callable[[str], MemoryStoreError] | None = None) -> None:
        db = self._db
        assert db is not None
        if refuse is None:
            self._pragmas()
            refuse = self._refuse_corrupt
        loaded: dict[str, tuple[LoadedDocs, int]] = {}
        for name, next_id in db.execute("SELECT name, next_id FROM memories ORDER BY name"):
            loaded[name] = ({}, int(next_id))
        for memory, doc_id, xml in db.execute("SELECT memory, id, xml FROM documents ORDER BY memory, id"):
            source = f"{self.path}: memory {memory!r} document {doc_id}"
            try:
                root = parse_bytes(bytes(xml), source=source)
            except XMLInputError as exc:
                raise refuse(f"memory {memory!r} document {doc_id} does not parse: {exc.message}") from exc
            docs, next_id = loaded.setdefault(memory, ({}, 1))
            if doc_id >= next_id:
                raise refuse(f"memory {memory!r} document {doc_id} is beyond its id counter {next_id}")
            docs[int(doc_id)] = (root, {})
        for memory, doc_id, name, dtype, shape, data in db.execute(
            "SELECT memory, doc_id, name, dtype, shape, data FROM attachments ORDER BY memory, doc_id, name"
        ):
            entry = loaded.get(memory, ({}, 1))[0].get(doc_id)
            if entry is None:
                raise refuse(f"attachment {name!r} of memory {memory!r} belongs to no document ({doc_id})")
            try:
                entry[1][name] = decode_attachment(dtype, shape, data)
            except (ValueError, TypeError) as exc:
                raise refuse(f"attachment {name!r} of document {doc_id} does not decode: {exc}") from exc
        self._loaded = loaded

    # ------------------------------------------------------------ reading
    @property
    def version(self) -> int:
        return SCHEMA_VERSION

    def memories(self) -> list[str]:
        """Names of the memories the store held when opened (or has written since)."""
        return sorted(self._loaded)

    def load(self, memory: str) -> tuple[LoadedDocs, int]:
        """The documents of ``memory`` as read at open, and its next id (1 for a new memory)."""
        if memory in self._claimed:
            raise MemoryStoreError(f"memory {memory!r} of this store is already open (one ActiveMemory per name)", source=str(self.path))
        self._claimed.add(memory)
        docs, next_id = self._loaded.get(memory, ({}, 1))
        self._loaded[memory] = ({}, next_id)  # handed over once; the memory owns them now
        return docs, next_id

    # ------------------------------------------------------------ writing
    def _writable(self) -> sqlite3.Connection:
        if self._db is None:
            raise MemoryStoreError("the memory store is closed", source=str(self.path))
        if self.readonly:
            raise MemoryStoreError("the memory store was opened read-only", source=str(self.path))
        return self._db

    def _transaction(self, write: Callable[[], _T]) -> _T:
        """``write()`` inside ``BEGIN IMMEDIATE`` ... ``COMMIT`` (the store's write lock; rolled back on failure)."""
        db = self._writable()
        try:
            db.execute("BEGIN IMMEDIATE")
            try:
                result = write()
                db.execute("COMMIT")
            except BaseException:
                db.execute("ROLLBACK")
                raise
        except sqlite3.Error as exc:
            raise MemoryStoreError(f"cannot write to the memory store (nothing was changed): {exc}", source=str(self.path)) from exc
        return result

    def _tx(self, stmts: list[tuple[str, tuple]]) -> None:
        db = self._writable()

        def write() -> None:
            for sql, args in stmts:
                db.execute(sql, args)

        self._transaction(write)

    def insert(self, memory: str, doc: etree._Element, attachments: Mapping[str, Attachment], *, at_least: int = 1) -> int:
        """Write a new document with these attachments, in one transaction; return its id.

        The id is allocated inside the write transaction, from the counter as
        it is on disk (never below ``at_least``, the memory's own counter): two
        processes writing to one store never get the same id, so neither
        replaces what the other confirmed.
        """
        db = self._writable()
        xml = serialize(doc)
        rows = [(name, *encode_attachment(attachments[name])) for name in sorted(attachments)]

        def write() -> int:
            row = db.execute("SELECT next_id FROM memories WHERE name = ?", (memory,)).fetchone()
            top = db.execute("SELECT MAX(id) FROM documents WHERE memory = ?", (memory,)).fetchone()[0]
            doc_id = max(at_least, 1 if row is None else int(row[0]), 1 if top is None else int(top) + 1)
            db.execute("INSERT INTO documents (memory, id, xml) VALUES (?, ?, ?)", (memory, doc_id, xml))
            db.executemany("INSERT INTO attachments VALUES (?, ?, ?, ?, ?, ?)", [(memory, doc_id, *r) for r in rows])
            db.execute(_BUMP, (memory, doc_id + 1))
            return doc_id

        return self._transaction(write)

    def put(self, memory: str, doc_id: int, doc: etree._Element, attachments: Mapping[str, Attachment], *, next_id: int) -> None:
        """Write (insert or replace) document ``doc_id`` with exactly these attachments, in one transaction.

        The id counter on disk only grows (to ``next_id`` at least). A new document takes
        :meth:`insert`, which allocates its id in the transaction.
        """
        stmts: list[tuple[str, tuple]] = [
            ("INSERT OR REPLACE INTO documents (memory, id, xml) VALUES (?, ?, ?)", (memory, doc_id, serialize(doc))),
            ("DELETE FROM attachments WHERE memory = ? AND doc_id = ?", (memory, doc_id)),
        ]
        for name in sorted(attachments):
            dtype, shape, data = encode_attachment(attachments[name])
            stmts.append(("INSERT INTO attachments VALUES (?, ?, ?, ?, ?, ?)", (memory, doc_id, name, dtype, shape, data)))
        stmts.append((_BUMP, (memory, next_id)))
        self._tx(stmts)

    def delete(self, memory: str, doc_id: int) -> None:
        """Remove one document and its attachments, in one transaction."""
        self._tx([
            ("DELETE FROM attachments WHERE memory = ? AND doc_id = ?", (memory, doc_id)),
            ("DELETE FROM documents WHERE memory = ? AND id = ?", (memory, doc_id)),
        ])

    def close(self) -> None:
        """Close the file (every change is already committed)."""
        if self._db is not None:
            self._db.close()
            self._db = None

    def __enter__(self) -> SqliteStore:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
