"""``homesim check FILE...``: validate any of the project's documents, chosen by its root element.

The kinds of documents (scenario, AFSM, and those other packages add, such
as the dialog's, by an entry point) are registered in :mod:`homesim.documents`.

``homesim check`` prints every problem as ``file:line: <element>: message``,
one ``file: ok (kind)`` line per good file, and exits 1 when any file has a
problem (2 for a bad command line), 0 otherwise.

How it fails: a file that does not parse is reported like any other problem
(the hardened parser's message with its line); a root element nobody
registered is a problem naming the kinds that are known.
"""

from __future__ import annotations

import sys
from collections.abc import Iterable
from pathlib import Path
from typing import Any

from lxml import etree

from .documents import DocumentType, document_types, example, register_document  # noqa: F401 (re-exported)
from .cliargs import count
from .errors import InputError
from .xmlio import parse_file

def _label(qname: str) -> str:
    q = etree.QName(qname)
    return f"<{q.localname}>" if q.namespace is None else f"<{q.localname} xmlns=\"{q.namespace}\">"


def check_path(path: str, types: dict[str, DocumentType] | None = None) -> tuple[str | None, list[InputError]]:
    """The kind of the document at ``path`` (None if unknown or unreadable) and every problem found."""
    types = document_types() if types is None else types
    try:
        root = parse_file(path)
    except InputError as exc:  # malformed, unreadable, not a regular file ...: a problem like any other
        return None, [exc]
    doc_type = types.get(root.tag) if isinstance(root.tag, str) else None
    if doc_type is None:
        known = ", ".join(f"{_label(r)} ({d.kind})" for r, d in types.items())
        return None, [InputError(f"root element {_label(str(root.tag))} is not a document homesim knows; known: {known}",
                                 source=path, line=root.sourceline)]
    return doc_type.kind, doc_type.check(path)


def check_paths(paths: Iterable[str], out: Any = None, err: Any = None) -> int:
    """Check every file; print problems and ok lines; 1 if any file has a problem, else 0."""
    out = sys.stdout if out is None else out
    err = sys.stderr if err is None else err
    types = document_types()
    bad = 0
    total = 0
    schema_only = False  # a file with schema problems: its names and geometry are not checked yet
    for path in paths:
        kind, problems = check_path(path, types)
        problems = sorted(problems, key=lambda p: p.line or 0)  # in line order, whichever check found them
        for p in problems:
            print(p, file=out)
        if problems:
            bad += 1
            total += len(problems)
            schema_only |= any(p.message.endswith(".xsd)") for p in problems)
        else:
            print(f"{path}: ok ({kind})", file=out)
    if bad:
        later = ("; a file with schema problems is checked for names, references and geometry once they are fixed"
                 if schema_only else "")
        print(f"homesim check: {count(total, 'problem')} in {count(bad, 'file')}{later}", file=err)
        return 1
    return 0


def register(sub: Any) -> None:
    """Add ``homesim check FILE...``."""
    p = sub.add_parser("check", help="validate scenario, AFSM (and other registered) documents: every problem, file:line",
                       examples=["homesim check scenarios/*.xml",
                                 f"homesim check {example('AFSM', 'MY_MACHINE.scxml')} scenarios/home_tour.xml"])
    p.add_argument("files", nargs="+", metavar="FILE", type=Path,
                   help="documents to check, e.g. scenarios/home_tour.xml (the kind is read from the root element)")
    p.set_defaults(func=lambda a: check_paths([str(f) for f in a.files]))

