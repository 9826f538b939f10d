"""The generated tour's user: which population she is drawn from, and how she answers the robot.

A generated user is a person with a ``profile=`` of ``humans/profiles.xml`` (her voice,
distance, patience, looking away, pointing, phrasing style and repairs are drawn from it with
the run's seed, :mod:`humans.profiles`). Which profile is drawn per tour from a *mix* (the
generator's ``--users`` option, a study's ``users=`` condition, one syntax for both):
``typical+impatient`` (alike) or ``typical:3+silent:1`` (weights; ``,`` also accepted by the generator). The draw comes from its own generator,
``default_rng([seed, k, USER_STREAM])``, so the flat, the objects and the script of tour k are
the same under every mix: two conditions that differ only in their users run the same homes.

Her answers to the robot's questions are reactions (``<on hears=...>``) inside the wait for
the answer to the request she just made (:func:`reactions`), so an answer can name what this
request was about ("Is this the kitchen?" -> "Yes"; "Is this the bedroom?" -> "No, this is
the kitchen"; "Which one do you mean?" -> pointing at it again, "the red one"). The patterns
are word patterns (:mod:`homesim.scenario.wordpattern`) over the everyday English question
forms a robot asks; tests/test_tour_users.py checks each of BIRON's confirmation and clarification
questions (``robot/dialog/biron-dialogs.xml``) is answered, without the generator reading the
robot's files: the user knows English, not the robot's dialog ids.
"""

from __future__ import annotations

import numpy as np
from lxml import etree

#: The default mix: mostly typical users, with some of every other population (our choice; no
#: published figure gives the share of impatient or vague users in a home; vary it in studies).
DEFAULT_MIX: tuple[tuple[str, float], ...] = (("typical", 0.4), ("cooperative", 0.1), ("impatient", 0.1),
                                             ("vague", 0.1), ("distracted", 0.1), ("silent", 0.1), ("wrong", 0.1))
#: Third key of the user's generator (tour k of seed N: ``default_rng([N, k, USER_STREAM])``).
USER_STREAM = 1
#: How often she answers one question within one wait (the robot asking again is then a repair).
ANSWERS = 2


#: What she takes as the robot having done what she asked (regular expressions over its words):
#: the everyday forms of "done" only, so that a rejection ("I am still following you; say stop
#: first"), a question or a failure ("Sorry, I don't know where to find your cup") leaves her
#: waiting and then repairing, as a person would (tests/test_tour_users.py checks every one of
#: BIRON's other sentences leaves these unmatched).
GREETED = r"I am BIRON|^(hello|hi)\b|already talking"
FOLLOWING = r"(OK,? I am|already) following you"
STOPPED = r"\bI stopped\b|^I am not moving"
PLACE_LEARNED = r"\bI will remember\b"
OBJECT_LEARNED = r"\bI have learned\b"
SEEN = r"\bI have seen\b"
EXPLAINED = r"\bnow you can\b"
GOING = r"\bI am going to\b"


class MixError(ValueError):
    """A users mix that names no known profile, or gives a bad weight."""


def parse_mix(text: str) -> tuple[tuple[str, float], ...]:
    """``typical,impatient`` or ``typical:3+silent:1`` (``,`` or ``+`` between) -> ((name, weight), ...)."""
    from humans.profiles import default_profiles

    known = default_profiles()
    out: dict[str, float] = {}
    for item in filter(None, (s.strip() for s in text.replace("+", ",").split(","))):
        name, colon, w = item.partition(":")
        name = name.strip()
        if name not in known:
            raise MixError(f"unknown user profile {name!r} (profiles: {', '.join(known)})")
        if name in out:
            raise MixError(f"user profile {name!r} given twice")
        try:
            weight = float(w) if colon else 1.0
        except ValueError:
            raise MixError(f"{item!r}: the weight after ':' is not a number") from None
        if not (weight > 0 and weight < float("inf")):
            raise MixError(f"{item!r}: a weight is a positive number")
        out[name] = weight
    if not out:
        raise MixError("no user profile given (e.g. typical,impatient or typical:3+silent:1)")
    return tuple(out.items())


def mix_text(mix: tuple[tuple[str, float], ...]) -> str:
    """The mix as the option writes it (``typical:0.5,silent:0.1``)."""
    return ",".join(f"{n}:{w:g}" for n, w in mix)


def draw_user(seed: int, k: int, mix: tuple[tuple[str, float], ...] = DEFAULT_MIX) -> str:
    """The profile of tour k's user: from ``default_rng([seed, k, USER_STREAM])`` alone."""
    rng = np.random.default_rng([seed, k, USER_STREAM])
    w = np.array([x for _, x in mix], dtype=float)
    u = float(rng.random())
    i = int(min(np.searchsorted(np.cumsum(w) / w.sum(), u, side="right"), len(w) - 1))
    return mix[i][0]


def max_patience(profile: str) -> int:
    """The most repairs a user of ``profile`` makes for one request (its declared upper bound)."""
    from humans.profiles import default_profiles

    return int(default_profiles()[profile].numeric["patience"].high)


# ------------------------------------------------------------------ reactions
Reaction = tuple[str, list[etree._Element]]  # (word pattern, acts)


def _say(**attrs: str) -> etree._Element:
    return etree.Element("say", attrs)


def alternatives(words: list[str]) -> str:
    """``(kitchen|living room)``: a word-pattern group of the words (letters, digits, ' and - only)."""
    clean = sorted({" ".join("".join(c for c in w.lower() if c.isalnum() or c in "'- ").split()) for w in words} - {""})
    return "(" + "|".join(clean) + ")"


#: How she answers "Which one do you mean?": by colour, by position (as the robot sees the
#: objects), by where it stands, or by pointing at it again ("this one").
WHICH_KINDS = ("colour", "side", "place", "pointing")


def which_answer(kind: str, obj: str, *, colour: str = "", place: str = "") -> list[etree._Element]:
    """Her acts answering "Which one do you mean?" about object ``obj`` (``kind`` of
    :data:`WHICH_KINDS`): "The red one" while pointing again; "The one on the left" (its side
    among the similar objects as the robot sees them when she speaks, ``side-of``); "The one on
    the table" (``place``: where it stands, "on the table"); "This one here" while pointing."""
    point = etree.Element("point", object=obj, duration="2")
    if kind == "colour":
        return [_say(request="which", about=colour, wait="false"), point]
    if kind == "side":
        return [_say(request="which-side", **{"side-of": obj})]
    if kind == "place":
        return [_say(request="which-place", about=place)]
    if kind == "pointing":
        return [_say(request="which-pointing", wait="false"), point]
    raise ValueError(f"no 'which one' answer {kind!r}: one of {', '.join(WHICH_KINDS)}")


def reactions(kind: str, *, words: list[str] | None = None, about: str = "", colour: str = "",
              obj: str | None = None, which: list[etree._Element] | None = None) -> list[Reaction]:
    """Her answers to the robot's questions about the request she just made.

    ``kind``: greet, follow, place, object, where, goto, goodbye. ``words``: her words (and the type's)
    for what the request is about, ``about`` the phrase she names it with ("the kitchen",
    "my cup"), ``colour`` and ``obj`` (the object's name in the scenario) for objects, and
    ``which``: her answer to "which one?" (:func:`which_answer`; default by colour, pointing).
    """
    yes: list[etree._Element] = [_say(request="yes")]
    alt = alternatives(words or [])
    if kind == "greet":
        return [("^did you say", yes)]
    if kind == "follow":
        return [("^shall i follow [you]", yes)]
    if kind == "place":
        return [(f"^is this [the] {alt}$", yes),
                ("^is this", [_say(request="correct", about=about)]),
                ("which room is this|what room is this|where are we", [_say(request="teach-place", about=about)])]
    if kind == "object":
        assert obj is not None
        return [(_object_yes(alt, about, colour), yes),
                ("^is this", [_say(request="correct", about=about)]),
                ("^what is (it|this|that)", [_say(request="teach-object", about=about)]),
                ("which one [do you mean]|^do you mean", which if which is not None else which_answer("colour", obj, colour=colour))]
    if kind == "where":
        return [("what are you looking for|what you are looking for", [_say(request="where-is", about=about)])]
    if kind == "goodbye":
        # her good-bye half heard, the robot asks before it ends: she meant it (talk18's tours never answered it)
        return [("do you want to end the tour|do you want to stop the tour|shall we end the tour", yes)]
    if kind == "goto":
        return [(f"^shall i go to [the] {alt}$", yes),
                ("^shall i go", [_say(request="no")]),
                ("where shall i go|where should i go", [_say(request="go-to", about=about)])]
    raise ValueError(f"no reactions for {kind!r}")


def _object_yes(alt: str, about: str, colour: str) -> str:
    """"Is this your red cup?" answered yes only when every word of it is right.

    The type must be hers (``alt``); a colour, if the robot says one, the object's (``colour``);
    "your" only if she said "my", "favourite" only if she said it. Anything else the robot
    adds (another colour, another owner) makes it a wrong confirmation, which she corrects.
    """
    said = about.lower().split()
    dets = ["the", "a", "an"] + (["your"] if "my" in said else [])
    parts = [f"[({'|'.join(dets)})]"]
    if "favourite" in said:
        parts.append("[favourite]")
    if colour.strip():
        parts.append(f"[{alternatives([colour])}]")
    return f"^is this {' '.join(parts)} {alt}$"


def step_aside(point: str, obj: str) -> Reaction:
    """"I cannot see it, you are standing in front of it. Could you step aside, please?": she
    steps to ``point`` (round the object) and points at it again."""
    return ("step aside|standing in front of it",
            [etree.Element("walk-to", point=point), etree.Element("point", object=obj, duration="2")])


def comeback() -> list[Reaction]:
    """What she does, at any point of her tour, when the robot has lost her or ended the interaction.

    "I have lost you. Please come back to me.": she walks back to it and asks it to follow her
    again (then walks on where she was going). "You left, so I will look around." or "Please
    look at me and say hello first.": she walks up to it and greets it again.
    """
    def back() -> list[etree._Element]:
        return [etree.Element("walk-to", robot="true", **{"stop-at": "1.2"}), etree.Element("face", robot="true")]

    follow = back() + [_say(request="follow"), etree.Element("wait-for", hears="(ok i am|already) following you", timeout="6")]
    attach(follow[-1], reactions("follow"))
    greet = back() + [_say(request="greet"), etree.Element("wait-for", hears="i am biron|^hello|already talking", timeout="6")]
    attach(greet[-1], reactions("greet"))
    return [("i have lost you|please come back to me", follow),
            ("you left|say hello [to me] first|please look at me", greet)]


def attach(wait_for: etree._Element, answers: list[Reaction]) -> None:
    """Put the reactions inside the ``<wait-for>``, each answering at most :data:`ANSWERS` times."""
    for hears, acts in answers:
        on = etree.SubElement(wait_for, "on", hears=hears, max=str(ANSWERS))
        for a in acts:
            on.append(a)
