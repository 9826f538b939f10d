"""``homesim memory show STORE``: what a memory store holds (read-only).

Prints, per memory, every document (id, XML, attachments as dtype/shape/sha256),
optionally only those matching ``--xpath`` or one memory (``--memory``). The
store is opened read-only: nothing is migrated, moved or written, and a store
that cannot be read is reported (exit status 2) and left as it is.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from lxml import etree

from ..errors import OptionError
from .core import ActiveMemory
from .protocol import attachment_element
from .sqlite import SqliteStore


def show(a: argparse.Namespace) -> int:
    with SqliteStore(a.store, readonly=True) as store:
        if a.memory is not None and a.memory not in store.memories():
            raise OptionError("--memory", f"no memory {a.memory!r} in {a.store} (it holds: {', '.join(store.memories()) or 'none'})")
        names = [a.memory] if a.memory else store.memories()
        print(f"{a.store}: schema version {store.version}, memories: {', '.join(store.memories()) or '(none)'}")
        for name in names:
            memory = ActiveMemory(name, store=store)
            recs = memory.query(a.xpath)
            print(f"\n[{name}] {len(recs)} of {len(memory)} document(s)")
            for rec in recs:
                print(f"  #{rec.id} {etree.tostring(rec.xml, encoding='unicode')}")
                for att in sorted(rec.attachments):
                    el = attachment_element(att, rec.attachments[att], inline=False)
                    print(f"      attachment {att}: dtype {el.get('dtype')} shape {el.get('shape')} sha256 {el.get('sha256')[:16]}")
    sys.stdout.flush()
    return 0


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Add ``homesim memory show``."""
    p = sub.add_parser("memory", help="inspect an active-memory store (read-only)")
    msub = p.add_subparsers(dest="memory_command", metavar="ACTION")
    s = msub.add_parser("show", help="print the documents of a store")
    s.add_argument("store", type=Path, help="the SQLite store, e.g. DIR/scene_model.sqlite")
    s.add_argument("--memory", default=None, help="only this memory (e.g. objects)")
    s.add_argument("--xpath", default=None, help="only documents matching this XPath")
    s.set_defaults(func=show)
