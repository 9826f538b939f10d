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

import collections
import hashlib
import itertools
import os
import sys
import tempfile
from dataclasses import dataclass, field
from typing import Any
from pathlib import Path

from lark import Lark, Token, Tree
from lark.exceptions import UnexpectedInput, UnexpectedToken
from lark.lexer import Lexer
from lxml import etree

from .lexicon import EDIT, Lexicon, Tok

GRAMMAR_FILE = Path(__file__).with_name("hometour.lark")

_E = etree.Element
_S = etree.SubElement


class _Tokens(Lexer):
    """lark lexer that hands over an already tokenised utterance (a list of lark Tokens)."""

    def __init__(self, lexer_conf: object) -> None:  # lark passes its configuration
        pass

    def lex(self, data: list[Token]) -> object:  # type: ignore[override]
        return iter(data)


def _cache_dir() -> Path:
    """Where built LALR tables are kept between processes (``HOMESIM_CACHE_DIR``, else the user's cache)."""
    env = os.environ.get("HOMESIM_CACHE_DIR")
    if env:
        return Path(env)
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "homesim"


def _lalr_parser(text: str) -> Lark:
    """The grammar's LALR parser, its tables loaded from the per-user cache when built before.

    Building the tables takes ~0.15 s of CPU at every start; loading them ~0.01 s. The cache
    file is named by the SHA-256 of the grammar text, lark's version and Python's, so a changed
    grammar never loads stale tables; it is written whole and renamed into place (workers
    starting together never read half a file), and a cache that cannot be read or written
    only costs the build. The tables are lark's own serialisation (``Lark.save``/``Lark.load``):
    the same states and actions, so the same parses.
    """
    import lark

    key = hashlib.sha256(f"{text}\0{lark.__version__}\0{sys.version_info[:2]}".encode()).hexdigest()[:32]
    path = _cache_dir() / f"grammar-{key}.lark"
    try:
        with path.open("rb") as f:
            return Lark.load(f)
    except Exception:  # absent, unreadable or from a broken write: build it (below)
        pass
    parser = Lark(text, parser="lalr", lexer=_Tokens, start="start", maybe_placeholders=False)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=".grammar-")
        try:
            with os.fdopen(fd, "wb") as f:
                parser.save(f)
            os.replace(tmp, path)
        except BaseException:
            os.unlink(tmp)
            raise
    except OSError:  # a read-only home: every start builds the tables
        pass
    return parser


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
    answer: str = ""  # "yes"/"no" said before the request ("no, the kitchen"): it answers an open question
    fragment: bool = False  # a noun phrase alone ("the kitchen"): an answer, not a request or statement by itself
    reason: str = ""  # why nothing was understood
    aside: bool = False  # said to someone else in the robot's hearing ("Tom, can you put the kettle on")
    stay: bool = False  # a WAIT that tells the robot to stay ("wait here", "stay"), not a hesitation ("hang on")

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
        self._in_owned_after_copula = False  # :meth:`_owned_after_copula` asks how the turn is understood without it
        self._in_new_rule = False  # :meth:`_without_new_rules`: lang24's greeting and remark rules switched off
        text = Path(grammar).read_text(encoding="utf-8")
        self.parser = _lalr_parser(text)
        declared = set(self.parser.terminals and [t.name for t in self.parser.terminals]) | _declared(text)
        missing = sorted(t for t in self.lexicon.terminals if t not in declared and t not in ("-", "EDIT"))
        if missing:
            raise ValueError(f"{GRAMMAR_FILE.name}: lexicon terminals the grammar does not declare: {missing}")

    def understand(self, words: str) -> Understanding:
        """Parse ``words``; never raises for any string."""
        lex = self.lexicon.tokens(words)
        res = Understanding(words, None, unknown=lex.unknown, corrected=lex.corrected)
        toks = lex.tokens
        said = Lexicon.words(words)
        beside = sum(1 for a, b in itertools.pairwise(said) if (a, b) == ("next", "door"))
        if beside and beside == said.count("door"):
            # "the living room is next door", "come on, the in is next door" (misheard): "next door" says where,
            # it names no door to teach or look at (fresh5 row_hidden_step_aside: "Is this the door?")
            toks = [t for t in toks if not (t.type == "OBJ" and t.text == "door")]
            lex.unknown.extend(["door"] * beside)
        gave_up = False  # a leading "never mind (her)": she sets aside what came before
        heed = False  # a leading "don't mind me", "never mind us": pay them no heed
        lead_edit: Tok | None = None
        while toks and toks[0].type == EDIT:  # "sorry, this is my cup": nothing before it to repair
            res.corrected.append(toks[0].text)
            gave_up = gave_up or toks[0].value == "never mind"
            heed = heed or toks[0].value == "mind me"
            lead_edit, toks = toks[0], toks[1:]
        taken_back = bool(lex.raw) and len(lex.raw) > 1 and lex.raw[-1].type == EDIT and lex.raw[-1].value == "never mind"
        if taken_back:
            # "follow me, oh never mind", "this is the kitchen, never mind": she takes back what she just said
            # (a no); the trailing editing term must not leave the request standing as if said whole
            gave_up, toks = True, [t for t in lex.raw[:-1] if t.type != EDIT]
        elif (gave_up or heed) and lead_edit is not None:
            # "never mind the kitchen, go to the living room", "never mind, this is my cup" (the lexicon's "never
            # mind this" took her deixis): the request after what she sets aside is what she wants, never a
            # frame built on the thing set aside (review13 items 2 and 8)
            found = self._request_after_never_mind(lead_edit, toks)
            if found is not None:
                aside_words, toks = found
                res.corrected += aside_words
                gave_up = False
            elif heed:
                # "don't mind me, I'm just passing", "never mind us": no request and nothing given up (not a
                # no that could answer an open question: review13 item 11); no "say that again" either
                res.ignored = [t.text for t in toks]
                res.reason, res.aside = "she asks the robot to pay no heed", True
                return res
        if gave_up and (taken_back or not any(t.type == "NOT" for t in toks)):
            # (a negation after it, "never mind, you're not in my way", is left to the negation rules below)
            # "never mind", "oh never mind, we will do that another time": she gives up what was asked
            # (a no); "never mind her, you come with me" keeps the request said after it (fresh4
            # loft_flatmates_talk: the whole turn was a no, the follow lost)
            res.corrected = [t.text for t in lex.tokens if t.type == EDIT and t.value == "never mind"][:1]
            given_up = [t.text for t in toks]  # the words after it, counted as not used
            toks = [Tok("NO", "no", "never mind")]
        else:
            given_up = []
        come_on: Tok | None = None  # a leading "come on": she calls the robot along
        if len(toks) > 1 and toks[0].type in ("OKAY", "COMEON") and any(
                t.type not in ("ROBOTNAME", "ROBOT") for t in toks[1:]):
            come_on = toks[0] if toks[0].type == "COMEON" else None
            toks = toks[1:]  # "okay, bye", "come on, this way": a leading okay or come-on only takes the turn
        if not toks:
            relief = self._relief_remark(words, said)
            if relief is not None:
                return relief  # "so, where were we": the words are known but say nothing to the robot (talk24)
            res.reason = "no known words" if lex.unknown else "nothing said"
            return res
        spots = [t for t in toks if t.type not in ("ROBOTNAME", "ROBOT")]
        if len(spots) == 1 and spots[0].type in ("HERE", "THERE") and spots[0].text.startswith("right "):
            # "right there", "right here, biron" said alone: the stop's verb left out ("stop right there"), as a
            # user says it while the robot comes after her; a plain "here" or "there" alone stays no request
            # (it may answer a which-one question or point), only the emphatic "right" marks the spot
            at = toks.index(spots[0])
            toks = [*toks[:at], Tok("STOP", "stop", ""), *toks[at:]]
        lead_spot = next((k for k, t in enumerate(toks) if t.type not in ("ROBOTNAME", "ROBOT")), None)
        if lead_spot is not None and lead_spot + 1 < len(toks) and toks[lead_spot].type in ("HERE", "THERE") \
                and toks[lead_spot + 1].type == "STOP":
            # "here, stop", "right there, stop": the spot said before the stop, as a leader who has just
            # stopped says it over her shoulder; the same request as "stop here" (fresh8
            # terr_fast_walker_passage: "here stop" heard word for word, "no parse", three times)
            k = lead_spot
            toks = [*toks[:k], toks[k + 1], toks[k], *toks[k + 2:]]
        if [t.type for t in spots] in (["YOU", "GO"], ["CAN", "GO"]) and not lex.unknown:
            # "[can] you go", "can [you] go": the short request to go somewhere with one word lost (the
            # recogniser drops short words); nothing else is said, so it is the go-to with no place, which the
            # dialog answers by asking where (lang_silence seeds 10, 11: "Sorry, I did not understand you")
            at = toks.index(spots[0])
            lost = Tok("CAN", "can", "") if spots[0].type == "YOU" else Tok("YOU", "you", "")
            toks = [*toks[:at], lost, *toks[at:]] if lost.type == "CAN" else [*toks[:at + 1], lost, *toks[at + 1:]]
        kinds = [t.type for t in spots]
        if kinds[:3] == ["WHAT", "CAN", "YOU"] and (len(kinds) == 3 or (len(kinds) == 4 and kinds[3] in _NO_LAST_WORD)) \
                and not lex.unknown:
            # "what can you [do]" with its verb lost or heard as a short word that cannot end the question ("what
            # can you a", "what can you that": the recogniser drops and swaps short words, and "do" is one): the
            # capabilities question, as "what [can] you do" and "what can [you] do" already are. A word that
            # could end another question ("what can you see") is not this one (perceive/step_aside_chat seeds
            # 0, 4, 6: "Sorry, I did not understand you" cost the repair that left no time for her good-bye)
            at = toks.index(spots[2]) + 1
            toks = [*toks[:at], Tok("DO", "do", ""), *toks[at:]]
        if toks[0].type == "HELLO" and toks[0].text in _OPENING_WORDS and len(toks) > 1:
            # "morning biron, follow me", "yo, follow me": a word that greets only by opening a turn, before
            # a whole request, is not heard as the greeting (the request is what she wants; these words
            # were not understood before they greeted, and the request was taken then)
            k = 1 + sum(1 for _ in itertools.takewhile(lambda t: t.type in ("ROBOTNAME", "ROBOT"), toks[1:]))
            after = self._parse(toks[k:]) if k < len(toks) else None
            if after is not None and after[0] is not None and not after[2] and not _guessed(after[0]) \
                    and tree_act(after[0]) not in _AFTER_CLOSING:
                res.unknown.append(toks[0].text)
                toks = toks[1:]
        errand = _errand(Lexicon.words(words), self.lexicon.hesitations)
        misheard = False
        if errand is None:
            # "let [me→a] just close the door", "[let→it] me just open the window": the errand's lead with one word
            # lost or misheard is still her errand (a wait, or the request said after it), never a teaching of the
            # door or the window (fresh8 lflat_elderly_hidden: "Is this the window?"); a word lost, so not sure
            errand = _errand_misheard(Lexicon.words(words), self.lexicon.hesitations)
            misheard = errand is not None
        if errand is not None:
            # "oh wait, I'll just get the post", "let me just put the water on": she announces a short
            # errand; what she asks of the robot is to wait for her (the words after the verb say where
            # she goes, not a request of their own: "put the water on" was an object with use water).
            # A whole request said after the errand ("I will just grab my phone, follow me please", "let
            # me just check, is this the kitchen") is what she asks: the errand is discourse (review13 item 1)
            after = self._request_after_errand(words, errand)
            if after is not None:
                return after
            tree, _, _ = self._parse([Tok("WAIT", "wait", "wait")])
            res.frame = build(tree)
            res.coverage = 1.0 - 1.0 / max(2, len(Lexicon.words(words))) if misheard else 1.0
            res.partial = misheard
            return res
        after = self._follow_to_what_she_shows(words, Lexicon.words(words))
        if after is not None:
            # "come over to my study with me", "come on, now I'll show you the nursery", "let me show you the
            # kitchen, come": she leads the way to what she will show there; a follow, never a teaching of this
            # spot nor a go-to (talk24: "Is this the study?", "Shall I go to the study?")
            return after
        after = self._everyday_short_forms(words, Lexicon.words(words))
        if after is not None:
            # "good, now stop", "yes, come on", "there, that's better", "so, where were we" (talk24)
            return after
        after = self._follow_after_suggestion(words, Lexicon.words(words))
        if after is not None:
            # "shall we go to the kitchen? follow me", "should we have a look at the study, come with me": a
            # question that suggests going somewhere together, then the follow she asks for; the room she
            # suggests is not here (no teaching: fresh8 lflat_bar_two_bottles, "Is this the kitchen?"), nor is
            # it a go-to or a stop: she leads the way
            return after
        after = self._request_before_remark(words, Lexicon.words(words))
        if after is not None:
            # "follow me quickly, I have to go soon", "follow me, I want you to see the garage", "hello biron, nice
            # that you are here", "hi robot, I am Tom": a whole follow or greeting, then a remark of hers (why, where
            # to, who she is): the request is what she asks (fresh10: taken as a good-bye, a place teaching, or a
            # doubted greeting, "Did you say hello to me?")
            return after
        after = self._greeting_with_pleasantries(words, Lexicon.words(words))
        if after is not None:
            # "hello there robot, nice to meet you, I'm Anna", "good evening, so you're the new robot": a whole
            # greeting, then pleasantries only (lang24: "Did you say hello to me?" to a greeting said whole)
            return after
        after = self._remark_about_a_thing(words, Lexicon.words(words))
        if after is not None:
            # "oh, and my keys are usually in the bowl by the door", "the plant over there needs water": a thing
            # named, nothing shown; a remark, no half teaching (lang24)
            return after
        after = self._request_after_remark(words, Lexicon.words(words))
        if after is not None:
            # "the ramp is free now, go to the living room please", "she's gone, you can go to the kitchen now",
            # "the hall is clear now, go to the kitchen": a remark that shows and names nothing here (no place to
            # teach: fresh7 split_goto_ramp_child, "Is this the living room?" to the go-to after it); the whole
            # request said after it is what she asks
            return after
        after = self._where_after_thing(words, Lexicon.words(words))
        if after is not None:
            # "and my glass, where it is now", "the kettle, where is it": the thing named first, then asked where
            # (a non-native or spoken order; talk23: taken as showing the glass, "Is this your glass?")
            return after
        after = self._owned_after_copula(words, Lexicon.words(words))
        if after is not None:
            # "this chair is my favourite", "the red flower behind me is my favourite plant": whose it is, said with
            # a word of praise and its noun again (talk23: the owner dropped, "Is this the red flower?")
            return after
        after = self._come_and_see(words, Lexicon.words(words))
        if after is not None:
            # "and now come and see the gallery", "come and have a look at my study": she invites the robot to
            # come with her to what she will show there (a follow with where to; talk23: not understood at all)
            return after
        after = self._follow_after_destination(words, Lexicon.words(words))
        if after is not None:
            # "now the study, follow me please", "and now the last room, follow me": where they go next, named
            # by a noun phrase alone, then the follow she asks for (the room is not here: no teaching, nor a
            # which-one answer: fresh7 corr_long_tour, "Sorry, I did not understand you")
            return after
        other = _said_to_another(toks, Lexicon.words(words), self.lexicon.hesitations) \
            or _greets_unknown_name(toks, said, lex.unknown, self.lexicon.hesitations)
        if other:
            # "Tom, can you put the kettle on", "yes dear, I'm coming", "isn't the robot clever": words for
            # someone else in the robot's hearing; no request, and no "say that again" either
            res.ignored = [t.text for t in toks]
            res.reason, res.aside = other, True
            return res
        negated = _negation(toks, Lexicon.words(words))
        if negated is not None:
            # "don't stop, keep going", "do not follow me": a request said negated is never that request;
            # what she says after it instead is (a repair, like "follow me, no wait, stop")
            tail = self._after_negation(toks, negated)
            greeted = self._greeting_before(toks, negated) if tail is None else None
            if greeted is not None:
                # "hello biron, don't follow me": she greets, then says what not to do; the greeting
                # stands (review9 item 6), the request said negated is not taken
                res.corrected += [t.text for t in toks[greeted:]]
                tail = toks[:greeted]
            if tail is None:
                res.ignored = [t.text for t in toks]
                res.reason = "a request said negated"
                return res
            res.corrected += [t.text for t in toks[: len(toks) - len(tail)]]
            toks = tail
        tree, ignored, partial = self._parse(toks)
        if tree is None and len(toks) > 1 and toks[0].type in _ONLY_POINTS:
            # "[yes→to] you got it", "[no→a] that is not right": the answer's first word misheard as a short word,
            # the rest a whole yes or no of two or more words (a one-word "to yes" stays unsure): she answers
            alt = self._parse(toks[1:])
            if alt[0] is not None and not alt[1] and not alt[2] and tree_act(alt[0]) in ("yes", "no") \
                    and sum(len(t.text.split()) for t in toks[1:]) > 1:
                tree, ignored, partial = alt[0], [toks[0].text], True
        guess = False  # an object teaching rebuilt from a lost first word, or asked as a question
        # a question with words the lexicon lacks ("is this the kitchen or the living room", "is it my
        # phone ringing") asks something else than the statement its known words make: no teaching
        asked = self._asked(toks) if not lex.unknown else None
        if asked is not None and lex.raw and lex.raw[-1].type == "NO":
            # "is that the kitchen, no": she asks and doubts it herself (review-lang7 item 9): nothing to confirm
            res.ignored = [t.text for t in toks]
            res.reason = "a question she answers no herself"
            return res
        if asked is not None:
            # "is this the kitchen?", "is that my cup?": she names what she shows and asks the robot to
            # take it up; the statement she asks about is the frame, at half the coverage, so the
            # dialog confirms it before anything is stored (and her question said back to the robot's
            # own "Is this the kitchen?" is that request again: it confirms)
            tree, ignored, partial = asked, [], False
            guess = True
        elif toks[0].type in ("IS", "ARE") and len(toks) > 1 and (tree is None or partial):
            # "is the living room", "is my cup": not a question about an object (nobody asks a bare
            # "is my cup"), a teaching whose "this" was lost: parsed as the statement it was
            alt = self._parse([_LOST_THIS, *toks])  # whole: "is my <lost>" lost too much to guess
            if alt[0] is not None and not alt[2]:
                # the copula stays counted as unheard: the statement is a guess from a word missing.
                # An object shown this way is a guess at half the coverage, so the dialog confirms it
                # ("Is this cup?"): the lost word may have been "where" as well, and a wrong teaching
                # stores an object where it is not
                tree, ignored, partial = alt[0], [toks[0].text, *alt[1]], True
                guess = tree_act(tree) == "teach_object"
        elif ignored and len(toks) > 2 and [t.text for t in toks[len(toks) - len(ignored):]] != ignored:
            # "that to the kitchen" (the recogniser's "that" for "go"): a word skipped inside the
            # phrase ("that [to] the kitchen", a teaching) against a first word misheard, the rest a
            # whole act ("to the kitchen", go there): as many words lost, but the rest is one request
            # said as a whole, so it wins (a wrong teaching would overwrite a taught place unasked).
            # Words left over at the end ("hello biron, follow me") are no skip inside.
            alt = self._parse(toks[1:])
            if alt[0] is not None and not alt[2]:
                tree, ignored, partial = alt[0], [toks[0].text], True
        if (tree is not None and len(toks) > 2 and toks[1].type in ("IS", "ARE") and ignored
                and ignored[0] == toks[1].text and toks[0].text not in ignored):
            # "to is the kitchen" (the recogniser's "to" for "this"): a parse that skips the copula
            # after the first word turns a statement into a request ("to [is] the kitchen", go
            # there). The copula says the turn is a statement: the first word was misheard and the
            # rest is a teaching whose "this" was lost, as "is the living room" above.
            alt = self._parse([_LOST_THIS, *toks[1:]])
            if alt[0] is not None and not alt[2] and tree_act(alt[0]) in _STATEMENT_ACTS:
                # either of the two first words may be the misheard one ("go is the kitchen" is "go
                # to the kitchen" as well): both count as unheard, so a confident guess is confirmed
                tree, ignored, partial = alt[0], [toks[0].text, toks[1].text], True
        if (tree is not None and tree_act(tree) in ("teach_place", "place_fragment") and len(toks) > 2
                and ignored == [toks[0].text] and toks[0].type in ("GO", "COME") and toks[1].type in ("THIS", "THAT", "IT")):
            # "go [to→this] the study" (the recogniser's "this" for "to"): the parse left out the go verb that opens
            # the turn and took the rest as a teaching of the room, which re-taught a room already shown where the
            # robot stood, unasked (look22_greets_behind_after_goto seed 1: "OK, this is the study. I will remember
            # it." in the bedroom). Nobody opens a teaching with "go": the word after the verb was its "to", and the
            # go-to is what she asks, a word lost (partial: confirmed when heard poorly)
            alt = self._parse([toks[0], Tok("TO", "to", ""), *toks[2:]])
            if alt[0] is not None and not alt[1] and not alt[2] and tree_act(alt[0]) == "goto":
                tree, ignored, partial = alt[0], [toks[1].text], True
        if tree is not None and ignored and tree_act(tree) in _STATEMENT_ACTS:
            sent = self._request_after_misheard_opening(toks)
            if sent is not None:
                # "biron [a] go to the lounge", "[can→a] you go to the kitchen please": a short word misheard at the
                # turn's opening made the rest a teaching of the room ("Is this the lounge?"); the whole go-to said
                # after it is what she asks (talk17's case, kept when the remark rule became one)
                k, tree, ignored, partial = sent
                res.corrected += [t.text for t in toks[:k]]
                toks = toks[k:]
        if tree is not None and tree_act(tree) == "wait" and ignored and toks[0].type == "WAIT" \
                and [t.text for t in toks[len(toks) - len(ignored):]] == ignored \
                and not _stays(toks[: len(toks) - len(ignored)], []):
            # "hang on, follow me", "wait a sec, this is my cup": a moment's wait that only opens the turn; the
            # whole request said after it is what she asks (review13 item 14; the follow was dropped)
            alt = self._parse(toks[len(toks) - len(ignored):])
            if alt[0] is not None and not alt[1] and not alt[2] and not _guessed(alt[0]) \
                    and tree_act(alt[0]) not in _NOT_REQUESTS and tree_act(alt[0]) != "wait":
                res.corrected += [t.text for t in toks[: len(toks) - len(ignored)]]
                toks = toks[len(toks) - len(ignored):]
                tree, ignored, partial = alt
        if tree is not None and ignored and tree_act(tree) in ("teach_object", "object_fragment") \
                and _owned(tree) not in (None, "speaker") and any(t.type == "MINE" and t.text in ignored for t in toks):
            # "the green jug there [is] mine, the white one belongs to my brother": the copula lost, the parse
            # skipped "mine" and took the other thing's owner for this one's; "mine" said of the thing she shows
            # is whose it is (the clause up to it, mended; the rest set aside: _owner_before_another_clause)
            title = build(tree).find("OBJECT/TITLE")
            mended = self._owner_before_another_clause(toks, title) if title is not None else None
            if mended is not None:
                tree, ignored, partial = mended
        if tree is not None and ignored and tree_act(tree) in ("teach_object", "object_fragment") \
                and _owned(tree) is None and any(t.type in ("MINE", "POSS") for t in toks):
            # "the red book [to] the shelf is mine" (the recogniser's "to" for "on"): the word that does not fit
            # sank every word after it, the owner said last with them (fresh5 stair_three_on_shelf: "I have
            # learned the red book", not hers). The fewest words left out that give the whole teaching with
            # its owner: still words lost (partial), so the dialog confirms it, with the owner said back
            kept = self._owner_after_skip(toks, build(tree).find("OBJECT/TITLE"))
            if kept is not None:
                tree, ignored, partial = kept
        if tree is not None and ignored and tree_act(tree) == "teach_object" and _owned(tree) is None:
            whose = self._whose_lost(toks, ignored)
            if whose is not None:  # whose it is, a guess: at half the coverage, so the dialog confirms it
                tree, ignored, partial = whose
                guess = True
        if tree is not None and ignored and tree_act(tree) in ("teach_object", "object_fragment"):
            thing = self._landmark_taken(toks, ignored)
            if thing is not None:
                tree, ignored, partial = thing
        if tree is not None and ignored and tree_act(tree) == "teach_object" and build(tree).find("OBJECT/POSITION") is None:
            ground = self._relation_lost(toks)
            if ground is not None:
                tree, ignored, partial = ground
        if tree is None or (tree_act(tree) in ("teach_object", "object_fragment") and _owned(tree) is None):
            mine = self._determiner_lost(toks)
            if mine is not None:  # whose it is, a guess: at half the coverage, so the dialog confirms it
                tree, ignored, partial = mine
                guess = True
        if tree is not None and ignored and tree_act(tree) == "that_one" and len(build(tree)[0]) == 0 \
                and not build(tree)[0].attrib:
            where = self._where_lost(toks, ignored)
            if where is not None:
                tree, ignored, partial = where
        if tree is not None and ignored and tree_act(tree) == "teach_place" and build(tree).find("PLACE/TITLE") is None:
            # "here we are, stop", "we are here, stop now": an arrival said before the stop, a place with no name
            # to ask about ("Which room is this?" and the stop lost: fresh5 stair_wait_walks_on, "I am still
            # following you; say stop first." to every teaching after it); the stop said after it is the request
            tail = toks[len(toks) - len(ignored):]
            alt = self._parse(tail) if [t.text for t in tail] == ignored else (None, [], True)
            if alt[0] is not None and not alt[1] and not alt[2] and tree_act(alt[0]) == "stop":
                res.corrected += [t.text for t in toks[: len(toks) - len(tail)]]
                toks, (tree, ignored, partial) = tail, alt
        restart = self._restart(lex.raw) if negated is None else None
        if restart is not None and restart[0][0].type == "TO" and tree_act(restart[1][0]) == "goto" \
                and tree is not None and not ignored and not partial and tree_act(tree) == "follow":
            # "follow me to the bathroom, um, no, to the kitchen": the repair is only where to, with no verb of
            # its own; it continues her follow (the lexicon aligned it: "follow me to the kitchen"), never a
            # go-to of its own to a room perhaps not yet shown (fresh9 wg_self_correcting: "Sorry, I do not
            # know where the kitchen is" and "You left"). "No, go to the kitchen" (a verb) still restarts
            restart = None
        if restart is not None:  # "follow me, no wait, stop": the repair is a whole new request
            toks, (tree, ignored, partial) = restart
        elif (tree is None or _guessed(tree)) and len(toks) > 2:
            # "let's go, follow me, I will show you around", "let me show you, this is the guest
            # room": a preamble the grammar cannot close, or closes only with a guessed empty place
            # or object ("let's go <lost place>"), before a whole request said after it: the request wins
            tail = self._whole_request_after(toks)
            if tail is not None:
                tree, ignored, partial = tail
        elif partial and ignored and len(toks) > 3 and (tree_act(tree) == "that_one" or (
                tree_act(tree) == "teach_object" and toks[0].type == "THERE" and toks[1].type not in ("IS", "ARE"))):
            # "behind me on the sideboard, that is my blue vase", "over there on the shelf, this is my red
            # book": words that set the scene (where, which side) parse as an answer nobody asked for and the
            # request after them is left over; the whole request said after them is what she asks (fresh5
            # row_hidden_step_aside: "Sorry, I did not understand you", twice, in 10 of 10 runs). Where she
            # says it is, is no word lost: said whole, the teaching counts whole. Not after "the one ..."
            # (a which-one answer, then more words), nor before a teaching with words skipped inside it,
            # nor before another request ("on the table, follow me" says no where of a follow)
            found = self._whole_request_at(toks)
            if found is not None and len(found[2]) < len(ignored) and tree_act(found[1]) == "teach_object" \
                    and all(t.type in _SCENE_WORDS for t in toks[:found[0]]) \
                    and any(t.type in ("REL", "SIDE", "HERE") for t in toks[:found[0]]):
                _, tree, ignored = found
                partial = bool(ignored)
        lead = 0
        while lead < len(toks) - 1 and toks[lead].type in _ANSWER_WORDS:
            lead += 1
        if lead and (tree is None or partial or tree_act(tree) in ("yes", "no")):
            alt = self._parse(toks[lead:])  # "no, the blue one", "yes, this is the kitchen": the rest counts
            if alt[0] is not None and alt[2] and not _guessed(alt[0]) and tree_act(alt[0]) not in _NOT_REQUESTS \
                    and alt[1] and [t.text for t in toks[len(toks) - len(alt[1]):]] == alt[1]:
                pass  # "alright, you can stop there, we have arrived": a whole request, then more words
            elif alt[0] is None or alt[2]:
                alt = (None, [], True)
                question = self._asked(toks[lead:]) if not lex.unknown else None
                lost = self._parse([_LOST_THIS, *toks[lead:]]) if toks[lead].type in ("IS", "ARE") else None
                if question is not None:  # "no, is it my laptop": the no answers, the question names it
                    alt, asked, guess = (question, [], False), question, True
                elif lost is not None and lost[0] is not None and not lost[2] \
                        and tree_act(lost[0]) in ("teach_place", "teach_object"):
                    # "no, no, is bathroom": the correction's "this" (or "it") lost, as "[this] is my cup" alone
                    alt, guess = (lost[0], [toks[lead].text], True), True
                elif len(toks) > lead + 2 and toks[lead].type not in ("IS", "ARE"):
                    # "right, [so→that] this room is the living room": the word after the answer misheard,
                    # the rest a whole request or statement of its own (not an answer): it counts
                    rest = self._parse(toks[lead + 1:])
                    if rest[0] is not None and not rest[2] and not _guessed(rest[0]) \
                            and tree_act(rest[0]) not in _NOT_REQUESTS:
                        alt = (rest[0], [toks[lead].text], True)
            if alt[0] is not None and tree_act(alt[0]) not in ("yes", "no", "goodbye") and not _owner_alone(alt[0]):
                # ("yes, that is mine" to "Is this your cup?" stays the yes: whose it is, said again, names
                # nothing new to show; "yes, bye" is her good-bye, review24 F1: only a send-off after a yes is
                # a yes, below)
                said = {t.type for t in toks[:lead]}
                res.answer = "no" if "NO" in said else "yes"
                toks = toks[lead:]
                tree, ignored, partial = alt
        if tree is not None and ignored and tree_act(tree) == "stop" and [t.text for t in toks[:len(ignored)]] == ignored \
                and _arrival(Lexicon.words(words)):
            # "we are here now, you may stop", "there we are, you can stop": the arrival said before the stop in
            # words the grammar does not parse as a place; the stop after it is said whole (talk19)
            alt = self._parse(toks[len(ignored):])
            if alt[0] is not None and not alt[1] and not alt[2] and tree_act(alt[0]) == "stop":
                res.corrected += ignored
                toks, (tree, ignored, partial) = toks[len(ignored):], alt
        closing = max((i for i, t in enumerate(toks) if t.type == "GOODBYE"), default=None)
        after = (self._parse(toks[closing + 1:]) if closing is not None and closing + 1 < len(toks)
                 and toks[closing + 1].type != "TO" else None)  # "goodbye to the kitchen" is a farewell
        if (closing is not None and (tree is None or partial) and after is not None and after[0] is not None
                and not after[2] and not _guessed(after[0]) and tree_act(after[0]) not in _AFTER_CLOSING):
            # "that will be all, now follow me": a whole request after the closing is what she wants now
            # (the closing ended the last task, not the tour); the closing counts as words not used
            tree, ignored, partial = after[0], [t.text for t in toks[: closing + 1]], True
        elif any(t.type == "GOODBYE" for t in toks) and (tree is None or partial) and (
                tree is None or tree_act(tree) != "goodbye"):
            # "that's it for today, goodbye": whatever else was in a closing turn, it closes
            tree, ignored, partial = self._parse([t for t in toks if t.type == "GOODBYE"])
            ignored = [t.text for t in toks if t.type != "GOODBYE"]
        opening = [t for t in lex.tokens if t.type != EDIT]
        lead = next((k for k, t in enumerate(opening) if t.type not in ("YES", "OKAY")), len(opening))
        if tree is not None and tree_act(tree) == "goodbye" and not res.answer and 0 < lead < len(opening) \
                and all(t.type == "GOODBYE" and t.value == "sendoff" for t in opening[lead:]):
            # only yes-words, then only a send-off: "okay, off you go" is her yes to an open "Shall I go to
            # ...?" (talk23), not the end of the tour. A farewell after a yes ("okay, bye then", "OK that's all
            # for now, see you soon") stays her good-bye, whatever the robot had asked (review24 F1)
            res.answer = "yes"
        if (tree is None and _room_unnamed(toks)) or (_where_we_are(toks) and (
                tree is None or (tree_act(tree) in _STATEMENT_ACTS and build(tree)[0].tag == "OBJECT"
                                 and build(tree)[0].get("type") is None))):
            # "this is the [lost] room", "uh is the room": she names this room and its name was lost; a
            # place with no name, so the dialog asks which room this is rather than to say it all again.
            # "this is where we live", "here is where I work": the room she stands in, said by what the
            # household does there and not by its name (the vague user's teaching): asked the same way
            tree, ignored, partial = self._parse([_LOST_THIS, Tok("IS", "is", ""), Tok("THE", "the", ""),
                                                  Tok("PLACE", "", "")])
            ignored, partial = [], True
        if tree is not None and tree_act(tree) == "teach_place" and (
                (ignored and _name_lost_before_room(toks, ignored))
                or (_hesitated_before_room(Lexicon.words(words), self.lexicon.hesitations)
                    and _room_alone(build(tree)[0]))):
            # "this is our [the→living] room": a word the grammar could not place stands where the room's
            # name goes, between her "our" and "room"; "our room" would store a room called "room" unasked.
            # The name was lost: a place with no name, so the dialog asks which room this is
            tree, _, _ = self._parse([_LOST_THIS, Tok("IS", "is", ""), Tok("THE", "the", ""), Tok("PLACE", "", "")])
            partial = True
        if tree is not None and ignored and _led_to(tree, toks, ignored):
            # "come with [me→the] to my study": a misheard word sank the follow, and what was left, "to my study",
            # parsed as a go-to without a verb. The follow words before it say she leads the way there (a follow
            # with a destination, never a go-to to a room perhaps not yet shown: "Sorry, I do not know where the
            # study is"); words were lost, so the dialog confirms it ("Shall I follow you?")
            tree, _, _ = self._parse([Tok("FOLLOW", "follow", ""), Tok("ME", "me", "")])
            partial = True
        called_along = come_on is not None and tree is not None and _place_said_elsewhere(tree, toks, ignored,
                                                                                          bool(lex.unknown), beside > 0)
        if called_along:
            # "come on, the living room is next door", "come on, the kitchen is through here": she calls the
            # robot along and says where they are going; the room is not here (no teaching: fresh5
            # row_hidden_step_aside, "Is this the living room?" and a room stored in the wrong one), and
            # "next door" is no object. What she asks is to come with her.
            res.corrected.append(come_on.text)
            tree, _, _ = self._parse([come_on])
            ignored, partial = [], False
            res.unknown = []  # the words of where they go ("next door") are no words lost
            toks = [come_on]
        if tree is None:
            res.ignored = [t.text for t in toks]
            res.reason = "no parse"
            return res
        frame = build(tree)
        obj = frame[0]
        if partial and lex.unknown and obj.tag == "OBJECT" and obj.get("type") is None and all(
                c.tag in ("GESTURE", "ATTRIBUTE") for c in obj):
            # "that's the end of the tour", "the weather is nice today": a deixis, an adjective and
            # words the robot does not know describe no object (a closing turn or small talk must
            # not become an empty object frame); "this is a <lost>" without unknown words stays an
            # object to look at
            res.ignored = [t.text for t in toks]
            res.reason = "nothing known said about it"
            return res
        inverted = self._said_where(tree, toks, ignored)
        if inverted is not None:
            # "the study is this room", "the keys are on the table": the noun phrase first, then where it
            # is; the same teaching as "this room is the study", "the keys are here on the table"
            tree, ignored, partial = inverted, [], False
            frame = build(tree)
            obj = frame[0]
        small_talk = (_small_talk(tree, obj, toks, Lexicon.words(words)) or _made_or_where(obj, toks, Lexicon.words(words))
                      or _said_of(tree, toks, ignored, bool(lex.unknown), beside > 0)
                      or _denied(tree, lex.raw))
        if small_talk:
            res.ignored = [t.text for t in toks]
            res.reason = small_talk
            return res
        if partial and ignored and tree_act(tree) == "that_one" and not asked:
            # "this one here, my kettle": the object named after the pointing is what "this one" is (a teaching
            # said in apposition; fresh4 loft_teach_walking_past, her re-show, "Sorry, I did not understand you")
            said = self._named_after_pointing(toks, ignored)
            if said is not None:
                tree, ignored, partial = said
                frame = build(tree)
                obj = frame[0]
        if partial and ignored and tree_act(tree) == "where":
            # "sorry where was [I], that vase is from my grandmother" ("I" lost): no where-question goes on with a
            # copula after its object; the words from the deixis on are a statement of their own about what she
            # shows (fresh4 ring_visitor_leaves seeds 4, 6, 7: "I don't know where to find the vase")
            said = self._statement_after_where(toks)
            if said is not None:
                tree, ignored, partial = said
                frame = build(tree)
                obj = frame[0]
        if ignored and tree_act(tree) == "teach_object" and _from_someone(toks, ignored):
            # "that vase is from my grandmother", "this is my cup, it's from my mother": where it came from is
            # said of the object she shows, no words lost (fresh4 ring_visitor_leaves: "Is this vase?")
            ignored, partial = [], False
        split = self._contrast_split(toks, bool(lex.unknown)) if tree_act(tree) == "teach_object" else None
        if split is not None:
            # "this lamp here is mine, the other one is my husband's", "this cup is mine, that one is anna's", "this
            # is my pen, the other one belongs to my son": a second clause that says whose another thing is (one she
            # does not show) contrasts with the teaching; it is set aside, and the teaching, whole, keeps its own
            # owner (talk21: the husband's lamp was stored, "belongs to my son" was taken as the pen's owner)
            res.corrected += [t.text for t in toks[split[0]:]]
            # whose the shown thing is, lost ("this lamp here [is mine], the other one is ..."): still a word lost
            tree, ignored, partial = split[1], [], split[2] or _owned(split[1]) is None
            if _owned(tree) is None and (mended := self._owned_clause(toks[:split[0]], None)) is not None:
                tree = mended  # only the copula lost ("this cup here [is] mine, that one is ..."): hers, partial
            frame = build(tree)
            obj = frame[0]
        res.frame = frame
        res.fragment = tree_act(tree) in _FRAGMENTS or _bare_side(tree)
        res.ignored = ignored + given_up
        res.partial = partial or bool(res.ignored)
        used = len(toks) - len(ignored)
        if ignored and tree_act(tree) == "greeting" and self._request_after_greeting(toks, ignored,
                                                                                       not lex.unknown):
            used = len(toks)  # "hello biron, follow me": the greeting is sure; the request is not noise
            res.rest = list(ignored)
        elif ignored and tree_act(tree) == "greeting" and _greeted_by_name(tree, toks, ignored):
            # "[good to] biron, it is a pleasure to meet you" ("good day" misheard): the robot named and greeted
            # in words it knows; what it could not place came before its name, the turn's opening misheard.
            # The greeting is sure (no "Did you say hello to me?" to a greeting said whole after the name)
            used = len(toks)
        vocative = _vocative_after(tree, Lexicon.words(words), self.lexicon.hesitations)
        if vocative:
            # "goodbye dear", "bye love", "hello friend": a greeting or good-bye that calls the one it is said to by
            # an endearment (the turn was not said to someone else: :func:`_said_to_another` came first) is whole;
            # the vocative is no word lost (it was a half-heard good-bye, "Do you want to end the tour?")
            res.ignored = [w for w in res.ignored if w not in vocative]
            res.unknown = [w for w in res.unknown if w not in vocative]
            lex.unknown = [w for w in lex.unknown if w not in vocative]
            used = len(toks) - len([w for w in ignored if w not in vocative])
            res.partial = partial and bool(res.ignored)
        if tree_act(tree) == "greeting" and res.ignored and not lex.unknown \
                and all(t.type in ("HELLO", "ROBOT", "ROBOTNAME") for t in toks) and toks[-1].type == "HELLO":
            # "hi robot, hi!", "hello biron hello": the greeting said again after the robot was named (a child's
            # greeting, fresh8 lflat_child_bedroom: "Did you say hello to me?" until the third try) is one whole
            # greeting; the repeated word is no word lost
            res.ignored, res.partial, used = [], False, len(toks)
        if tree_act(tree) == "greeting" and _hello_to_someone_else(toks, Lexicon.words(words), lex.unknown):
            # "hi sara, how are you doing": a hello to a name it does not know, its own name not said, greets
            # someone else (a phone call, a visitor); the words that go with a greeting make it no surer that it
            # is meant for the robot, so they count as words not used and the dialog asks (review17 F7)
            used -= sum(1 for t in toks if t.type == "MEET")
        if any(t.type == "PLACE" and t.text in lex.coined for t in toks) and not set(lex.coined) <= set(res.ignored):
            # "this is the craft room": a room named with a word the lexicon lacks may be a remark ("the
            # cold room") or a misheard word: a guess the dialog confirms before it is stored or driven to
            guess = True
        if obj.tag == "PLACE" and _only_room(obj):
            # "this is our room", "this is my room": a place named by the word "room" alone says which room
            # only by whose it is; it is also what is left when the recogniser loses the name ("this is our
            # [living] room", fresh2/diag_paraphrase_confirm seed 2): a guess the dialog confirms first
            guess = True
        res.coverage = 1.0 if called_along else \
            used / max(1, len(toks) + len(given_up) + len(lex.unknown)) * (0.5 if guess else 1.0)
        why = "" if called_along else _not_meant(tree, toks, res, [w for w in Lexicon.words(words) if w not in _SOUNDS],
                                                 asked is not None)
        if why:
            res.frame, res.fragment, res.rest = None, False, []
            res.ignored = [t.text for t in toks]
            res.reason = why
        elif obj.tag == "WAIT":
            res.stay = _stays(toks, Lexicon.words(words))
        return res

    def _said_where(self, tree: Tree, toks: list[Tok], ignored: list[str]) -> Tree | None:
        """The teaching a noun phrase, a copula and where it is make, or None.

        "the study is this room", "my cup is this one" say "this room is the study", "this one is my cup"
        with the noun phrase first; "the keys are on the table" is "the keys are here on the table". The
        grammar places only the noun phrase (a fragment, the rest not placed): the statement said in the
        order the grammar knows is the teaching, when it parses whole.
        """
        at = _copula_at(tree, toks, ignored)
        if at is None or at + 1 >= len(toks):
            return None
        np, cop, rest = toks[:at], toks[at], toks[at + 1:]
        if rest[0].type in _DEIXIS:
            alt = self._parse([*rest, cop, *np])
        elif rest[0].type in _RELATIONS:
            alt = self._parse([*np, cop, _SAID_HERE, *rest])
        else:
            return None
        if alt[0] is None or alt[2] or alt[1] or _guessed(alt[0]) or tree_act(alt[0]) not in _STATEMENT_ACTS:
            return None
        return alt[0]

    def _asked(self, toks: list[Tok]) -> Tree | None:
        """The teaching a yes/no question about what she shows asks about, or None.

        "is this the kitchen", "is that my cup", "is this room the study", "is it the red book": the
        copula first, then a deixis, then a place or an object named by its noun. The question is
        parsed as the statement it asks about (the copula moved before the noun phrase): a whole
        place or object teaching with its noun said, not of the robot's own things ("is this your
        cup", "are these shoes yours" ask about the robot, and teach nothing), and nothing left over.
        """
        starts = [k for k in range(len(toks) - 2) if toks[k].type in ("IS", "ARE")
                  and toks[k + 1].type in ("THIS", "THAT", "IT")]
        if not starts or starts[0] != 0 or any(t.type not in ("IS", "ARE", "THIS", "THAT", "IT")
                                               for t in toks[: starts[-1]]):
            return None
        toks = toks[starts[-1]:]  # "is it, is this the bedroom": the question said again counts
        while len(toks) > 3 and toks[-1].type in ("YES", "OKAY"):
            toks = toks[:-1]  # "is this the bathroom, right?": a tag asks for the same yes
        at = next((k for k in range(2, len(toks)) if toks[k].type in _NP_START), None)
        if at is None:
            return None
        tree, ignored, partial = self._parse([*toks[1:at], toks[0], *toks[at:]])
        if tree is None or partial or ignored or _guessed(tree) or tree_act(tree) not in ("teach_place",
                                                                                            "teach_object"):
            return None
        if any(t.type in ("YOUR", "MINE") and t.value == "robot" for t in toks):
            return None
        if any(t.type == "NAME" and self.lexicon.entries.get(tuple(t.text.split()), ("", ""))[0] in ("ROBOT", "ROBOTNAME")
               for t in toks):
            return None  # "is this biron's cup", "is that the robot's charger": the robot's own things
        return tree

    def _after_negation(self, toks: list[Tok], at: int) -> list[Tok] | None:
        """What she says instead after a negated request (``toks[at]`` is its verb), or None.

        The first tail after the verb that is a whole request by itself (not a noun phrase, a yes/no
        or a which-one answer) and differs from the negated one: "don't stop, keep going" (follow),
        "don't go to the kitchen, go to the bathroom" (the bathroom). """
        for k in range(at + 1, len(toks)):
            tree, _, partial = self._parse(toks[k:])
            if tree is None or partial or _guessed(tree) or tree_act(tree) in _NOT_REQUESTS:
                continue
            said, _, cut = self._parse(toks[at:k])
            if said is None or cut or _guessed(said):
                continue  # the negation's scope is a whole request: "don't go [to the kitchen]" is one
            if etree.tostring(build(said)) == etree.tostring(build(tree)):
                continue  # "don't stop, stop": the same request said again is still negated
            return toks[k:]
        return None

    def _restart(self, raw: list[Tok]) -> tuple[list[Tok], tuple[Tree | None, list[str], bool]] | None:
        """The words after the last editing term, when they are a whole request by themselves.

        A repair that starts a new clause ("this is a cup, no, it's a glass", "follow me, no wait,
        stop") replaces everything before it; a repair that continues a phrase ("the red, no, the
        blue cup") is aligned with its reparandum by the lexicon instead.
        """
        last = None
        for i, t in enumerate(raw):
            if i and (t.type == EDIT or (t.type == "NO" and any(x.type not in ("NO", EDIT) for x in raw[:i]))):
                last = i
        if last is None:
            return None
        tail = raw[last + 1 :]
        while tail and tail[0].type in (EDIT, "NO"):
            tail = tail[1:]
        if not tail:
            return None
        parsed = self._parse(tail)
        if parsed[0] is None or parsed[2] or tree_act(parsed[0]) in _NOT_RESTARTS:
            return None
        return tail, parsed

    def _whole_request_after(self, toks: list[Tok]) -> tuple[Tree, list[str], bool] | None:
        """The longest tail of ``toks`` (from the second token on) that opens with a whole request.

        A request is an act of its own (not a noun phrase, a yes/no or a which-one answer), closed
        without a guessed empty object or place; words after it may be left over. The words before
        it are reported as ignored, so the coverage falls with the preamble's length.
        """
        found = self._whole_request_at(toks)
        if found is None:
            return None
        i, tree, ignored = found
        return tree, [t.text for t in toks[:i]] + ignored, True

    def _owner_after_skip(self, toks: list[Tok], title: etree._Element | None) -> tuple[Tree, list[str], bool] | None:
        """The object teaching with an owner that a copula put in for one misheard word before the owner, or
        leaving out the fewest contiguous words (one to three, not the first word), gives, parsed whole, of the
        same thing (``title``: the noun the first parse heard); None when none does."""
        if title is None:
            return None
        trials = [(i, 1, toks[:i] + [_SAID_IS] + toks[i + 1:]) for i in range(1, len(toks) - 1)
                  if toks[i].type not in ("IS", "ARE") and toks[i + 1].type in ("MINE", "MY", "NAME")]
        trials += [(-1, 0, [])]  # (then the clause up to "mine", the rest set aside: _owner_before_another_clause)
        trials += [(i, n, toks[:i] + toks[i + n:]) for n in (1, 2, 3) for i in range(1, len(toks) - n)]
        # the copula misheard ("the red book on the shelf [is→a] mine", fresh5 stair_three_on_shelf seeds 5, 6)
        # first, then the fewest words left out
        for i, n, rest in trials:
            if i < 0:
                clause = self._owner_before_another_clause(toks, title)
                if clause is not None:
                    return clause
                continue
            tree, lost, _ = self._parse(rest)
            if tree is None or lost or _guessed(tree) or tree_act(tree) not in ("teach_object", "object_fragment"):
                continue
            said = build(tree).find("OBJECT/TITLE")
            if _owned(tree) is not None and said is not None and said.get("name") == title.get("name"):
                return tree, [t.text for t in toks[i:i + n]], True
        return None

    def _owner_before_another_clause(self, toks: list[Tok], title: etree._Element) -> tuple[Tree, list[str], bool] | None:
        """"The blue mug here [is] mine, the red and the yellow belong to my flatmates" (the copula lost, then a
        second clause about other things): the clause up to the first "mine"/"ours" (``MINE``), with the copula put in
        before it when it was lost, is the teaching of the same thing (``title``) with the speaker as owner; the words
        after it are set aside (whose the other things are: she does not show them) and, with the copula lost, the
        teaching is partial, so the dialog confirms it with the owner said back ("Is this your blue mug?"). Before,
        the owner sank with the clause after it and the mug was stored without her (fresh12 studio_three_mugs seed
        0). None when the clause, so mended, is no whole teaching of that thing with an owner, or nothing follows."""
        m = next((k for k, t in enumerate(toks) if t.type == "MINE"), None)
        if m is None or m < 2:
            return None
        tree = self._owned_clause(toks[:m + 1], title.get("name"))
        return (tree, [t.text for t in toks[m + 1:]], True) if tree is not None else None

    def _owned_clause(self, head: list[Tok], title: str | None) -> Tree | None:
        """The whole teaching with an owner that the clause ``head`` (ending in "mine"/"ours") gives, with the
        copula put in before the owner when it was lost ("the blue mug here [is] mine"), of the thing ``title``
        (any, when None); None when it gives none."""
        m = len(head) - 1
        if m < 2 or head[m].type != "MINE":
            return None
        tries = [head] if head[m - 1].type in ("IS", "ARE") else [[*head[:m], _SAID_IS, head[m]], head]
        for words in tries:
            tree, lost, _ = self._parse(words)
            if tree is None or lost or _guessed(tree) or tree_act(tree) not in ("teach_object", "object_fragment") \
                    or _owned(tree) is None:
                continue
            said = build(tree).find("OBJECT/TITLE")
            if title is None or (said is not None and said.get("name") == title):
                return tree
        return None

    def _whose_lost(self, toks: list[Tok], ignored: list[str]) -> tuple[Tree, list[str], bool] | None:
        """"This bottle is [mine→this]", "that vase is [mine→uh]": a pointed teaching whose subject
        names the thing (deixis and noun, parsed whole) and whose predicate after the copula, the last
        word, was lost (a function word that cannot end the sentence, or nothing). The only one-word
        predicates the language has for "this bottle is ..." say whose it is (mine, ours, Anna's), and
        "mine" is what people showing their things say: the teaching with the speaker as owner, still
        words lost (partial), so the dialog confirms it with the owner said back ("Is this your
        bottle?") and she can say no. None when the words say anything else."""
        k = len(toks) - len(ignored)
        if k < 2 or toks[0].type not in _DEIXIS or [t.text for t in toks[k:]] != ignored or toks[k].type not in ("IS", "ARE") \
                or len(ignored) > 2 or any(t.type not in _LOST_PREDICATE for t in toks[k + 1:]):
            return None
        head, lost, _ = self._parse(toks[:k])
        if head is None or lost or _guessed(head) or tree_act(head) != "teach_object" or _owned(head) is not None \
                or build(head).find("OBJECT/TITLE") is None:
            return None
        tree, lost, _ = self._parse([*toks[:k], toks[k], _SAID_MINE])
        if tree is None or lost or _owned(tree) != "speaker":
            return None
        return tree, ignored[1:] or ignored, True

    def _determiner_lost(self, toks: list[Tok]) -> tuple[Tree, list[str], bool] | None:
        """"This is [my→and] vase", "that one is [my→it] cup", "here you can see [my→] blue bag": a teaching
        whose noun phrase after the copula (or "here you can see") has no determiner, or a function word
        that is none in its place (it, that, this, to, in; the lexicon drops "and", "uh" and a doubled
        "is" before the grammar sees them). A singular noun after "is" needs one, and people showing
        their things in their home say "my" (the owners the generated tours lost, measure16: 12 of 67):
        the word there was lost, and which one it was is not known. The teaching with the speaker as
        owner, words lost (partial) and a guess, so the dialog confirms it with the owner said back
        ("Is this your vase?") and she can say no or say it again without "my" (the dialog then drops
        the owner it guessed). None when a determiner was heard ("this is a vase", "the vase", "Anna's
        vase": no evidence of a lost word; a/the misheard for my cannot be told from a/the said)."""
        heads = [i for i, t in enumerate(toks) if t.type == "OBJ"]
        if not heads or any(t.type in ("MY", "OUR", "YOUR", "MINE", "POSS", "NAME", "BELONGS") for t in toks):
            return None
        k = heads[0]
        while k > 0 and toks[k - 1].type in _NP_MODIFIERS:
            k -= 1
        shown = heads[0] == len(toks) - 2 and toks[-1].type in ("THERE", "HERE")
        if shown and (k == 0 or (k == 1 and toks[0].type in _LOST_DETERMINER - {"THIS", "THAT"})):
            # "[my→] remote control, there", "[my→to] orange ball there": the thing named and where, said
            # whole, with nothing (or a function word that is none) before the noun phrase
            at, lost, tail = 0, [t.text for t in toks[:k]] + [toks[-1].text], toks[k:-1]
        elif k < 1:
            return None
        elif toks[k - 1].type in ("IS", "ARE", "HERE"):
            at, lost, tail = k, [], toks[k:]  # nothing heard between the copula and the noun phrase
        elif k >= 2 and toks[k - 1].type in _LOST_DETERMINER and toks[k - 2].type in ("IS", "ARE", "HERE"):
            at, lost, tail = k - 1, [toks[k - 1].text], toks[k:]  # a function word that is no determiner in its place
        else:
            return None
        if at > 0 and toks[at - 1].type == "HERE" and not any(t.type in _DEIXIS - {"HERE"} for t in toks[:at - 1]) \
                and toks[at - 1].text in ("here", "there"):
            return None  # "here [is] ...": "here" alone before the noun ("here keys") is no "here you can see"
        tree, missed, _ = self._parse([*toks[:at], _SAID_MY, *tail])
        if tree is None or missed or _guessed(tree) or tree_act(tree) not in ("teach_object", "object_fragment") \
                or _owned(tree) != "speaker":
            return None
        return tree, lost, True

    def _landmark_taken(self, toks: list[Tok], ignored: list[str]) -> tuple[Tree, list[str], bool] | None:
        """"this is my blue [mug] on the table", "the green [vase] on the piano was a present": the thing's noun
        lost, the parse skipped the relation and took the landmark after it as the thing ("Is this your blue
        table?"; talk22, fresh10's kind). The landmark said after "on/at/... the" is where the thing stands, never
        the thing: the teaching without the landmark's words (what it is unknown: the dialog asks), still partial.
        None when a noun came before the relation (the thing was said) or the relation was not left out."""
        rel = next((i for i, t in enumerate(toks) if t.type in ("REL", "IN")), None)
        if rel is None or toks[rel].text not in ignored or any(t.type == "OBJ" for t in toks[:rel]):
            return None
        end = rel + 1
        while end < len(toks) and toks[end].type in ("THE", "A", "MY", "OUR", *_NP_MODIFIERS):
            end += 1
        if end >= len(toks) or toks[end].type != "OBJ" or end == rel + 1:
            return None
        kept = [*toks[:rel], *toks[end + 1:]]
        alt, lost, _ = self._parse(kept) if kept else (None, [], True)
        if alt is None or tree_act(alt) not in ("teach_object", "object_fragment") \
                or build(alt).find("OBJECT/TITLE") is not None:
            return None
        return alt, [*lost, *(t.text for t in toks[rel:end + 1])], True

    def _relation_lost(self, toks: list[Tok]) -> tuple[Tree, list[str], bool] | None:
        """"That blue vase [on→this] the sideboard was a wedding present", "this is my cup [on→to] the table": an
        object teaching whose relation word before the landmark was misheard (a function word that is no relation),
        so the landmark and every word after it were left out. Where she said it is, is what the robot's
        look needs when it does not see her point (fresh6/div_long_tour seed 0: the vase "could not be found",
        her gesture never seen and the sideboard lost). The teaching with the thing at that landmark (``POSITION``
        with ``RELATION name="at"``, as :meth:`_where_lost`); the words after the landmark stay left out; still
        partial. None when no landmark follows the thing in that way."""
        heads = [i for i, t in enumerate(toks) if t.type == "OBJ"]
        if len(heads) < 2:
            return None
        h = heads[0]
        for k in range(h + 2, min(h + 4, len(toks))):
            # the thing, then a word that is no relation (after the copula, if said), then "the <landmark>"; none
            # at all ("the vase the sideboard") is left alone: nothing says a word was lost there
            if toks[k].type not in ("THE", "A", "MY", "OUR") or any(t.type not in _LOST_PREDICATE for t in toks[h + 1:k]) \
                    or toks[k - 1].type in ("IS", "ARE"):
                continue
            end = k + 1
            while end < len(toks) and toks[end].type in _NP_MODIFIERS:
                end += 1
            if end >= len(toks) or toks[end].type != "OBJ":
                return None
            tree, lost, _ = self._parse([*toks[:k - 1], _SAID_AT, *toks[k:end + 1]])
            if tree is None or lost or _guessed(tree) or tree_act(tree) != "teach_object" \
                    or build(tree).find("OBJECT/POSITION/TITLE") is None:
                return None
            return tree, [toks[k - 1].text] + [t.text for t in toks[end + 1:]], True
        return None

    def _where_lost(self, toks: list[Tok], ignored: list[str]) -> tuple[Tree, list[str], bool] | None:
        """"the one [on→to] the table", "the one [on→] the counter": a which-one answer whose relation
        word was lost (a function word that is no relation, or none), the place after it heard whole: the
        one at that place (``POSITION`` with the landmark; the object attention takes the option standing
        on it, and asks again when that singles none out). Still words lost (partial). None otherwise."""
        k = len(toks) - len(ignored)
        if k < 1 or toks[k - 1].type != "ONE" or [t.text for t in toks[k:]] != ignored:
            return None
        rest = toks[k + 1:] if toks[k].type in _LOST_PREDICATE and len(toks) > k + 1 and toks[k + 1].type in ("THE", "A", "MY", "OUR") \
            else toks[k:]
        if not rest or rest[0].type not in ("THE", "A", "MY", "OUR"):
            return None
        tree, lost, _ = self._parse([*toks[:k], _SAID_AT, *rest])
        if tree is None or lost or tree_act(tree) != "that_one" or build(tree).find("THAT_ONE/POSITION/TITLE") is None:
            return None
        return tree, ignored[: len(ignored) - len(rest)], True

    def _whole_request_at(self, toks: list[Tok]) -> tuple[int, Tree, list[str]] | None:
        """(where it starts, its tree, the words left over after it) of :meth:`_whole_request_after`'s request."""
        for i in range(1, len(toks) - 1):
            tree, ignored, _ = self._parse(toks[i:])
            if tree is None or _guessed(tree) or tree_act(tree) in _NOT_REQUESTS:
                continue
            if ignored and [t.text for t in toks[len(toks) - len(ignored):]] != ignored:
                continue  # a word skipped inside the request: not said as a whole
            return i, tree, ignored
        return None

    def _named_after_pointing(self, toks: list[Tok], ignored: list[str]) -> tuple[Tree, list[str], bool] | None:
        """The object teaching "this one here, my kettle" makes: a which-one pointing ("this one", "this one
        here") and then, as the turn's tail, a noun phrase with its noun ("my kettle", "the red cup"), read as
        "this is my kettle"; None otherwise."""
        tail = toks[len(toks) - len(ignored):]
        if [t.text for t in tail] != ignored or not tail or tail[0].type in ("IS", "ARE") \
                or not any(t.type == "OBJ" for t in tail) or toks[0].type not in ("THIS", "THAT"):
            return None
        tree, lost, cut = self._parse([Tok("THIS", "this", ""), Tok("IS", "is", ""), *tail])
        if tree is None or cut or lost or _guessed(tree) or tree_act(tree) != "teach_object":
            return None
        return tree, [], False

    def _statement_after_where(self, toks: list[Tok]) -> tuple[Tree, list[str], bool] | None:
        """The object teaching said after a "where" whose object a copula follows ("where [was I] that vase
        is from my grandmother"): the tail from the first deixis after "where", when it parses as a teaching
        with a copula in it and no word lost but where the object came from, else None."""
        at = next((k for k, t in enumerate(toks) if t.type == "WHERE"), None)
        if at is None:
            return None
        k = next((k for k in range(at + 1, len(toks)) if toks[k].type in ("THIS", "THAT")), None)
        if k is None or not any(t.type in ("IS", "ARE") for t in toks[k + 1:]) \
                or not any(t.type in ("IS", "ARE") for t in toks[k + 2:]):
            return None
        tree, ignored, partial = self._parse(toks[k:])
        if tree is None or _guessed(tree) or tree_act(tree) != "teach_object":
            return None
        if ignored and not _from_someone(toks[k:], ignored):
            return None
        return tree, [t.text for t in toks[:k]], True  # where it came from is said of it (no words lost)

    def _request_after_errand(self, words: str, rest: list[str]) -> Understanding | None:
        """The understanding of a whole request said after an errand's verb and its object ("[I will just
        grab] my phone, follow me please"), or None when the errand ends the turn.

        The first tail of ``rest`` (the words after the verb: "let me just see, where is my cup") understood whole
        by itself: a request or statement with no word lost (not a noun phrase, a yes/no or a which-one
        answer), so "let me just put the water on" stays a wait (its tails are noun phrases)."""
        for j in range(len(rest)):
            tail = self.understand(" ".join(rest[j:]))
            if tail.frame is None or tail.partial or tail.fragment or tail.aside or tail.act in ("YES", "NO", "THAT_ONE"):
                continue
            tail.words = words
            return tail
        return None

    def _request_after_remark(self, words: str, said: list[str]) -> Understanding | None:
        """The understanding of the whole request said after a leading remark (:func:`_remark_ends`), or None.

        The first place after the remark's verb where the rest, understood by itself, is a whole request (no word
        lost, not a noun phrase, a yes/no or a which-one answer, not an aside) that opens with a request's verb or
        a request word ("go to", "you can go", "follow me", "could you go"); the remark's words count as set aside
        (``corrected``). One rule for "the way is free now, go to X" and any other remark that shows nothing."""
        verb = _remark_verb(said, self.lexicon)
        if verb is None:
            return None
        for at in range(verb + 2, len(said) - 1):
            rest = self.lexicon.tokens(" ".join(said[at:]))
            opening = next((j for j in range(at, len(said)) if self.lexicon.tokens(said[j]).tokens
                            or self.lexicon.tokens(said[j]).unknown), None)  # the first word not a filler
            if not rest.tokens or rest.tokens[0].type not in _REQUEST_OPENERS or opening is None \
                    or self.lexicon.tokens(said[opening]).unknown:
                continue
            tail = self.understand(" ".join(said[at:]))
            if tail.frame is None or tail.partial or tail.fragment or tail.aside \
                    or tail.act in ("YES", "NO", "THAT_ONE", "PLACE", "OBJECT"):
                continue
            tail.words = words
            tail.corrected = [*said[:at], *tail.corrected]
            return tail
        return None

    def _contrast_split(self, toks: list[Tok], name_lost: bool) -> tuple[int, Tree, bool] | None:
        """Where a clause saying whose another thing is (:func:`_contrast`) starts after a whole object teaching
        (its owner perhaps lost), and that teaching parsed by itself; None when the turn has no such two parts."""
        for k in range(2, len(toks) - 2):
            if toks[k].type not in ("THE", "THAT") or not _contrast(toks[k:], name_lost):
                continue
            head, lost, part = self._parse(toks[:k])
            if head is not None and not _guessed(head) and tree_act(head) == "teach_object":
                return k, head, bool(lost or part)
        return None

    def _follow_after_suggestion(self, words: str, said: list[str]) -> Understanding | None:
        """The whole follow request said after a suggestion question ("shall we go to the kitchen? follow me"),
        or None.

        A turn that opens (after openers and hesitations) with a suggestion to go together ("shall we", "should
        we", "shall i", "how about", "what about", "why don't we"): the first tail after the suggestion's next
        word that, understood by itself, is a whole follow (no word lost) is what she asks; the suggestion's words
        count as set aside (``corrected``). Only a follow: a suggestion alone, or one followed by anything
        else, is left to the other rules."""
        plain = [w for w in said if w not in _SOUNDS and w not in self.lexicon.hesitations]
        start = next((i for i, w in enumerate(plain) if w not in _SUGGESTION_BEFORE), len(plain))
        if not any(tuple(plain[start:start + len(lead)]) == lead for lead in _SUGGESTION_LEADS):
            return None
        return self._whole_follow_in_tail(words, plain, range(start + 3, len(plain)))

    def _where_after_thing(self, words: str, said: list[str]) -> Understanding | None:
        """A where-question asked after the thing is named ("and my glass, where it is now", "the keys, where are
        they", "my red cup, where is it please"), or None (talk23).

        After openers the turn opens with a determiner or owner (:data:`_DESTINATION_DETERMINERS`, "your", "the")
        and at most three more words with no verb or copula, then "where" and only a pronoun and a copula in
        either order ("it is", "is it", "they are", "are they"), then at most "now", "please", "gone" or the
        robot's name. The question is the one about the named thing ("where is my glass")."""
        plain = [w for w in said if w not in _SOUNDS and w not in self.lexicon.hesitations]
        start = next((i for i, w in enumerate(plain) if w not in _SUGGESTION_BEFORE), len(plain))
        if "where" not in plain[start:]:
            return None
        at = plain.index("where", start)
        head, tail = plain[start:at], plain[at + 1:]
        if not 2 <= len(head) <= 4 or head[0] not in (*_DESTINATION_DETERMINERS, "your") \
                or any(w in _NOT_A_NOUN_PHRASE for w in head[1:]):
            return None
        while tail and tail[-1] in ("now", "please", "gone", "biron", "robot", "then", "again"):
            tail = tail[:-1]
        if tuple(tail) not in _WHERE_TAILS:
            return None
        verb = "are" if tail[0] in ("they", "are") else "is"
        out = self.understand(f"where {verb} {' '.join(head)}")
        if out.act != "WHERE" or out.partial or out.aside:
            return None
        out.words = words
        out.corrected = plain[:start]
        return out

    def _owned_after_copula(self, words: str, said: list[str]) -> Understanding | None:
        """A thing shown and said to be hers with its noun or a word of praise after "my"/"our" ("this chair is my
        favourite", "that lamp is our old lamp", "the red flower behind me is my favourite plant"), or None (talk23).

        The last "is" is followed by "my" or "our" and one or two words: attributes the lexicon knows and at most
        one noun, of the same kind as the thing before "is" (or "one", "thing"). The turn is understood as if she
        had said "... is mine" / "... is ours" (its owner; partial as that is), with the attributes added."""
        if self._in_owned_after_copula:
            return None
        plain = [w for w in said if w not in _SOUNDS and w not in self.lexicon.hesitations]
        at = max((i for i, w in enumerate(plain) if w == "is"), default=None)
        if at is None or at < 2 or at + 2 >= len(plain) or plain[at + 1] not in ("my", "our") or len(plain) - at - 2 > 2:
            return None
        tail = plain[at + 2:]
        kinds = [[t.type for t in self.lexicon.tokens(w).tokens] for w in tail]
        if not all(k in (["ATTR"], ["OBJ"]) or w in ("one", "thing") for k, w in zip(kinds, tail)) \
                or sum(k == ["OBJ"] for k in kinds) > 1:
            return None  # "... is my mother's", "... is my son's old one": whose else, or more than a word of praise
        head = self.understand(" ".join([*plain[:at], "is", "mine" if plain[at + 1] == "my" else "ours"]))
        if head.act != "OBJECT" or head.frame is None or head.aside:
            return None
        obj = head.frame[0]
        if obj.find("OWNER") is None or obj.get("type") is None:
            return None
        again = self.understand(" ".join(["this", "is", plain[at + 1], *tail]))
        if again.act == "OBJECT" and again.frame is not None and not again.partial:
            named = again.frame[0]
            if named.get("type") not in (None, obj.get("type")):
                return None
            attrs = [a.get("name") for a in named.iter("ATTRIBUTE")]
        elif all(self.lexicon.tokens(w).tokens and self.lexicon.tokens(w).tokens[0].type == "ATTR" for w in tail) \
                or tail[-1] in ("one", "thing"):
            attrs = [t.value for w in tail for t in self.lexicon.tokens(w).tokens if t.type == "ATTR"]
        else:
            return None
        if head.partial:
            # words lost besides ("the red flower behind me is my favourite plant"): only where the turn is that very
            # teaching anyway, with its owner lost (a loose rule cost a held-out row; counts only)
            self._in_owned_after_copula = True
            try:
                alone = self.understand(words)
            finally:
                self._in_owned_after_copula = False
            if alone.act != "OBJECT" or alone.frame is None or alone.frame[0].get("type") != obj.get("type") \
                    or alone.frame[0].find("OWNER") is not None:
                return None
        have = {a.get("name") for a in obj.iter("ATTRIBUTE")}
        after = [k for k, c in enumerate(obj) if c.tag in ("GESTURE", "TITLE", "OWNER", "COLOUR", "ATTRIBUTE")]
        at_el = after[-1] + 1 if after else len(obj)
        for a in attrs:
            if a and a not in have:
                el = etree.Element("ATTRIBUTE", name=a)
                obj.insert(at_el, el)
                at_el += 1
                have.add(a)
        head.words = words
        return head

    def _greeting_with_pleasantries(self, words: str, said: list[str]) -> Understanding | None:
        """A whole greeting, then only pleasantries said to the robot, or None (lang24).

        The turn opens with a greeting word; the shortest head ``plain[:at]`` understood by itself as a whole
        GREETING (no word lost, nothing left over) is followed by words that split into pleasantries only
        (:meth:`_pleasantries`): a greeting formula of its own ("nice to meet you", "lovely to see you"), who she
        is ("i'm anna"), a welcome to the home ("welcome", "welcome to our flat") or a remark or question about
        the robot that asks for nothing the robot does ("so you're the new robot", "did you have a good trip").
        The greeting is then whole, the pleasantries set aside (``corrected``); before, such a turn was a greeting
        with words lost, and the robot asked "Did you say hello to me?" (fresh11 G). Anything that is a request,
        a teaching or a question the robot answers in the tail leaves the turn to the other rules."""
        if self._in_new_rule:
            return None
        plain = [w for w in said if w not in _SOUNDS and w not in self.lexicon.hesitations and w != "oh"]
        if len(plain) < 3 or len(plain) > _GREETING_TURN_WORDS:
            return None
        first = self.lexicon.tokens(" ".join(plain[:2])).tokens  # "good evening": a greeting of two words
        if not first or first[0].type != "HELLO" or not first[0].text.startswith(plain[0]):
            return None
        alone = self._without_new_rules(words)
        if alone.frame is not None and (alone.act not in ("GREETING", "GOODBYE") or alone.aside or alone.rest
                                        or not (alone.partial or alone.coverage < 1.0)):
            return None  # understood otherwise, or whole already (a half good-bye: "hello, ... lovely to see you")
        self._in_new_rule = True  # the head and the pieces are understood without lang24's rules (no nesting)
        try:
            return self._greeting_head(words, plain, alone)
        finally:
            self._in_new_rule = False

    def _greeting_head(self, words: str, plain: list[str], alone: Understanding) -> Understanding | None:
        """:meth:`_greeting_with_pleasantries` once the turn may be one: its shortest whole greeting head
        followed by pleasantries only, or None."""
        seen: dict[tuple[str, ...], bool] = {}
        for at in range(1, len(plain)):  # the shortest head: "hello biron" keeps the name a longer one may lose
            if plain[at] in ("biron", "robot", "there", "POSS"):
                continue  # "hello biron, ...", "hello there, ...": the name goes with the greeting
            if self.lexicon.tokens(plain[at]).unknown and plain[at] not in _PLAIN_WORDS:
                return None  # "hi sara, how are you doing": a hello to someone named, not the robot (review17 F7)
            head = self.understand(" ".join(plain[:at]))
            if head.act != "GREETING" or head.partial or head.aside or head.frame is None or head.rest \
                    or head.answer or head.coverage < 1.0:
                continue
            if not self._pleasantries(tuple(plain[at:]), seen):
                continue
            if alone.act == "GREETING":
                head.frame = alone.frame  # as the whole turn has it (its name, "hello there, ... biron")
            head.words, head.unknown = words, list(alone.unknown)
            head.corrected = [*head.corrected, *plain[at:]]
            return head
        return None

    def _without_new_rules(self, words: str) -> Understanding:
        """How ``words`` are understood without lang24's two rules (they apply only where that is a half greeting
        or a thing shown)."""
        self._in_new_rule = True
        try:
            return self.understand(words)
        finally:
            self._in_new_rule = False

    def _pleasantries(self, tail: tuple[str, ...], seen: dict[tuple[str, ...], bool]) -> bool:
        """Whether ``tail`` splits into pleasantries said after a greeting (:meth:`_greeting_with_pleasantries`)."""
        if not tail:
            return True
        if tail in seen:
            return seen[tail]
        seen[tail] = False
        for k in range(min(len(tail), _PLEASANTRY_WORDS), 0, -1):
            if self._pleasantry(list(tail[:k])) and self._pleasantries(tail[k:], seen):
                seen[tail] = True
                return True
        return False

    def _pleasantry(self, piece: list[str]) -> bool:
        """One pleasantry (:meth:`_greeting_with_pleasantries`): a greeting formula, who she is, a welcome to the
        home, or words about the robot ("you", its name, "robot") that the understanding takes as no act at all."""
        if piece[0] in ("and", "so", "well", "oh") and len(piece) > 1:
            piece = piece[1:]
        if _introduces(piece):
            return True
        if _praises_or_says_where_she_is(piece) or _introduces_another(piece):
            return True  # "good job", "well done", "i'm here behind you", "this is my son ben" (talk24)
        if piece[0] == "welcome" and all(w in _WELCOME_WORDS for w in piece):
            return True  # "welcome", "welcome welcome", "welcome to our home" (not "welcome to my study": a room)
        if piece[0] in _ANSWER_WORDS_ALONE:
            return False  # "yes", "no", "okay" answer something: not said in passing
        if len(piece) <= 6 and piece[0] in ("nice", "lovely", "good", "great", "wonderful", "so") \
                and any(piece[i:i + 3] == ["to", "see", "you"] for i in range(1, len(piece) - 2)):
            return True  # "lovely to see you" after a hello greets (alone it may take leave)
        if len(piece) <= 7 and piece[0] in ("nice", "lovely", "good", "great", "wonderful", "so") \
                and piece[1:4] == ["to", "have", "you"] and all(w in _HAVE_YOU_TAIL for w in piece[4:]):
            return True  # "nice to have you with us", "lovely to have you here" (talk24)
        alone = self.understand(" ".join(piece))
        if alone.aside or (alone.corrected and alone.act != "GREETING") or alone.answer or alone.rest:
            return False
        about_robot = any(w in _ABOUT_THE_ROBOT for w in piece)
        if alone.act == "GREETING":
            return not alone.partial or about_robot
        if piece[-1] in ("robot", "biron") and piece[0] in ("this", "that", "you") and alone.frame is None:
            return True  # "so this is the famous robot", "that's biron": the deixis is the robot itself
        lost = len([w for w in self.lexicon.tokens(" ".join(piece)).unknown if w not in _PLAIN_WORDS])
        return alone.frame is None and about_robot and not any(w in _NOT_IN_A_PLEASANTRY for w in piece) \
            and len(piece) >= 3 and 3 * lost <= len(piece)  # words about it, mostly known ("did you have a good trip")

    def _remark_about_a_thing(self, words: str, said: list[str]) -> Understanding | None:
        """A remark that names a thing without showing it, or None (lang24).

        A teaching needs a deictic act: a deictic word ("this", "that") with the gesture it goes with, or a
        thing named and said to be here. A remark names a thing and says something else of it: the noun phrase
        opens with an article or owner ("the", "my", "our", ...; never "this"/"that"), is followed at most by
        "over there"/"here", and then by a predicate that is no naming: a verb the lexicon does not know ("the
        plant over there needs water", "the printer caught fire, can you believe it") or a habit ("my keys are
        usually in the bowl by the door", "the remote is always on the sofa": where things are kept, not shown
        here; with "here"/"there" or a deixis anywhere in the turn it stays a teaching). Such a turn is not
        understood, and set aside as said in passing (``aside``): no question "Is this the plant?", no half-stored
        thing and no "say that again" (fresh11 H, the long tour's remarks)."""
        if self._in_new_rule:
            return None
        plain = [w for w in said if w not in _SOUNDS and w not in self.lexicon.hesitations]
        start = next((i for i, w in enumerate(plain) if w not in _REMARK_LEAD), len(plain))
        if start >= len(plain) - 2 or plain[start] not in _REMARK_DETERMINERS:
            return None
        if any(w in ("this", "that", "these", "those") and (i + 1 == len(plain) or plain[i + 1] not in _NO_DEIXIS_AFTER)
               and (i == 0 or plain[i - 1] not in ("the", "a", "an")) for i, w in enumerate(plain)):
            # a deixis ("this morning" is a time; "kept [in→this] the bowl" a relation misheard, "in the [blue→that]
            # bowl" a word misheard after an article: no deixis)
            return None
        noun = None  # the index of the thing's noun's last word (a noun of two words: "remote control")
        j = start + 1
        while j < min(start + 6, len(plain)):
            span = next((k for k in (3, 2, 1) if j + k <= len(plain) and _one_token(self.lexicon, plain[j:j + k])), 0)
            kinds = [t.type for t in self.lexicon.tokens(" ".join(plain[j:j + max(span, 1)])).tokens]
            if kinds == ["OBJ"]:
                noun, j = j + span - 1, j + span
                continue
            if noun is not None or (kinds and kinds[0] not in ("ATTR", "COLOUR", "NAME", "MY", "USE")) \
                    or (not kinds and plain[j] != "POSS"):
                break
            j += max(span, 1)
        if noun is None:
            return None
        rest = plain[noun + 1:]
        while rest and rest[0] in ("over", "here", "there", "back"):
            rest = rest[1:]
        where = self.lexicon.tokens(" ".join(rest[:1])).tokens
        if where and where[0].type in _RELATIONS and len(rest) > 2:
            # "the plant by the window needs water": where the thing stands, then what is said of it
            for k in range(2, min(5, len(rest) - 1) + 1):
                kinds = [t.type for t in self.lexicon.tokens(" ".join(rest[1:k])).tokens]
                if kinds and kinds[-1] in ("OBJ", "PLACE", "ROOM") and self.lexicon.tokens(rest[k]).unknown:
                    rest = rest[k:]
                    break
        if not rest:
            return None
        habit = len(rest) > 1 and rest[0] in _COPULAS and rest[1] in _HABITS \
            or rest[0] in _HABITS
        if habit and any(w in ("here", "there") for w in plain):
            return None
        heard = self.lexicon.tokens(" ".join(rest))
        after = self.lexicon.tokens(" ".join(rest[1:2])).tokens
        verb = not habit and bool(heard.unknown) and heard.unknown[0] == rest[0] \
            and not any(t.text.split()[:1] == [rest[0]] for t in heard.tokens) \
            and rest[0] not in _NOT_A_PREDICATE and len(rest[0]) > 2 and len(rest) > 1 \
            and not (after and after[0].type in (*_RELATIONS, *_DEIXIS))  # "lies on the table": where it is
        if not (habit or verb):
            return None
        if any(t.type in (*_VERBS, "WAIT", "GOODBYE", "WHERE") or (t.type == "HELLO" and t.text not in _TIMES_OF_DAY)
               for t in heard.tokens):
            return None  # "the flowers need water, wait a moment": a request said after the remark is no remark
        if self._without_new_rules(words).act != "OBJECT":
            return None  # only what would be taken as showing a thing (a half teaching) is set aside
        out = Understanding(words, None, unknown=self.lexicon.tokens(words).unknown)
        out.ignored = [t.text for t in self.lexicon.tokens(words).tokens]
        out.reason, out.aside = "a remark about a thing she does not show", True
        return out

    def _come_and_see(self, words: str, said: list[str]) -> Understanding | None:
        """A follow said as an invitation to come and see something ("come and see the gallery", "come have a
        look at my study", "now come and see where I sleep"), or None (talk23).

        After openers and hesitations the turn opens with :data:`_COME_AND_SEE` and goes on with a short noun
        phrase (a determiner, then at most four words, none a verb or copula of :data:`_NOT_A_NOUN_PHRASE`) or
        "where" and a short clause: where she goes, what she will show there. The frame is the follow
        (``<FOLLOW/>``, as "follow me to the kitchen"); the words after the lead count as set aside."""
        plain = [w for w in said if w not in _SOUNDS and w not in self.lexicon.hesitations]
        start = next((i for i, w in enumerate(plain) if w not in _SUGGESTION_BEFORE), len(plain))
        lead = next((n for n in _COME_AND_SEE if tuple(plain[start:start + len(n)]) == n), None)
        if lead is None:
            return None
        rest = plain[start + len(lead):]
        while rest and rest[-1] in ("please", "biron", "robot", "now", "then"):
            rest = rest[:-1]
        if not 2 <= len(rest) <= 5:
            return None
        if rest[0] in _DESTINATION_DETERMINERS or rest[0] in ("your", "his", "her", "their"):
            if any(w in _NOT_A_NOUN_PHRASE for w in rest[1:]):
                return None
        elif rest[0] != "where":
            return None
        out = self.understand("follow me")
        if out.act != "FOLLOW":
            return None
        out.words = words
        out.corrected = [*plain[:start], *rest]
        return out

    def _follow_after_destination(self, words: str, said: list[str]) -> Understanding | None:
        """The whole follow request said after a noun phrase alone that names where they go next ("now the
        study, follow me please", "and now the last room, follow me", "next the kitchen, come with me"), or None.

        After openers and hesitations the turn opens with a determiner ("the", "my", "our"), the words up to
        the first tail that, understood by itself, is a whole follow (no word lost) hold no verb and no copula
        (a noun phrase: "the last room is the bedroom, follow me" and "the kitchen is this way" are left to
        the other rules), and that tail is what she asks; the noun phrase counts as set aside (``corrected``)."""
        plain = [w for w in said if w not in _SOUNDS and w not in self.lexicon.hesitations]
        start = next((i for i, w in enumerate(plain) if w not in _SUGGESTION_BEFORE and w != "next"), len(plain))
        if start >= len(plain) or plain[start] not in _DESTINATION_DETERMINERS:
            return None
        return self._whole_follow_in_tail(words, plain, range(start + 2, min(len(plain), start + 6)),
                                          stop_after=_NOT_A_NOUN_PHRASE)

    def _follow_to_what_she_shows(self, words: str, said: list[str]) -> Understanding | None:
        """A follow request that names where she leads, or None (talk24).

        After openers and hesitations, either (1) "come" [over/along/on/back] "to"/"into" a short noun phrase,
        then "with me" ("come over to my study with me"), or (2) a head that understood by itself is a whole
        follow ("come on", "come", "come with me", "follow me") with, before or after it, a clause that says
        she will show something (:data:`_SHOW_LEADS`: "i will show you", "let me show you", "i want you to
        see", ... and a short noun phrase: "come on, now I'll show you the nursery", "let me show you the
        kitchen, come"). The frame is the follow (as "follow me to the kitchen": the room is named when they
        are there); the words that name it are set aside (``corrected``). Before, the noun phrase was taken as
        a teaching of this spot ("Is this the nursery?", or stored at once) or a go-to ("Shall I go to ...?")."""
        plain = [w for w in said if w not in _SOUNDS and w not in self.lexicon.hesitations]
        start = next((i for i, w in enumerate(plain) if w not in _SUGGESTION_BEFORE), len(plain))
        body = plain[start:]
        while body and body[-1] in _AFTER_A_REQUEST:
            body = body[:-1]
        if len(body) < 4 or len(body) > 14:
            return None
        come = next((i for i, w in enumerate(body[:2]) if w == "come"), None)
        misheard_come = come is None and len(body) > 1 and body[0] in _MISHEARD_SHORT \
            and body[1] in ("over", "along", "across", "through")  # "[come→to] along to my study with me"
        if misheard_come:
            come = 0
        tail = next((n for n in (2, 1) if _with_me(body[-n:])), 0)
        if come is not None and tail and come < len(body) - tail - 1:
            # (1) "come [over] to my study with me"; one short word misheard ("[now→to] come over ...", "... with
            # [me→the]", "come [over→a] to ...") leaves it a follow, but one not sure of (partial: "Shall I
            # follow you?")
            k = come + 1
            while k < len(body) and body[k] in _COME_ADVERBS:
                k += 1
            lost = int(come > 0 and body[0] in _MISHEARD_SHORT) + int(body[-tail:] != ["with", "me"]) \
                + int(misheard_come)
            if body[k] in ("to", "into"):
                k += 1
                if body[k] == "to":  # "come [along→to] to my study with me"
                    k, lost = k + 1, lost + 1
            elif body[k] in _MISHEARD_SHORT:
                lost += 1
                k += 1 + int(body[k + 1] in ("to", "into"))
            if lost <= 1 and self._short_noun_phrase(body[k:len(body) - tail]):
                return self._as_follow(words, "come with me", [*plain[:start], *body[come + 1:len(body) - tail]],
                                       sure=not lost)
            return None
        shows = next((i for i in range(1, len(body) - 2) if body[i] in ("show", "see", "take")
                      and (body[i + 1] == "you" or "you" in body[max(0, i - 2):i])), None)
        if shows is None:
            return None
        # (2) a follow's head, then what she will show ("come on, now I'll show you the nursery"), or the other
        # way round ("let me show you the kitchen, come"); the clause's lead may lose a word ("[i→a] will show")
        after = body[shows + 1:]
        if after[:1] == ["you"]:
            after = after[1:]
        if after[:1] == ["to"] and body[shows] == "take":
            after = after[1:]
        lead_at = shows
        while lead_at > 0 and body[lead_at - 1] in _SHOW_LEAD_WORDS:
            lead_at -= 1
        lost = 0
        if lead_at > 0 and body[lead_at - 1] in _MISHEARD_SHORT and body[lead_at - 1] not in _SHOW_OPENERS \
                and lead_at < shows:
            lead_at, lost = lead_at - 1, 1  # "come on [now→a] i will show you the nursery"
        while lead_at > 0 and body[lead_at - 1] in _SHOW_OPENERS:
            lead_at -= 1
        cut = next((c for c in range(min(len(after), 5), 1, -1) if self._short_noun_phrase(after[:c])), None)
        if cut is None:
            return None
        behind = after[cut:]  # the noun phrase, then (maybe) the follow's head
        for at in range(lead_at, shows):  # the clause may start later ("come with me, let me show you ...")
            lead = body[at:shows]
            if not any(w in ("i", "me", "let", "will", "want", "going") for w in lead):
                break  # "show you" alone: no clause of hers ("can you show me the kitchen" is no lead)
            before = body[:at]
            if (before and behind) or not (before or behind):
                continue
            head = before or behind
            said_head = "come with me" if head == ["come"] else " ".join(head)  # "..., come": come along
            aside = body[len(head):] if before else body[:len(body) - len(head)]
            out = self._as_follow(words, said_head, aside, sure=not lost)
            if out is not None:
                return out
        return None

    def _short_noun_phrase(self, words: list[str]) -> bool:
        """A determiner ("the", "my", "our") and one to four words, none a verb, copula or deixis of
        :data:`_NOT_A_NOUN_PHRASE` ("the nursery", "my sleeping corner", "our little garden")."""
        return 2 <= len(words) <= 5 and words[0] in _DESTINATION_DETERMINERS \
            and not any(w in _NOT_A_NOUN_PHRASE or w in _SHOW_NOT_IN_NP for w in words[1:])

    def _as_follow(self, words: str, head: str, aside: list[str], sure: bool = True) -> Understanding | None:
        """``head`` understood by itself as a whole follow, for the turn ``words`` (``aside`` set aside), or None;
        not ``sure``: a word of the turn was misheard, so the follow is partial (the dialog asks first)."""
        out = self.understand(head)
        if out.act != "FOLLOW" or out.partial or out.aside or out.frame is None or out.rest:
            return None
        out.words = words
        out.corrected = [*out.corrected, *aside]
        if not sure:
            out.partial = True
            out.coverage = 1.0 - 1.0 / max(2, len(Lexicon.words(words)))
        return out

    def _everyday_short_forms(self, words: str, said: list[str]) -> Understanding | None:
        """Three everyday short forms (talk24), or None.

        (1) A word of praise first ("good", "great", "lovely", "perfect"), then a whole stop, wait or follow
        ("good, now stop", "great, wait here"): the praise takes the turn as "okay" does. (2) Yes-words or
        "okay", then "come on" ("yes, come on", "okay, come on then"): a follow, with the yes as its answer (it
        answers "Shall I follow you?"). (3) A remark of relief or of taking up the thread, said in passing
        ("there, that's better", "that's much better", "so, where were we", "now, where was I"): not understood
        and said in passing (``aside``), so the robot does not ask to hear it again."""
        plain = [w for w in said if w not in _SOUNDS and w not in self.lexicon.hesitations]
        while plain and plain[-1] in ("biron", "robot"):
            plain = plain[:-1]
        if len(plain) < 2 or len(plain) > 8:
            return None
        if plain[0] in _PRAISE_OPENERS and plain[1] not in _TIMES_OF_DAY:  # "good morning, follow me": a greeting
            k = 1
            while k < len(plain) and plain[k] in ("now", "then", "so", "biron", "robot", "and"):
                k += 1
            if k < len(plain):
                rest = self.understand(" ".join(plain[k:]))
                if rest.act in ("STOP", "WAIT", "FOLLOW") and not rest.partial and not rest.aside and not rest.rest \
                        and rest.frame is not None and not rest.answer:
                    rest.words = words
                    rest.corrected = [*plain[:k], *rest.corrected]
                    return rest
            return None
        k = 0
        while k < len(plain) and plain[k] in _YES_BEFORE_COME_ON:
            k += 1
        if 0 < k and plain[k:k + 2] == ["come", "on"] and all(w in _AFTER_A_REQUEST for w in plain[k + 2:]):
            out = self.understand("come on")
            if out.act != "FOLLOW" or out.frame is None:
                return None
            out.words = words
            out.answer = "yes" if any(w in _ANSWER_WORDS_ALONE and w not in ("okay", "ok", "right") for w in plain[:k]) \
                else out.answer
            out.corrected = [*out.corrected, *[w for w in plain[:k] if w not in _ANSWER_WORDS_ALONE]]
            return out
        return self._relief_remark(words, said)

    def _relief_remark(self, words: str, said: list[str]) -> Understanding | None:
        """:meth:`_everyday_short_forms` (3): a remark of relief or of taking up the thread ("there, that's
        better", "so, where were we"), not understood and said in passing (``aside``), or None."""
        plain = [w for w in said if w not in _SOUNDS and w not in self.lexicon.hesitations]
        while plain and plain[-1] in ("biron", "robot"):
            plain = plain[:-1]
        k = 0
        while k < len(plain) and plain[k] in _RELIEF_OPENERS:
            k += 1
        if tuple(plain[k:]) not in _RELIEF_REMARKS:
            return None
        out = Understanding(words, None, unknown=self.lexicon.tokens(words).unknown)
        out.ignored = [t.text for t in self.lexicon.tokens(words).tokens]
        out.reason, out.aside = "a remark of relief or of taking up the thread", True
        return out

    def _request_before_remark(self, words: str, said: list[str]) -> Understanding | None:
        """A whole follow or greeting said first, then a remark of hers, or None (talk22).

        The head ``said[:at]`` understood by itself is a whole FOLLOW or GREETING (no word lost) and the rest is a
        remark: it opens with a first-person subject ("i", "we", "my name is") or, after a greeting, with a word
        of welcome said of the robot ("nice that you are here", "how lovely that you came"); understood by itself
        it asks for nothing else: nothing at all, a good-bye with words of its own ("I have to go soon": why she
        hurries, not a good-bye), or, after a follow, the room she will show ("I want you to see the garage":
        where they go, not a teaching here). A remark that is a whole request of its own ("follow me, we can
        stop here", "hello, I need you to stop") or a repair is left to the other rules. The remark's words
        count as set aside (``corrected``)."""
        plain = [w for w in said if w not in _SOUNDS and w not in self.lexicon.hesitations]
        for at in range(1, len(plain) - 1):
            if plain[at] not in _REMARK_OPENERS:
                continue
            head = self.understand(" ".join(plain[:at]))
            if head.act not in ("FOLLOW", "GREETING") or head.partial or head.aside or head.frame is None \
                    or head.rest:
                continue
            tail = plain[at:]
            if plain[at] in _GREETING_TAILS:
                # "hi biron, let's get going", "hello robot, welcome to our home" (talk23): after a greeting, a start
                # proposed or a welcome; a whole request of its own ("let's go") is left to the other rules
                if head.act != "GREETING":
                    return None
                rest = self.understand(" ".join(tail))
                if rest.act is not None or rest.corrected or rest.answer or rest.aside or len(tail) > 6:
                    return None
                head.words = words
                head.corrected = [*head.corrected, *tail]
                return head
            if plain[at] not in _SUBJECTS and (head.act != "GREETING" or "you" not in tail):
                return None
            if plain[at] in _SUBJECTS and head.act == "GREETING" and not _introduces(tail):
                return None
            rest = self.understand(" ".join(tail))
            if rest.corrected or rest.answer or rest.aside:
                return None
            if rest.act is not None and not (
                    (rest.act == "GOODBYE" and (rest.coverage < 1.0 or head.act == "FOLLOW"))
                    or (rest.act == "PLACE" and head.act == "FOLLOW" and _SHOWS & set(tail))):
                return None
            head.words = words
            head.corrected = [*head.corrected, *tail]
            return head
        return None

    def _whole_follow_in_tail(self, words: str, plain: list[str], starts: range,
                              stop_after: frozenset[str] | set[str] = frozenset()) -> Understanding | None:
        """The first tail ``plain[at:]`` (``at`` in ``starts``) that, understood by itself, is a whole follow (no
        word lost), with the words before it set aside (``corrected``); None when there is none, or when a word
        of ``stop_after`` ends the words before a tail first (they are no longer a lead-in)."""
        for at in starts:
            if plain[at - 1] in stop_after:
                return None
            tail = self.understand(" ".join(plain[at:]))
            if tail.act != "FOLLOW" or tail.partial or tail.aside or tail.frame is None:
                continue
            tail.words = words
            tail.corrected = [*plain[:at], *tail.corrected]
            return tail
        return None

    def _request_after_misheard_opening(self, toks: list[Tok]) -> tuple[int, Tree, list[str], bool] | None:
        """The whole go-to said after the robot's name and short words only (a misheard opening: "biron [a]",
        "[a]"), or None; never after a deixis, a copula or a word of meaning ("this go to the kitchen" stays)."""
        for k in range(1, len(toks) - 1):
            if toks[k - 1].type not in _MISHEARD_OPENING:
                return None
            if toks[k].type not in ("GO", "COME", "TAKE", "CAN", "YOU", "LETS"):
                continue
            alt = self._parse(toks[k:])
            if alt[0] is not None and not alt[1] and not alt[2] and tree_act(alt[0]) == "goto" \
                    and any(t.type in ("GO", "COME", "TAKE") for t in toks[k:]):
                return k, *alt
        return None

    def _request_after_never_mind(self, edit: Tok, toks: list[Tok]) -> tuple[list[str], list[Tok]] | None:
        """The words set aside and the whole request said after a leading "never mind (X)", or None.

        The first tail of ``toks`` that parses whole by itself (a request or statement, not a noun phrase, a
        yes/no or a which-one answer, no word lost, nothing guessed) is the request; the words before it are
        what she sets aside ("never mind [the kitchen], go to the living room"). When the editing phrase
        ended in a deixis ("never mind this", "never mind that", "never mind it"), the deixis may have
        opened the request instead ("never mind, that is the kitchen"): that reading is tried too."""
        readings = [toks]
        last = edit.text.split()[-1]
        if last in ("this", "that", "it") and len(edit.text.split()) > 1:
            readings.append([*self.lexicon.tokens(last).tokens, *toks])
        for loose in (False, True):  # then a request with words after it it could not place ("..., ehm yes")
            for i in range(max(map(len, readings))):
                for said in readings:
                    if i >= len(said):
                        continue
                    tree, ignored, cut = self._parse(said[i:])
                    if tree is None or _guessed(tree) or tree_act(tree) in _NOT_REQUESTS:
                        continue
                    if (ignored or cut) and not (loose and ignored and _left_at_end(said[i:], ignored)):
                        continue
                    if i and not self._set_aside(said[:i]):
                        continue  # "never mind, you're not [in my way]": a clause of hers, not a thing set aside
                    return [t.text for t in said[:i]], said[i:]
        return None

    def _set_aside(self, toks: list[Tok]) -> bool:
        """Whether ``toks`` name something she sets aside after "never mind": a noun phrase ("the kitchen",
        "my mug") or words that only address ("you", "biron"); never a clause or a negation."""
        if all(t.type in _ADDRESS for t in toks):
            return True
        if any(t.type == "NOT" for t in toks):
            return False
        tree, ignored, cut = self._parse(toks)
        return tree is not None and not ignored and not cut and tree_act(tree) in ("object_fragment", "place_fragment")

    def _greeting_before(self, toks: list[Tok], negated: int) -> int | None:
        """Where a negated request starts when a whole greeting comes before it ("hello biron, don't
        follow me", "hi, please do not follow me"), else None."""
        k = negated
        while k > 0 and (toks[k - 1].type in _BEFORE_VERB or toks[k - 1].type in ("NOT", "DO")):
            k -= 1
        if k == 0 or toks[0].type != "HELLO":
            return None
        tree, ignored, partial = self._parse(toks[:k])
        return k if tree is not None and not partial and not ignored and tree_act(tree) == "greeting" else None

    def _request_after_greeting(self, toks: list[Tok], ignored: list[str], asking: bool = True) -> bool:
        """Whether the words a greeting's parse left out are the utterance's end and a whole act alone.

        A greeting that opens a request ("hello biron, follow me") is a sure
        greeting: the frame is the greeting (what opens the interaction) and the
        request, reported in ``rest``, is left for the user to say again. Words
        that do not make a complete act by themselves stay noise and lower the
        coverage. A question about what she shows ("hello, is this the kitchen") is such an act too,
        when every word is known (``asking``), as the question said alone.
        """
        tail = toks[len(toks) - len(ignored):]
        if [t.text for t in tail] != ignored:
            return False
        if asking and self._asked(tail) is not None:
            return True  # "hello, is this the kitchen": a question she asks about what she shows (review9 item 6)
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
        except UnexpectedToken:
            pass
        ignored: list[str] = []
        # again token by token from the start, keeping the parser's state after each token it
        # took: a token that does not fit is skipped; at the end, the longest prefix that makes a
        # whole act wins over a guessed rest ("this is a nice cup, isn't it", "no, that is <lost>")
        ip = self.parser.parse_interactive()
        taken: list[Any] = []
        fed: list[int] = []
        for i, t in enumerate(stream):
            try:
                ip.feed_token(t)
            except UnexpectedToken:
                ignored.append(toks[i].text)
                continue
            taken.append(ip.copy())
            fed.append(i)
        used = len(stream) - len(ignored)
        if ignored:
            try:
                return ip.copy().feed_eof(), ignored, True
            except UnexpectedInput:
                pass
        for k in range(len(taken) - 2, -1, -1):
            try:
                tree = taken[k].copy().feed_eof()
            except UnexpectedInput:
                continue
            kept = set(fed[: k + 1])
            rest = [toks[i] for i in range(len(stream)) if i not in kept]
            if (tree_act(tree) == "that_one" and rest[0].type in ("IS", "ARE")
                    and any(t.type not in _ONLY_POINTS for t in rest)):
                # "this one here is my reading <lost>": a statement about the one she points at,
                # its noun lost (a teaching to ask about), not the which-one answer "this one here"
                break
            if (tree_act(tree) == "teach_object" and any(t.type in ("IS", "ARE") for t in rest)
                    and any(t.type == "THING" for t in toks)
                    and not any(isinstance(c, Tree) and c.data == "object_np" for c in tree.iter_subtrees())):
                # "this thing [here] that is my favourite red <lost>": what she says of it after the
                # copula (owner, colour) is kept with its noun lost, rather than "this thing" alone
                break
            return tree, [t.text for t in rest], True
        if used < 2:
            return None, ignored, True  # one word and a guessed rest is no understanding
        skipped = set(ignored)
        if all(t.type in _ONLY_POINTS for t in toks if t.text not in skipped):
            # a deixis, articles and prepositions alone are noise ("this the to", "to the"), not an
            # object or place the user began to describe ("this is my favourite <lost word>")
            return None, ignored, True
        if toks[0].type in ("IS", "ARE"):
            # "is the <lost words>": a question whose object was lost is no question to answer
            return None, ignored, True
        for filler in ("OBJ", "PLACE"):  # "this is my ...": close it with an empty object/place
            trial = ip.copy()
            try:
                trial.feed_token(Token(filler, Tok(filler, "", "")))
                return trial.feed_eof(), ignored, True
            except UnexpectedInput:
                continue
        return None, ignored, True


#: Words of a follow ("come with me", "walk along", "this way", "follow"): said before a verbless "to <room>" whose
#: verb the parse could not use, she leads the way there.
_FOLLOW_WORDS = frozenset({"COME", "FOLLOW", "FOLLOWING", "WITH", "ALONG", "WAY", "COMEON"})


def _led_to(tree: Tree, toks: list[Tok], ignored: list[str]) -> bool:
    """Whether ``tree`` is a go-to said without a verb ("to my study") after words of a follow it left out."""
    act = next((c for c in tree.children if isinstance(c, Tree) and c.data != "address"), None)
    if act is None or act.data != "goto" or not act.children:
        return False
    first = act.children[0]
    if not (isinstance(first, Token) and first.type == "TO"):
        return False
    at = next((i for i, t in enumerate(toks) if t is _tok(first)), None)
    return at is not None and any(t.type in _FOLLOW_WORDS and t.text in ignored for t in toks[:at])


def _hello_to_someone_else(toks: list[Tok], words: list[str], unknown: list[str]) -> bool:
    """Whether a turn says hello to a name the robot does not know ("hi sara", a word it does not know right
    after the hello) and not its own name."""
    if any(t.type == "ROBOTNAME" for t in toks) or not unknown:
        return False
    hellos = {t.text.split()[-1] for t in toks if t.type == "HELLO" and t.text}
    return any(a in hellos and b in unknown for a, b in zip(words, words[1:]))


def _greeted_by_name(tree: Tree, toks: list[Tok], ignored: list[str]) -> bool:
    """Whether a greeting names the robot and is whole but for words before the name when it greets after it
    ("[good to] biron, nice to meet you"), or for words after the name when it greets before it ("hello biron,
    it is [is] pleasure to meet you")."""
    name = next((i for i, t in enumerate(toks) if t.type == "ROBOTNAME"), None)
    if name is None or not any(t.type == "ROBOTNAME" for a in _subs(tree, "address") for t in _tokens(a)):
        return False
    before, after = toks[:name], toks[name + 1:]
    if (bool(after) and [t.text for t in before[:len(ignored)]] == ignored and len(ignored) <= name
            and all(t.type in ("HELLO", "MEET", "THERE") for t in after)):
        return True
    # "good day biron, it is [is] pleasure to meet you": a whole greeting with the name opens the turn and the
    # words that go with a greeting close it; the words between them the parse could not place take nothing
    # from it (other words after a greeting, "hello biron follow [the]", still do: a request half heard)
    said_after = collections.Counter(t.text for t in after)
    return (any(t.type == "HELLO" for t in before) and all(t.type in ("HELLO", "THERE") for t in before)
            and any(t.type == "MEET" for t in after) and not collections.Counter(ignored) - said_after)


def _owner_alone(tree: Tree) -> bool:
    """Whether ``tree`` says only whose the thing she points at is ("that one is mine")."""
    return any(isinstance(c, Tree) and c.data == "owner_alone" for c in tree.iter_subtrees())


#: Where the noun phrase of a question's statement begins ("is this [the kitchen]", "is this room [my study]").
#: ("is that toy there" is no such question: "that toy" is its noun phrase, and it asks where the toy is)
_NP_START = frozenset({"A", "THE", "MY", "OUR", "NAME"})
#: Words a preamble that says where the thing shown is may be made of ("behind me on the sideboard, that
#: is my vase", "over there on the left, this is my cup"): relations, sides, deixis of place, articles,
#: owners, colours and the landmark; no "one" (a which-one answer) and no verb.
_SCENE_WORDS = frozenset({"REL", "IN", "SIDE", "HERE", "THERE", "THE", "A", "MY", "OUR", "YOUR", "ME", "YOU", "OF", "OBJ",
                          "COLOUR", "ATTR", "USE", "TO"})
#: Words that answer a question before the request that follows them ("no, the kitchen").
_ANSWER_WORDS = frozenset({"YES", "OKAY", "NO"})
#: The "this" of a statement the recogniser lost ("[this] is my cup"): put back to parse the statement.
_LOST_THIS = Tok("THIS", "this", "")
#: The copula put in for a word misheard in its place before an owner ("the red book on the shelf [a] mine").
_SAID_IS = Tok("IS", "is", "")
#: The relation put in for one lost before the landmark of "the one [on] the table" (:meth:`Understander._where_lost`).
_SAID_AT = Tok("REL", "at", "at")
#: The owner put in for the last word of "this bottle is [lost]" (:meth:`Understander._whose_lost`).
_SAID_MINE = Tok("MINE", "speaker", "mine")
#: The "my" put in for a determiner lost before the noun phrase of "this is [my] vase" (:meth:`Understander._determiner_lost`).
_SAID_MY = Tok("MY", "speaker", "my")
#: Words before the noun in a noun phrase ("my [big blue coffee] mug").
_NP_MODIFIERS = frozenset({"COLOUR", "ATTR", "USE"})
#: Words the recogniser puts where a determiner was that are no determiner there ("this is [it] vase").
_LOST_DETERMINER = frozenset({"IT", "THAT", "THIS", "TO", "IN"})
#: Words that cannot end "this bottle is ...": a word misheard there (the recogniser's fillers are such words).
_LOST_PREDICATE = frozenset({"THIS", "THAT", "IT", "A", "THE", "TO", "IN", "AND", "IS", "ARE"})
#: "here" put before the relation of "the keys are on the table": said there, as "are here on the table".
_SAID_HERE = Tok("HERE", "here", "")
#: Words that start the "where" of "the study is this room", "my cup is that one over there".
_DEIXIS = frozenset({"THIS", "THAT", "HERE", "THERE"})
#: Words that start the "where" of "the keys are on the table", "my keys are in the drawer".
_RELATIONS = frozenset({"REL", "IN"})
#: Words after "X is" that say which or where it is (not what it is like): no remark.
_REFERRING = _DEIXIS | _RELATIONS | frozenset({"ONE", "SIDE", "COLOUR", "OBJ", "PLACE", "ROOM"})
#: Noun phrases alone: they answer a question; a whole statement ("this is the kitchen") is a request of its own.
_FRAGMENTS = frozenset({"object_fragment", "place_fragment"})
#: Acts that continue a phrase rather than start a new clause: a repair made of them is aligned.
#: what "<lost this> is ..." can be: a place or an object shown
_STATEMENT_ACTS = frozenset({"place_fragment", "object_fragment", "teach_place", "teach_object"})
#: Acts that are no request by themselves: answers to a question the robot asked.
_NOT_REQUESTS = frozenset({"object_fragment", "place_fragment", "that_one", "yes", "no"})
#: Greeting words that greet only as the turn's first word ("morning, biron"; not "in the morning", "the
#: morning show", "every evening").
_OPENING_WORDS = frozenset({"morning", "evening", "yo"})
#: token types a question cannot end on ("what can you a"): articles, a demonstrative or "it" left without its noun
#: or verb, a preposition, the copula. A word the recogniser put in place of a lost one is usually one of these
_NO_LAST_WORD = frozenset({"A", "THE", "THAT", "THIS", "IT", "IN", "TO", "IS"})
#: What a closing followed by more words stays a closing with ("that will be all, thank you, goodbye", "bye,
#: yes"): answers and greetings are no request of their own.
_AFTER_CLOSING = frozenset({"object_fragment", "place_fragment", "that_one", "yes", "no", "goodbye", "greeting"})
_NOT_RESTARTS = frozenset({"object_fragment", "place_fragment", "that_one", "yes", "no"})

# word classes that say nothing about a dangling object or place: deixis, articles, prepositions
# (and the copula: "it is", "this is the" name nothing; the dialog asks to hear it again rather than
# start teaching an object nobody named)
_ONLY_POINTS = frozenset({"THIS", "THAT", "HERE", "THERE", "IT", "A", "THE", "TO", "IN", "REL", "OF", "ONE",
                          "IS", "ARE", "CALLED"})


#: Verbs of the requests a "don't"/"do not" negates ("don't stop", "do not go to the kitchen").
_VERBS = frozenset({"STOP", "WAIT", "FOLLOW", "FOLLOWING", "COME", "COMEON", "GO", "TAKE", "BACK", "LOOK"})
#: Words between the negation and the verb ("don't you follow me", "I don't want you to go there").
_BEFORE_VERB = frozenset({"YOU", "I", "ME", "WANT", "TO", "CAN"})
#: What a bare word act may be said with and still be that act alone ("back again", "come on, please").
_ALONE_WITH = {"BACK": frozenset({"again"}), "COMEON": frozenset({"please"})}
#: Hesitation sounds: they say nothing about what else was said ("uh, come on" is still "come on").
_SOUNDS = frozenset({"uh", "um", "uhm", "er", "erm", "hmm", "hm", "mm", "well"})
#: First-person subjects that open a remark after a whole follow or greeting ("follow me, I have to go soon").
_SUBJECTS = frozenset({"i", "we", "my"})
#: Words that open a remark after a whole follow or greeting (a subject, or a welcome said of the robot).
#: Words that open what a greeting says next without a subject: a start proposed, a welcome (talk23).
_GREETING_TAILS = frozenset({"let's", "lets", "let", "welcome"})
_REMARK_OPENERS = _SUBJECTS | _GREETING_TAILS | frozenset({"nice", "good", "great", "lovely", "wonderful", "glad", "so", "how"})
#: Words after "i am" that say where or how she is, not who ("i am in the kitchen", "i am just looking").
_NOT_A_NAME = frozenset({"in", "at", "on", "here", "there", "going", "just", "not", "so", "very", "looking", "back",
                         "coming", "busy", "sorry", "afraid", "the", "a", "your", "in"})
#: Words a welcome to the home is made of, after "welcome" (lang24): "welcome to our home", "welcome welcome".
_WELCOME_WORDS = frozenset({"welcome", "to", "our", "my", "the", "home", "house", "flat", "apartment", "place", "in",
                            "here", "back", "again", "biron", "robot", "you", "are", "very", "most"})
#: At most this many words make one pleasantry, and a greeting turn split into them (lang24; bounds the search).
_PLEASANTRY_WORDS = 10
_GREETING_TURN_WORDS = 20
#: Time words the lexicon has as greetings ("this morning", "every evening"): inside a remark no greeting (lang24).
_TIMES_OF_DAY = frozenset({"morning", "afternoon", "evening", "night"})
#: Nouns of time after "this"/"that" ("this morning", "that week"): no deixis (lang24).
_TIME_NOUNS = frozenset({"morning", "afternoon", "evening", "night", "week", "weekend", "year", "month", "time",
                         "summer", "winter", "spring", "autumn"})
#: Words after "this"/"that" that make it no deixis (lang24): a time, or an article (a relation misheard, as
#: `_relation_lost` reads "that vase [on→this] the sideboard").
_NO_DEIXIS_AFTER = _TIME_NOUNS | frozenset({"the", "a", "an", "my", "our", "your", "his", "her", "their"})
#: Everyday words the lexicon lacks that a pleasantry is made of (lang24): they count as known there.
_PLAIN_WORDS = frozenset({"was", "were", "did", "had", "has", "been", "be", "meet", "finally", "at", "last", "all",
                          "about", "heard", "told", "much", "so", "too", "really"})
#: Words that say a pleasantry is about the robot (lang24): said to it or of it.
_ABOUT_THE_ROBOT = frozenset({"you", "you're", "your", "yours", "biron", "robot"})
#: Answer words: a piece that opens with one answers something (lang24).
_ANSWER_WORDS_ALONE = frozenset({"yes", "yeah", "no", "nope", "okay", "ok", "sure", "right"})
#: Words that make words about the robot no pleasantry: a deixis, a request's or a question's verb (lang24).
_NOT_IN_A_PLEASANTRY = frozenset({"this", "that", "these", "those", "here", "there", "where", "what", "find", "follow",
                                  "go", "stop", "wait", "come", "look", "show", "bring", "take", "not", "don't"})
#: Words before the noun phrase of a remark (lang24): openers said in passing.
_REMARK_LEAD = frozenset({"oh", "and", "also", "so", "btw", "anyway", "actually", "ah", "now",
                          "look", "right", "okay", "ok", "well"})
#: Determiners and owners a remark's noun phrase opens with (lang24; never a deixis).
_REMARK_DETERMINERS = frozenset({"the", "my", "our", "his", "her", "their", "your", "a", "an"})
#: Habits: where a thing is usually kept is no showing (lang24).
_HABITS = frozenset({"usually", "always", "normally", "generally", "often", "sometimes", "mostly", "typically",
                     "mainly", "kept"})
#: Unknown words after a noun phrase that are no verb of a remark (lang24): function words, adverbs of place, and the
#: copula or "belonged" in the past ("the teapot on the table was my mother's": whose it is, a teaching).
_NOT_A_PREDICATE = frozenset({"POSS", "one", "ones", "was", "were", "be", "been", "belongs", "belonged", "belong", "about",
                              "for", "with", "from", "of", "and", "or", "but", "which",
                              "who", "too", "also", "as", "like", "than", "down", "up", "out", "off", "right", "just",
                              "left", "there", "here", "over", "again", "now", "then", "still", "only", "even", "all",
                              "both", "each", "some", "any", "very", "really", "quite", "pretty", "so", "such"})


def _one_token(lexicon: Lexicon, words: list[str]) -> bool:
    """Whether ``words`` are one lexicon entry (a noun of two words: "remote control"; lang24)."""
    toks = lexicon.tokens(" ".join(words))
    return len(toks.tokens) == 1 and not toks.unknown and len(toks.tokens[0].text.split()) == len(words)
#: Verbs of showing: after a follow, "I want you to see the garage" names where they go, no room here.
_SHOWS = frozenset({"show", "see", "meet"})


def _introduces(tail: list[str]) -> bool:
    """Whether a first-person remark after a greeting says who she is ("i am tom", "my name is ida", "i'm
    anna, welcome"): "i am" or "my name is" and at most three words more."""
    lead = 2 if tail[:2] == ["i", "am"] else 3 if tail[:3] == ["my", "name", "is"] else 0
    if lead and "welcome" in tail[lead + 1:lead + 4]:
        # "i am sara, welcome to our flat" (talk23): who she is, then a welcome of at most five words
        end = tail.index("welcome", lead + 1)
        return 0 < end - lead <= 3 and len(tail) - end <= 5 and tail[lead] not in _NOT_A_NAME
    return bool(lead) and 0 < len(tail) - lead <= 3 and tail[lead] not in _NOT_A_NAME


#: talk24: praise said to the robot after a greeting ("hi again biron, good job")
_PRAISE_PIECES = frozenset({("good", "job"), ("great", "job"), ("nice", "job"), ("well", "done"), ("good", "work"),
                            ("great", "work"), ("nice", "work"), ("good", "boy"), ("good", "girl"), ("clever", "robot"),
                            ("good", "robot"), ("very", "good"), ("very", "well", "done")})
#: talk24: where she is, said after a greeting ("i'm here behind you", "we are back")
_WHERE_SHE_IS = frozenset({"here", "back", "behind", "you", "next", "to", "beside", "now", "already", "again",
                           "with", "too", "over", "right"})
#: talk24: who she brings along ("and this is my son ben")
_KIN = frozenset({"son", "daughter", "husband", "wife", "partner", "friend", "mother", "father", "mum", "mom", "dad",
                  "boy", "girl", "kids", "children", "brother", "sister", "flatmate", "grandson", "granddaughter",
                  "little", "youngest", "oldest", "best", "neighbour", "colleague", "family"})


#: talk24: what may end "nice to have you ..." ("with us", "here", "around", "in our home")
_HAVE_YOU_TAIL = frozenset({"with", "us", "here", "around", "at", "last", "finally", "in", "our", "home", "house", "flat",
                            "biron", "robot", "today"})


def _praises_or_says_where_she_is(piece: list[str]) -> bool:
    """Whether a piece said after a greeting praises the robot ("good job", "well done biron") or says where she
    is ("i am here behind you", "we are back"): no request, nothing shown (talk24)."""
    words = [w for w in piece if w not in ("biron", "robot", "again", "today", "there", "really", "so")] or piece
    if tuple(words) in _PRAISE_PIECES:
        return True
    lead = 2 if words[:2] in (["i", "am"], ["we", "are"]) else 0
    return bool(lead) and len(words) > lead and words[lead] in ("here", "back") and len(words) - lead <= 4 \
        and all(w in _WHERE_SHE_IS for w in words[lead:])


def _introduces_another(piece: list[str]) -> bool:
    """Whether a piece said after a greeting says who she brings ("this is my son ben", "these are my kids"):
    "this is" / "these are", "my" or "our", a word of kin, then at most two words (a name) (talk24)."""
    lead = 2 if piece[:2] in (["this", "is"], ["these", "are"]) else 0
    if not lead or len(piece) < lead + 2 or piece[lead] not in ("my", "our"):
        return False
    kin = [k for k, w in enumerate(piece[lead + 1:], lead + 1) if w in _KIN]
    return bool(kin) and kin[0] <= lead + 2 and len(piece) - kin[-1] - 1 <= 2 \
        and not any(w in _NOT_A_NAME or w in _DEIXIS_WORDS for w in piece[kin[-1] + 1:])


_DEIXIS_WORDS = frozenset({"this", "that", "here", "there", "these", "those"})
#: The spot words that say "we are there" in "that's the spot" (not "the corner", "the view").
_ARRIVED = frozenset({"spot", "place"})


#: Words that call a person by a term of endearment ("yes dear", "darling, can you get the door"): said first
#: (after an answer word) or last, they address someone; the robot is called by its name or "robot".
ENDEARMENTS = frozenset({"dear", "darling", "honey", "sweetie", "sweetheart", "love", "babe", "hun", "sugar"})
#: Endearments that are also verbs or nouns said last ("a cup which I really love"): a vocative only said first.
_ALSO_VERBS = frozenset({"love", "sugar"})
#: Acts a vocative does not take from the robot: a greeting or good-bye may name anyone ("tara love", "bye tom").
_SOCIAL = frozenset({"HELLO", "GOODBYE"})
#: Words a user may call the robot by in a greeting or good-bye ("bye friend"): no call to another person.
_MAY_CALL_ROBOT = frozenset({"friend", "buddy", "pal", "mate"})
#: Tokens a greeting or good-bye with a name is made of; with anything else the name calls someone ("hey tom, look").
_GREETING_ALONE = frozenset({"HELLO", "GOODBYE", "NAME", "YES", "OKAY", "ATTR", "MY", "YOUR", "OUR", "THE"})
#: Words before a name that make it no vocative: an owner, a determiner, an object of a verb or preposition,
#: a person introduced ("this is peter", "I want you to meet peter").
_NOT_CALLING = frozenset({"the", "my", "our", "your", "his", "her", "their", "a", "to", "with", "of", "for", "at", "and",
                          "is", "are", "was", "like", "from", "by", "about", "as", "than", "in", "on", "near", "behind",
                          "beside", "meet", "called", "named", "call", "ask", "tell", "POSS"})
#: Words after a name that make it no vocative: an owner ("tom's cup"), a statement about the person
#: ("peter is my husband", "tom and I live here"), a name that is no call ("mark this as the kitchen").
_NOT_CALLED = frozenset({"POSS", "and", "is", "are", "was", "were", "has", "as"})
#: Words after a name that still make it a call ("tom, this is my cup", "anna, the kettle is on"), unless the turn
#: goes on with "as": "mark this as the kitchen" marks, it calls no Mark.
_DETERMINERS_AFTER_CALL = frozenset({"this", "that", "these", "those", "the", "a", "an", "it"})
#: Token kinds after a name that make the name a modifier, not a call ("guests bedroom", "family room").
_NAME_AS_MODIFIER = frozenset({"PLACE", "ROOM", "OBJ", "SPOT", "NAME"})
#: Words a call may come after: answer words, fillers, "come on", "hey" ("come on tom, follow me", "hey tom").
_BEFORE_CALL = frozenset({"yes", "yeah", "no", "okay", "ok", "oh", "well", "so", "right", "please", "hey", "hi",
                          "hello", "come", "on", "now"})
#: Determiners an answer fragment starts with ("no love, the kitchen": a correction said to the robot).
_ANSWER_START = frozenset({"the", "a", "an", "my", "your", "our", "his", "her", "this", "that"})
#: An endearment and then a sentence, not an answer fragment: "darling, this is my cup" is said to him.
_COPULAS = frozenset({"is", "are", "was", "were"})
#: Words in which she speaks of herself ("I'm coming, dear"): said with a final endearment, to someone else.
_FIRST_PERSON = frozenset({"i", "we", "i'm", "i'll", "we're", "we'll"})


def _token_of(toks: list[Tok], word: str) -> Tok | None:
    """The token whose words include ``word`` (None: a word the lexicon does not know)."""
    return next((t for t in toks if word in t.text.split()), None)


def _contrast(tail: list[Tok], name_lost: bool) -> bool:
    """Whether ``tail`` is a clause that says whose another thing is: "the other one is my husband's", "that one
    is anna's", "the red one is ours", "the other cup is his", "the other (one) belongs to my son" (a determiner
    or "that", words for which one, then "one" or a noun, unless "other" says it; the copula then only whose, or
    "belongs to" and whom, that name perhaps a word the robot does not know: ``name_lost``)."""
    if len(tail) < 3 or tail[0].type not in ("THE", "THAT", "A"):
        return False
    cop = next((k for k, t in enumerate(tail) if t.type in ("IS", "ARE", "BELONGS")), None)
    if cop is None or cop < 2 or any(t.type not in ("ORD", "COLOUR", "ATTR", "ONE", "OBJ") for t in tail[1:cop]):
        return False
    other = any(t.type == "ORD" and t.text == "other" for t in tail[1:cop])
    if tail[cop - 1].type not in ("ONE", "OBJ") and not other:
        return False
    if tail[0].type in ("THE", "A") and not any(t.type in ("ORD", "COLOUR", "ATTR") for t in tail[1:cop]):
        return False  # "the cup is mine" names the thing; only "the other/red one" points away from it
    whose = tail[cop + 1:]
    if tail[cop].type == "BELONGS":
        if not whose or whose[0].type != "TO":
            return False
        whose = whose[1:]
        return (not whose and name_lost) or (bool(whose) and all(t.type in ("MY", "OUR", "YOUR", "NAME", "ME", "US")
                                                                  for t in whose))
    return bool(whose) and all(t.type in ("MY", "OUR", "YOUR", "NAME", "POSS", "MINE", "OBJ") for t in whose) \
        and any(t.type in ("MINE", "POSS", "NAME") or (t.type == "MY" and t.text != "my") for t in whose)


def _said_to_another(toks: list[Tok], words: list[str], hesitations: frozenset[str]) -> str:
    """Why a turn is said to someone else in the robot's hearing ("" when it may be for the robot).

    - It calls another person by name or kin word, wherever the name stands: first ("Tom, can you put the
      kettle on", "come on tom, follow me", "hey tom, look at this") or last ("go to the kitchen, peter",
      "stop it tom"), and does not call the robot. A name is no call when it is an owner ("tom's cup"), the
      object of a preposition or verb ("belongs to anna", "meet peter"), introduced ("this is peter"), the
      subject of a statement ("peter is my husband", "tom and I"), a modifier ("guests bedroom") or followed
      by a word the lexicon does not know ("partner mode"), or "mark this as ...".
    - It calls someone by a term of endearment first ("darling, can you get the door", "yes dear, just a
      minute"), unless what follows is an answer ("no love, the kitchen"); or ends with one while she speaks
      of herself ("I'm coming, dear"). A request, teaching or thanks ending in "dear" may be for the robot
      ("follow me please dear", "thank you dear"): people call a robot "dear" too.
    - "Not you, BIRON": she tells the robot the last words were for someone else.
    - It speaks of the robot in the third person ("look, the robot is listening", "isn't the robot clever").
    - A greeting or good-bye that names another person and not the robot ("see you tomorrow Julia", "bye
      Tom", "hello anna") is said to that person: a visitor's farewell to the partner must not end the
      partner's tour (fresh4 ring_visitor_leaves), and the partner's "bye Tom" to a visitor leaving is no
      good-bye to the robot. A term of endearment or "friend" may call the robot ("tara love", "bye my
      friend"): those keep the greeting or good-bye.
    """
    if not toks:
        return ""
    if any(t.type in _SOCIAL for t in toks) and all(t.type in _GREETING_ALONE for t in toks):
        if any(t.type in ("ROBOTNAME", "ROBOT") for t in toks):
            return ""
        called = [t for k, t in enumerate(toks) if t.type == "NAME" and t.text not in _MAY_CALL_ROBOT
                  and not (k and toks[k - 1].type in ("MY", "YOUR", "OUR", "POSS"))]
        return "a greeting or good-bye said to someone else" if called else ""
    said = [w for w in words if w not in hesitations]
    i = 0
    while i < len(said) and said[i] in _BEFORE_CALL:
        i += 1
    calls_robot = any(t.type in ("ROBOTNAME", "ROBOT") for t in toks)
    if i < len(said) - 1 and said[i] == "not" and said[i + 1] == "you":
        return "said to someone else"  # "no, not you BIRON, I was talking to Peter"
    if any(a == "the" and b in ("robot", "robots") and c != "POSS"
           for a, b, c in zip(said, said[1:], [*said[2:], ""])) \
            and not any(t.type == "MEET" and " robot" in t.text for t in toks):
        # ("you must be the robot", a greeting's words said to the robot itself, are not about it: talk21)
        return "said about the robot, to someone else"
    if calls_robot or not said:
        return ""
    names = {t.text for t in toks if t.type == "NAME"}
    first = said[i] if i < len(said) else ""
    after = said[i + 1] if i + 1 < len(said) else ""
    if first in names and after and after not in _NOT_CALLED \
            and not (after in _DETERMINERS_AFTER_CALL and "as" in said[i + 2:]):
        nxt = _token_of(toks, after)
        if nxt is not None and nxt.type not in _NAME_AS_MODIFIER:
            return "said to someone else"
    if len(said) > 1 and said[-1] in names and said[-2] not in _NOT_CALLING and said[-2] not in names:
        return "said to someone else"
    if first in ENDEARMENTS and after and (after not in _ANSWER_START or _COPULAS & set(said[i + 2:])):
        return "said to someone else"
    if len(said) > 1 and said[-1] in ENDEARMENTS - _ALSO_VERBS and said[-2] not in _NOT_CALLING \
            and any(w in _FIRST_PERSON for w in said):
        return "said to someone else"
    return ""


def _vocative_after(tree: Tree, words: list[str], hesitations: frozenset[str]) -> set[str]:
    """The words after a greeting's or good-bye's last word that only call the one it is said to ("goodbye
    dear", "bye love", "hello friend"): endearments and :data:`_MAY_CALL_ROBOT`; empty when anything else
    follows or the act is no greeting or good-bye."""
    if tree_act(tree) not in ("greeting", "goodbye"):
        return set()
    said = [w for w in words if w not in hesitations]
    tail: list[str] = []
    for w in reversed(said):
        if w in ENDEARMENTS - _ALSO_VERBS or w in ("love",) or w in _MAY_CALL_ROBOT:
            tail.append(w)
        else:
            break
    if not tail or len(tail) == len(said):
        return set()
    return set(tail)


def _greets_unknown_name(toks: list[Tok], words: list[str], unknown: list[str], hesitations: frozenset[str]) -> str:
    """Why a greeting is said to someone whose name the lexicon does not know ("" when it may be for the robot).

    The first word she says greets ("hi", "hello", "hey") and the next one is a word the lexicon does not know
    ("hi Sara, yes it is me", "hello love", "hey Jule how are you"): a vocative, and the robot's name is in the
    lexicon, so it is someone else's (a person on the phone, a visitor at the door). A greeting that also names
    the robot ("hello darling BIRON", "hi little robot") or calls it a friend ("hello buddy") is the robot's.
    Known names are :func:`_said_to_another`'s ("hi mum", "hello anna")."""
    if not toks or toks[0].type != "HELLO" or any(t.type in ("ROBOTNAME", "ROBOT") for t in toks):
        return ""
    said = [w for w in words if w not in hesitations]
    at = next((k for k, w in enumerate(said) if w == toks[0].text), None)
    if at is None or at + 1 >= len(said):
        return ""
    after = said[at + 1]
    if after in _MAY_CALL_ROBOT or after not in unknown:
        return ""
    return "a greeting said to someone the robot does not know by name"


#: Words before "from" in a tail saying where a shown object came from ("[it] is [a present] from my mother").
_BEFORE_FROM = frozenset({"IT", "IS", "ARE", "A", "THE"})
#: Words of the giver after "from" ("from my grandmother", "from anna", "from the market").
_GIVER = frozenset({"MY", "OUR", "YOUR", "THE", "A", "NAME", "POSS", "ATTR", "PLACE"})


def _from_someone(toks: list[Tok], ignored: list[str]) -> bool:
    """Whether the words a teaching's parse left out are its tail saying where the object came from
    ("that vase is from my grandmother", "this is my cup, it is from my mother"): a remark about the
    object shown, not words lost from the teaching."""
    tail = toks[len(toks) - len(ignored):]
    if [t.text for t in tail] != ignored:
        return False
    at = next((k for k, t in enumerate(tail) if t.type == "REL" and t.value == "from"), None)
    return (at is not None and at + 1 < len(tail) and all(t.type in _BEFORE_FROM for t in tail[:at])
            and all(t.type in _GIVER for t in tail[at + 1:]))


#: How she announces what she does next herself ("I'll", "let me", "I'm going to", "I have to").
_ERRAND_LEADS = (("i", "will"), ("let", "me"), ("i", "am", "going", "to"), ("i", "have", "to"), ("i", "need", "to"),
                 ("i", "must"), ("i", "am", "just", "going", "to"))
#: Verbs of a short errand in the flat (not "go", "take", "show": "I'll take you to the kitchen" leads the robot).
_ERRAND_VERBS = frozenset({"get", "fetch", "grab", "put", "check", "answer", "bring", "make", "turn", "switch", "feed",
                           "open", "find", "pop", "water", "pick", "hang", "call", "ring", "see", "wash", "clear",
                           "close", "shut", "draw", "tidy", "move", "fix", "lock", "light", "wipe", "fold", "air"})
#: Suggestions to go somewhere together, said as a question ("shall we go to the kitchen?").
_SUGGESTION_LEADS = (("shall", "we"), ("should", "we"), ("shall", "i"), ("how", "about"), ("what", "about"),
                     ("why", "do", "not", "we"), ("why", "not"),
                     # going somewhere together said as a statement ("let's go over to the kitchen, follow me", "we
                     # are going to the study now, come with me"): the same lead of a follow (talk21)
                     ("let's",), ("lets",), ("let", "us"), ("we", "go"), ("we", "will"), ("we'll",), ("we", "are", "going"),
                     ("we're", "going"), ("we", "need", "to", "go"))
#: Words that may open a turn before the suggestion ("so, shall we ...", "okay then, shall we ...").
_DESTINATION_DETERMINERS = frozenset({"the", "my", "our"})
#: What may follow "where" after the thing was named ("my glass, where it is now"; talk23).
_WHERE_TAILS = frozenset({("it", "is"), ("is", "it"), ("they", "are"), ("are", "they"), ("it", "'s"), ("is",), ("are",)})
#: The invitation that opens a follow "come and see ..." (talk23): come, then a verb of seeing.
_COME_AND_SEE = (("come", "and", "have", "a", "look", "at"), ("come", "have", "a", "look", "at"), ("come", "and", "look", "at"),
                 ("come", "look", "at"), ("come", "and", "see"), ("come", "see"), ("come", "and", "meet"), ("come", "meet"))
# words that make the lead before a follow more than a noun phrase naming where (a clause: left to the other rules)
_NOT_A_NOUN_PHRASE = frozenset({"is", "are", "was", "were", "be", "'s", "s", "this", "that", "here", "there", "where", "not",
                                "don't", "dont", "do", "does", "has", "have", "had", "can", "will", "go", "come", "stop", "wait", "follow", "look",
                                # "the one on the table, follow me": a which-one answer, then the request (talk21);
                                # the robot or a pronoun after the article is no place ("[hey→the] biron, follow me",
                                # "[can→the] you follow me": a word misheard, still partial)
                                "one", "biron", "byron", "robot", "you", "me", "i"})
#: talk24: what may follow a request at its end ("come with me please", "come on then")
_AFTER_A_REQUEST = frozenset({"please", "biron", "robot", "now", "then", "too", "quickly"})
#: talk24: words between "come" and "to" in "come over to my study with me"
_COME_ADVERBS = frozenset({"over", "along", "on", "back", "here", "across", "through"})
#: talk24: the leads of a clause that says she will show something (after Lexicon.words: "i'll" is "i will")
_SHOW_LEADS = (("i", "will", "show", "you"), ("let", "me", "show", "you"), ("i", "want", "to", "show", "you"),
               ("i", "am", "going", "to", "show", "you"), ("i", "want", "you", "to", "see"),
               ("i", "would", "like", "to", "show", "you"), ("i", "will", "take", "you", "to"),
               ("let", "me", "take", "you", "to"), ("i", "can", "show", "you"))
#: talk24: the words of a show clause's lead ("i will", "let me", "i want to", "i am going to", "i would like to")
_SHOW_LEAD_WORDS = frozenset({"i", "will", "let", "me", "want", "to", "am", "going", "would", "like", "can", "you",
                              "gonna", "just", "quickly"})


def _with_me(words: list[str]) -> bool:
    """Whether a follow request's last words are "with me", or it with one short word misheard or lost ("with
    the", "in me", "me"; talk24)."""
    if words == ["with", "me"] or words in (["me"], ["with"]):
        return True
    return len(words) == 2 and (words[0] == "with" and words[1] in _MISHEARD_SHORT
                                or words[1] == "me" and words[0] in _MISHEARD_SHORT)


#: talk24: what may come between the follow's head and the clause ("come on, now I'll show you ...")
_SHOW_OPENERS = frozenset({"now", "and", "so", "then", "next", "i", "think"})
#: talk24: words that end a noun phrase after a show lead (a clause of its own follows)
_SHOW_NOT_IN_NP = frozenset({"come", "follow", "me", "with", "on", "please", "now", "then"})
#: talk24: praise said first that only takes the turn ("good, now stop")
_PRAISE_OPENERS = frozenset({"good", "great", "lovely", "perfect", "excellent", "brilliant", "wonderful", "super",
                             "nice", "fine", "alright", "right"})
#: talk24: yes-words before "come on" ("yes, come on", "okay, come on")
_YES_BEFORE_COME_ON = frozenset({"yes", "yeah", "yep", "sure", "okay", "ok", "alright", "right", "oh", "well", "so"})
#: talk24: remarks of relief or of taking up the thread, said in passing
_RELIEF_OPENERS = frozenset({"there", "so", "now", "okay", "ok", "right", "well", "oh", "ah", "alright", "anyway",
                             "phew", "then"})
_RELIEF_REMARKS = frozenset({("that", "is", "better"), ("that", "is", "much", "better"), ("much", "better"),
                             ("that", "is", "more", "like", "it"), ("where", "were", "we"), ("where", "was", "i"),
                             ("that", "is", "better", "now"), ("that", "is", "a", "lot", "better"),
                             ("where", "did", "we", "stop"), ("where", "did", "i", "stop"), ("that", "was", "better"),
                             ("better",)})
_SUGGESTION_BEFORE = frozenset({"so", "okay", "ok", "right", "now", "then", "well", "and", "alright", "biron", "robot"})
#: Words between the lead and the verb ("I'll just quickly go and get").
_ERRAND_FILL = frozenset({"just", "quickly", "quick", "first", "only", "go", "and", "run", "nip", "dash"})
#: Words that may come before the announcement ("oh wait", "hang on", "sorry", "one moment").
_ERRAND_BEFORE = frozenset({"oh", "wait", "hang", "hold", "on", "one", "moment", "minute", "second", "sec", "sorry",
                            "okay", "ok", "right", "so", "well", "just", "a", "excuse", "me", "biron", "robot", "now",
                            "ah", "oops", "please"})


#: Words before what she needs ("I need some milk").
_SOME = frozenset({"a", "an", "some", "my", "the", "more"})
#: Openers that make a first-person announcement a break in the tour ("oh wait, I have to get the door").
_ERRAND_OPENERS = frozenset({"wait", "hang", "hold", "moment", "minute", "second", "sec", "sorry", "excuse", "oops"})
#: Words that put the announcement off to later.
_LATER = frozenset({"later", "tomorrow", "tonight", "afterwards", "soon"})


#: Words that only address someone or take the turn ("never mind her, [you] come with me").
_ADDRESS = frozenset({"YOU", "ROBOT", "ROBOTNAME", "OKAY", "YES", "NO"})
#: Words that may trail a request without being part of one ("this is my kettle, ehm yes", "follow me okay biron").
_TRAILING = frozenset({"YES", "NO", "OKAY", "ROBOT", "ROBOTNAME", "HERE", "THERE", "NOW"})


#: Words after a wait that say she goes and comes back ("wait here until I come back", "I'll be right back").
_COMING_BACK = frozenset({"until", "till", "back", "return", "returns"})


def _stays(toks: list[Tok], words: list[str]) -> bool:
    """Whether a WAIT tells the robot to stay where it is rather than to hold on a moment (review13 item 9).

    A wait with a place ("wait here", "stay there", "wait for me at the door"), "stay", "don't move",
    "wait for me" (she goes and the robot waits for her) or a coming back ("until I come back", "I'll be
    right back") tells it to stay; "wait", "hang on", "just a moment", "wait a sec" hold it a moment."""
    verb = next((i for i, t in enumerate(toks) if t.type == "WAIT"), None)
    if verb is None:
        return False
    after = toks[verb + 1:]
    return (toks[verb].value == "stay" or any(t.type in ("HERE", "THERE") for t in after)
            or [t.type for t in after[:2]] == ["FOR", "ME"] or bool(_COMING_BACK & set(words)))


def _left_at_end(toks: list[Tok], ignored: list[str]) -> bool:
    """Whether the words a parse could not place are the turn's last words and only words that trail a request
    (not the start of one: "the kitchen go [to the living rom]" left "to the", the real request's place)."""
    left = toks[len(toks) - len(ignored):]
    return [t.text for t in left] == ignored and all(t.type in _TRAILING for t in left)


#: What a misheard turn opening may hold before a whole go-to: the robot's name and short words.
_MISHEARD_OPENING = frozenset({"ROBOTNAME", "ROBOT", "A", "THE", "TO", "IN", "OF", "CAN", "YOU", "IT"})
#: The first word of a request said after a remark (its verb, or the words that ask): "go to", "you can go",
#: "could you go", "follow me", "let's go", "take me to", "stop", "wait".
_REQUEST_OPENERS = frozenset({"GO", "COME", "TAKE", "FOLLOW", "STOP", "WAIT", "CAN", "YOU", "I", "LETS", "BACK"})
#: Words that make a turn's head no remark: it shows or names something here, asks, answers, greets or denies.
_NOT_IN_A_REMARK = frozenset({"THIS", "THAT", "HERE", "THERE", "IT", "WHERE", "WHAT", "HOW", "HELLO", "GOODBYE",
                              "YES", "NO", "NOT", "EDIT", "MEET"})


def _remark_verb(words: list[str], lexicon: Lexicon) -> int | None:
    """Where the verb of a leading remark stands in ``words`` ("the ramp [is] free now | go to the living room",
    "the hall['s] clear again | ...", "my son [has] moved | ...", "ok the passage [is] clear now | could you go ..."),
    or None: a subject of one to four words, then a copula ("is", "are", the "'s" of "ramp's") or "has"/"have";
    the subject (an "ok" may open the turn) is no request and no deixis, and no word before the verb, nor the
    one after it, shows, asks, answers or denies (:data:`_NOT_IN_A_REMARK`: "this is the hall, go to the
    kitchen" names the room she stands in; "the way is not free" is no way free)."""
    for i in range(1, min(len(words), 6)):
        if words[i] not in ("is", "are", "POSS", "has", "have"):
            continue
        head = lexicon.tokens(" ".join(words[: i + 2])).tokens
        kinds = [t.type for t in head]
        while kinds and kinds[0] == "OKAY":
            kinds = kinds[1:]
        if (kinds and kinds[0] in _REQUEST_OPENERS) or words[0] in ("is", "are", "has", "have", "POSS") \
                or any(k in _NOT_IN_A_REMARK for k in kinds) or any(w in ("not", "never") for w in words[: i + 2]):
            return None
        return i
    return None


def _errand(words: list[str], hesitations: frozenset[str]) -> list[str] | None:
    """The words after the errand's verb when the turn announces a short errand of hers ("oh wait I will
    just get the post", "let me just put the water on", "I'm going to check the oven"): a lead in the first
    person, the errand's verb and nothing but openers before it; she asks the robot to wait for her
    (fresh12 items 3 and 11). None when the turn announces none."""
    said = [w for w in words if w not in hesitations]
    if _LATER & set(said):
        return None  # "I will call my sister later": what she plans, not an errand now
    k = next((j for j, w in enumerate(said) if w not in _ERRAND_BEFORE), len(said))
    if said[k:k + 2] == ["i", "need"] and len(said) > k + 3 and said[k + 2] in _SOME and _ERRAND_OPENERS & set(said):
        # "I need a tea towel, one moment", "one second, I need some sugar": what she needs, with a word that
        # asks for a moment, is her errand as "I need to get ..." is (talk22; without the moment, "I need a
        # new kettle" is a remark)
        return said[k + 3:]
    for i in range(len(said)):
        if said[i] not in ("i", "let"):
            if said[i] not in _ERRAND_BEFORE:
                return None
            continue
        for lead in _ERRAND_LEADS:
            if tuple(said[i:i + len(lead)]) != lead:
                continue
            k = i + len(lead)
            while k < len(said) and said[k] in _ERRAND_FILL:
                k += 1
            if k < len(said) and said[k] in _ERRAND_VERBS and k + 1 < len(said):
                # "just" or an opener ("oh wait", "sorry") marks it as a short break in the tour; "I need to
                # find my keys now" (a bystander's remark in the library's distractor) is no errand announced
                marked = "just" in said[i:k] or any(w in _ERRAND_OPENERS for w in said[:i])
                if marked and not (said[k] == "get" and said[k + 1] in ("past", "by", "through", "out")):
                    return said[k + 1:]
                return None
        return None
    return None


#: Short words the recogniser puts in place of a lost one ("me" heard as "a").
_MISHEARD_SHORT = frozenset({"a", "the", "to", "in", "it", "is", "and", "this", "that", "of", "an"})


def _errand_misheard(words: list[str], hesitations: frozenset[str]) -> list[str] | None:
    """The words after the errand's verb when the turn is an errand whose lead "let me just" lost or misheard one
    word (:func:`_errand`): an errand verb with words after it, before it that lead with one word left out or
    put by a short word, nothing said before but openers; else None. "Let me check ..." (no "just", nothing
    misheard) is no errand announced, as in :func:`_errand`."""
    said = [w for w in words if w not in hesitations and w not in _ERRAND_OPENERS and w not in ("oh", "okay", "ok")]
    lead = ("let", "me", "just")
    for k in range(2, min(4, len(said) - 1)):
        if said[k] not in _ERRAND_VERBS:
            continue
        got = tuple(said[:k])
        lost = any(got == lead[:i] + lead[i + 1:] for i in range(3)) and got != ("let", "me")
        swapped = len(got) == 3 and sum(a != b for a, b in zip(got, lead)) == 1 \
            and all(a == b or a in _MISHEARD_SHORT for a, b in zip(got, lead))
        if lost or swapped:
            return said[k + 1:]
    return None


def _negation(toks: list[Tok], words: list[str]) -> int | None:
    """Index of the verb a "do not"/"don't"/"never" negates, or None.

    "Why don't you follow me" is a suggestion, not a negation."""
    if "why" in words:
        return None
    for i, t in enumerate(toks):
        if t.type != "NOT" or (i and toks[i - 1].type in ("IS", "ARE")):
            continue  # "that is not the kitchen": a no or a contrast (lexicon), not a negated request
        k = i + 1
        while k < len(toks) and toks[k].type in _BEFORE_VERB:
            k += 1
        if k < len(toks) and toks[k].type in _VERBS:
            return k
    return None


def _said_besides(toks: list[Tok], words: list[str]) -> list[str]:
    """The words of the utterance that no token stands for (fillers, politeness, unknown words)."""
    rest = list(words)
    for t in toks:
        for w in t.text.split():
            if w in rest:
                rest.remove(w)
    return [w for w in rest if w != "POSS"]


def _not_meant(tree: Tree, toks: list[Tok], res: Understanding, words: list[str], asked: bool = False) -> str:
    """Why a parse is not what she meant ("" when it is): a request heard in words that say otherwise.

    - "back" greets (a partner's return) and "come on" follows only said alone: "back off", "step
      back", "back please" ask the robot to move back; "oh come on", "come on, really" are exasperation.
    - "that's the spot" stops only as a whole turn with "spot"/"place": "this is the spot where I read",
      "this is the corner", "that's the view" are statements about the room.
    - A question ("is this with me", "are these shoes yours") is never a command or a teaching, but one
      that names what she shows ("is this the kitchen", ``asked``) asks about that teaching.
    - A stop or wait heard in a partial parse under half its words, its verb followed at once by a word it
      does not know ("stay tuned for a music": a TV), is no command: stopping a go-to on noise is worse
      than asking again.
    """
    act = next((c for c in tree.children if isinstance(c, Tree) and c.data != "address"), None)
    if act is None:
        return ""
    kind = str(act.data)
    own = _tokens(act)
    if len(own) == 1 and own[0].type in _ALONE_WITH and kind in ("greeting", "follow"):
        besides = set(_said_besides(toks, words))
        if res.partial or res.unknown or not besides <= _ALONE_WITH[own[0].type]:
            return "said with other words, not alone" if own[0].type == "BACK" else "an exasperated remark"
    if (kind == "that_one" and len(act.children) == 2 and _sub(act, "here") is not None
            and (d := _sub(act, "deixis")) is not None
            and (_tokens(d)[0].type not in ("THIS", "THAT") or res.partial or res.unknown)):
        # "that there" answers which one only as the whole turn; "it there", "this here this": noise
        return "a deixis and 'here' alone point at nothing"
    if kind == "yes" and own and own[0].type not in ("YES", "OKAY") and any(t.type in ("IS", "ARE") for t in own) \
            and (res.partial or res.unknown):
        # "that is exactly right", "you are correct" say yes only as the whole turn: "you are standing right
        # where I want to go", "it is right next to the door" say where something is
        return "a statement with 'right' in it, not a yes"
    if kind == "teach_place" and any(t.type == "REL" and t.value != "at" for t in own):
        # "you are next to the bathroom", "we are near the kitchen": a room beside the one she stands in;
        # taught, the robot would store where it stands (outside that room) as that room
        return "a room nearby, not the one we are in"
    if kind == "teach_place" and own and own[0].type == "YOU" and _guessed(act):
        # "you are in the kitchen" tells the robot where it is; "you are in my way" names no room
        return "no room named"
    if kind == "make_way" and (why := _not_in_the_way(toks, res)):
        return why
    if kind == "stop" and any(t.type == "SPOT" for t in own):
        spot = next(t for t in own if t.type == "SPOT")
        if res.partial or res.unknown or spot.value not in _ARRIVED or _said_besides(toks, words):
            return "a spot in a statement, not a stop"
    if kind == "where" and toks[0].type in ("IS", "ARE") and words and words[0] in res.unknown:
        # "they are on the table in the hall" (an answer to someone else), "[mumble] is the cup in the kitchen":
        # a word the robot does not know before the copula is a subject; a statement, not "is my cup in the
        # kitchen?" (the question puts the copula first)
        return "a statement about something, not a where-question"
    if toks[0].type in ("IS", "ARE") and len(toks) > 1 and toks[1].type in ("THIS", "THAT", "IT") \
            and kind != "where" and not asked:
        return "a question, not a request or a teaching"
    if kind in ("stop", "wait") and res.partial and res.unknown and res.coverage < 0.5:
        verb = next((t for t in own if t.type in ("STOP", "WAIT")), None)
        last = verb.text.split()[-1] if verb is not None else ""
        at = words.index(last) if last in words else -1
        if 0 <= at < len(words) - 1 and words[at + 1] in res.unknown:
            # "stay tuned for a music", "stop ..." followed at once by a word it does not know: the verb
            # is part of a phrase it does not know, not a command ("wait here until I come back" is)
            return "a command heard in words it does not know"
    return ""


def _not_in_the_way(toks: list[Tok], res: Understanding) -> str:
    """Why words about being in the way do not ask the robot to move ("" when they do).

    Backing off drives the robot into the half its laser does not see, so the words must say it is in the
    way: a "not" anywhere but in "can't" ("you are not in my way", "you're not blocking anything", "it isn't
    in the way any more") says the opposite, and so does "I can get past" (her statement that she can;
    "can I get past" and "I can't get past" ask). A bare "blocking" says it is in the way only of the
    person or of what the grammar knows as a way or a thing: "you are blocking my view", heard as a partial
    parse round words it does not take, is a remark.
    """
    for i, t in enumerate(toks):
        if t.type == "NOT" and not (i and toks[i - 1].type == "CAN"):
            return "said not to be in the way"
        if t.type == "I" and i + 1 < len(toks) and toks[i + 1].type == "CAN" \
                and not (i + 2 < len(toks) and toks[i + 2].type == "NOT"):
            return "she says she can get past"
    block = next((i for i, t in enumerate(toks) if t.type == "BLOCK"), None)
    if block is not None and toks[block].text == "blocking" and res.partial and res.ignored:
        return "blocking something else, not the way"
    return ""


#: Words that say how much of a quality ("so boring", "very nice"): a remark follows, no name.
_INTENSIFIERS = frozenset({"so", "very", "really", "quite", "too", "pretty", "super", "rather"})


def _small_talk(tree: Tree, obj: etree._Element, toks: list[Tok], words: tuple[str, ...] | list[str] = ()) -> str:
    """Why an object frame without a noun is small talk, not an object shown ("" when it is not).

    "this is nice", "that's lovely": an adjective said of what she points at, with no article and no
    owner, evaluates it; nobody names a thing that way, so no object is taught (with an article,
    "this is a nice <lost word>", a noun was said and lost: the dialog asks what it is). "that's my
    favourite spot", "this is my corner": a word for a spot in the room (lexicon class SPOT) is no
    object either.
    """
    room = next((i for i, t in enumerate(toks) if t.type == "ROOM"), None)
    if obj.tag == "PLACE" and obj.find("TITLE") is None and _guessed(tree) and room is not None and (
            any(t.type == "ATTR" for t in toks[room:]) or any(w in _INTENSIFIERS for w in words)):
        # "this room is nice", "dude, this room is so boring": an adjective (or "so", "very" before a word not
        # known) said of the room after its copula is no name (no article, no owner before the word lost), so
        # no nameless place to ask about ("Which room is this?"); "this room is my <lost>" keeps its owner and
        # "this room is <lost>" stays a place whose name was lost
        nps = [st for st in tree.iter_subtrees() if st.data == "place_np"]
        if nps and not any(isinstance(c, Tree) and c.data in ("det", "possessor") for c in nps[0].children):
            return "a remark about the room, not its name"
    if obj.tag != "OBJECT" or obj.get("type") is not None:
        return ""
    if any(t.type == "SPOT" for t in toks):
        return "a spot in the room, not an object"
    if any(t.type == "ROOM" for t in toks) and all(c.tag in ("GESTURE", "ATTRIBUTE") for c in obj):
        # "this is a lovely room", "what a big room": an adjective said of the room is no object
        return "a remark about the room, not an object"
    act = next((c for c in tree.children if isinstance(c, Tree) and c.data != "address"), None)
    np = _sub(act, "object_np") if act is not None else None
    if (act is not None and act.data == "teach_object" and np is not None and _sub(np, "det") is None
            and _sub(np, "possessor") is None and all(c.tag in ("GESTURE", "ATTRIBUTE") for c in obj)
            and obj.find("ATTRIBUTE") is not None):
        return "an evaluation, not an object named"
    return ""


#: Verbs that tell who made or did up a thing ("my father built that shelf"): said before the thing, the turn is
#: a story about it, not a teaching (after it, "this is the cup my son made", the teaching stands)
_MADE_VERBS = frozenset({"built", "made", "carved", "painted", "knitted", "sewed", "sewn", "designed", "repaired",
                         "fixed", "assembled", "welded", "crafted"})


def _made_or_where(obj: etree._Element, toks: list[Tok], words: tuple[str, ...] | list[str]) -> str:
    """Why an object frame is small talk about who made the thing or what the spot is for ("" when not).

    "my husband made this table", "I painted that picture myself": who made it, said before the thing, is a
    story, no thing shown to be learned. "this is where the dog sleeps": the copula followed by "where" says
    what happens at the spot (a nameless object with the rest as its use before).
    """
    if obj.tag != "OBJECT":
        return ""
    title = obj.find("TITLE")
    noun = title.get("name", "").split()[-1] if title is not None and title.get("name") else None
    made = next((i for i, w in enumerate(words) if w in _MADE_VERBS), None)
    if made is not None and noun is not None and noun in words[made + 1:] and noun not in words[:made]:
        return "who made it, not an object shown"
    cop = next((i for i, t in enumerate(toks) if t.type in ("IS", "ARE")), None)
    if obj.get("type") is None and cop is not None and cop + 1 < len(toks) and toks[cop + 1].type == "WHERE":
        return "what the spot is for, not an object"
    return ""


def _bare_side(tree: Tree) -> bool:
    """Whether the parse is a side or distance said alone ("left", "closer", "further"): an answer to a
    which-one question only (said unasked, "closer please", "turn left" ask for something else)."""
    act = next((c for c in tree.children if isinstance(c, Tree) and c.data != "address"), None)
    return (act is not None and act.data == "that_one" and len(act.children) == 1
            and isinstance(act.children[0], Token) and act.children[0].type == "SIDE")


#: Words of an arrival said before a stop ("here we are at last", "there we are now").
_ARRIVAL_WORDS = frozenset({"here", "there", "we", "are", "now", "at", "last", "finally", "so", "okay", "ok", "well",
                            "then", "right", "alright"})


def _arrival(words: list[str]) -> bool:
    """Whether the turn opens with an arrival ("we are here", "there we are", "here we are at last")."""
    lead = list(itertools.takewhile(lambda w: w in _ARRIVAL_WORDS, words))
    pairs = set(itertools.pairwise(lead))
    return bool({("we", "are"), ("we're", "here")} & pairs) and bool({"here", "there"} & set(lead))


def _where_we_are(toks: list[Tok]) -> bool:
    """Whether ``toks`` say what the speaker's household does in the room she stands in, not its name: a
    deixis, a copula (or none: the recogniser drops it), "where", then "we" or "I" ("this is where we live", "here is
    where I work", "that's where we eat"). "this is where the dog sleeps" (someone else, a spot) stays small talk (:func:`_made_or_where`)."""
    kinds = [t.type for t in toks]
    if kinds[1:2] in (["IS"], ["ARE"]):
        kinds = kinds[:1] + kinds[2:]  # "this [is] where we live": the copula lost
    return (len(kinds) >= 3 and kinds[0] in ("THIS", "THAT", "HERE", "IT")
            and kinds[1] == "WHERE" and kinds[2] in ("WE", "I"))


def _room_unnamed(toks: list[Tok]) -> bool:
    """Whether ``toks`` are a statement about "the room" whose name was lost: a deixis or copula, then
    "the"/"a" and "room" and nothing else ("this is the room", "is the room", "this the room")."""
    kinds = [t.type for t in toks]
    return (len(kinds) >= 3 and kinds[-2:] in (["THE", "ROOM"], ["A", "ROOM"])
            and all(k in ("THIS", "THAT", "IT", "HERE", "IS", "ARE") for k in kinds[:-2]))


def _name_lost_before_room(toks: list[Tok], ignored: list[str]) -> bool:
    """Whether a word the parse left out stands right before the last "room", after an article or an
    owner ("this is our [the] room", "this is my [a] room"): where the room's name goes, so the name was
    misheard."""
    at = max((i for i, t in enumerate(toks) if t.type == "ROOM"), default=None)
    return (at is not None and at >= 2 and toks[at - 1].text in ignored
            and toks[at - 1].type not in ("MY", "OUR", "POSS", "NAME")
            and toks[at - 2].type in ("MY", "OUR", "POSS", "THE", "YOUR"))


#: Words after which a room's name goes: "our [living] room", "the [guest] room", "anna's [music] room".
_NAME_GOES_AFTER = frozenset({"my", "our", "your", "the", "POSS"})


def _hesitated_before_room(words: list[str], hesitations: frozenset[str]) -> bool:
    """Whether a hesitation stands where the room's name goes ("this is our uh room"): the recogniser puts
    "uh" for a word it could not make out, so the name may be lost (a speaker who says "our room" says
    it without a pause inside)."""
    return any(words[i] in hesitations and words[i + 1] == "room" and words[i - 1] in _NAME_GOES_AFTER
               for i in range(1, len(words) - 1))


def _place_said_elsewhere(tree: Tree, toks: list[Tok], ignored: list[str], unknown: bool, where: bool) -> bool:
    """A room named first, then a copula and words that say where it is from here ("the living room is next
    door", "the kitchen is through here", "the bedroom is upstairs"): said while going there, not of the room
    she stands in. Not "this is the kitchen" (a deixis first) nor "the kitchen is here" (said whole: here)."""
    if tree_act(tree) not in ("place_fragment", "teach_place") or not toks or toks[0].type in _DEIXIS:
        return False
    cop = next((k for k, t in enumerate(toks) if t.type in ("IS", "ARE")), None)
    if cop is None or not any(t.type == "PLACE" for t in toks[:cop]) or _said_of(tree, toks, ignored, unknown, where):
        return False  # "come on, the bedroom is nice": a remark about it
    # words after the copula the grammar could not place, or the lexicon does not know ("next door",
    # "upstairs", "through here"): where it is from here, not "here"
    return bool(ignored) or unknown


def _copula_at(tree: Tree, toks: list[Tok], ignored: list[str]) -> int | None:
    """Where the copula stands when the parse is a noun phrase alone and everything from a copula after
    it on was left out ("the sofa | is new", "the study | is this room"), else None."""
    if tree_act(tree) not in _FRAGMENTS or not ignored:
        return None
    at = len(toks) - len(ignored)
    if at < 1 or [t.text for t in toks[at:]] != ignored or toks[at].type not in ("IS", "ARE"):
        return None
    return at


def _said_of(tree: Tree, toks: list[Tok], ignored: list[str], unknown: bool, where: bool = False) -> str:
    """Why a noun phrase followed by a copula and words the grammar could not place is no answer: she says
    something of the thing ("oh the bed is not made, sorry", "the sofa is new", "the kitchen is a mess"),
    a remark about it, not "this is the bed" (galley_long_tour: "Is this bed?"). Empty when it is none.

    Words after the copula that point or refer ("is the left one", "is next door", "is on the table":
    a deixis, "one", a side, a colour, a relation or a thing) say which or where it is, not what it is
    like: the noun phrase still answers (review9 item 1)."""
    at = _copula_at(tree, toks, ignored)
    if at is None or where:  # where: "next door" said after it (where it is, not what it is like)
        return ""
    if len(ignored) < 2 and not unknown:
        return ""  # "the kitchen is": the rest of the sentence was not heard, the noun phrase may answer
    if any(t.type in _REFERRING for t in toks[at + 1:]):
        return ""
    return "a remark about it"


def _denied(tree: Tree, raw: list[Tok]) -> str:
    """Why a teaching she ends with a bare "no" is none: "this is the kitchen, no", "this is my cup no no"
    (review9 item 5). She says it and takes it back, as "is that the kitchen, no" (a question she answers
    no herself): nothing to store or confirm. A "no" before the statement ("no, this is the kitchen")
    corrects what the robot said and still teaches. Empty when it is none."""
    if tree_act(tree) not in ("teach_place", "teach_object") or not raw or raw[-1].type != "NO":
        return ""
    if all(t.type == "NO" for t in raw):
        return ""
    return "a statement she answers no herself"


def _room_alone(place: etree._Element) -> bool:
    """Whether a place frame names no room but "room" itself, whoever's ("our room", "anna's room"): a
    hesitation before its "room" may stand for the lost name; "the children's uh room" names one, and a
    hesitation never changes a frame that is whole without it."""
    title = place.find("TITLE")
    return title is None or title.get("name") == "room"


def _only_room(place: etree._Element) -> bool:
    """Whether a place is named "room" alone, hers or theirs ("my room", "our room"), not someone's by name
    ("my daughter's room" says which room)."""
    title, owner = place.find("TITLE"), place.find("OWNER")
    return (title is not None and title.get("name") == "room"
            and (owner is None or owner.get("name") in ("speaker", "us")))


def _declared(text: str) -> set[str]:
    out: set[str] = set()
    for line in text.splitlines():
        if line.startswith("%declare"):
            out.update(line.split()[1:])
    return out


def _guessed(tree: Tree) -> bool:
    """Whether the parse closed a dangling object or place with a guessed empty one ("this is my ...")."""
    return any(isinstance(t, Token) and t.type in ("OBJ", "PLACE") and not _tok(t).text for t in tree.scan_values(
        lambda v: isinstance(v, Token)))


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


def _owned(tree: Tree) -> str | None:
    """The owner the object frame ``tree`` builds, or None."""
    owner = build(tree).find("OBJECT/OWNER")
    return owner.get("name") if owner is not None else None


def _owner(tree: Tree | None) -> str | None:
    """An owner from ``possessor`` or ``owner_tail``: 'speaker', 'robot', 'us' or a name."""
    if tree is None:
        return None
    toks = _tokens(tree)
    named = [t for t in toks if t.type == "NAME"]
    if named:  # "my daughter's room": the daughter's
        return named[-1].value
    for t in toks:
        if t.type in ("MY", "MINE", "YOUR", "OUR"):
            return t.value
        if t.type == "ME":
            return "speaker" if t.value == "me" else t.value
    return None


#: Object types whose "of" names what they show ("a photo of my daughter"), not whose they are.
DEPICTING = frozenset({"picture"})


def _object(np: Tree | None, *, gesture: bool, position: Tree | None = None, tail: Tree | None = None,
            shown: Tree | None = None) -> etree._Element:
    """``OBJECT`` of a noun phrase; ``shown``: the act, whose own modifiers describe the thing she points at
    ("that red thing is my backpack": red)."""
    if np is None:  # "look at this": the pointing says which, the scene what
        el = _E("OBJECT")
        if gesture:
            _S(el, "GESTURE", val="probably_pointing")
        owner = _owner(tail)  # "this is mine": whose, not what (the dialog asks "What is it?")
        if owner is not None:
            _S(el, "OWNER", name=owner)
        return el
    toks = _tokens(np)
    noun = next((t for t in toks if t.type == "OBJ"), None)
    el = _E("OBJECT")
    if noun is not None and noun.value:
        el.set("type", noun.value)
    if gesture:
        _S(el, "GESTURE", val="probably_pointing")
    if noun is not None and noun.value:
        _S(el, "TITLE", name=noun.text)
    # "the cup of anna": her cup; but "a picture of my daughter" shows the daughter, it is not hers
    # (review-lang7 item 14): a picture's "of" names what it depicts, never an owner
    of_owner = None if noun is not None and noun.value in DEPICTING else _sub(np, "of_owner")
    owner = _owner(tail) or _owner(_sub(np, "possessor")) or _owner(of_owner)
    if owner is not None:
        _S(el, "OWNER", name=owner)
    colours, attrs = _modifiers(np)
    if shown is not None:
        before = _modifiers(shown)
        colours, attrs = before[0] + colours, list(dict.fromkeys(before[1] + attrs))
    if colours:
        _S(el, "COLOUR", name=colours[-1])
    for a in attrs:
        _S(el, "ATTRIBUTE", name=a)
    use = next((t for t in toks if t.type == "USE"), None)
    if use is not None:  # "my coffee cup": what it is for
        _S(el, "USE", name=use.value)
    if position is not None and not _said_of_it(position):
        el.append(_position(position))
    return el


def _modifiers(tree: Tree) -> tuple[list[str], list[str]]:
    colours: list[str] = []
    attrs: list[str] = []
    for m in _subs(tree, "modifier"):
        for t in _tokens(m):
            (colours if t.type == "COLOUR" else attrs).append(t.value)
    return colours, list(dict.fromkeys(attrs))


def _said_of_it(position: Tree) -> bool:
    """A position whose landmark is "it" ("the blue book next to it"): it stands by the thing she showed
    before, which the pointing finds; no landmark to look for by name."""
    return _tokens(position)[-1].type == "IT"


def _position(tree: Tree) -> etree._Element:
    toks = _tokens(tree)
    pos = _E("POSITION")
    rel = toks[0]
    _S(pos, "RELATION", name=rel.value if rel.type == "REL" else "in")
    ground = toks[-1]
    if ground.value:
        _S(pos, "TITLE", name=ground.text if ground.type == "OBJ" else ground.value)
    return pos


#: Sides that say how far along her arm (or from whom) the one meant stands: "the nearer one", "the one
#: in front", "the far one", "the one at the back", "the one behind it".
DEPTH_SIDES = frozenset({"near", "front", "far", "back"})


def _that_one(act: Tree) -> etree._Element:
    """``THAT_ONE`` (index, side, view, type; GESTURE, TITLE, COLOUR, ATTRIBUTE*, POSITION): which of several.

    ``view="speaker"``: a left/right said from her side ("on my left"); without it a side is the robot's
    (the side the robot's own question named: docs/semantics.md §4). A distance ("the one closer to me")
    carries whose: ``view="speaker"`` (nearer her), ``view="addressee"`` (nearer the robot), none when
    not said (the question's own words say from where)."""
    el = _E("THAT_ONE")
    toks = _tokens(act)
    where = _sub(act, "ref_where")
    side_tree = _sub(act, "side") or (_sub(where, "side") if where is not None else None)
    sides = [t for t in toks if t.type == "SIDE"] + ([t for t in _tokens(side_tree) if t.type == "SIDE"]
                                                     if side_tree is not None else [])
    pointing = any(t.type in ("THIS", "THAT", "HERE") for d in _subs(act, "deixis") for t in _tokens(d)) or (
        where is not None and any(t.type == "POINTING" for t in _tokens(where)))
    # whose left: the robot's unless she says hers ("on my left", "the one left of me"); the robot
    # words its own question from its side ("the cup on the left"), so a plain side is the robot's too
    speaker_view = bool(sides) and (
        (side_tree is not None and _owner(_sub(side_tree, "possessor")) == "speaker")
        or _owner(_sub(act, "possessor")) == "speaker"  # a side alone ("on my left")
        or (side_tree is not None and any(t.type == "ME" and t.value == "me" for t in _tokens(side_tree)))
        or any(t.type == "ME" and t.value == "me" for t in toks))
    np = _sub(act, "object_np")
    if np is not None:
        toks = toks + _tokens(np)
        act = np
    for t in toks:
        if t.type == "ORD":
            el.set("index", t.value)
    if sides:
        el.set("side", sides[-1].value)
        if speaker_view and sides[-1].value in ("left", "right"):
            el.set("view", "speaker")
        elif sides[-1].value in DEPTH_SIDES:  # "closer to me" is nearer her, "closer to you" nearer the robot
            if any(t.type == "ME" for t in toks):
                el.set("view", "speaker")
            elif any(t.type == "YOU" for t in toks):
                el.set("view", "addressee")
    noun = next((t for t in toks if t.type == "OBJ"), None)
    if noun is not None and noun.value:
        el.set("type", noun.value)
    if pointing:
        _S(el, "GESTURE", val="probably_pointing")
    if noun is not None and noun.value:
        _S(el, "TITLE", name=noun.text)
    colours, attrs = _modifiers(act)
    if colours:
        _S(el, "COLOUR", name=colours[-1])
    for a in attrs:
        _S(el, "ATTRIBUTE", name=a)
    position = (_sub(act, "position") or (_sub(where, "position") if where is not None else None)
                or _sub(act, "landmark"))  # "on the table": the answer names where it stands
    if position is not None and not _said_of_it(position):
        el.append(_position(position))
    return el


def _place(np: Tree) -> etree._Element:
    el = _E("PLACE")
    toks = _tokens(np)
    place = next((t for t in toks if t.type in ("PLACE", "ROOM")), None)
    if place is not None and place.value:
        # the user's words are the name ("that's the study" is the study, "the study room" the study
        # room); the lexicon's synonyms only let the grammar know it is a place
        room = next((t for t in toks if t.type == "ROOM"), None) if place.type == "PLACE" else None
        _S(el, "TITLE", name=place.text if room is None else f"{place.text} {room.text}")
    owner = _owner(_sub(np, "possessor")) or _owner(_sub(np, "of_owner"))  # "the room of my daughter"
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
    elif kind in ("goodbye", "capabilities", "follow", "stop", "wait", "yes", "no", "make_way"):
        _S(speech, {"goodbye": "GOODBYE", "capabilities": "CAPABILITIES"}.get(kind, kind.upper()))
    elif kind == "that_one":
        speech.append(_that_one(act))
    elif kind in ("teach_object", "object_fragment"):
        speech.append(_object(_sub(act, "object_np"), gesture=kind == "teach_object",  # type: ignore[arg-type]
                              position=_sub(act, "position"), tail=_sub(act, "owner_tail") or _sub(act, "owner_alone"), shown=act))
    elif kind in ("teach_place", "place_fragment"):
        speech.append(_place(_sub(act, "place_np")))  # type: ignore[arg-type]
    elif kind == "goto":
        np = _sub(act, "place_np")
        req = _sub(act, "request")
        if np is None and req is not None and any(t.type == "LETS" for t in _tokens(req)):
            _S(speech, "FOLLOW")  # "let's go": together, and she knows where
        else:
            _S(speech, "GOTO").append(_place(np) if np is not None else _E("PLACE"))
    elif kind == "where":
        w = _S(speech, "WHERE")
        np = _sub(act, "object_np")
        w.append(_object(np, gesture=False) if np is not None else _place(_sub(act, "place_np")))  # type: ignore[arg-type]
    else:  # pragma: no cover - every act rule of the grammar is handled above
        raise AssertionError(f"grammar rule {kind!r} has no frame")
    return speech
