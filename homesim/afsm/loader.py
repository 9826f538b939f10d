"""AFSM documents in and out: text -> hardened parse -> profile check -> XSD -> model -> validation.

The ES's machine is an SCXML document (W3C State Chart XML vocabulary) with
the ES's extras in the namespace ``urn:homesim:afsm:1`` (prefix ``es``)::

    <scxml xmlns="http://www.w3.org/2005/07/scxml" xmlns:es="urn:homesim:afsm:1"
           version="1.0" name="demo" initial="Idle" es:default-lifetime="5">
      <es:module name="dialog" layer="deliberative"/>
      <es:event name="greeting" lifetime="2.5" source="dialog"/>
      <!-- why Idle exists -->
      <state id="Idle">
        <transition event="greeting" target="Busy" cond="@confidence &gt; 0.5">
          <send event="greeted" target="dialog" es:kind="condition">
            <param name="who" expr="person"/>
          </send>
        </transition>
      </state>
      <state id="Busy"/>
    </scxml>

Each stage reports problems as :class:`~homesim.errors.AFSMError` naming the
file, the line and the rule broken. SCXML features the engine does not
implement (``<parallel>``, ``<onentry>``, ``delay`` ...) are named as such
rather than left to a generic schema message. :func:`check` returns every
problem found; :func:`load`/:func:`loads` raise :class:`AFSMProblems` carrying
them all. Malformed XML stops at the parser; schema problems stop before the
semantic stage (whose checks would only repeat them).
"""

from __future__ import annotations

import os
import re
from copy import deepcopy
from decimal import Decimal, InvalidOperation
from functools import lru_cache
from pathlib import Path

from lxml import etree

from ..errors import AFSMError, AFSMProblems, XMLInputError
from ..xmlio import Schema, parse_bytes, parse_file
from .model import (
    DEFAULT_LIFETIME_NS,
    EventDecl,
    Machine,
    ModuleDecl,
    Param,
    Send,
    State,
    Transition,
    validate,
)

SCXML_NS = "http://www.w3.org/2005/07/scxml"
ES_NS = "urn:homesim:afsm:1"
_S = "{%s}" % SCXML_NS
_E = "{%s}" % ES_NS

PROFILE_XSD = Path(__file__).with_name("afsm-profile.xsd")

#: The SCXML elements the engine implements.
SUPPORTED = ("scxml", "state", "transition", "send", "param")
#: SCXML elements it knows but does not implement (named in the error).
UNSUPPORTED_ELEMENTS = (
    "parallel", "final", "history", "initial", "onentry", "onexit", "datamodel", "data",
    "script", "assign", "raise", "log", "if", "elseif", "else", "foreach", "invoke",
    "finalize", "donedata", "content", "cancel",
)
#: SCXML attributes of supported elements that the engine does not implement.
UNSUPPORTED_ATTRIBUTES = {
    "scxml": ("datamodel", "binding"),
    "transition": ("type",),
    "send": ("eventexpr", "targetexpr", "type", "typeexpr", "id", "idlocation", "delay", "delayexpr", "namelist"),
    "param": ("location",),
}

_NS_LABEL = re.compile(r"\{([^}]*)\}")


@lru_cache(maxsize=1)
def profile_schema() -> Schema:
    """The compiled profile XSD (SCXML subset + ES namespace), loaded once."""
    root = parse_file(PROFILE_XSD)
    # The profile imports afsm-es.xsd by a relative location: give the tree its URL.
    root.getroottree().docinfo.URL = str(PROFILE_XSD)
    return Schema(PROFILE_XSD.name, etree.XMLSchema(root))


def _label(text: str) -> str:
    """``{scxml-ns}state`` -> ``state``, ``{es-ns}event`` -> ``es:event`` in messages."""
    return _NS_LABEL.sub(lambda m: "" if m.group(1) == SCXML_NS else ("es:" if m.group(1) == ES_NS else m.group(0)), text)


def _seconds_ns(text: str) -> int:
    """Decimal seconds as integer nanoseconds (exact, no float rounding)."""
    return int(Decimal(text.strip()) * 1_000_000_000)


# ------------------------------------------------------------------- stages
def _profile_problems(root: etree._Element, source: str) -> list[AFSMError]:
    """SCXML features outside the ES profile, named precisely (before the XSD's generic words)."""
    out: list[AFSMError] = []
    if root.tag != _S + "scxml":
        out.append(AFSMError(
            f"root element is {_label(str(root.tag))!r}; an AFSM is an SCXML document "
            f"(<scxml xmlns=\"{SCXML_NS}\">)", source=source, line=root.sourceline, element=_label(str(root.tag)),
        ))
        return out
    for el in root.iter(etree.Element):
        tag = el.tag
        if not isinstance(tag, str) or not tag.startswith(_S):
            continue
        local = tag[len(_S):]
        if local in UNSUPPORTED_ELEMENTS:
            out.append(AFSMError(
                f"SCXML <{local}> is not supported by the ES engine (it implements {', '.join('<%s>' % s for s in SUPPORTED)})",
                source=source, line=el.sourceline, element=local,
            ))
        for attr in UNSUPPORTED_ATTRIBUTES.get(local, ()):
            if attr in el.attrib:
                out.append(AFSMError(
                    f"SCXML attribute {attr!r} of <{local}> is not supported by the ES engine",
                    source=source, line=el.sourceline, element=local,
                ))
    return out


def _without_unsupported(root: etree._Element) -> etree._Element:
    """A copy without the SCXML features the profile check already named.

    libxml2 stops checking a parent's later children after one unexpected
    element, so leaving them in would hide the problems that follow.
    """
    copy = deepcopy(root)
    doomed = [el for el in copy.iter(etree.Element)
              if isinstance(el.tag, str) and el.tag.startswith(_S) and el.tag[len(_S):] in UNSUPPORTED_ELEMENTS]
    for el in doomed:
        parent = el.getparent()
        if parent is not None:
            parent.remove(el)
    for el in copy.iter(etree.Element):
        if isinstance(el.tag, str) and el.tag.startswith(_S):
            for attr in UNSUPPORTED_ATTRIBUTES.get(el.tag[len(_S):], ()):
                el.attrib.pop(attr, None)
    return copy


def _schema_problems(root: etree._Element, source: str) -> list[AFSMError]:
    out = []
    for line, message in profile_schema().errors(_without_unsupported(root)):
        m = re.match(r"Element '([^']*)'", message)
        element = _label(m.group(1)) if m else None
        out.append(AFSMError(f"schema {PROFILE_XSD.name}: {_label(message)}", source=source, line=line or None, element=element))
    return out


def _doc_comment(el: etree._Element) -> str:
    """The comment(s) right before ``el`` (or, failing that, its first child comment)."""
    parts: list[str] = []
    prev = el.getprevious()
    while prev is not None and isinstance(prev, etree._Comment):
        parts.append((prev.text or "").strip())
        prev = prev.getprevious()
    if parts:
        return " ".join(reversed(parts))
    for child in el:
        if isinstance(child, etree._Comment):
            return (child.text or "").strip()
        break
    return ""


def _build(root: etree._Element, source: str) -> tuple[Machine, list[AFSMError]]:
    """The model of a schema-valid document, plus duplicate-id problems."""
    problems: list[AFSMError] = []
    dl = root.get(_E + "default-lifetime")
    m = Machine(
        name=root.get("name") or Path(source).stem,
        states={},
        roots=[],
        initial=root.get("initial"),
        default_lifetime_ns=_seconds_ns(dl) if dl else DEFAULT_LIFETIME_NS,
        source=source,
        line=root.sourceline,
    )
    for el in root:
        if el.tag == _E + "module":
            name = el.get("name")
            if name in m.modules:
                problems.append(AFSMError(f"module {name!r} declared twice (first at line {m.modules[name].line})", source=source, line=el.sourceline, element="es:module"))
                continue
            m.modules[name] = ModuleDecl(name, el.get("layer"), el.sourceline)
        elif el.tag == _E + "event":
            name = el.get("name")
            if name in m.events:
                problems.append(AFSMError(f"event {name!r} declared twice (first at line {m.events[name].line})", source=source, line=el.sourceline, element="es:event"))
                continue
            lt = el.get("lifetime")
            m.events[name] = EventDecl(name, _seconds_ns(lt) if lt else None, el.get("source"), el.sourceline)
        elif el.tag == _S + "state":
            _build_state(m, el, None, problems)
    return m, problems


def _build_state(m: Machine, el: etree._Element, parent: str | None, problems: list[AFSMError]) -> None:
    sid = el.get("id")
    if sid in m.states:
        first = m.states[sid].line
        problems.append(AFSMError(f"duplicate state id {sid!r} (first defined at line {first}; rule: ids are unique)", source=m.source, line=el.sourceline, element="state"))
        return
    st = State(id=sid, parent=parent, initial=el.get("initial"), doc=_doc_comment(el), line=el.sourceline)
    m.states[sid] = st
    if parent is None:
        m.roots.append(sid)
    else:
        m.states[parent].children.append(sid)
    for child in el:
        if child.tag == _S + "transition":
            st.transitions.append(_build_transition(child))
        elif child.tag == _S + "state":
            _build_state(m, child, sid, problems)


def _build_transition(el: etree._Element) -> Transition:
    sends = []
    for s in el:
        if s.tag != _S + "send":
            continue
        params = tuple(Param(p.get("name"), p.get("expr"), p.sourceline) for p in s if p.tag == _S + "param")
        sends.append(Send(s.get(_E + "kind"), s.get("target"), s.get("event"), params, s.sourceline))
    return Transition(el.get("event"), el.get("target"), el.get("cond"), tuple(sends), el.sourceline)


# --------------------------------------------------------------- public API
def check_root(root: etree._Element, *, source: str, fragment: bool = False) -> tuple[Machine | None, list[AFSMError]]:
    """Run every stage after parsing; return the machine (None if it could not be built) and all problems.

    A ``fragment`` (an extension to merge into a running machine) gets the
    structural checks only: its targets and modules may live in the machine
    it extends, so the semantic checks run on the merged result instead.
    """
    problems = _profile_problems(root, source)
    if problems and root.tag != _S + "scxml":
        return None, problems
    problems += _schema_problems(root, source)
    if problems:
        return None, sorted(problems, key=lambda p: p.line or 0)
    try:
        machine, dup = _build(root, source)
    except (InvalidOperation, ValueError) as exc:  # pragma: no cover - the XSD types lifetimes
        return None, [AFSMError(f"cannot read the document: {exc}", source=source)]
    problems = sorted(dup + ([] if fragment else validate(machine)), key=lambda p: p.line or 0)
    return machine, problems


def check(data: bytes | str, *, source: str = "<string>") -> list[AFSMError]:
    """Every problem of an AFSM document given as text (empty list when it loads)."""
    try:
        root = parse_bytes(data, source=source)
    except XMLInputError as exc:
        return [AFSMError(exc.message, source=exc.source, line=exc.line)]
    return check_root(root, source=source)[1]


def check_file(path: str | os.PathLike[str]) -> list[AFSMError]:
    """Every problem of an AFSM file (empty list when it loads)."""
    try:
        root = parse_file(path)
    except XMLInputError as exc:
        return [AFSMError(exc.message, source=exc.source, line=exc.line)]
    return check_root(root, source=str(path))[1]


def from_element(root: etree._Element, *, source: str, fragment: bool = False) -> Machine:
    """The machine of a parsed document; raises :class:`AFSMProblems` listing every problem."""
    machine, problems = check_root(root, source=source, fragment=fragment)
    if problems or machine is None:
        raise AFSMProblems(problems)
    return machine


def loads(data: bytes | str, *, source: str = "<string>", fragment: bool = False) -> Machine:
    """Load an AFSM from text. Raises XMLInputError (malformed) or AFSMProblems."""
    return from_element(parse_bytes(data, source=source), source=source, fragment=fragment)


def load(path: str | os.PathLike[str], *, fragment: bool = False) -> Machine:
    """Load an AFSM file. Raises XMLInputError (malformed) or AFSMProblems naming file and lines."""
    return from_element(parse_file(path), source=str(path), fragment=fragment)


# --------------------------------------------------------------------- dump
def _fmt_seconds(ns: int) -> str:
    text = format(Decimal(ns) / Decimal(1_000_000_000), "f")
    if "." in text:
        text = text.rstrip("0").rstrip(".")
    return text


def to_element(m: Machine) -> etree._Element:
    """The machine as an SCXML element tree (the inverse of :func:`from_element`)."""
    nsmap = {None: SCXML_NS, "es": ES_NS}
    root = etree.Element(_S + "scxml", nsmap=nsmap)
    root.set("version", "1.0")
    root.set("name", m.name)
    if m.initial is not None:
        root.set("initial", m.initial)
    root.set(_E + "default-lifetime", _fmt_seconds(m.default_lifetime_ns))
    for d in m.modules.values():
        etree.SubElement(root, _E + "module", name=d.name, layer=d.layer)
    for e in m.events.values():
        el = etree.SubElement(root, _E + "event", name=e.name)
        if e.lifetime_ns is not None:
            el.set("lifetime", _fmt_seconds(e.lifetime_ns))
        if e.source is not None:
            el.set("source", e.source)
    for sid in m.roots:
        _dump_state(m, root, sid)
    return root


def _dump_state(m: Machine, parent: etree._Element, sid: str) -> None:
    st = m.states[sid]
    if st.doc:
        parent.append(etree.Comment(" " + st.doc.replace("--", "- -") + " "))
    el = etree.SubElement(parent, _S + "state", id=sid)
    if st.initial is not None:
        el.set("initial", st.initial)
    for t in st.transitions:
        te = etree.SubElement(el, _S + "transition", event=t.event)
        if t.target is not None:
            te.set("target", t.target)
        if t.cond is not None:
            te.set("cond", t.cond)
        for s in t.sends:
            se = etree.SubElement(te, _S + "send", event=s.name, target=s.target)
            se.set(_E + "kind", s.kind)
            for p in s.params:
                etree.SubElement(se, _S + "param", name=p.name, expr=p.expr)
    for child in st.children:
        _dump_state(m, el, child)


def dumps(m: Machine) -> str:
    """The machine as SCXML text (pretty-printed, loadable by :func:`loads`)."""
    return etree.tostring(to_element(m), encoding="unicode", pretty_print=True)
