"""``homesim memory show STORE``: what a memory store holds (read-only).

``STORE`` is the directory given to ``homesim run --memory DIR`` (every
``*.sqlite`` store in it is shown) or one store file.

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

from ..errors import HomesimError, OptionError
from .core import ActiveMemory
from .protocol import attachment_element
from .sqlite import SqliteStore


def store_files(path: Path) -> list[Path]:
    """The SQLite stores ``path`` names: the file itself, or every ``*.sqlite`` in the directory given to ``--memory``."""
    if not path.is_dir():
        return [path]
    files = sorted(p for p in path.glob("*.sqlite") if p.is_file())
    if not files:
        raise HomesimError(f"{path}: no store in this directory (no *.sqlite file; 'homesim run SCENARIO --memory {path}' "
                           "writes one)")
    return files


def show(a: argparse.Namespace) -> int:
    """Print every store ``a.store`` names (a store file or a ``--memory`` directory)."""
    for i, path in enumerate(store_files(a.store)):
        if i:
            print()
        _show_store(path, a.memory, a.xpath)
    sys.stdout.flush()
    return 0


def _show_store(path: Path, only: str | None, xpath: str | None) -> None:
    with SqliteStore(path, readonly=True) as store:
        if only is not None and only not in store.memories():
            raise OptionError("--memory", f"no memory {only!r} in {path} (it holds: {', '.join(store.memories()) or 'none'})")
        names = [only] if only else store.memories()
        print(f"{path}: schema version {store.version}, memories: {', '.join(store.memories()) or '(none)'}")
        for name in names:
            memory = ActiveMemory(name, store=store)
            recs = memory.query(xpath)
            print(f"\n[{name}] {len(recs)} of {len(memory)} document(s)")
            for rec in recs:
                print(f"  #{rec.id} {etree.tostring(rec.xml, encoding='unicode')}")
                for att in sorted(rec.attachments):
                    el = attachment_element(att, rec.attachments[att], inline=False)
                    print(f"      attachment {att}: dtype {el.get('dtype')} shape {el.get('shape')} sha256 {el.get('sha256')[:16]}")


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Add ``homesim memory show``."""
    p = sub.add_parser("memory", help="inspect an active-memory store (read-only)",
                       examples=["homesim memory show out/memory"])
    msub = p.add_subparsers(dest="memory_command", metavar="ACTION")
    s = msub.add_parser("show", help="print the documents of a store",
                        examples=["homesim memory show out/memory", "homesim memory show out/memory --memory objects",
                                  "homesim memory show out/memory/scene_model.sqlite --xpath '//object[@name=\"cup\"]'"])
    s.add_argument("store", type=Path,
                   help="the directory given to 'homesim run --memory', e.g. out/memory, or its SQLite file (DIR/scene_model.sqlite)")
    s.add_argument("--memory", default=None, metavar="NAME", help="only this memory, e.g. objects (default: all)")
    s.add_argument("--xpath", default=None, help="only documents matching this XPath (default: all)")
    s.set_defaults(func=show)
