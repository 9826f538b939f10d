"""One pipeline for the project's checked XML documents: read -> hardened parse -> check -> model.

State machines (``homesim/afsm/loader.py``) and dialog documents (the robot's dialog loader) are
read the same way: bytes of a regular file of bounded size (:func:`~homesim.xmlio.read_input`) or
text, parsed only by the hardened parser (:func:`~homesim.xmlio.parse_bytes`), then the kind's own
``check_root`` (its schema, every problem with file and line, then the rules a schema cannot say)
gives the model or every problem. A kind differs only in that ``check_root``, its error types, an
optional look at the raw bytes after parsing, and whether a malformed document raises the parser's
:class:`~homesim.errors.XMLInputError` or joins the kind's problem list.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, Generic, TypeVar

from lxml import etree

from .errors import InputError, XMLInputError
from .xmlio import parse_bytes, read_input

M = TypeVar("M")
E = TypeVar("E", bound=InputError)


@dataclass(frozen=True)
class DocumentKind(Generic[M, E]):
    """How one kind of XML document is checked and loaded (see the module docstring)."""

    #: ``check_root(root, source=..., **options) -> (model or None, problems)``.
    check_root: Callable[..., tuple[M | None, list[E]]]
    #: One problem: ``error(message, source=..., line=...)``.
    error: Callable[..., E]
    #: The exception that carries every problem: ``problems([error, ...])``.
    problems: Callable[[list[E]], Exception]
    #: Called with the parsed root and the raw bytes (e.g. to mend line numbers), before the checks.
    prepare: Callable[[etree._Element, bytes], None] | None = None
    #: ``loads``/``load`` of a malformed document raise the kind's problems (else the parser's error).
    malformed_as_problems: bool = True

    def parse(self, data: bytes | str, *, source: str = "<string>") -> etree._Element:
        """The root of a document given as text; :class:`XMLInputError` when malformed or unsafe."""
        raw = data.encode("utf-8") if isinstance(data, str) else data
        root = parse_bytes(raw, source=source)
        if self.prepare is not None:
            self.prepare(root, raw)
        return root

    def parse_file(self, path: str | os.PathLike[str]) -> etree._Element:
        """The root of a file (a regular file of bounded size only)."""
        return self.parse(read_input(path), source=str(path))

    def _malformed(self, exc: XMLInputError) -> list[E]:
        return [self.error(exc.message, source=exc.source, line=exc.line)]

    def check(self, data: bytes | str, *, source: str = "<string>") -> list[E]:
        """Every problem of a document given as text (empty: it loads)."""
        try:
            root = self.parse(data, source=source)
        except XMLInputError as exc:
            return self._malformed(exc)
        return self.check_root(root, source=source)[1]

    def check_file(self, path: str | os.PathLike[str]) -> list[E]:
        """Every problem of a file (empty: it loads)."""
        try:
            root = self.parse_file(path)
        except XMLInputError as exc:
            return self._malformed(exc)
        return self.check_root(root, source=str(path))[1]

    def from_element(self, root: etree._Element, *, source: str, **options: Any) -> M:
        """The model of a parsed document; raises the kind's problems listing every problem."""
        model, problems = self.check_root(root, source=source, **options)
        if problems or model is None:
            raise self.problems(list(problems))
        return model

    def _load(self, read: Callable[[], etree._Element], source: str, options: dict[str, Any]) -> M:
        try:
            root = read()
        except XMLInputError as exc:
            if not self.malformed_as_problems:
                raise
            raise self.problems(self._malformed(exc)) from exc
        return self.from_element(root, source=source, **options)

    def loads(self, data: bytes | str, *, source: str = "<string>", **options: Any) -> M:
        """The model of a document given as text."""
        return self._load(lambda: self.parse(data, source=source), source, options)

    def load(self, path: str | os.PathLike[str], **options: Any) -> M:
        """The model of a file."""
        return self._load(lambda: self.parse_file(path), str(path), options)


__all__: Sequence[str] = ("DocumentKind",)
