"""The project's one hardened XML parser, and XML Schema loading.

Every XML input (scenario files, state machines, dialogs, bus messages given
as text, memory files) goes through :func:`parse_bytes` or :func:`parse_file`.
The parser resolves no entities, loads no DTD, touches no network and keeps
libxml2's limits on tree size and depth (``huge_tree=False``). Documents that
carry a DOCTYPE are refused outright: nothing in homesim needs one, and a
DOCTYPE is how entity-expansion and external-entity attacks arrive.
"""

from __future__ import annotations

import os
import re
from functools import lru_cache
from pathlib import Path

from lxml import etree

from .errors import SchemaValidationError, XMLInputError

#: Largest document accepted, in bytes. Bus messages are small; scenario files
#: and memory files stay far below this.
MAX_DOCUMENT_BYTES = 16 * 1024 * 1024

_Element = etree._Element

# A DOCTYPE may only follow the XML declaration, comments, processing
# instructions and white space; finding it there lets us refuse it before
# libxml2 looks at any entity or external DTD.
# The repetition is possessive (``*+``): without it, a prolog of many
# processing instructions or comments backtracks exponentially.
_PROLOG_DOCTYPE = re.compile(rb"\A(?:\xef\xbb\xbf)?(?:\s|<\?.*?\?>|<!--.*?-->)*+<!DOCTYPE", re.S)


def _new_parser() -> etree.XMLParser:
    return etree.XMLParser(
        resolve_entities=False,
        no_network=True,
        load_dtd=False,
        dtd_validation=False,
        huge_tree=False,
        remove_comments=False,
        strip_cdata=True,
        collect_ids=False,
    )


# One parser per process: lxml parsers are not shared across threads, and the
# simulation is single-threaded by construction.
_PARSER = _new_parser()


def hardened_parser() -> etree.XMLParser:
    """Return the shared hardened parser (for lxml APIs that take one)."""
    return _PARSER


def parse_bytes(data: bytes | str, *, source: str = "<string>") -> _Element:
    """Parse one XML document safely and return its root element.

    Raises :class:`XMLInputError` naming ``source`` and the line when the text
    is malformed, not UTF-8 as declared, too large, too deep, or carries a
    DOCTYPE. Nothing is returned half-parsed.
    """
    if isinstance(data, str):
        data = data.encode("utf-8")
    if len(data) > MAX_DOCUMENT_BYTES:
        raise XMLInputError(
            f"document is {len(data)} bytes, larger than the limit of {MAX_DOCUMENT_BYTES}",
            source=source,
        )
    m = _PROLOG_DOCTYPE.match(data)
    if m is not None:
        raise XMLInputError(
            "documents with a DOCTYPE are refused (no DTDs or entities are allowed)",
            source=source,
            line=data.count(b"\n", 0, m.end()) + 1,
        )
    try:
        root = etree.fromstring(data, _PARSER)
    except etree.XMLSyntaxError as exc:
        raise XMLInputError(_syntax_message(exc), source=source, line=exc.lineno or None) from exc
    except ValueError as exc:  # e.g. unicode strings with an encoding declaration
        raise XMLInputError(str(exc), source=source) from exc
    _refuse_doctype(root.getroottree(), source)
    return root


def parse_file(path: str | os.PathLike[str]) -> _Element:
    """Parse an XML file safely; errors name the file and the line."""
    p = Path(path)
    try:
        data = p.read_bytes()
    except OSError as exc:
        raise XMLInputError(f"cannot read file: {exc.strerror}", source=str(p)) from exc
    return parse_bytes(data, source=str(p))


def _refuse_doctype(tree: etree._ElementTree, source: str) -> None:
    docinfo = tree.docinfo
    if docinfo.doctype or docinfo.internalDTD is not None or docinfo.externalDTD is not None:
        raise XMLInputError(
            "documents with a DOCTYPE are refused (no DTDs or entities are allowed)",
            source=source,
            line=1,
        )


def _syntax_message(exc: etree.XMLSyntaxError) -> str:
    msg = exc.msg or str(exc)
    # libxml2 appends ", line N, column M"; we report the line ourselves.
    cut = msg.rfind(", line ")
    if cut > 0:
        msg = msg[:cut]
    return f"malformed XML: {msg}"


def serialize(element: _Element) -> bytes:
    """Serialize an element as compact UTF-8 bytes (no XML declaration)."""
    return etree.tostring(element, encoding="utf-8")


def to_text(element: _Element) -> str:
    """Serialize an element as a str (for traces and transcripts)."""
    return etree.tostring(element, encoding="unicode")


class Schema:
    """A compiled XML Schema with a name, validating elements with clear errors."""

    __slots__ = ("name", "_xsd")

    def __init__(self, name: str, xsd: etree.XMLSchema) -> None:
        self.name = name
        self._xsd = xsd

    def is_valid(self, element: _Element) -> bool:
        """True when ``element`` satisfies the schema (no exception, no message)."""
        return bool(self._xsd.validate(element))

    def check(self, element: _Element, *, source: str = "<element>") -> None:
        """Raise :class:`SchemaValidationError` naming source, schema and libxml2's message."""
        if self._xsd.validate(element):
            return
        err = self._xsd.error_log.last_error
        line = err.line if err is not None and err.line > 0 else None
        detail = err.message if err is not None else "invalid"
        raise SchemaValidationError(
            f"does not satisfy schema {self.name}: {detail}", source=source, line=line
        )

    def errors(self, element: _Element) -> list[tuple[int, str]]:
        """Every (line, message) libxml2 reports for ``element``; empty when valid."""
        if self._xsd.validate(element):
            return []
        return [(e.line, e.message) for e in self._xsd.error_log]

    def __repr__(self) -> str:
        return f"Schema({self.name!r})"


@lru_cache(maxsize=None)
def _load_schema_cached(path: str) -> Schema:
    root = parse_file(path)
    try:
        xsd = etree.XMLSchema(root)
    except etree.XMLSchemaParseError as exc:
        raise XMLInputError(f"not a valid XML Schema: {exc}", source=path) from exc
    return Schema(Path(path).name, xsd)


def load_schema(path: str | os.PathLike[str]) -> Schema:
    """Load (once per process) and compile an XSD file."""
    return _load_schema_cached(str(Path(path).resolve()))


def schema_from_text(name: str, text: str | bytes) -> Schema:
    """Compile an XSD given as text (tests, small inline types)."""
    root = parse_bytes(text, source=name)
    try:
        return Schema(name, etree.XMLSchema(root))
    except etree.XMLSchemaParseError as exc:
        raise XMLInputError(f"not a valid XML Schema: {exc}", source=name) from exc
