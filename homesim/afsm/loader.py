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
them all. Malformed XML stops at the parser; after a schema problem, the
offending element or attribute is taken out and the rest is checked again,
then modelled and checked semantically, so one run reports every problem.
"""

from __future__ import annotations

import os
import re
from copy import deepcopy
from decimal import Decimal, InvalidOperation
from functools import lru_cache
from pathlib import Path
from typing import Any

from lxml import etree

from ..errors import AFSMError, AFSMProblems
from ..xmldoc import DocumentKind
from ..xmlio import Schema, load_schema
from .model import (
    DEFAULT_LIFETIME_NS,
    EventDecl,
    Machine,
    ModuleDecl,
    Param,
    Send,
    State,
    Store,
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
    # load_schema lets the profile import its sibling afsm-es.xsd, nothing else.
    return load_schema(PROFILE_XSD)


def _label(text: str) -> str:
    """``{scxml-ns}state`` -> ``state``, ``{es-ns}event`` -> ``es:event`` in messages."""
    return _NS_LABEL.sub(lambda m: "" if m.group(1) == SCXML_NS else ("es:" if m.group(1) == ES_NS else m.group(0)), text)


def _seconds_ns(text: str) -> int:
    """Decimal seconds as integer nanoseconds (exact, no float rounding)."""
    return int(Decimal(text.strip()) * 1_000_000_000)


# ------------------------------------------------------------------ parsing
_TOKENS = re.compile(rb"<!--.*?-->|<!\[CDATA\[.*?\]\]>|<\?.*?\?>|</[^>]*>|<([^\s/>!?]+)", re.S)


def _start_lines(root: etree._Element, data: bytes) -> None:
    """Give every element the line its start tag *begins* on.

    libxml2 records the line where a start tag ends, so an element whose
    attributes span several lines would be reported at its last line. ``<``
    cannot occur inside attribute values, so the k-th start tag in the text
    is the k-th element in document order; if the counts disagree nothing is
    changed.
    """
    starts = []
    line, pos = 1, 0
    for m in _TOKENS.finditer(data):
        if m.group(1) is not None:
            line += data.count(b"\n", pos, m.start())
            pos = m.start()
            starts.append(line)
    elements = list(root.iter(etree.Element))
    if len(starts) != len(elements):
        return
    for el, line in zip(elements, starts):
        if el.sourceline != line and line < 65535:
            el.sourceline = line


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
        why = _refused_form(el, local)
        if why is not None:
            out.append(AFSMError(why, source=source, line=el.sourceline, element=local))
    return out


def _refused_form(el: etree._Element, local: str) -> str | None:
    """Standard SCXML forms of supported elements that the ES does not implement, named (or None).

    Eventless transitions (the ES only ever reacts to an event), event lists
    (``event="a b"``) and an ``initial`` naming several states (parallel
    entry). Left to the XSD they would read as a missing attribute or a
    regular-expression facet error.
    """
    if local == "transition":
        event = el.get("event")
        if event is None:
            return ("eventless transitions are not supported by the ES engine (it only reacts to events): "
                    "give the transition an event=\"...\"")
        names = event.split()
        if len(names) > 1:
            return (f"event lists are not supported by the ES engine (event={event!r}): one event name per "
                    f"transition; write one <transition> for each of {', '.join(repr(n) for n in names)}")
    elif local in ("scxml", "state"):
        initial = el.get("initial")
        if initial is not None and len(initial.split()) > 1:
            return (f"an initial naming several states is not supported by the ES engine (initial={initial!r}: "
                    "parallel regions are not implemented); name one state")
    return None


def _without_unsupported(root: etree._Element) -> tuple[etree._Element, set[str], set[str]]:
    """A copy without the SCXML features the profile check already named.

    libxml2 stops checking a parent's later children after one unexpected
    element, so leaving them in would hide the problems that follow. Also
    returns the ids the removed elements declared (``<final id="pass">``:
    a target or initial naming them would only repeat the refusal) and the
    states a refused transition or initial named (they may look unreachable
    only because of it).
    """
    copy = deepcopy(root)
    withdrawn: set[str] = set()
    named: set[str] = set()
    doomed = []
    for el in copy.iter(etree.Element):
        if not isinstance(el.tag, str) or not el.tag.startswith(_S):
            continue
        local = el.tag[len(_S):]
        if local in UNSUPPORTED_ELEMENTS or (local == "transition" and _refused_form(el, local)):
            doomed.append(el)
            named.update((el.get("target") or "").split())
    for el in doomed:
        parent = el.getparent()
        if parent is not None:
            withdrawn.update(str(d.get("id")) for d in el.iter(etree.Element) if d.get("id"))
            parent.remove(el)
    for el in copy.iter(etree.Element):
        if isinstance(el.tag, str) and el.tag.startswith(_S):
            local = el.tag[len(_S):]
            for attr in UNSUPPORTED_ATTRIBUTES.get(local, ()):
                el.attrib.pop(attr, None)
            if local in ("scxml", "state") and _refused_form(el, local):
                named.update(el.attrib.pop("initial").split())
    return copy, withdrawn, named


#: Attributes the profile requires: an element whose required attribute is
#: missing or invalid cannot be understood and is left out of the model.
REQUIRED_ATTRIBUTES = {
    _S + "state": ("id",),
    _S + "transition": ("event",),
    _S + "send": ("event", "target", _E + "kind"),
    _S + "param": ("name", "expr"),
    _E + "module": ("name", "layer"),
    _E + "event": ("name",),
    _E + "store": ("name", "expr"),
}

#: Validation rounds of the schema pass (each takes out what the last one
#: reported; libxml2 reports one unexpected child per parent and round).
MAX_SCHEMA_ROUNDS = 25

_ATTRIBUTE_IN_MESSAGE = re.compile(r"^Element '[^']*', attribute '([^']*)'")
_PATH_STEP = re.compile(r"^(?:([^:\[]+):)?([^\[]+)(?:\[(\d+)\])?$")


def _resolve_path(root: etree._Element, path: str | None, cache: dict[tuple[Any, ...], list[etree._Element]] | None = None) -> etree._Element | None:
    """The element a libxml2 node path (``/*/*[2]/es:module[3]``) names, or None.

    libxml2 writes ``*[n]`` for an element in a default namespace (n counts
    every element sibling) and ``prefix:name[n]`` for a prefixed one (n counts
    siblings with that prefix and name). ``cache`` (valid while the tree does
    not change) keeps each parent's sibling lists, so resolving one path per
    problem stays linear in the document, not quadratic.
    """
    if not path or not path.startswith("/"):
        return None
    if cache is None:
        cache = {}
    steps = path[1:].split("/")
    cur: etree._Element | None = None
    for k, step in enumerate(steps):
        m = _PATH_STEP.match(step)
        if m is None:
            return None
        prefix, name, index = m.group(1), m.group(2), int(m.group(3) or 1)
        if k == 0:
            siblings = [root]
        else:
            key = (cur, prefix, name)
            siblings = cache.get(key)  # type: ignore[assignment]
            if siblings is None:
                siblings = [c for c in cur if isinstance(c.tag, str)]  # type: ignore[union-attr]
                if name != "*":
                    siblings = [c for c in siblings if etree.QName(c).localname == name and c.prefix == prefix]
                cache[key] = siblings
        if index > len(siblings):
            return None
        cur = siblings[index - 1]
    return cur


def _schema_pass(root: etree._Element, source: str) -> tuple[etree._Element, list[AFSMError], set[str], set[str]]:
    """Every schema problem, and a stripped copy of ``root`` that satisfies the schema.

    libxml2 stops checking a parent's later children after one unexpected
    element, so one validation does not find every problem. Each round takes
    out what the reported problems point at (an unexpected element; an
    attribute that is not allowed or has a bad value; an element whose
    required attribute is missing or bad) and validates again, until no new
    problem appears. The copy keeps every line number, so the model built
    from it and its semantic problems name the right lines. Returns the copy,
    the problems, the names (state ids, module names) of elements taken
    out, and the states named by refused transitions and initials, so that
    problems that only follow from them are not repeated.
    """
    copy, withdrawn, named = _without_unsupported(root)
    xsd = profile_schema()._xsd
    seen: set[tuple[int, str]] = set()
    problems: list[AFSMError] = []
    for _round in range(MAX_SCHEMA_ROUNDS):  # each round removes something, or stops
        if xsd.validate(copy):
            break
        if _round == MAX_SCHEMA_ROUNDS - 1:  # bounded work: a refusal stays near-linear in the size
            problems.append(AFSMError(f"schema {PROFILE_XSD.name}: more problems may follow (the check stops after "
                                      f"{MAX_SCHEMA_ROUNDS} rounds of validation); fix these first", source=source,
                                      line=max((p.line or 0 for p in problems), default=0) or None))
            break
        entries = list(xsd.error_log)
        paths: dict[tuple[Any, ...], list[etree._Element]] = {}
        fresh = False
        actions: list[tuple[etree._Element, str | None, bool]] = []
        for e in entries:
            key = (e.line, e.message)
            if key not in seen:
                seen.add(key)
                fresh = True
                m = re.match(r"Element '([^']*)'", e.message)
                element = _label(m.group(1)) if m else None
                problems.append(AFSMError(f"schema {PROFILE_XSD.name}: {_label(e.message)}", source=source,
                                          line=e.line or None, element=element))
            node = _resolve_path(copy, e.path, paths)
            if node is None:
                continue
            am = _ATTRIBUTE_IN_MESSAGE.match(e.message)
            attr = am.group(1) if am else None
            if "This element is not expected" in e.message:
                actions.append((node, None, True))
            elif attr is not None and "is required but missing" not in e.message \
                    and attr not in REQUIRED_ATTRIBUTES.get(node.tag, ()):
                actions.append((node, attr, False))
            else:
                actions.append((node, None, True))
        if not fresh or not actions:
            break
        for node, attr, drop in actions:
            if drop:
                parent = node.getparent()
                if parent is None:
                    continue  # the root stays; its problems are reported
                for el in node.iter(_S + "state", _E + "module"):
                    name = el.get("id") if el.tag == _S + "state" else el.get("name")
                    if name:
                        withdrawn.add(name)
                parent.remove(node)
            else:
                node.attrib.pop(attr, None)  # type: ignore[arg-type]
    return copy, problems, withdrawn, _states_within(copy, named)


def _states_within(root: etree._Element, ids: set[str]) -> set[str]:
    """``ids`` and the ids of every state inside the states they name."""
    out = set(ids)
    for el in root.iter(_S + "state"):
        if el.get("id") in ids:
            out.update(d.get("id") for d in el.iter(_S + "state") if d.get("id"))
    return out


def _follows_from_withdrawn(problem: AFSMError, withdrawn: set[str], named: set[str] = frozenset()) -> bool:  # type: ignore[assignment]
    """A semantic problem that only repeats an earlier refusal.

    A target, initial or module naming an element taken out ("does not
    exist", "unknown module"), or a state that is unreachable only because
    the refused transition or initial that named it was taken out.
    """
    msg = problem.message
    if "is unreachable" in msg:
        return any(f"state {name!r} is unreachable" in msg for name in named)
    if "does not exist" not in msg and "unknown module" not in msg:
        return False
    return any(f"{name!r}" in msg for name in withdrawn)


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
            m.modules[name] = ModuleDecl(name, el.get("layer"), el.sourceline, source)
        elif el.tag == _E + "event":
            name = el.get("name")
            if name in m.events:
                problems.append(AFSMError(f"event {name!r} declared twice (first at line {m.events[name].line})", source=source, line=el.sourceline, element="es:event"))
                continue
            lt = el.get("lifetime")
            m.events[name] = EventDecl(name, _seconds_ns(lt) if lt else None, el.get("source"), el.sourceline, source)
        elif el.tag == _S + "state":
            _build_state(m, el, None, problems)
    return m, problems


def _build_state(m: Machine, el: etree._Element, parent: str | None, problems: list[AFSMError]) -> None:
    sid = el.get("id")
    if sid in m.states:
        first = m.states[sid].line
        problems.append(AFSMError(f"duplicate state id {sid!r} (first defined at line {first}; rule: ids are unique)", source=m.source, line=el.sourceline, element="state"))
        return
    st = State(id=sid, parent=parent, initial=el.get("initial"), doc=_doc_comment(el), line=el.sourceline, file=m.source)
    m.states[sid] = st
    if parent is None:
        m.roots.append(sid)
    else:
        m.states[parent].children.append(sid)
    for child in el:
        if child.tag == _S + "transition":
            st.transitions.append(_build_transition(child, m.source))
        elif child.tag == _S + "state":
            _build_state(m, child, sid, problems)


def _build_transition(el: etree._Element, source: str) -> Transition:
    sends = []
    stores = []
    for s in el:
        if s.tag == _E + "store":
            stores.append(Store(s.get("name"), s.get("expr"), s.get("append") in ("true", "1"), s.sourceline, source))
            continue
        if s.tag != _S + "send":
            continue
        params = tuple(Param(p.get("name"), p.get("expr"), p.sourceline, source, tuple((p.get(_E + "with") or "").split()))
                       for p in s if p.tag == _S + "param")
        sends.append(Send(s.get(_E + "kind"), s.get("target"), s.get("event"), params, s.sourceline, source))
    return Transition(el.get("event"), el.get("target"), el.get("cond"), tuple(sends), el.sourceline, source, tuple(stores))


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
    stripped, schema_problems, withdrawn, named = _schema_pass(root, source)
    problems += schema_problems
    try:
        machine, dup = _build(stripped, source)
    except (InvalidOperation, ValueError) as exc:  # pragma: no cover - bad values are stripped
        return None, sorted(problems + [AFSMError(f"cannot read the document: {exc}", source=source)],
                            key=lambda p: p.line or 0)
    semantic = dup + ([] if fragment else validate(machine))
    problems += [p for p in semantic if not _follows_from_withdrawn(p, withdrawn, named)]
    problems.sort(key=lambda p: p.line or 0)
    return (None if problems else machine), problems


#: The read -> parse -> check -> model pipeline of an AFSM document (malformed text raises XMLInputError).
AFSM_DOCUMENT: DocumentKind[Machine, AFSMError] = DocumentKind(
    check_root=check_root, error=AFSMError, problems=AFSMProblems, prepare=_start_lines, malformed_as_problems=False)


def check(data: bytes | str, *, source: str = "<string>") -> list[AFSMError]:
    """Every problem of an AFSM document given as text (empty list when it loads)."""
    return AFSM_DOCUMENT.check(data, source=source)


def check_file(path: str | os.PathLike[str]) -> list[AFSMError]:
    """Every problem of an AFSM file (empty list when it loads)."""
    return AFSM_DOCUMENT.check_file(path)


def from_element(root: etree._Element, *, source: str, fragment: bool = False) -> Machine:
    """The machine of a parsed document; raises :class:`AFSMProblems` listing every problem."""
    return AFSM_DOCUMENT.from_element(root, source=source, fragment=fragment)


def loads(data: bytes | str, *, source: str = "<string>", fragment: bool = False) -> Machine:
    """Load an AFSM from text. Raises XMLInputError (malformed) or AFSMProblems."""
    return AFSM_DOCUMENT.loads(data, source=source, fragment=fragment)


def load(path: str | os.PathLike[str], *, fragment: bool = False) -> Machine:
    """Load an AFSM file. Raises XMLInputError (malformed) or AFSMProblems naming file and lines."""
    return AFSM_DOCUMENT.load(path, fragment=fragment)


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
                pe = etree.SubElement(se, _S + "param", name=p.name, expr=p.expr)
                if p.stored:
                    pe.set(_E + "with", " ".join(p.stored))
        for sto in t.stores:
            sx = etree.SubElement(te, _E + "store", name=sto.name, expr=sto.expr)
            if sto.append:
                sx.set("append", "true")
    for child in st.children:
        _dump_state(m, el, child)


def dumps(m: Machine) -> str:
    """The machine as SCXML text (pretty-printed, loadable by :func:`loads`)."""
    return etree.tostring(to_element(m), encoding="unicode", pretty_print=True)
