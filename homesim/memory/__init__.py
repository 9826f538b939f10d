"""The active memory (docs/semantics.md §5): XML documents with insert, update, remove,
XPath query, indexes and subscriptions, in memory or persisted on SQLite.

* :mod:`homesim.memory.core` — :class:`ActiveMemory` (the documents, indexes, subscriptions);
* :mod:`homesim.memory.sqlite` — :class:`SqliteStore` (atomic commits, versioned schema,
  refusal of corrupt and newer stores);
* :mod:`homesim.memory.protocol` — requests, replies and notifications as XML on the bus.

The kernel's memory knows nothing of BIRON: what the documents mean is the
business of the knowledge bases that use it (the robot's).
"""

from .core import ACTIONS, INSERT, REMOVE, UPDATE, ActiveMemory, MemoryEvent, Record, compile_xpath
from .sqlite import SCHEMA_VERSION, SqliteStore

__all__ = [
    "ACTIONS", "INSERT", "REMOVE", "UPDATE", "ActiveMemory", "MemoryEvent", "Record", "compile_xpath",
    "SCHEMA_VERSION", "SqliteStore",
]
