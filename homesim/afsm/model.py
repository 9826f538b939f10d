"""The AFSM as plain data, and its semantic validation.

An augmented finite state machine (AFSM) is what the execution supervisor
runs: leaf states, *categories* (compound states grouping leaves so that
events can be retained while the machine is anywhere inside them),
transitions labelled with exactly one event name (optionally guarded by an
XPath on the event's payload), and on each transition a list of *sends*:
orders (downward, to intermediate and reactive modules) and conditions
(upward, to deliberative modules) whose parameters are copied from the
triggering event by XPath.

This module holds data and checks only: no file I/O, no time, no bus
(sismic's ``model/``). :func:`validate` returns every problem it finds as an
:class:`~homesim.errors.AFSMError` naming the source, line and element, so
``homesim afsm check`` can list them all. Knows nothing about BIRON.
"""

from __future__ import annotations

import re
from bisect import bisect_left
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field, replace
from typing import Any

from lxml import etree

from ..errors import AFSMError

#: Message kinds a ``<send>`` can have.
ORDER = "order"
CONDITION = "condition"
SEND_KINDS = (ORDER, CONDITION)

#: The three layers of the architecture, top to bottom. Conditions go up to
#: the deliberative layer; orders go down to the intermediate and reactive ones.
LAYERS = ("deliberative", "intermediate", "reactive")
LAYER_OF_KIND = {CONDITION: ("deliberative",), ORDER: ("intermediate", "reactive")}

#: Lifetime used for events whose name has no declared lifetime and that carry
#: none themselves (seconds, as integer nanoseconds).
DEFAULT_LIFETIME_NS = 5_000_000_000
#: Longest event lifetime (one hour, as the event schema's ``lifetime``): an event the ES keeps longer
#: than any home tour is a mistake, and an unbounded one overflows every clock it meets.
MAX_LIFETIME_NS = 3600 * 1_000_000_000

_EVENT_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_.\-]*$")
#: A module name: an XML NCName (letters, digits, ``_ . -``, not starting with a
#: digit, ``.`` or ``-``); it becomes a bus channel segment, so no ``/ * :`` or spaces.
_MODULE_NAME = re.compile(r"^[^\W\d][\w.\-]*$")


@dataclass(frozen=True, slots=True)
class Param:
    """One parameter of an order/condition: ``expr`` is an XPath on the event payload.

    ``stored`` (``es:with``): names of data stored by earlier transitions
    (:class:`Store`); the parameter's value is their contents, in this order,
    followed by what ``expr`` selects now (the ES copies data, it does not
    interpret it).
    """

    name: str
    expr: str
    line: int | None = field(default=None, compare=False)  # where it was written; not part of its meaning
    file: str | None = field(default=None, compare=False)  # the file it was written in (None: the machine's)
    stored: tuple[str, ...] = ()


@dataclass(frozen=True, slots=True)
class Store:
    """``<es:store name expr>`` on a transition: keep a copy of what ``expr`` selects in the event,
    under ``name``, for later transitions' parameters (``es:with``); ``append``: add to what is
    stored instead of replacing it."""

    name: str
    expr: str
    append: bool = False
    line: int | None = field(default=None, compare=False)
    file: str | None = field(default=None, compare=False)


@dataclass(frozen=True, slots=True)
class Send:
    """An order or condition emitted when its transition is taken."""

    kind: str  # ORDER or CONDITION
    target: str  # module name
    name: str  # message name (SCXML ``event`` attribute of <send>)
    params: tuple[Param, ...] = ()
    line: int | None = field(default=None, compare=False)  # where it was written; not part of its meaning
    file: str | None = field(default=None, compare=False)  # the file it was written in (None: the machine's)


@dataclass(frozen=True, slots=True)
class Transition:
    """A transition on one event name; ``target`` None means stay (targetless, as in SCXML)."""

    event: str
    target: str | None
    cond: str | None = None
    sends: tuple[Send, ...] = ()
    line: int | None = field(default=None, compare=False)  # where it was written; not part of its meaning
    file: str | None = field(default=None, compare=False)  # the file it was written in (None: the machine's)
    stores: tuple[Store, ...] = ()  # es:store: data kept when the transition is taken (after its sends)


@dataclass(slots=True)
class State:
    """A leaf state, or a category when it has children.

    ``parent`` is None for top-level states. ``initial`` (compound states
    only) names the descendant entered when the category itself is targeted;
    None means the first child, as in SCXML. ``doc`` is the comment that
    documents why the state exists (kept for rendering).
    """

    id: str
    parent: str | None = None
    children: list[str] = field(default_factory=list)
    transitions: list[Transition] = field(default_factory=list)
    initial: str | None = None
    doc: str = ""
    line: int | None = field(default=None, compare=False)  # where it was written; not part of its meaning
    file: str | None = field(default=None, compare=False)  # the file it was written in (None: the machine's)

    @property
    def is_category(self) -> bool:
        return bool(self.children)


@dataclass(frozen=True, slots=True)
class ModuleDecl:
    """A module the machine may send to, with its architectural layer."""

    name: str
    layer: str
    line: int | None = field(default=None, compare=False)  # where it was written; not part of its meaning
    file: str | None = field(default=None, compare=False)  # the file it was written in (None: the machine's)


@dataclass(frozen=True, slots=True)
class EventDecl:
    """A declared event name: its default lifetime and (optionally) its source module."""

    name: str
    lifetime_ns: int | None = None
    source: str | None = None
    line: int | None = field(default=None, compare=False)  # where it was written; not part of its meaning
    file: str | None = field(default=None, compare=False)  # the file it was written in (None: the machine's)


@dataclass(slots=True)
class Machine:
    """A whole AFSM. ``states`` keeps document order (dicts are ordered)."""

    name: str
    states: dict[str, State]
    roots: list[str]
    initial: str | None = None
    modules: dict[str, ModuleDecl] = field(default_factory=dict)
    events: dict[str, EventDecl] = field(default_factory=dict)
    default_lifetime_ns: int = DEFAULT_LIFETIME_NS
    source: str = "<machine>"
    line: int | None = field(default=None, compare=False)  # where it was written; not part of its meaning

    # ------------------------------------------------------------ structure
    def leaves(self) -> list[str]:
        """Leaf state ids in document order."""
        return [s.id for s in self.states.values() if not s.children]

    def categories(self) -> list[str]:
        """Category (compound state) ids in document order."""
        return [s.id for s in self.states.values() if s.children]

    def ancestors(self, state_id: str) -> list[str]:
        """The state itself, then its parent, grandparent, ... (innermost first)."""
        out = []
        cur: str | None = state_id
        while cur is not None:
            out.append(cur)
            cur = self.states[cur].parent
        return out

    def category_of(self, state_id: str) -> str | None:
        """The innermost compound state containing ``state_id`` (None at top level)."""
        return self.states[state_id].parent

    def descendants(self, state_id: str) -> list[str]:
        """Every state strictly inside ``state_id``, depth first in document order."""
        out: list[str] = []
        stack = list(reversed(self.states[state_id].children))
        while stack:
            sid = stack.pop()
            out.append(sid)
            stack.extend(reversed(self.states[sid].children))
        return out

    def initial_leaf(self) -> str:
        """The leaf the machine starts in."""
        start = self.initial if self.initial is not None else self.roots[0]
        return self.resolve_leaf(start)

    def resolve_leaf(self, state_id: str) -> str:
        """The leaf entered when ``state_id`` is targeted (initial children, recursively)."""
        sid = state_id
        seen = 0
        while self.states[sid].children:
            st = self.states[sid]
            sid = st.initial if st.initial is not None else st.children[0]
            if st.initial is not None and sid not in self.states:
                raise KeyError(sid)
            seen += 1
            if seen > len(self.states):  # an initial outside its category (validate reports it with its line)
                raise AFSMError("cyclic initial states", source=self.source)
        return sid

    def transitions(self) -> Iterator[tuple[str, Transition]]:
        """Every (owning state id, transition) in document order."""
        for st in self.states.values():
            for t in st.transitions:
                yield st.id, t

    def event_names(self) -> list[str]:
        """Every event name used on a transition, in first-use order."""
        seen: dict[str, None] = {}
        for _sid, t in self.transitions():
            seen.setdefault(t.event, None)
        return list(seen)

    def lifetime_ns(self, event_name: str) -> int:
        """Default lifetime for events of this name."""
        decl = self.events.get(event_name)
        if decl is not None and decl.lifetime_ns is not None:
            return decl.lifetime_ns
        return self.default_lifetime_ns

    def copy(self) -> Machine:
        """A copy whose states and lists can be changed without touching this one."""
        states = {
            sid: replace(st, children=list(st.children), transitions=list(st.transitions))
            for sid, st in self.states.items()
        }
        return replace(self, states=states, roots=list(self.roots), modules=dict(self.modules), events=dict(self.events))


# ---------------------------------------------------------------- validation
def _err(m: Machine, msg: str, where: Any, element: str | None) -> AFSMError:
    """A problem at ``where`` (an element of ``m``, or ``m``): in its own file, else the machine's."""
    return AFSMError(msg, source=getattr(where, "file", None) or m.source, line=where.line, element=element)


_BOOLEAN_WORD = re.compile(r"\s*(true|false)\s*", re.I)
_SCXML_EVENT_VAR = re.compile(r"(?<![\w.\-:])\$?_event(?![\w\-])")


def _guard_problem(cond: str) -> str | None:
    """A guard written as SCXML users write them, that as XPath never means what it says (or None).

    The ES refuses these rather than guess: ``cond="true"`` is a path to a
    child element named ``true`` of the event (it holds only if the event
    happens to have one), and SCXML's ``_event`` is not defined here (the
    guard's context node is the event element itself).
    """
    m = _BOOLEAN_WORD.fullmatch(cond)
    if m:
        word = m.group(1)
        return (f"{cond!r} is not a boolean: as XPath it selects a child element <{word}> of the event "
                f"and holds only if the event has one; write {word.lower()}() for the constant"
                + (" (or leave cond out)" if word.lower() == "true" else "")
                + ", or test the event, e.g. @confidence > 0.5 or SPEECH/GREETING")
    if _SCXML_EVENT_VAR.search(cond):
        return (f"{cond!r} uses SCXML's _event, which the ES does not define: the guard is an XPath "
                "evaluated on the <event> element itself; write @attr or CHILD/... (e.g. SPEECH/GREETING)")
    return None


#: Bounds on guard and parameter XPaths (with the engine's MAX_PAYLOAD_ELEMENTS
#: they bound a guard's cost: at most n**MAX_XPATH_DEEP_STEPS node visits on
#: a payload of n elements, 65 536 for 256).
MAX_XPATH_LENGTH = 1000
MAX_XPATH_DEEP_STEPS = 2
_DEEP_STEP = re.compile(r"//|\b(?:descendant|descendant-or-self|ancestor|ancestor-or-self|following|preceding|following-sibling|preceding-sibling)\s*::")


def _xpath_problem(expr: str) -> str | None:
    """None when ``expr`` compiles, is within the cost bounds and evaluates on an empty event, else the reason."""
    if len(expr) > MAX_XPATH_LENGTH:
        return f"XPath of {len(expr)} characters is longer than {MAX_XPATH_LENGTH} (rule: guards stay cheap)"
    deep = len(_DEEP_STEP.findall(expr))
    if deep > MAX_XPATH_DEEP_STEPS:
        return (f"XPath {expr[:80]!r} has {deep} descendant/ancestor/sibling steps; at most {MAX_XPATH_DEEP_STEPS} "
                "are allowed (rule: a guard's cost is bounded: each such step may scan the whole payload)")
    try:
        xp = etree.XPath(expr)
    except etree.XPathSyntaxError as exc:
        return f"invalid XPath {expr!r}: {exc}"
    try:
        xp(etree.Element("event"))
    except etree.XPathError as exc:
        return f"XPath {expr!r} cannot be evaluated: {exc}"
    return None


def reachable_leaves(m: Machine) -> list[str]:
    """Leaves reachable from the initial leaf, in document order.

    A transition written on a category applies in each of its states, so the
    transitions of every ancestor of a reachable leaf count; a target that is
    a category enters its initial leaf.
    """
    if not m.roots:
        return []
    try:
        start = m.initial_leaf()
    except KeyError:
        return []
    seen = {start}
    todo = [start]
    while todo:
        leaf = todo.pop()
        for sid in m.ancestors(leaf):
            for t in m.states[sid].transitions:
                if t.target is None or t.target not in m.states:
                    continue
                try:
                    nxt = m.resolve_leaf(t.target)
                except (KeyError, AFSMError):  # missing or cyclic initial: reported by validate
                    continue
                if nxt not in seen:
                    seen.add(nxt)
                    todo.append(nxt)
    return [sid for sid in m.leaves() if sid in seen]


def _lifetime_ok(ns: Any) -> bool:
    """A lifetime in integer nanoseconds, in (0, MAX_LIFETIME_NS]."""
    return isinstance(ns, int) and not isinstance(ns, bool) and 0 < ns <= MAX_LIFETIME_NS


def validate(m: Machine) -> list[AFSMError]:
    """Every semantic problem of ``m`` (empty list when it can run).

    Rules: at least one state; module names are NCNames; the initial states
    exist (a category's initial is one of its descendants); every target exists; event names are plain
    names (no SCXML wildcards or prefix lists) and no transition's event is a dot-prefix of another
    name in the machine (SCXML would match it by prefix, the ES matches exactly); guards and parameters are
    valid XPath; every send goes to a declared module, orders downward and
    conditions upward; lifetimes are positive; every leaf is reachable.
    """
    problems: list[AFSMError] = []
    add = problems.append
    if not m.states:
        add(_err(m, "the machine has no states (rule: at least one <state>)", m, "scxml"))
        return problems
    if m.initial is not None and m.initial not in m.states:
        add(_err(m, f"initial state {m.initial!r} does not exist (rule: initial names a state)", m, "scxml"))
    if not _lifetime_ok(m.default_lifetime_ns):
        add(_err(m, f"default lifetime must be positive and at most {MAX_LIFETIME_NS // 10**9} s", m, "scxml"))
    for key, decl in m.modules.items():
        if not isinstance(decl.name, str) or not _MODULE_NAME.fullmatch(decl.name) or key != decl.name:
            add(_err(m, f"module name {decl.name!r} is not an NCName (rule: module names are XML NCNames, "
                        "used as bus channel segments: letters, digits, _ . -)", decl, "es:module"))
        if decl.layer not in LAYERS:
            add(_err(m, f"module {decl.name!r} has unknown layer {decl.layer!r} (one of {', '.join(LAYERS)})", decl, "es:module"))
    for decl in m.events.values():
        if decl.lifetime_ns is not None and not _lifetime_ok(decl.lifetime_ns):
            add(_err(m, f"event {decl.name!r}: lifetime must be positive and at most {MAX_LIFETIME_NS // 10**9} s", decl, "es:event"))
        if decl.source is not None and decl.source not in m.modules:
            add(_err(m, f"event {decl.name!r} comes from unknown module {decl.source!r} (rule: declare it with <es:module>)", decl, "es:event"))
    stored_names = {sto.name for _sid, t in m.transitions() for sto in t.stores}
    for _sid, t in m.transitions():
        for sto in t.stores:
            why = _xpath_problem(sto.expr)
            if why:
                add(_err(m, f"es:store {sto.name!r}: {why}", sto, "es:store"))
        for snd in t.sends:
            for prm in snd.params:
                for name in prm.stored:
                    if name not in stored_names:
                        add(_err(m, f"{snd.kind} {snd.name!r} parameter {prm.name!r} uses stored data {name!r} that no "
                                    "transition stores (rule: es:with names an es:store)", prm, "param"))
    for st in m.states.values():
        if st.initial is not None and (st.initial not in m.states or st.initial == st.id or st.id not in m.ancestors(st.initial)):
            what = "does not exist" if st.initial not in m.states else f"is not inside {st.id!r}"
            add(_err(m, f"initial state {st.initial!r} of {st.id!r} {what} (rule: a category's initial is one of its states)", st, "state"))
        for t in st.transitions:
            _check_transition(m, st, t, add)
    # SCXML matches a transition's event by prefix ("error" matches "error.send"); the ES matches
    # names exactly. A name that is a dot-prefix of another name in the machine would behave
    # differently from SCXML without a word, so it is refused.
    names = sorted({t.event for _sid, t in m.transitions()} | set(m.events))
    for sid, t in m.transitions():
        # the first name after "event." in sorted order is the smallest longer one, if any (log n, not n)
        at = bisect_left(names, t.event + ".")
        longer = names[at:at + 1] if at < len(names) and names[at].startswith(t.event + ".") else []
        if longer:
            add(_err(m, f"transition in {sid!r}: event {t.event!r} is a prefix of {longer[0]!r}; SCXML would match "
                        f"{longer[0]!r} to it, the ES matches names exactly (rule: no event name is a dot-prefix "
                        "of another; write the full name)", t, "transition"))
    try:
        m.initial_leaf()
        start_ok = True
    except (KeyError, AFSMError):
        start_ok = False  # a missing or cyclic initial, already reported with its line above
    if start_ok:
        reach = set(reachable_leaves(m))
        for leaf in m.leaves():
            if leaf not in reach:
                st = m.states[leaf]
                add(_err(m, f"state {leaf!r} is unreachable from the initial state (rule: every state is reachable)", st, "state"))
    return problems


def _check_transition(m: Machine, st: State, t: Transition, add: Any) -> None:
    if not _EVENT_NAME.fullmatch(t.event):
        add(_err(m, f"transition in {st.id!r}: event {t.event!r} is not a plain event name (wildcards and prefix matching are not supported)", t, "transition"))
    if t.target is not None and t.target not in m.states:
        add(_err(m, f"transition in {st.id!r} on {t.event!r}: target {t.target!r} does not exist (rule: targets name a state)", t, "transition"))
    if t.cond is not None:
        why = _guard_problem(t.cond) or _xpath_problem(t.cond)
        if why:
            add(_err(m, f"transition in {st.id!r} on {t.event!r}: guard {why}", t, "transition"))
    for s in t.sends:
        if s.kind not in SEND_KINDS:
            add(_err(m, f"send {s.name!r}: kind must be order or condition, not {s.kind!r}", s, "send"))
            continue
        decl = m.modules.get(s.target)
        if decl is None:
            add(_err(m, f"{s.kind} {s.name!r} is sent to unknown module {s.target!r} (rule: declare it with <es:module>)", s, "send"))
        elif decl.layer in LAYERS and decl.layer not in LAYER_OF_KIND[s.kind]:
            direction = "upward" if s.kind == ORDER else "downward"
            rule = "orders go down to intermediate/reactive modules" if s.kind == ORDER else "conditions go up to deliberative modules"
            add(_err(m, f"{s.kind} {s.name!r} sent {direction} to {decl.layer} module {s.target!r} (rule: {rule})", s, "send"))
        names: dict[str, None] = {}
        for p in s.params:
            if p.name in names:
                add(_err(m, f"{s.kind} {s.name!r}: duplicate parameter {p.name!r}", p, "param"))
            names[p.name] = None
            why = _xpath_problem(p.expr)
            if why:
                add(_err(m, f"{s.kind} {s.name!r} parameter {p.name!r}: {why}", p, "param"))


def merge(base: Machine, ext: Machine) -> Machine:
    """``base`` extended by ``ext``: new states added, transitions appended.

    A state of ``ext`` whose id exists in ``base`` contributes its
    transitions (appended after the existing ones) and its new children; a
    new id is added under its parent in ``ext`` (or at top level). Modules
    and events are added; a module redeclared with another layer is a
    conflict. What comes from ``ext`` keeps its own file (``file``, or
    ``ext.source``), so problems found in the result name the extension's
    file and line. The result is not validated here (see :func:`validate`).
    """
    out = base.copy()
    here = ext.source
    for decl in ext.modules.values():
        old = out.modules.get(decl.name)
        if old is not None and old.layer != decl.layer:
            raise AFSMError(
                f"module {decl.name!r} redeclared as {decl.layer} (was {old.layer})",
                source=ext.source, line=decl.line, element="es:module",
            )
        out.modules.setdefault(decl.name, decl if decl.file else replace(decl, file=here))
    for decl in ext.events.values():
        out.events[decl.name] = decl if decl.file else replace(decl, file=here)
    for st in ext.states.values():
        if st.id in out.states:
            cur = out.states[st.id]
            if st.parent is not None and cur.parent != st.parent:
                raise AFSMError(
                    f"state {st.id!r} exists under {cur.parent!r}, cannot move it under {st.parent!r}",
                    source=ext.source, line=st.line, element="state",
                )
            cur.transitions.extend(_in_file(t, st.file or here) for t in st.transitions)
            if st.initial is not None:
                cur.initial = st.initial
        else:
            out.states[st.id] = replace(st, children=[], file=st.file or here,
                                        transitions=[_in_file(t, st.file or here) for t in st.transitions])
            if st.parent is None:
                out.roots.append(st.id)
            else:
                out.states[st.parent].children.append(st.id)
    return out


def _in_file(t: Transition, file: str) -> Transition:
    """``t`` with ``file`` on it and on its sends and parameters that name none (errors point there)."""
    if t.file and all(snd.file and all(p.file for p in snd.params) for snd in t.sends):
        return t
    sends = tuple(replace(snd, file=snd.file or file, params=tuple(p if p.file else replace(p, file=file) for p in snd.params))
                  for snd in t.sends)
    return replace(t, file=t.file or file, sends=sends)


def iter_problems(items: Iterable[AFSMError]) -> list[str]:
    """The problems as one formatted line each (for CLIs and reports)."""
    return [str(p) for p in items]

