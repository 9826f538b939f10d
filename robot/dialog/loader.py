"""Sub-dialog documents: hardened parse -> XSD -> model -> semantic checks, every problem with file and line.

The pipeline is the supervisor's (:mod:`homesim.afsm.loader`): the text is
parsed by the project's hardened parser, validated against ``dialogs.xsd``
(every schema problem is reported, not only the first), turned into the
immutable model of :mod:`robot.dialog.model`, and checked for what a schema
cannot say: slots that exist, acts and events the robot knows, triggers that
do not compete, templates and XPaths that compile, policies that can end.
:func:`check` returns every problem; :func:`load`/:func:`loads` raise
:class:`DialogProblems` carrying them all, so nothing is ever half-loaded.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

from lxml import etree

from homesim.errors import InputError
from homesim.xmldoc import DocumentKind
from homesim.xmlio import load_schema

from .model import (
    ACTS,
    DIALOG_EVENTS,
    STATUSES,
    Action,
    DialogDef,
    Dialogs,
    Fill,
    Rejection,
    Rule,
    template_fields,
)

SCHEMA_FILE = Path(__file__).with_name("dialogs.xsd")
BIRON_DIALOGS = Path(__file__).with_name("biron-dialogs.xml")
ROOT = "dialogs"

#: The manager's own words, each a ``<sentence id>`` of the document, with the fields its template may use.
SENTENCES: dict[str, frozenset[str]] = {
    "not-understood-reask": frozenset(),  # before an open question said again when nothing was understood
    "give-up": frozenset(),  # a dialog gives up after too many re-asks
    # a third turn in a row not understood, no question open: no third "could you say that again?"
    # but what she can say (the robot never asks the same question more than twice)
    "not-understood-help": frozenset(),
    "can-now": frozenset({"capabilities"}),  # the self-explanation's list of what the user can do now
    "list": frozenset({"items", "last"}),  # how a list is said: "{items} or {last}"
    "option": frozenset({"option"}),  # one option of a clarification question: "the {option}"
    "same-noun": frozenset(),  # the word for a repeated noun in options ("the blue one")
    # she showed something while the robot followed (refused then): asked about once she has stopped
    "shown-in-passing": frozenset({"object"}),
}


class DialogError(InputError):
    """A dialog document cannot be loaded (names file, line and element)."""


class DialogProblems(DialogError):
    """Every problem of a dialog document; ``problems`` lists them in document order."""

    def __init__(self, problems: list[DialogError]) -> None:
        if not problems:
            raise ValueError("DialogProblems needs at least one problem")
        self.problems = list(problems)
        first = problems[0]
        more = len(problems) - 1
        msg = first.message + (f" (and {more} more problem{'s' if more > 1 else ''})" if more else "")
        super().__init__(msg, source=first.source, line=first.line, element=first.element)


def _line(el: etree._Element) -> int | None:
    return el.sourceline if el.sourceline else None


class _Checker:
    def __init__(self, source: str) -> None:
        self.source = source
        self.problems: list[DialogError] = []

    def add(self, el: etree._Element | None, message: str) -> None:
        tag = None if el is None else etree.QName(el).localname
        self.problems.append(DialogError(message, source=self.source, line=None if el is None else _line(el), element=tag))

    def xpath(self, el: etree._Element, expr: str, what: str) -> etree.XPath | None:
        try:
            return etree.XPath(expr)
        except etree.XPathSyntaxError as exc:
            self.add(el, f"{what} {expr!r} is not a valid XPath: {exc}")
            return None


def _text(el: etree._Element) -> str:
    return " ".join((el.text or "").split())


def _build(root: etree._Element, c: _Checker) -> Dialogs:
    """The model of a schema-valid document; semantic problems go to ``c``."""
    states: dict[str, frozenset[str]] = {}
    for el in root.iterfind("states"):
        if el.get("id") in states:
            c.add(el, f"state set {el.get('id')!r} is defined twice")
        states[el.get("id", "")] = frozenset(_text(el).split())
    caps: dict[str, str] = {}
    for el in root.iterfind("capability"):
        ev = el.get("event", "")
        if ev not in DIALOG_EVENTS:
            c.add(el, f"capability for {ev!r}: the dialog sends no such event (it sends {', '.join(DIALOG_EVENTS)})")
        if ev in caps:
            c.add(el, f"capability for {ev!r} is given twice")
        caps[ev] = _text(el)
    phrases = {el.get("state", ""): _text(el) for el in root.iterfind("state-phrase")}
    rejections = tuple(
        Rejection(el.get("event"), el.get("reason"), el.get("state"), _text(el), _line(el)) for el in root.iterfind("rejection")
    )
    if not any(r.event is None and r.reason is None and r.state is None for r in rejections):
        c.add(root, "no default <rejection> (without event, reason and state): some rejection would have no words")
    nu = root.find("not-understood")
    sentences: dict[str, str] = {}
    for el in root.iterfind("sentence"):
        sid = el.get("id", "")
        if sid not in SENTENCES:
            c.add(el, f"sentence {sid!r} is not one the dialog manager says (sentences: {', '.join(SENTENCES)})")
            continue
        if sid in sentences:
            c.add(el, f"sentence {sid!r} is given twice")
        text = _text(el)
        for name, _xp, _ in template_fields(text):
            if name not in SENTENCES[sid]:
                allowed = ", ".join(sorted(SENTENCES[sid])) or "none"
                c.add(el, f"sentence {sid!r}: field {{{name}}} is not one it has (fields: {allowed})")
        sentences[sid] = text
    for sid in SENTENCES:
        if sid not in sentences:
            c.add(root, f"no <sentence id=\"{sid}\">: the dialog manager would have no words for it")
    dialogs: dict[str, DialogDef] = {}
    triggers: dict[str, str] = {}
    conditions: dict[str, str] = {}
    for del_ in root.iterfind("dialog"):
        d = _build_dialog(del_, c, states)
        if d.id in dialogs:
            c.add(del_, f"dialog {d.id!r} is defined twice")
        dialogs[d.id] = d
        for act in d.trigger:
            if act in triggers:
                c.add(del_, f"dialog {d.id!r}: {act} already starts dialog {triggers[act]!r}")
            triggers[act] = d.id
        if d.condition is not None:
            if d.condition in conditions:
                c.add(del_, f"dialog {d.id!r}: condition {d.condition!r} already starts dialog {conditions[d.condition]!r}")
            conditions[d.condition] = d.id
    return Dialogs(
        name=root.get("name", ""),
        confirm_below=float(root.get("confirm-below", "0.5")),
        max_reasks=int(root.get("max-reasks", "2")),
        max_depth=int(root.get("max-depth", "4")),
        drop_after=int(root.get("drop-after", "2")),
        states=states,
        capabilities=caps,
        state_phrases=phrases,
        rejections=rejections,
        not_understood=_text(nu) if nu is not None else "",
        dialogs=dialogs,
        sentences=sentences,
    )


def _build_dialog(el: etree._Element, c: _Checker, states: dict[str, frozenset[str]]) -> DialogDef:
    did = el.get("id", "")
    slots: list[str] = []
    for s in el.iterfind("slot"):
        name = s.get("name", "")
        if name in slots:
            c.add(s, f"dialog {did!r}: slot {name!r} is declared twice")
        slots.append(name)

    def slot_ok(node: etree._Element, name: str | None, what: str) -> None:
        if name is not None and name not in slots:
            c.add(node, f"dialog {did!r}: {what} names slot {name!r}, which is not declared (slots: {', '.join(slots)})")

    trigger = tuple((el.get("trigger") or "").split())
    for act in trigger:
        if act not in ACTS:
            c.add(el, f"dialog {did!r}: trigger {act!r} is not a frame act (acts: {', '.join(ACTS)})")
    in_set = el.get("in")
    if in_set is not None and in_set not in states:
        c.add(el, f"dialog {did!r}: in={in_set!r} names no <states> set")
    sent: set[str] = set()
    rules: list[Rule] = []
    can_end = False
    for rel in el.iterfind("policy/rule"):
        whens = tuple((w.get("slot", ""), w.get("status", "")) for w in rel.iterfind("when"))
        for w, (slot, _) in zip(rel.iterfind("when"), whens):
            slot_ok(w, slot, "<when>")
        if len(set(s for s, _ in whens)) != len(whens):
            c.add(rel, f"dialog {did!r}: a rule tests the same slot twice")
        actions: list[Action] = []
        for a in rel:
            if not isinstance(a.tag, str) or a.tag == "when":
                continue
            kind = a.tag
            text = _text(a) if kind in ("say", "ask", "confirm") else ""
            slot = a.get("slot")
            slot_ok(a, slot, f"<{kind}>")
            for name, _xp, _ in template_fields(text):
                slot_ok(a, name, "the template")
                if _xp:
                    c.xpath(a, _xp, "template field")
            copies: tuple[tuple[str, str], ...] = ()
            event = a.get("event")
            if kind == "send":
                if event not in DIALOG_EVENTS:
                    c.add(a, f"dialog {did!r}: event {event!r} is not one the dialog sends (events: {', '.join(DIALOG_EVENTS)})")
                sent.add(event or "")
                copies = tuple((cp.get("slot", ""), cp.get("as", "")) for cp in a.iterfind("copy"))
                for cp, (s, _) in zip(a.iterfind("copy"), copies):
                    slot_ok(cp, s, "<copy>")
            can_end |= kind == "end"
            lifetime = a.get("lifetime")
            actions.append(Action(kind, slot=slot, text=text, event=event,
                                  lifetime=float(lifetime) if lifetime is not None else None,
                                  copies=copies, pose=a.find("pose") is not None, line=_line(a),
                                  once=kind == "ask" and a.get("once") in ("true", "1")))
        rule_in = rel.get("in")
        if rule_in is not None and rule_in not in states:
            c.add(rel, f"dialog {did!r}: rule in={rule_in!r} names no <states> set")
        rules.append(Rule(whens, tuple(actions), _line(rel), states.get(rule_in) if rule_in else None))
    if not can_end:
        c.add(el.find("policy"), f"dialog {did!r}: no rule has <end/>, so the dialog could never finish")
    fills: list[Fill] = []
    for f in el.iterfind("fill"):
        slot_ok(f, f.get("slot"), "<fill>")
        sources = [k for k in ("frame", "condition", "rejected") if f.get(k) is not None]
        if len(sources) != 1:
            c.add(f, f"dialog {did!r}: a <fill> needs exactly one of frame, condition, rejected (has {sources or 'none'})")
        if f.get("status") is not None and f.get("test") is not None:
            c.add(f, f"dialog {did!r}: a <fill> has status or test, not both")
        frame = tuple((f.get("frame") or "").split()) or None
        for act in frame or ():
            if act not in ACTS:
                c.add(f, f"dialog {did!r}: frame {act!r} is not a frame act (acts: {', '.join(ACTS)})")
        rej = f.get("rejected")
        if rej is not None and rej not in sent:
            c.add(f, f"dialog {did!r}: fills on the rejection of {rej!r}, an event this dialog never sends")
        sel = f.get("select")
        test = f.get("test")
        fills.append(Fill(
            slot=f.get("slot", ""), frame=frame, condition=f.get("condition"), rejected=rej,
            select=c.xpath(f, sel, "select") if sel else None, status=f.get("status"),
            test=c.xpath(f, test, "test") if test else None, line=_line(f),
        ))
    for act in trigger:
        if not any(fl.frame and act in fl.frame for fl in fills):
            c.add(el, f"dialog {did!r}: trigger {act} fills no slot (add a <fill frame=\"{act}\">)")
    cond = el.get("condition")
    if cond is not None and not any(fl.condition == cond for fl in fills):
        c.add(el, f"dialog {did!r}: condition {cond!r} starts it but fills no slot")
    goal = tuple((w.get("slot", ""), w.get("status", "")) for w in el.iterfind("goal/when"))
    for w in el.iterfind("goal/when"):
        slot_ok(w, w.get("slot"), "<goal>")
    resume = el.find("resume")
    if resume is not None:
        for name, xp, _ in template_fields(_text(resume)):
            slot_ok(resume, name, "the template")
            if xp:
                c.xpath(resume, xp, "template field")
    assert all(s in STATUSES for _, s in goal)
    return DialogDef(
        id=did, trigger=trigger, condition=cond, in_states=states.get(in_set) if in_set else None,
        interrupts=el.get("interrupts") in ("true", "1"), clears=el.get("clears") in ("true", "1"),
        slots=tuple(slots), fills=tuple(fills), goal=goal,
        resume=_text(resume) if resume is not None else None, rules=tuple(rules), line=_line(el),
        another_request_no=el.get("another-request") == "no",
    )


def check_root(root: etree._Element, *, source: str) -> tuple[Dialogs | None, list[DialogError]]:
    """Schema, model and semantic checks of a parsed document; the model only when there is no problem."""
    c = _Checker(source)
    if etree.QName(root).localname != ROOT or etree.QName(root).namespace is not None:
        c.add(root, f"the root element must be <{ROOT}> (no namespace), not <{root.tag}>")
        return None, c.problems
    schema = load_schema(SCHEMA_FILE)
    errors = schema.errors(root)
    for line, message in errors:
        c.problems.append(DialogError(f"does not satisfy {SCHEMA_FILE.name}: {message}", source=source, line=line or None))
    if errors:
        return None, c.problems
    model = _build(root, c)
    _check_templates(model, c, root)
    return (None if c.problems else model), c.problems


_TEMPLATE = re.compile(r"\{[^{}]*\}")


def _check_templates(model: Dialogs, c: _Checker, root: etree._Element) -> None:
    for el in root.iter("say", "ask", "confirm", "resume", "sentence"):
        text = _text(el)
        if text.count("{") != len(_TEMPLATE.findall(text)) or text.count("}") != text.count("{"):
            c.add(el, f"unbalanced braces in the template {text!r}")


#: The read -> parse -> check -> model pipeline of a dialog document (malformed text is one more problem).
DIALOG_DOCUMENT: DocumentKind[Dialogs, DialogError] = DocumentKind(
    check_root=check_root, error=DialogError, problems=DialogProblems)


def check(data: bytes | str, *, source: str = "<string>") -> list[DialogError]:
    """Every problem of a dialog document given as text (empty: it loads)."""
    return DIALOG_DOCUMENT.check(data, source=source)


def check_file(path: str | os.PathLike[str]) -> list[DialogError]:
    """Every problem of a dialog file (empty: it loads)."""
    return DIALOG_DOCUMENT.check_file(path)


def loads(data: bytes | str, *, source: str = "<string>") -> Dialogs:
    """Load a dialog document from text; raises :class:`DialogProblems` with every problem."""
    return DIALOG_DOCUMENT.loads(data, source=source)


def load(path: str | os.PathLike[str] = BIRON_DIALOGS) -> Dialogs:
    """Load a dialog file; raises :class:`DialogProblems` (file, line, element) with every problem."""
    return DIALOG_DOCUMENT.load(path)
