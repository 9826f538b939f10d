"""Recognised words -> grammar tokens: the lexicon, fillers, repetitions and self-corrections.

The recogniser's vocabulary lives in ``lexicon.tsv`` (phrase, terminal, value).
:meth:`Lexicon.tokens` turns a word string into the terminals the grammar
(``hometour.lark``) is written in, in four steps a spoken-language front end
needs before any parser:

1. words: lower case, punctuation dropped, "anna's" split into "anna" + POSS;
2. longest-match look-up of multi-word phrases ("remote control", "living room");
   fillers and politeness words (terminal ``-``) are dropped; words not in the
   lexicon are *unknown*: skipped and reported, never an error;
3. self-corrections: "the red, no, the blue cup" - an editing term (``no``
   not at the start, ``sorry``, ``i mean``, ...) and the reparandum before it
   are removed: the repair's first token is aligned backwards with the latest
   token of the same word class ("the" <- "the", "blue" <- "red");
4. repetitions: an n-gram (n <= 3) said twice in a row is kept once
   ("this is this is my cup").

Nothing here raises on odd input: any word string gives a (maybe empty) token list.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

LEXICON_FILE = Path(__file__).with_name("lexicon.tsv")

#: Terminal of a word dropped without being reported (fillers, politeness).
DROP = "-"
#: Terminal of an editing term that introduces a self-correction.
EDIT = "EDIT"

_WORD = re.compile(r"[a-z0-9]+(?:'[a-z]+)?'?")

#: Contractions said as two words ("we're" -> "we are"), so the grammar needs one form only.
CONTRACTIONS = {
    "i'm": ("i", "am"), "you're": ("you", "are"), "we're": ("we", "are"), "they're": ("they", "are"),
    "isn't": ("is", "not"), "aren't": ("are", "not"), "don't": ("do", "not"), "doesn't": ("does", "not"),
    "didn't": ("did", "not"), "can't": ("can", "not"), "cannot": ("can", "not"), "won't": ("will", "not"),
    "wouldn't": ("would", "not"), "couldn't": ("could", "not"), "haven't": ("have", "not"),
    "i'd": ("i", "would"), "you'd": ("you", "would"), "we'd": ("we", "would"), "i've": ("i", "have"),
    "we've": ("we", "have"), "you've": ("you", "have"), "i'll": ("i", "will"), "we'll": ("we", "will"),
    "you'll": ("you", "will"), "that'll": ("that", "will"), "there's": ("there", "is"), "he's": ("he", "is"),
    "she's": ("she", "is"), "who's": ("who", "is"), "how's": ("how", "is"), "wasn't": ("was", "not"),
    "gotta": ("got", "to"), "wanna": ("want", "to"), "gonna": ("going", "to"),
}
#: Sounds a listener makes; a turn made only of them, with one that agrees, is a yes ("mhm", "uh huh").
BACKCHANNELS = frozenset({"mhm", "mhmm", "mm", "hmm", "hm", "uh", "huh", "hmhm", "aha", "ah"})
_AGREEING = frozenset({"mhm", "mhmm", "huh", "hmhm", "aha", "mm"})
#: Words whose "'s" is "is", not a possessive.
_IS_CONTRACTED = frozenset({"that's", "it's", "what's", "where's", "here's", "this's",
                            # "this one's my cup", "the blue one's ours": the pronoun "one" owns nothing (talk21:
                            # it was the owner "One", "Is this One's cup?")
                            "one's"})


@dataclass(frozen=True, slots=True)
class Tok:
    """One grammar token: terminal, canonical value and the words said for it."""

    type: str
    value: str
    text: str

    def __str__(self) -> str:  # lark makes a str of each token's value: keep it cheap (no dataclass repr)
        return self.text


@dataclass(slots=True)
class Tokens:
    """The tokens of an utterance and what the front end took out."""

    tokens: list[Tok]
    unknown: list[str] = field(default_factory=list)  # words not in the lexicon, in order
    corrected: list[str] = field(default_factory=list)  # words removed by a self-correction
    repeated: list[str] = field(default_factory=list)  # words removed as repetitions
    words: int = 0  # how many words the utterance had
    raw: list[Tok] = field(default_factory=list)  # the tokens before self-corrections and repetitions
    coined: list[str] = field(default_factory=list)  # room names made of a word not in the lexicon + "room"


class LexiconError(ValueError):
    """The lexicon file is malformed (names file and line)."""


class Lexicon:
    """Phrase -> (terminal, value) with longest-match look-up over words."""

    def __init__(self, entries: dict[tuple[str, ...], tuple[str, str]]) -> None:
        self.entries = entries
        self.longest = max((len(k) for k in entries), default=1)
        # first word -> the phrase lengths starting with it, longest first (one dict look-up per word)
        lengths: dict[str, set[int]] = {}
        for k in entries:
            lengths.setdefault(k[0], set()).add(len(k))
        self.lengths = {w: sorted(ls, reverse=True) for w, ls in lengths.items()}
        # Fillers that may fall inside a phrase ("the living, uh, room"): single dropped words
        # that are part of no multi-word phrase go before the phrases are matched.
        in_phrases = {w for k in entries if len(k) > 1 for w in k}
        self.hesitations = frozenset(k[0] for k, (t, _) in entries.items() if len(k) == 1 and t == DROP and k[0] not in in_phrases)
        self.terminals = frozenset(t for t, _ in entries.values())

    @classmethod
    def load(cls, path: str | Path = LEXICON_FILE) -> Lexicon:
        """Read a lexicon TSV; raises :class:`LexiconError` naming file and line."""
        entries: dict[tuple[str, ...], tuple[str, str]] = {}
        for n, line in enumerate(Path(path).read_text(encoding="utf-8").splitlines(), 1):
            if not line.strip() or line.startswith("#"):
                continue
            parts = line.split("\t")
            if len(parts) != 3 or not all(p.strip() for p in parts):
                raise LexiconError(f"{path}:{n}: expected 'phrase<TAB>terminal<TAB>value', got {line!r}")
            phrase, term, value = (p.strip() for p in parts)
            if term != DROP and not re.fullmatch(r"[A-Z][A-Z_]*", term):
                raise LexiconError(f"{path}:{n}: terminal {term!r} is not an upper-case name")
            key = tuple(phrase.split())
            if key in entries:
                raise LexiconError(f"{path}:{n}: phrase {phrase!r} is listed twice")
            entries[key] = (term, value)
        return cls(entries)

    # ------------------------------------------------------------------ words
    @staticmethod
    def words(text: str) -> list[str]:
        """Lower-case words; "anna's" becomes "anna" + "POSS" (the possessive), "let's" stays."""
        out: list[str] = []
        for w in _WORD.findall(text.lower().replace("\u2019", "'")):
            if w in CONTRACTIONS:
                out += CONTRACTIONS[w]
            elif w in _IS_CONTRACTED:
                out += [w[:-2], "is"]
            elif w.endswith("'s") and w != "let's":
                out += [w[:-2], "POSS"]
            elif w.endswith("s'") and len(w) > 2:  # "the kids' room", "my parents' bedroom"
                out += [w[:-1], "POSS"]
            else:
                out.append(w.rstrip("'"))
        return out

    def tokens(self, text: str) -> Tokens:
        """The grammar tokens of ``text`` after fillers, unknown words, corrections and repetitions."""
        words = self.words(text)
        if words and all(w in BACKCHANNELS or w in self.hesitations for w in words) and any(
                w in _AGREEING for w in words):
            # "mhm", "uh huh", "mm hmm" said alone: a listener's yes; inside a turn they are hesitations
            return Tokens([Tok("YES", "yes", " ".join(words))], words=len(words),
                          raw=[Tok("YES", "yes", " ".join(words))])
        hes = self.hesitations
        words = [w for w in words if w not in hes]
        toks: list[Tok] = []
        unknown: list[str] = []
        coined: list[str] = []
        i, n = 0, len(words)
        entries = self.entries
        lengths = self.lengths
        while i < n:
            for k in lengths.get(words[i], ()):
                if i + k > n:
                    continue
                key = tuple(words[i : i + k])
                hit = entries.get(key)
                if hit is not None and not (i and k == 1 and words[i] in OPENING_ONLY):
                    term, value = hit
                    if term != DROP:
                        toks.append(Tok(term, value, words[i] if k == 1 else " ".join(key).replace(" POSS", "'s")))
                    i += k
                    break
            else:
                if i + 1 < n and words[i + 1] == "POSS":  # "sarah's cup": whoever owns it is named
                    toks.append(Tok("NAME", words[i], words[i]))
                elif (i + 1 < n and words[i + 1] in _ROOM_WORDS and toks and toks[-1].type in _NAMING
                      and words[i] not in NEVER_ROOM):
                    # "the craft room", "my sewing room": a room she names with a word the lexicon lacks
                    # is a place, named in her words; a guess from a word not known (reported in
                    # ``coined``: the understanding halves the coverage, so the dialog asks first)
                    toks.append(Tok("PLACE", f"{words[i]} {words[i + 1]}", f"{words[i]} {words[i + 1]}"))
                    coined.append(f"{words[i]} {words[i + 1]}")
                    i += 2
                    continue
                else:
                    unknown.append(words[i])
                i += 1
        toks = _owners(toks)
        toks = _things(toks, unknown)
        toks = _rooms_of(toks)
        toks = _named_rooms(toks)
        toks = _sides(toks)
        out = Tokens(toks, unknown, words=n, raw=_compounds(list(toks)), coined=coined)
        out.tokens = _repairs(out.tokens, out.corrected)
        out.tokens = _negated(out.tokens, out.corrected)
        out.tokens = _repetitions(out.tokens, out.repeated)
        out.tokens = _restatements(out.tokens, out.corrected)
        out.tokens = _compounds(out.tokens)
        return out


#: Words after a word the lexicon lacks that name a room or a part of one in her words ("the sewing room", "the
#: dining corner", "our games area": talk22, an open plan's parts are named so). A known word before a part ("the
#: reading corner", "the sofa corner") is left as it was: it may say where something is.
_ROOM_WORDS = frozenset({"room", "corner", "area", "nook"})
#: Words before a room she names ("the reading room", "my sewing room", "anna's blue room"): not "a"
#: ("a lovely room", "a big room" evaluate a room, they name none).
_NAMING = frozenset({"THE", "MY", "OUR", "POSS"})
#: Words not in the lexicon that never name a room before "room": they say which room or what it is like
#: ("the next room", "the same room", "the whole room", "the cold room"), so "this is the next room" is no
#: place called "next room" (review-lang7 item 3).
NEVER_ROOM = frozenset({
    "next", "same", "other", "whole", "main", "last", "first", "previous", "entire", "own", "only", "very",
    "wrong", "empty", "new", "old", "cold", "warm", "hot", "little", "small", "large", "huge", "tiny", "nice",
    "lovely", "messy", "clean", "dark", "bright", "quiet", "second", "third", "final", "whole", "certain",
    "different", "another", "biggest", "smallest", "best", "favourite", "favorite", "entire", "actual",
})
#: Words that make a room's name with "room" after them: a noun, a use, a colour ("the breakfast room",
#: "the reading room", "the blue room").
_ROOM_NAMERS = frozenset({"OBJ", "USE", "COLOUR"})


#: What "thing" refers with: a deixis and the words that describe it ("that red thing", "this thing here").
_THING_AFTER = frozenset({"THIS", "THAT", "IT", "COLOUR", "ATTR"})


#: Words of a question before "that thing": it asks about the thing, it shows nothing.
_THING_ASKED = frozenset({"WHERE", "WHAT", "HAVE", "CAN", "DID", "SEEK", "FIND", "KNOW", "HOW"})


def _things(toks: list[Tok], unknown: list[str]) -> list[Tok]:
    """"Thing" is what she points at only after a deixis or its describing words ("that red thing is my
    backpack"); elsewhere ("to thing is my toy", the recogniser's "to" for "this") it says nothing the
    grammar can use: a word not understood, as before it was in the lexicon."""
    out: list[Tok] = []
    for i, t in enumerate(toks):
        if t.type == "THING":
            k = i - 1
            while k >= 0 and toks[k].type in ("COLOUR", "ATTR"):
                k -= 1
            if k < 0 or toks[k].type not in _THING_AFTER or any(x.type in _THING_ASKED for x in toks[:k]):
                # "where is that thing", "what is this thing", "have you seen that thing": a question
                # about it, never a teaching ("where is" is never teaching: docs/semantics.md §4)
                unknown.append(t.text)
                continue
        out.append(t)
    return out


#: Greeting words that greet only as the first word of a turn ("morning, biron"): "in the morning", "the
#: morning show", "every evening we watch tv" say when, and greet nobody (review-lang7 item 12); elsewhere
#: they are words not understood.
OPENING_ONLY = frozenset({"morning", "evening", "yo"})


def _rooms_of(toks: list[Tok]) -> list[Tok]:
    """"The room of my daughter" is "my daughter's room": the owner said after "room" with "of" becomes the
    possessor (the grammar then needs one form; "the room" alone stays no place's name)."""
    for i in range(len(toks) - 3):
        if [t.type for t in toks[i:i + 3]] == ["THE", "ROOM", "OF"]:
            k = i + 3
            mine = toks[k] if toks[k].type in ("MY", "OUR") else None
            k += mine is not None or toks[k].type == "THE"
            if k < len(toks) and toks[k].type == "NAME":
                owner = ([mine] if mine is not None else []) + [toks[k], Tok("POSS", "poss", "POSS")]
                return toks[:i] + owner + [toks[i + 1]] + toks[k + 1:]
    return toks


def _named_rooms(toks: list[Tok]) -> list[Tok]:
    """A noun, a use or a colour before "room" after an article or owner names a room: one PLACE in her
    words ("the drawing room" is no drawing, "the reading room" no reading lamp)."""
    out: list[Tok] = []
    for t in toks:
        if (t.type == "ROOM" and len(out) >= 2 and out[-1].type in _ROOM_NAMERS
                and out[-2].type in _NAMING | {"NAME"}):
            prev = out.pop()
            out.append(Tok("PLACE", f"{prev.text} {t.text}", f"{prev.text} {t.text}"))
            continue
        out.append(t)
    return out


#: "left" after "have", "I", "did", "we" is the verb ("where could I have left my bag").
_LEFT_AS_PUT = frozenset({"HAVE", "I", "DID", "WE", "YOU"})

#: Words that name a side after an article or before "one"/a noun ("the right one", "at the back",
#: "the right cup") and something else elsewhere ("right!", "go back").
_SIDE_WORDS = {"right": "right", "back": "back"}
_BEFORE_SIDE = frozenset({"THE", "A", "THIS", "THAT", "MY", "YOUR"})  # "to my right", "on your right"
_AFTER_SIDE = frozenset({"ONE", "OBJ", "COLOUR", "ATTR"})


#: After "the one" or a noun, "behind" or "in front of it" that ends the answer ("the one behind",
#: "the plant behind it") says which of two along her arm: the one at the back, the one in front; not a
#: place behind a landmark ("the one behind the sofa" stays one).
_BEHIND_AFTER = frozenset({"ONE", "OBJ"})
_BEHIND_WHAT = frozenset({"IT", "THAT", "THIS"})
_DEPTH_RELATIONS = {"behind": "back", "in_front_of": "front"}


def _sides(toks: list[Tok]) -> list[Tok]:
    """Read "right" and "back" as a side where the words around them say so, and "behind" / "in front
    of it" ending an answer ("the one behind", "the plant behind it") as the side "back" / "front"."""
    toks = _left_right(toks)
    for i, t in enumerate(toks):
        depth = _DEPTH_RELATIONS.get(t.value) if t.type == "REL" else None
        if (depth is not None and i and toks[i - 1].type in _BEHIND_AFTER
                and (i + 1 == len(toks) or (i + 2 == len(toks) and toks[i + 1].type in _BEHIND_WHAT))
                and not any(x.type == "WHERE" or (x.type == "SIDE" and x.value not in _DEPTH_VALUES)
                            for x in toks[:i])):
            # not when a left/right was said already ("the right one behind it": the side stays right) nor
            # in a question ("where have I left the cup behind it")
            return [*toks[:i], Tok("SIDE", depth, t.text)]
    return toks


_DEPTH_VALUES = frozenset({"near", "front", "far", "back"})


def _left_right(toks: list[Tok]) -> list[Tok]:
    """"left" as the verb after "have"/"I", and "right"/"back" as a side where the words around say so."""
    for i, t in enumerate(toks):
        if t.type == "SIDE" and t.text == "left" and i and toks[i - 1].type in _LEFT_AS_PUT:
            toks[i] = Tok("PUT", "put", t.text)
            continue
        side = _SIDE_WORDS.get(t.text)
        if side is None:
            continue
        before = toks[i - 1].type if i else ""
        after = toks[i + 1].type if i + 1 < len(toks) else ""
        if before in _BEFORE_SIDE or (after in _AFTER_SIDE and before not in ("GO", "COME", "IS", "YES")) or (
                after == "OF" and i + 2 < len(toks) and toks[i + 2].type == "ME"):  # "the one right of me"
            toks[i] = Tok("SIDE", side, t.text)
    return toks


def _owners(toks: list[Tok]) -> list[Tok]:
    """A word before a possessive names an owner ("the dog's bowl", "the baby's bottle")."""
    out: list[Tok] = []
    for i, t in enumerate(toks):
        if i + 1 < len(toks) and toks[i + 1].type == "POSS" and t.type not in ("NAME", "POSS", EDIT, "NO"):
            head, _, rest = t.text.partition(" ")
            if t.type == "ROBOT" and head == "my" and rest:
                # "my friend's cup": a way to address the robot ("my friend") said before a possessive
                # is her friend, owned as "my sister's cup" is: MY, then the name without "my"
                # (review-lang7 item 14)
                out += [Tok("MY", "speaker", head), Tok("NAME", rest, rest)]
                continue
            t = Tok("NAME", t.text, t.text)
        out.append(t)
    return out


#: Nouns that say what something is made of when they stand before another noun ("a glass vase").
MATERIAL_NOUNS = frozenset({"glass", "paper", "stone", "metal", "plastic", "wood", "leather", "china", "iron"})


def _compounds(toks: list[Tok]) -> list[Tok]:
    """Noun-noun compounds: the last noun is the head and gives the type, the words said are the title.

    "the bathroom mirror" (a place before an object), "the bed lamp" (an object before an object):
    one OBJ with the head's type and the compound's words. A material noun before a noun is an
    attribute ("a glass vase"); a use word before a noun stays a USE ("a coffee cup").
    """
    out: list[Tok] = []
    for t in toks:
        prev = out[-1] if out else None
        if t.type == "OBJ" and prev is not None and prev.type in ("OBJ", "PLACE"):
            if prev.type == "OBJ" and prev.text in MATERIAL_NOUNS:
                out[-1] = Tok("ATTR", prev.text, prev.text)
                out.append(t)
            else:
                out[-1] = Tok("OBJ", t.value, f"{prev.text} {t.text}")
            continue
        out.append(t)
    return out


# Word classes for aligning a repair with its reparandum: a determiner replaces a determiner, etc.
_CLASS = {"A": "DET", "THE": "DET", "MY": "DET", "YOUR": "DET", "OUR": "DET", "THIS": "DEIXIS", "THAT": "DEIXIS"}


def _cls(t: Tok) -> str:
    return _CLASS.get(t.type, t.type)


def _repairs(toks: list[Tok], removed: list[str]) -> list[Tok]:
    """Take out "reparandum + editing term" before each repair ("the red no the blue cup")."""
    changed = True
    while changed:
        changed = False
        for e in range(1, len(toks)):
            t = toks[e]
            if t.type != EDIT and t.type != "NO":
                continue
            if t.type == "NO" and all(x.type == "NO" for x in toks[:e]):
                continue  # "no", "no no": an answer, not a correction
            end = e + 1
            while end < len(toks) and toks[end].type in (EDIT, "NO"):
                end += 1  # "no sorry", "no no"
            if end >= len(toks):
                removed += [x.text for x in toks[e:]]
                del toks[e:]  # a trailing "sorry": nothing repaired
                changed = True
                break
            cls = _cls(toks[end])
            start = next((k for k in range(e - 1, -1, -1) if _cls(toks[k]) == cls), None)
            if start is None and (np := _np_at(toks, end)) is not None and toks[np[0] - 1].type != "ONE":
                # "where is [the→uh] kettle, sorry, the bowl": the reparandum's article was lost; the repair
                # is a noun phrase, so it replaces the nearest noun phrase of its kind before the editing term
                k = next((k for k in range(e - 1, -1, -1) if _HEADS.get(toks[k].type) == np[1]), None)
                if k is not None:
                    while k > 0 and toks[k - 1].type in _NP_WORDS:
                        k -= 1
                    start = k
            if start is None:
                start = e  # no aligned word: drop only the editing term(s)
            elif start < e and (k := _np_start(toks, start)) and toks[k - 1].type == "NOT":
                # "not the kitchen, I said the bathroom": the phrase she repairs was said negated; the "not"
                # goes with it (left alone it made the whole turn a no, the bathroom lost)
                start = k - 1
            removed += [x.text for x in toks[start:end]]
            del toks[start:end]
            changed = True
            break
    return toks


#: Words of a noun phrase before its head, and its heads by class ("the red one", "my cup", "the kitchen").
_NP_WORDS = frozenset({"A", "THE", "MY", "YOUR", "OUR", "NAME", "POSS", "COLOUR", "ATTR", "USE", "ORD", "SIDE"})
_HEADS = {"OBJ": "OBJ", "ONE": "OBJ", "PLACE": "PLACE", "ROOM": "PLACE"}


def _np_start(toks: list[Tok], i: int) -> int:
    """Where the noun phrase whose word stands at ``i`` begins (its article, owner, colour before it)."""
    while i > 0 and toks[i - 1].type in _NP_WORDS:
        i -= 1
    return i


def _np_at(toks: list[Tok], i: int) -> tuple[int, str] | None:
    """(end, head class) of the noun phrase that starts at ``i``, or None."""
    j = i
    while j < len(toks) and toks[j].type in _NP_WORDS:
        j += 1
    if j < len(toks) and toks[j].type in _HEADS:
        while j + 1 < len(toks) and toks[j + 1].type in _HEADS and _HEADS[toks[j + 1].type] == _HEADS[toks[j].type]:
            j += 1  # "the living room" said as PLACE ROOM
        return j + 1, _HEADS[toks[j].type]
    return None


def _negated(toks: list[Tok], removed: list[str]) -> list[Tok]:
    """A contrast names what is not meant and what is: only what is meant counts.

    "not the kitchen, the bathroom", "that's not the kitchen, that's the bathroom", "no, it's not a
    cup, it's a glass" (the negated phrase first, the right one after it) and "it's a mug, not a
    cup", "the kitchen, not the bathroom" (the negated one last): the negated noun phrase (with its
    "that is not") is taken out when a noun phrase of the same kind (an object, a place) stands on
    the other side. A "not" with nothing to contrast ("this is not my cup") is left alone: a no.
    """
    for i, t in enumerate(toks):
        if t.type != "NOT":
            continue
        np = _np_at(toks, i + 1)
        if np is None:
            continue
        end, kind = np
        start = i
        if i >= 1 and toks[i - 1].type in ("IS", "ARE"):
            start = i - 1
            if i >= 2 and toks[i - 2].type in ("THIS", "THAT", "IT"):
                start = i - 2
        after = next((k for k in range(end, len(toks)) if _np_at(toks, k) is not None), None)
        if after is not None and _np_at(toks, after)[1] == kind and all(  # type: ignore[index]
                x.type in ("THIS", "THAT", "IT", "IS", "ARE", "NO", EDIT) for x in toks[end:after]):
            removed += [x.text for x in toks[start:end]]
            return toks[:start] + toks[end:]  # the corrected phrase follows
        before = [k for k in range(0, i) if (n := _np_at(toks, k)) is not None and n[0] == i]
        if end == len(toks) and before and _np_at(toks, before[0])[1] == kind:  # type: ignore[index]
            removed += [x.text for x in toks[i:end]]
            return toks[:i]  # "a mug, not a cup": the contrast said last
    return toks


def _restatements(toks: list[Tok], removed: list[str]) -> list[Tok]:
    """A noun phrase said again at once with another noun is a repair without an editing term
    ("this is a cup, uh, a mug"): the later one counts."""
    i = 0
    while i + 3 < len(toks):
        a, x, b, y = toks[i : i + 4]
        if _cls(a) == "DET" and _cls(b) == "DET" and x.type == y.type and x.type in ("OBJ", "PLACE") and x.value != "":
            removed += [a.text, x.text]
            del toks[i : i + 2]
        else:
            i += 1
    return toks


def _repetitions(toks: list[Tok], removed: list[str]) -> list[Tok]:
    """Keep one copy of an n-gram (n = 3, 2, 1) said twice in a row (two stops in a row are one, whatever words)."""
    for n in (3, 2, 1):
        i = 0
        while i + 2 * n <= len(toks):
            a = [(t.type, t.text) for t in toks[i : i + n]]
            b = [(t.type, t.text) for t in toks[i + n : i + 2 * n]]
            # a stop said twice in other words ("stop, that is far enough", "that will do, stop") is one stop
            # (talk21: it was half understood, the dialog unsure of a plain stop)
            same = a == b or (n == 1 and toks[i].type == toks[i + 1].type == "STOP")
            if same and not (n == 1 and toks[i].type in ("HELLO", "GOODBYE", "YES", "NO")):
                removed += [t.text for t in toks[i + n : i + 2 * n]]
                del toks[i + n : i + 2 * n]
            else:
                i += 1
    return toks
