"""The project's one hardened XML parser, and XML Schema loading.

Every XML input (scenario files, state machines, dialogs, bus messages given
as text, memory files) goes through :func:`parse_bytes` or :func:`parse_file`.
The parser resolves no entities, loads no DTD, touches no network and keeps
libxml2's limits on tree size and depth (``huge_tree=False``). Documents that
carry a DOCTYPE are refused outright: nothing in homesim needs one, and a
DOCTYPE is how entity-expansion and external-entity attacks arrive.

Defence in depth, each layer enough on its own against external loads:

1. **UTF-8 only.** A UTF-16/UTF-32 byte-order mark, a NUL byte (UTF-16/32
   without a mark) or an encoding declaration other than UTF-8/US-ASCII is
   refused before parsing, and the parser is told the text *is* UTF-8 (so a
   declared ``UTF-7`` cannot re-encode ``<!DOCTYPE`` behind our back). The
   byte-level DOCTYPE check below therefore sees the same characters libxml2
   sees.
2. **DOCTYPE refused before parsing** (byte scan of the prolog) **and after**
   (the parsed tree's docinfo).
3. **The parser loads nothing.** ``collect_ids`` stays on: with
   ``collect_ids=False`` lxml sets libxml2's ``XML_SKIP_IDS`` load-subset flag,
   which makes libxml2 read external subsets and parameter entities even with
   ``load_dtd=False`` (that was the hole the UTF-16 bypass used). And every
   external resource libxml2 still asks for goes to a resolver that refuses it
   (only a schema's own ``xs:import``/``xs:include`` next to it is allowed,
   see :func:`load_schema`).

Files are read with :func:`read_input`: regular files only (no devices,
FIFOs or directories), at most :data:`MAX_DOCUMENT_BYTES`.
"""

from __future__ import annotations

import os
import re
import stat
from functools import lru_cache
from pathlib import Path

from lxml import etree

from .errors import InputError, SchemaValidationError, XMLInputError

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

#: Encodings a document may declare (case-insensitive); everything is read as UTF-8.
ACCEPTED_ENCODINGS = frozenset({"utf-8", "utf8", "us-ascii", "ascii"})
_XML_DECL_ENCODING = re.compile(rb"\A(?:\xef\xbb\xbf)?<\?xml\s[^>]{0,200}?\bencoding\s*=\s*([\"'])(.{0,64}?)\1", re.S)
_FOREIGN_BOMS = (
    (b"\x00\x00\xfe\xff", "UTF-32"),
    (b"\xff\xfe\x00\x00", "UTF-32"),
    (b"\xfe\xff", "UTF-16"),
    (b"\xff\xfe", "UTF-16"),
)
_FOREIGN_BOM_PREFIXES = tuple(bom for bom, _ in _FOREIGN_BOMS)


class ExternalResourceRefused(Exception):
    """Raised inside libxml2's loader when a document asks for an outside resource."""


class _RefuseExternal(etree.Resolver):
    """Refuse every external resource (DTD, entity, XInclude...) libxml2 asks for.

    ``allowed_dir``: a schema's own directory, whose ``.xsd`` files its
    ``xs:import``/``xs:include`` may load (our own schemas only).
    """

    def __init__(self, allowed_dir: Path | None = None) -> None:
        super().__init__()
        self.allowed_dir = allowed_dir

    def resolve(self, system_url: str | None, public_id: str | None, context: object) -> object:
        if self.allowed_dir is not None and system_url:
            path = Path(system_url.removeprefix("file://"))
            if path.suffix == ".xsd" and path.resolve().parent == self.allowed_dir and path.resolve().is_file():
                return self.resolve_filename(str(path.resolve()), context)
        raise ExternalResourceRefused(system_url or public_id or "?")


def _new_parser(allowed_dir: Path | None = None) -> etree.XMLParser:
    parser = etree.XMLParser(
        encoding="utf-8",  # whatever the document declares (declarations are checked first)
        resolve_entities=False,
        no_network=True,
        load_dtd=False,
        dtd_validation=False,
        attribute_defaults=False,
        huge_tree=False,
        remove_comments=False,
        strip_cdata=True,
        # collect_ids=False would set XML_SKIP_IDS in libxml2's loadsubset and
        # make it load external subsets and parameter entities: keep the default.
        collect_ids=True,
    )
    parser.resolvers.add(_RefuseExternal(allowed_dir))
    return parser


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
    return _parse(data, source, _PARSER)


def _parse(data: bytes | str, source: str, parser: etree.XMLParser, base_url: str | None = None) -> _Element:
    if isinstance(data, str):
        data = data.encode("utf-8")
    if len(data) > MAX_DOCUMENT_BYTES:
        raise XMLInputError(
            f"document is {len(data)} bytes, larger than the limit of {MAX_DOCUMENT_BYTES}",
            source=source,
        )
    check_utf8_only(data, source)
    m = _PROLOG_DOCTYPE.match(data)
    if m is not None:
        raise XMLInputError(
            "documents with a DOCTYPE are refused (no DTDs or entities are allowed)",
            source=source,
            line=data.count(b"\n", 0, m.end()) + 1,
        )
    try:
        root = etree.fromstring(data, parser, base_url=base_url)
    except ExternalResourceRefused as exc:
        raise XMLInputError(f"refers to an external resource ({exc}); refused", source=source) from exc
    except etree.XMLSyntaxError as exc:
        raise XMLInputError(_syntax_message(exc), source=source, line=exc.lineno or None) from exc
    except ValueError as exc:  # e.g. unicode strings with an encoding declaration
        raise XMLInputError(str(exc), source=source) from exc
    _refuse_doctype(root.getroottree(), source)
    return root


def check_utf8_only(data: bytes, source: str) -> None:
    """Refuse UTF-16/UTF-32 text (with or without byte-order mark) and foreign encoding declarations.

    homesim reads UTF-8 (and its subset US-ASCII) only. Anything else is
    refused here, before libxml2 sees it, naming the encoding found.
    """
    if data.startswith(_FOREIGN_BOM_PREFIXES):  # (one C call; which one, only when refusing)
        for bom, name in _FOREIGN_BOMS:
            if data.startswith(bom):
                raise XMLInputError(f"{name} text (byte-order mark) is refused: homesim reads UTF-8 only", source=source, line=1)
    nul = data.find(b"\x00")
    if nul >= 0:
        raise XMLInputError(
            "NUL byte in the text (UTF-16 or UTF-32 without a byte-order mark?): homesim reads UTF-8 only",
            source=source,
            line=data.count(b"\n", 0, nul) + 1,
        )
    m = _XML_DECL_ENCODING.match(data)
    if m is not None:
        declared = m.group(2).decode("ascii", "replace")
        if declared.strip().lower() not in ACCEPTED_ENCODINGS:
            raise XMLInputError(
                f"declared encoding {declared!r} is refused: homesim reads UTF-8 (or US-ASCII) only",
                source=source,
                line=1,
            )


def read_input(path: str | os.PathLike[str], *, limit: int = MAX_DOCUMENT_BYTES, error: type[InputError] = XMLInputError) -> bytes:
    """Read a whole input file that must be a regular file of at most ``limit`` bytes.

    Devices (``/dev/zero``), FIFOs, sockets and directories are refused before
    a single byte is read: the file is opened non-blocking (a FIFO with no
    writer cannot block the open) and checked with ``fstat``; a file larger
    than ``limit`` (or one growing past it while read) is refused. Errors name
    the file and what is wrong.
    """
    p = str(path)
    fd = open_regular(p, error=error)
    try:
        size = os.fstat(fd).st_size
        if size > limit:
            raise error(f"file is {size} bytes, larger than the limit of {limit}", source=p)
        chunks: list[bytes] = []
        total = 0
        while True:
            chunk = os.read(fd, min(1 << 20, limit + 1 - total))
            if not chunk:
                break
            chunks.append(chunk)
            total += len(chunk)
            if total > limit:
                raise error(f"file grew past the limit of {limit} bytes while being read", source=p)
        return b"".join(chunks)
    except OSError as exc:
        raise error(f"cannot read file: {exc.strerror}", source=p) from exc
    finally:
        os.close(fd)


def open_regular(path: str | os.PathLike[str], *, error: type[InputError] = XMLInputError) -> int:
    """Open ``path`` for reading and return the descriptor, refusing anything but a regular file.

    Opened non-blocking, so a FIFO without a writer cannot hang the open; the
    type is checked on the open descriptor (``fstat``), so a symbolic link to
    ``/dev/zero`` is seen for what it is. Raises ``error`` naming the file.
    """
    p = str(path)
    try:
        fd = os.open(p, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0))
    except OSError as exc:
        raise error(f"cannot read file: {exc.strerror}", source=p) from exc
    try:
        mode = os.fstat(fd).st_mode
    except OSError as exc:
        os.close(fd)
        raise error(f"cannot read file: {exc.strerror}", source=p) from exc
    if not stat.S_ISREG(mode):
        os.close(fd)
        raise error(f"is not a regular file ({_file_kind(mode)}); homesim reads regular files only", source=p)
    return fd


def _file_kind(mode: int) -> str:
    for test, name in (
        (stat.S_ISDIR, "a directory"),
        (stat.S_ISFIFO, "a FIFO"),
        (stat.S_ISCHR, "a character device"),
        (stat.S_ISBLK, "a block device"),
        (stat.S_ISSOCK, "a socket"),
    ):
        if test(mode):
            return name
    return "not a regular file"


def parse_file(path: str | os.PathLike[str]) -> _Element:
    """Parse an XML file safely; errors name the file and the line."""
    return parse_bytes(read_input(path), source=str(path))


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
    # Our own schemas may import/include sibling .xsd files, and nothing else.
    parser = _new_parser(Path(path).parent)
    root = _parse(read_input(path), path, parser, base_url=path)
    try:
        xsd = etree.XMLSchema(root)
    except etree.XMLSchemaParseError as exc:
        raise XMLInputError(f"not a valid XML Schema: {exc}", source=path) from exc
    return Schema(Path(path).name, xsd)


_BY_GIVEN: dict[str, Schema] = {}  # an absolute path as given -> its schema (no resolve() per call)


def load_schema(path: str | os.PathLike[str]) -> Schema:
    """Load (once per process) and compile an XSD file."""
    given = os.fspath(path)
    schema = _BY_GIVEN.get(given) if isinstance(given, str) else None
    if schema is None:
        schema = _load_schema_cached(str(Path(path).resolve()))
        if isinstance(given, str) and os.path.isabs(given):  # a relative one depends on the working directory
            _BY_GIVEN[given] = schema
    return schema


def schema_from_text(name: str, text: str | bytes) -> Schema:
    """Compile an XSD given as text (tests, small inline types)."""
    root = parse_bytes(text, source=name)
    try:
        return Schema(name, etree.XMLSchema(root))
    except etree.XMLSchemaParseError as exc:
        raise XMLInputError(f"not a valid XML Schema: {exc}", source=name) from exc
