"""The sub-dialog model: what a dialog document says, immutable once loaded.

A :class:`Dialogs` holds the sub-dialogs (:class:`DialogDef`), the sentences
for rejections and self-explanation, and the repair parameters. A dialog's
state is the combination of its slots' statuses (:data:`STATUSES`); its
policy is an ordered list of :class:`Rule` s from such combinations to
actions. Templates (``{slot}``, ``{slot:xpath}``, ``{slot:xpath|default}``)
put slot values into sentences; :func:`render` never raises (a missing value
gives the default, or nothing); besides XPath 1.0 they may use ``noun-phrase()``
(:func:`noun_phrase`: an object as the robot says it back, "your favourite cup").
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any

from lxml import etree

#: Slot statuses (docs/semantics.md §4).
STATUSES = ("empty", "filled", "true", "false")

#: Dialog acts of the understanding's frames (the children of <SPEECH>).
ACTS = (
    "GREETING", "GOODBYE", "CAPABILITIES", "FOLLOW", "STOP", "WAIT", "YES", "NO", "THAT_ONE",
    "GOTO", "WHERE", "OBJECT", "PLACE", "MAKE_WAY",
)

#: Events the dialog sends to the supervisor (docs/robot-contract.md).
DIALOG_EVENTS = (
    "greeting", "follow", "stop", "goodbye", "object_teaching", "query_object", "place_teaching", "goto", "make_way",
)


@dataclass(frozen=True, slots=True)
class Fill:
    """How a slot is filled: from a frame act, a condition, or the rejection of an event."""

    slot: str
    frame: tuple[str, ...] | None
    condition: str | None
    rejected: str | None
    select: etree.XPath | None  # value, relative to the act element / the condition / the rejection
    status: str | None  # fixed status; None: from the confidence (frames) or the test
    test: etree.XPath | None
    line: int | None = None


@dataclass(frozen=True, slots=True)
class Action:
    """One policy action: say, send, ask, confirm, explain, explain-rejection, clear, end."""

    kind: str
    slot: str | None = None
    text: str = ""
    event: str | None = None
    lifetime: float | None = None
    copies: tuple[tuple[str, str], ...] = ()
    pose: bool = False
    line: int | None = None
    once: bool = False  # an ask put at most once: an answer without its slot sets it "false"


@dataclass(frozen=True, slots=True)
class Rule:
    """When every (slot, status) holds (and the supervisor is in ``in_states``, if given), do the actions (in order)."""

    whens: tuple[tuple[str, str], ...]
    actions: tuple[Action, ...]
    line: int | None = None
    in_states: frozenset[str] | None = None


@dataclass(frozen=True, slots=True)
class DialogDef:
    """One sub-dialog: slots, how they fill, goal, policy."""

    id: str
    trigger: tuple[str, ...]
    condition: str | None
    in_states: frozenset[str] | None
    interrupts: bool
    clears: bool
    slots: tuple[str, ...]
    fills: tuple[Fill, ...]
    goal: tuple[tuple[str, str], ...]
    resume: str | None
    rules: tuple[Rule, ...]
    line: int | None = None
    #: another request said while its confirmation is open answers that question no (``another-request="no"``):
    #: the question asked whether to act ("Do you want to end the tour?"); she asked for something else instead
    another_request_no: bool = False


@dataclass(frozen=True, slots=True)
class Rejection:
    """A sentence for a rejected event; ``None`` fields match anything."""

    event: str | None
    reason: str | None
    state: str | None
    text: str
    line: int | None = None

    def score(self, event: str, reason: str, state: str) -> int:
        """How specifically this entry matches (-1: it does not)."""
        s = 0
        for mine, theirs in ((self.event, event), (self.reason, reason), (self.state, state)):
            if mine is None:
                continue
            if mine != theirs:
                return -1
            s += 1
        return s


@dataclass(frozen=True, slots=True)
class Dialogs:
    """A loaded dialog document."""

    name: str
    confirm_below: float
    max_reasks: int
    max_depth: int
    states: dict[str, frozenset[str]]
    capabilities: dict[str, str]
    state_phrases: dict[str, str]
    rejections: tuple[Rejection, ...]
    not_understood: str
    dialogs: dict[str, DialogDef]
    sentences: dict[str, str]  # the manager's own words by id (loader.SENTENCES), templates
    drop_after: int = 2  # user turns passing over an interrupted dialog's question before it is dropped

    def sentence(self, sid: str, **values: Any) -> str:
        """The document's sentence ``sid`` with its fields filled (a missing one: empty)."""
        return render(self.sentences.get(sid, ""), values)

    def listing(self, items: list[str]) -> str:
        """Items as the document lists them ("a, b or c" from its ``list`` sentence)."""
        items = [i for i in items if i]
        if len(items) <= 1:
            return items[0] if items else ""
        return self.sentence("list", items=", ".join(items[:-1]), last=items[-1])

    def rejection_text(self, event: str, reason: str, state: str) -> str:
        """The most specific sentence for a rejection (ties: the first in the document)."""
        best, best_score = "", -1
        for r in self.rejections:
            sc = r.score(event, reason, state)
            if sc > best_score:
                best, best_score = r.text, sc
        return best

    def by_trigger(self, act: str) -> DialogDef | None:
        for d in self.dialogs.values():
            if act in d.trigger:
                return d
        return None

    def by_condition(self, name: str) -> DialogDef | None:
        for d in self.dialogs.values():
            if d.condition == name:
                return d
        return None


_FIELD = re.compile(r"\{(\w+)(?::([^}|]*))?(?:\|([^}]*))?\}")


def template_fields(text: str) -> list[tuple[str, str, str | None]]:
    """(slot, xpath, default) of each ``{...}`` field of a template."""
    return [(m.group(1), m.group(2) or "", m.group(3)) for m in _FIELD.finditer(text)]


#: Owners as the understanding and the object attention write them, seen from the partner's side.
_OWNED_BY_PARTNER = frozenset({"speaker", "partner", "my", "me", "mine", "i"})
_OWNER_WORDS = {"robot": "my", "your": "my", "us": "our", "our": "our"}
#: Owners named by kin or household nouns ("my husband's", "the kids'"): said back as hers ("your husband's
#: blue book"), not as a name ("Husband's blue book", fresh5 stair_three_on_shelf).
_KIN = frozenset({"husband", "wife", "son", "daughter", "mother", "father", "mum", "dad", "mother in law",
                  "father in law", "grandmother", "grandfather", "grandma", "grandpa", "brother", "sister", "kids",
                  "children", "child", "boyfriend", "girlfriend", "friend", "roommate", "flatmate", "neighbour",
                  "aunt", "uncle", "niece", "nephew", "cousin", "baby", "boss", "lodger", "family", "parents",
                  "grandparents", "cleaner", "nanny", "guests"})


def noun_phrase(el: etree._Element) -> str:
    """An object as the robot says it back: owner, attributes, colour, use, noun ("your favourite cup").

    ``el`` is an ``OBJECT`` as the understanding frames it (``TITLE``, ``OWNER``, ``COLOUR``,
    ``ATTRIBUTE`` children) or as the object attention reports it (``name``/``type``, ``owner``,
    ``colour`` attributes): so that the partner hears what the robot understood, and can correct it.
    The owner is said from the partner's side ("my cup" -> "your cup", "the robot's" -> "my",
    a name -> "Anna's"); without one the article is "the". Never raises (no noun: "the object").
    """
    def child(tag: str) -> str:
        c = el.find(tag)
        return " ".join((c.get("name") or "").split()) if c is not None else ""

    noun = child("TITLE") or " ".join((el.get("name") or el.get("type") or "").split()) or "object"
    owner = (child("OWNER") or el.get("owner") or "").strip()
    if not owner:
        det = "the"
    elif owner.lower() in _OWNED_BY_PARTNER:
        det = "your"
    elif owner.lower() in _OWNER_WORDS:
        det = _OWNER_WORDS[owner.lower()]
    elif owner.lower() in _KIN:
        det = f"your {owner.lower()}'" if owner.lower().endswith("s") else f"your {owner.lower()}'s"
    else:
        det = f"{owner[:1].upper()}{owner[1:]}'s"
    attrs = list(dict.fromkeys(" ".join((a.get("name") or "").split()) for a in el.iterfind("ATTRIBUTE")))
    colour = child("COLOUR")  # only a colour she said: the camera's own colour (colour=) is not echoed
    use = child("USE") or " ".join((el.get("use") or "").split())  # "your coffee cup"
    if use and use in noun.split():
        use = ""
    return " ".join(w for w in (det, *attrs, colour, use, noun) if w)


def _xpath_noun_phrase(context: Any, nodes: Any = None) -> str:
    if isinstance(nodes, list):
        el = next((n for n in nodes if isinstance(n, etree._Element)), None)
    else:
        el = context.context_node if nodes is None else None
    return noun_phrase(el) if isinstance(el, etree._Element) else ""


#: Nouns ending in "s" that are singular ("the glass is", "the bus is"); other nouns that end in "s" are plural.
_SINGULAR_S = frozenset({"glass", "bus", "atlas", "canvas", "cactus", "lens", "chess", "news", "iris",
                         "dress", "mattress", "compass", "address", "globus", "tennis", "octopus", "walrus", "fungus",
                         "hibiscus", "asparagus", "hummus", "harness", "christmas", "gas", "bass", "moss", "boss",
                         "class", "grass", "cross", "process", "press", "chassis", "series", "species", "abacus",
                         "circus", "campus", "bonus", "virus", "radius", "status", "thesis", "basis", "analysis",
                         "crisis", "oasis", "axis", "pelvis", "trellis", "ibis", "bias", "alias"})
#: Plural nouns that do not end in "s".
_PLURAL = frozenset({"people", "children", "mice", "feet", "teeth", "geese", "men", "women", "pyjamas", "clothes",
                     "dishes", "cutlery"})


def is_plural(noun: str) -> bool:
    """Whether a noun as the user said it is plural ("keys", "glasses", "scissors"), for the verb said with it
    ("the keys are on the table", gen12: "The keys is on ..."). The last word decides ("car keys")."""
    words = noun.lower().split()
    if not words:
        return False
    last = words[-1]
    if last in _PLURAL:
        return True
    return last.endswith("s") and last not in _SINGULAR_S and not last.endswith(("ss", "us", "is", "'s"))


def _xpath_be(context: Any, nodes: Any = None) -> str:
    """``be()``: "are" for an object whose noun is plural, else "is" (of the context node or the argument's
    first node; read as :func:`noun_phrase` reads the noun)."""
    if isinstance(nodes, list):
        el = next((n for n in nodes if isinstance(n, etree._Element)), None)
    else:
        el = context.context_node if nodes is None else None
    if not isinstance(el, etree._Element):
        return "is"
    title = el.find("TITLE")
    noun = (title.get("name") if title is not None else None) or el.get("name") or el.get("type") or ""
    return "are" if is_plural(noun) else "is"


#: XPath functions templates may use beyond XPath 1.0: ``noun-phrase()`` (of the context node, or of
#: the first node of its argument), see :func:`noun_phrase`; ``be()`` ("is" or "are" for it), see :func:`is_plural`.
XPATH_EXTENSIONS = {(None, "noun-phrase"): _xpath_noun_phrase, (None, "be"): _xpath_be}


def value_text(value: Any, xpath: str = "") -> str:
    """A slot value (element or text) as words, optionally through an XPath."""
    if value is None:
        return ""
    if xpath:
        if not isinstance(value, etree._Element):
            return ""
        try:
            res = value.xpath(xpath, extensions=XPATH_EXTENSIONS)
        except etree.XPathError:
            return ""
        if isinstance(res, list):
            res = res[0] if res else ""
        if isinstance(res, etree._Element):
            return value_text(res)
        if isinstance(res, bool):
            return "yes" if res else ""
        if isinstance(res, float):
            return "" if res != res else (str(int(res)) if res == int(res) else str(res))
        return " ".join(str(res).split())
    if isinstance(value, etree._Element):
        if value.tag == "param" and len(value):  # a condition's parameter: what it holds
            return value_text(value[0])
        name = value.get("name") if value.tag != "param" else None
        if name:
            return name
        title = value.find("TITLE")
        if title is not None and title.get("name"):
            return title.get("name", "")
        return " ".join("".join(value.itertext()).split())
    return " ".join(str(value).split())


def render(text: str, values: dict[str, Any]) -> str:
    """Fill a template's fields from slot values; never raises."""

    def one(m: re.Match[str]) -> str:
        got = value_text(values.get(m.group(1)), m.group(2) or "")
        return got if got else (m.group(3) or "")

    return " ".join(_FIELD.sub(one, text).split())
