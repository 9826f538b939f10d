"""Speech understanding: recognised words -> the frame XML of docs/semantics.md §4.

The grammar (``hometour.lark``) is run by lark's LALR(1) parser over the
tokens of :mod:`robot.speech.lexicon`. :meth:`Understander.understand` never
raises on words: it returns an :class:`Understanding` whose ``frame`` is a
``<SPEECH>`` element, or ``None`` with ``reason`` saying why nothing was
understood.

Best partial parse: the tokens are fed one by one to lark's interactive
parser; a token the grammar cannot take at that point is skipped (reported
in ``ignored``), and an utterance that stops where an object or a place
must follow ("this is my ...") is closed with an empty object/place, so the
frame keeps what was said (owner, gesture, colour) and the dialog asks for
the rest (only when a word says something about it: a deixis, articles and
prepositions alone, "to the", "this the to", are noise and nothing is understood). A
greeting that opens a whole request ("hello biron, follow me") is the frame
at full coverage; the request is reported in ``ignored`` and ``rest``. A
leading "no" followed by more words is a correction: the rest is understood.

Frames (children in this order): ``<OBJECT type>`` with ``GESTURE``
(``val="probably_pointing"`` when a deictic word refers to it), ``TITLE``
(the noun as said), ``OWNER``, ``COLOUR``, ``ATTRIBUTE``\\*, ``POSITION``
(``RELATION`` + ``TITLE``); ``<PLACE>`` with ``TITLE`` (canonical place
name) and ``OWNER``; and the act elements ``GREETING`` (``name="biron"``
when addressed by name), ``GOODBYE``, ``CAPABILITIES``, ``FOLLOW``,
``STOP``, ``WAIT``, ``YES``, ``NO``, ``THAT_ONE``, ``GOTO``, ``WHERE``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from lark import Lark, Token, Tree
from lark.exceptions import UnexpectedInput, UnexpectedToken
from lark.lexer import Lexer
from lxml import etree

from .lexicon import Lexicon, Tok

GRAMMAR_FILE = Path(__file__).with_name("hometour.lark")

_E = etree.Element
_S = etree.SubElement


class _Tokens(Lexer):
    """lark lexer that hands over an already tokenised utterance (a list of lark Tokens)."""

    def __init__(self, lexer_conf: object) -> None:  # lark passes its configuration
        pass

    def lex(self, data: list[Token]) -> object:  # type: ignore[override]
        return iter(data)


@dataclass(slots=True)
class Understanding:
    """What the understanding made of one word string."""

    words: str
    frame: etree._Element | None  # <SPEECH>, or None: not understood
    unknown: list[str] = field(default_factory=list)  # words not in the lexicon (skipped)
    ignored: list[str] = field(default_factory=list)  # known words the grammar could not place
    corrected: list[str] = field(default_factory=list)  # reparanda and editing terms taken out
    partial: bool = False  # the frame needed a skipped token or a missing object/place
    coverage: float = 0.0  # share of the meaningful words the frame used, 0..1
    rest: list[str] = field(default_factory=list)  # a whole request after a greeting, left out of the frame
    reason: str = ""  # why nothing was understood

    @property
    def act(self) -> str | None:
        """The frame's first child tag (GREETING, OBJECT, ...), or None."""
        if self.frame is None or len(self.frame) == 0:
            return None
        return str(self.frame[0].tag)


class Understander:
    """The semantic grammar: load once, then :meth:`understand` word strings (~tens of µs each)."""

    def __init__(self, lexicon: Lexicon | None = None, grammar: str | Path = GRAMMAR_FILE) -> None:
        self.lexicon = lexicon or Lexicon.load()
        text = Path(grammar).read_text(encoding="utf-8")
        self.parser = Lark(text, parser="lalr", lexer=_Tokens, start="start", maybe_placeholders=False)
        declared = set(self.parser.terminals and [t.name for t in self.parser.terminals]) | _declared(text)
        missing = sorted(t for t in self.lexicon.terminals if t not in declared and t not in ("-", "EDIT"))
        if missing:
            raise ValueError(f"{GRAMMAR_FILE.name}: lexicon terminals the grammar does not declare: {missing}")

    def understand(self, words: str) -> Understanding:
        """Parse ``words``; never raises for any string."""
        lex = self.lexicon.tokens(words)
        res = Understanding(words, None, unknown=lex.unknown, corrected=lex.corrected)
        toks = lex.tokens
        if len(toks) > 1 and toks[0].type == "OKAY":  # "okay, bye": a leading okay only takes the turn
            toks = toks[1:]
        if not toks:
            res.reason = "no known words" if lex.unknown else "nothing said"
            return res
        tree, ignored, partial = self._parse(toks)
        if toks[0].type == "NO" and len(toks) > 1 and (tree is None or partial or tree_act(tree) == "no"):
            alt = self._parse(toks[1:])  # "no, the blue one": the correction is what counts
            if alt[0] is not None and not alt[2]:
                tree, ignored, partial = alt
                res.corrected.append(toks[0].text)
        if tree is None:
            res.ignored = [t.text for t in toks]
            res.reason = "no parse"
            return res
        res.frame = build(tree)
        res.ignored = ignored
        res.partial = partial or bool(ignored)
        used = len(toks) - len(ignored)
        if ignored and tree_act(tree) == "greeting" and self._request_after_greeting(toks, ignored):
            used = len(toks)  # "hello biron, follow me": the greeting is sure; the request is not noise
            res.rest = list(ignored)
        res.coverage = used / max(1, len(toks) + len(lex.unknown))
        return res

    def _request_after_greeting(self, toks: list[Tok], ignored: list[str]) -> bool:
        """Whether the words a greeting's parse left out are the utterance's end and a whole act alone.

        A greeting that opens a request ("hello biron, follow me") is a sure
        greeting: the frame is the greeting (what opens the interaction) and the
        request, reported in ``rest``, is left for the user to say again. Words
        that do not make a complete act by themselves stay noise and lower the
        coverage.
        """
        tail = toks[len(toks) - len(ignored):]
        if [t.text for t in tail] != ignored:
            return False
        tree, _, partial = self._parse(tail)
        return tree is not None and not partial and tree_act(tree) not in ("greeting", "object_fragment",
                                                                           "place_fragment")

    def _parse(self, toks: list[Tok]) -> tuple[Tree | None, list[str], bool]:
        """Parse; on an error, skip tokens that do not fit and close a dangling object/place.

        The fast path is one plain LALR parse. Only a failed parse goes on from
        the parser state at the error, token by token.
        """
        stream = [Token(t.type, t) for t in toks]
        try:
            return self.parser.parse(stream), [], False
        except UnexpectedToken as exc:
            ip = exc.interactive_parser
            bad = exc.token
        ignored: list[str] = []
        used = len(stream)
        if bad.type != "$END":
            at = next(i for i, t in enumerate(stream) if t is bad)
            ignored.append(toks[at].text)
            for t in stream[at + 1 :]:
                try:
                    ip.feed_token(t)
                except UnexpectedToken:
                    ignored.append(t.value.text)
            used -= len(ignored)
            try:
                return ip.copy().feed_eof(), ignored, True
            except UnexpectedInput:
                pass
        if used < 2:
            return None, ignored, True  # one word and a guessed rest is no understanding
        skipped = set(ignored)
        if all(t.type in _ONLY_POINTS for t in toks if t.text not in skipped):
            # a deixis, articles and prepositions alone are noise ("this the to", "to the"), not an
            # object or place the user began to describe ("this is my favourite <lost word>")
            return None, ignored, True
        for filler in ("OBJ", "PLACE"):  # "this is my ...": close it with an empty object/place
            trial = ip.copy()
            try:
                trial.feed_token(Token(filler, Tok(filler, "", "")))
                return trial.feed_eof(), ignored, True
            except UnexpectedInput:
                continue
        return None, ignored, True


# word classes that say nothing about a dangling object or place: deixis, articles, prepositions
_ONLY_POINTS = frozenset({"THIS", "THAT", "HERE", "THERE", "IT", "A", "THE", "TO", "IN", "REL", "OF", "ONE"})


def _declared(text: str) -> set[str]:
    out: set[str] = set()
    for line in text.splitlines():
        if line.startswith("%declare"):
            out.update(line.split()[1:])
    return out


def tree_act(tree: Tree) -> str:
    """The name of the act rule under ``start``."""
    for c in tree.children:
        if isinstance(c, Tree) and c.data != "address":
            return str(c.data)
    return ""


# ---------------------------------------------------------------------- frames
def _tok(t: Token) -> Tok:
    return t.value  # type: ignore[no-any-return]


def _tokens(tree: Tree) -> list[Tok]:
    return [_tok(c) for c in tree.children if isinstance(c, Token)]


def _sub(tree: Tree, name: str) -> Tree | None:
    for c in tree.children:
        if isinstance(c, Tree) and c.data == name:
            return c
    return None


def _subs(tree: Tree, name: str) -> list[Tree]:
    return [c for c in tree.children if isinstance(c, Tree) and c.data == name]


def _owner(tree: Tree | None) -> str | None:
    """An owner from ``possessor`` or ``owner_tail``: 'speaker', 'robot', 'us' or a name."""
    if tree is None:
        return None
    for t in _tokens(tree):
        if t.type == "NAME":
            return t.value
        if t.type in ("MY", "MINE", "YOUR", "OUR"):
            return t.value
        if t.type == "ME":
            return "speaker"
    return None


def _object(np: Tree, *, gesture: bool, position: Tree | None = None, tail: Tree | None = None) -> etree._Element:
    toks = _tokens(np)
    noun = next((t for t in toks if t.type == "OBJ"), None)
    el = _E("OBJECT")
    if noun is not None and noun.value:
        el.set("type", noun.value)
    if gesture:
        _S(el, "GESTURE", val="probably_pointing")
    if noun is not None and noun.value:
        _S(el, "TITLE", name=noun.text)
    owner = _owner(tail) or _owner(_sub(np, "possessor"))
    of = [t for t in toks if t.type == "NAME"]  # "the cup of anna"
    if owner is None and of:
        owner = of[-1].value
    if owner is not None:
        _S(el, "OWNER", name=owner)
    colours, attrs = _modifiers(np)
    if colours:
        _S(el, "COLOUR", name=colours[-1])
    for a in attrs:
        _S(el, "ATTRIBUTE", name=a)
    if position is not None:
        el.append(_position(position))
    return el


def _modifiers(tree: Tree) -> tuple[list[str], list[str]]:
    colours: list[str] = []
    attrs: list[str] = []
    for m in _subs(tree, "modifier"):
        for t in _tokens(m):
            (colours if t.type == "COLOUR" else attrs).append(t.value)
    return colours, list(dict.fromkeys(attrs))


def _position(tree: Tree) -> etree._Element:
    toks = _tokens(tree)
    pos = _E("POSITION")
    rel = toks[0]
    _S(pos, "RELATION", name=rel.value if rel.type == "REL" else "in")
    ground = toks[-1]
    if ground.value:
        _S(pos, "TITLE", name=ground.text if ground.type == "OBJ" else ground.value)
    return pos


def _place(np: Tree) -> etree._Element:
    el = _E("PLACE")
    place = next((t for t in _tokens(np) if t.type in ("PLACE", "ROOM")), None)
    if place is not None and place.value:
        _S(el, "TITLE", name=place.value)
    owner = _owner(_sub(np, "possessor"))
    if owner is not None:
        _S(el, "OWNER", name=owner)
    return el


def build(tree: Tree) -> etree._Element:
    """The ``<SPEECH>`` frame of a parse tree of ``start``."""
    speech = _E("SPEECH")
    named = any(t.type == "ROBOTNAME" for a in _subs(tree, "address") for t in _tokens(a))
    act = next(c for c in tree.children if isinstance(c, Tree) and c.data != "address")
    kind = act.data
    if kind == "greeting":
        g = _S(speech, "GREETING")
        if named:
            g.set("name", "biron")
    elif kind in ("goodbye", "capabilities", "follow", "stop", "wait", "yes", "no"):
        _S(speech, {"goodbye": "GOODBYE", "capabilities": "CAPABILITIES"}.get(kind, kind.upper()))
    elif kind == "that_one":
        el = _S(speech, "THAT_ONE")
        for t in _tokens(act):
            if t.type == "ORD":
                el.set("index", t.value)
            elif t.type in ("SIDE", "SIDEONE"):
                el.set("side", t.value)
        colours, attrs = _modifiers(act)
        if colours:
            _S(el, "COLOUR", name=colours[-1])
        for a in attrs:
            _S(el, "ATTRIBUTE", name=a)
        pos = _sub(act, "position")
        if pos is not None:
            el.append(_position(pos))
        if _sub(act, "deixis") is not None and not el.attrib and len(el) == 0:
            el.set("deixis", "true")  # bare "this one", "that one": look where the speaker points
    elif kind in ("teach_object", "object_fragment"):
        speech.append(_object(_sub(act, "object_np"), gesture=kind == "teach_object",  # type: ignore[arg-type]
                              position=_sub(act, "position"), tail=_sub(act, "owner_tail")))
    elif kind in ("teach_place", "place_fragment"):
        speech.append(_place(_sub(act, "place_np")))  # type: ignore[arg-type]
    elif kind == "goto":
        _S(speech, "GOTO").append(_place(_sub(act, "place_np")))  # type: ignore[arg-type]
    elif kind == "where":
        w = _S(speech, "WHERE")
        np = _sub(act, "object_np")
        w.append(_object(np, gesture=False) if np is not None else _place(_sub(act, "place_np")))  # type: ignore[arg-type]
    else:  # pragma: no cover - every act rule of the grammar is handled above
        raise AssertionError(f"grammar rule {kind!r} has no frame")
    return speech
