"""Kinds of documents the project checks, chosen by their root element: a registry.

Each kind of document (scenario, AFSM, and those other packages add, such as
the dialog's) registers a :class:`DocumentType`: the root element's QName in
Clark notation (``scenario``, ``{http://www.w3.org/2005/07/scxml}scxml``), a
short name for messages and a function ``check(path) -> [InputError]`` that
returns every problem it finds (empty when the document loads). A package
outside the kernel registers its type without the kernel importing it, by an
entry point in ``pyproject.toml``::

    [project.entry-points."homesim.documents"]
    mykind = "mypackage.document:DOCUMENT_TYPE"

or at run time with :func:`register_document`. ``homesim check``
(:mod:`homesim.check`) uses :func:`document_types`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from importlib.metadata import entry_points

from .errors import InputError

ENTRY_POINT_GROUP = "homesim.documents"


@dataclass(frozen=True)
class DocumentType:
    """One kind of document: its root element (Clark QName), a name, and its checker."""

    root: str
    kind: str
    check: Callable[[str], list[InputError]]


def _afsm(path: str) -> list[InputError]:
    from .afsm.loader import check_file

    return list(check_file(path))


def _scenario(path: str) -> list[InputError]:
    from .scenario.loader import check_scenario_file

    return check_scenario_file(path)


def _deployment(path: str) -> list[InputError]:
    from .deployment import check_file

    return check_file(path)


#: The kernel's own document types (others come from entry points or :func:`register_document`).
BUILTIN: tuple[DocumentType, ...] = (
    DocumentType("scenario", "scenario", _scenario),
    DocumentType("{http://www.w3.org/2005/07/scxml}scxml", "AFSM", _afsm),
    DocumentType("deployment", "deployment", _deployment),
)

_registered: dict[str, DocumentType] = {}

#: Kind -> a file of that kind a user can try, for ``--help`` examples; the package that ships one registers it
#: (the kernel ships no AFSM of its own: the run package names the robot's).
_examples: dict[str, str] = {}


def register_example(kind: str, path: str) -> None:
    """Name ``path`` (relative to the repository) as the example document of ``kind`` in ``--help``."""
    _examples[kind] = path


def example(kind: str, fallback: str) -> str:
    """The registered example document of ``kind``, else ``fallback`` (a placeholder the user replaces)."""
    return _examples.get(kind, fallback)


def register_document(doc_type: DocumentType) -> None:
    """Add (or replace) the checker for ``doc_type.root``."""
    _registered[doc_type.root] = doc_type


def document_types() -> dict[str, DocumentType]:
    """Root QName -> document type: built-in, then entry points, then :func:`register_document`'s."""
    out = {d.root: d for d in BUILTIN}
    for ep in sorted(entry_points(group=ENTRY_POINT_GROUP), key=lambda e: e.name):
        d = ep.load()
        if not isinstance(d, DocumentType):
            raise TypeError(f"entry point {ep.name} = {ep.value} in {ENTRY_POINT_GROUP} is not a DocumentType")
        out[d.root] = d
    out.update(_registered)
    return out
