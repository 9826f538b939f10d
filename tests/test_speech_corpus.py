"""The home-tour corpus: its size, the held-out slice kept apart, and the understanding rate on it.

``robot/speech/corpus/tuning.tsv`` is what the lexicon and grammar were grown on (every row
must give its frame: tests/test_speech_grammar.py). ``heldout.tsv`` was written before that
growth and never used to tune it (robot/speech/corpus/README.md): the rate measured on it is
the understanding rate issue 26 item 8 asks for (about 9 in 10).
"""

from __future__ import annotations

from pathlib import Path

import pytest
from lxml import etree

from robot.speech.lexicon import CONTRACTIONS, DROP, Lexicon
from robot.speech.module import shared_understander

CORPUS = Path(__file__).resolve().parent.parent / "robot" / "speech" / "corpus"


def _rows(name: str) -> list[tuple[str, str]]:
    rows = []
    for line in (CORPUS / name).read_text(encoding="utf-8").splitlines():
        if line.startswith("#") or not line.strip("\t"):
            continue
        words, frame, _ = line.split("\t")
        rows.append((words, frame))
    return rows


def understood_share(rows: list[tuple[str, str]]) -> float:
    """Share of rows whose frame equals the expected one exactly (NOT_UNDERSTOOD included)."""
    u = shared_understander()
    ok = 0
    for words, frame in rows:
        got = u.understand(words).frame
        ok += ("NOT_UNDERSTOOD" if got is None else etree.tostring(got, encoding="unicode")) == frame
    return ok / len(rows)


HELD_OUT = ("heldout.tsv", "heldout-2.tsv", "heldout-3.tsv", "heldout-4.tsv")
# heldout-5.tsv (fresh7, the outside checker) was written without reading the grammar, the lexicon or
# tuning.tsv; it is kept apart and well formed like the others, and its rate is measured and reported
# (the README in the corpus folder), not held to the 9-in-10 line here.
# heldout-6.tsv (fresh9, the second outside checker, the same way: an elderly slow speaker, a user who changes
# her mind, one who talks to someone else in between, one who points from afar, a child): kept apart and well
# formed, its rate measured once and reported in the corpus README.
# heldout-7.tsv (lang12, committed before it was run): rooms in British, American and old-fashioned words, phrasal go-tos,
# informal stops and good-byes, "you are in my way", words to another person, furniture.
# heldout-8.tsv (fresh13, the outside checker, committed before it was run): fresh5's users, a hand-over, phone talk, own words.
# heldout-9.tsv (fresh14, the outside checker, committed before it was run): fresh6's users, a teenager, a polite non-native speaker,
# terse and very polite speakers, corrections, go-to and where-is in their own words, which-one answers, small talk; measured and
# reported (corpus README), not held to the 9-in-10 line.
# heldout-10.tsv (fresh16, the outside checker, committed before it was run): fresh7's users, an elderly soft-spoken lady, a talkative
# one, non-native speakers, a fast walker, flatmates and children as bystanders, rooms in their own words; measured and reported
# (corpus README), not held to the 9-in-10 line.
# heldout-11.tsv (fresh18, the outside checker, committed before it was run): a hesitant speaker, an elderly lady, a child, non-native
# speakers, flatmates and children as bystanders, rooms in their own words (lounge, hobby room, sun room); measured and reported
# (corpus README), not held to the 9-in-10 line.
# heldout-12.tsv (fresh20, the outside checker, committed before it was run): students in a shared flat and their flatmates, a visiting
# mother, a user who corrects herself, rooms in their own words (common room, laundry room, sitting room); measured and reported
# (corpus README), not held to the 9-in-10 line.
# heldout-13.tsv (fresh22, the outside checker, committed before it was run): fresh10's users, a family with children, an elderly lady,
# a child, a non-native speaker, fast, impatient and talkative users, bystanders' words, rooms in their own words (music room, front
# room, family room); measured and reported (corpus README), not held to the 9-in-10 line.
# heldout-14.tsv (fresh23, the outside checker, committed before it was run): fresh11's users, a hesitant speaker, talkative users, a
# non-native speaker, a child, an elderly lady, a user who corrects herself, bystanders' words, rooms in their own words (lounge, den,
# parlour, sewing room, fish room, gallery); measured and reported (corpus README), not held to the 9-in-10 line.
# heldout-15.tsv (fresh24, the outside checker, committed before it was run): fresh12's users (vague, distracted, impatient,
# typical, cooperative; a couple handing over, a child, bystanders), zones and rooms in their words (kitchenette, sleeping corner,
# living area, nursery), furniture the library rarely has (chest of drawers, trolley, umbrella stand, shoe rack, bench, cot);
# measured and reported (corpus README), not held to the 9-in-10 line.
# heldout-16.tsv (fresh25, the outside checker, committed before it was run): fresh13's users (silent, wrong, vague, distracted,
# typical; a visitor talking to the partner, bystanders, a user who corrects herself mid-request), rooms in their words (lounge, den,
# sunroom, reading nook, scullery, playroom), furniture (sideboard, nightstand, chest, hall stand); measured and reported (corpus
# README), not held to the 9-in-10 line.
ALL_HELD_OUT = (*HELD_OUT, "heldout-5.tsv", "heldout-6.tsv", "heldout-7.tsv", "heldout-8.tsv", "heldout-9.tsv", "heldout-10.tsv",
                "heldout-11.tsv", "heldout-12.tsv", "heldout-13.tsv", "heldout-14.tsv", "heldout-15.tsv", "heldout-16.tsv")


def test_the_corpus_has_500_utterances_and_a_fifth_held_out():
    tuning, held = _rows("tuning.tsv"), [r for name in ALL_HELD_OUT for r in _rows(name)]
    assert len(tuning) + len(held) >= 500
    assert len(held) / (len(tuning) + len(held)) >= 0.2


def test_the_held_out_slices_share_no_utterance_with_the_tuning_part_or_each_other():
    words = [{w for w, _ in _rows(name)} for name in ("tuning.tsv", *ALL_HELD_OUT)]
    assert sum(map(len, words)) == len(set().union(*words))


_FILLERS = frozenset(k[0] for k, (t, _) in Lexicon.load().entries.items() if len(k) == 1 and t == DROP)


def _said(words: str) -> tuple[str, ...]:
    """An utterance as the understanding hears it: lower case, no punctuation, contractions said as two
    words, fillers and politeness words (the lexicon's dropped words) left out."""
    fillers = _FILLERS
    out: list[str] = []
    for w in Lexicon.words(words):
        out += ["'s"] if w == "POSS" else list(CONTRACTIONS.get(w, (w,)))
    return tuple(w for w in out if w not in fillers)


_DEIXIS = frozenset({"this", "that", "here", "it", "these", "those", "there"})


def near_duplicates(a: str, b: str) -> bool:
    """Whether two utterances are one phrasing: the same words once fillers, contractions and punctuation
    are taken out, or but one deixis word apart ("this is the room of my daughter" / "here is ...")."""
    x, y = _said(a), _said(b)
    if x == y:
        return True
    diff = [(p, q) for p, q in zip(x, y) if p != q] if len(x) == len(y) else []
    return len(diff) == 1 and diff[0][0] in _DEIXIS and diff[0][1] in _DEIXIS


@pytest.mark.parametrize("a, b, same", [("um, could you follow me, please?", "could you follow me", True),
                                        ("this is the room of my daughter", "here is the room of my daughter", True),
                                        ("where's my cup", "where is my cup", True),
                                        ("this is the kitchen", "this is the bathroom", False),
                                        ("this is my cup", "this is my red cup", False)])
def test_near_duplicates_are_one_phrasing(a, b, same):
    assert near_duplicates(a, b) == same


#: Tuning rows (4 words or more as heard) that are one phrasing with some held-out row, counted when this
#: check was added (2026-11-27, review-lang7 item 15): most are everyday requests every slice holds ("go to
#: the kitchen"); "this is the room of my daughter" and "this is where we cook this is the kitchen" were
#: added by lang7 after heldout-5 was in the repository (heldout-5's gains from them are exposed, not
#: unseen: corpus README). No tuning row may join them: a held-out rate is an unseen figure only while
#: the tuning part holds no copy of its rows.
KNOWN_NEAR_DUPLICATES = frozenset({
    'come along with me please', 'come with me biron', 'could you follow me please',
    'er could you um follow me', 'follow me this way please', 'go to the kitchen',
    'go to the kitchen no the living room', 'go to the kitchen please',
    'go to the kitchen uh i mean the bathroom', 'hello i am back', 'here is the bathroom',
    "here's the bathroom", 'i cannot find my phone', 'i would like you to follow me',
    "i'd like you to follow me please", "i'm off bye", 'it is that one there', 'maybe go to the kitchen',
    'no it is not', 'no that is wrong', "no that's not right", "please don't follow me",
    'please hold on a second', 'please tell me what you can do', 'take me back to the kitchen please',
    'thank you very much and goodbye', 'that is the remote', "that's the bathroom", 'the one on the right',
    'this is a mug', "this is my son's room", 'this is the fruit bowl', 'this is the guest room',
    'this is the lamp next to the sofa', 'this is the room of my daughter', 'this is the study',
    'this is the utility room', 'this is where we cook this is the kitchen', 'uh could you maybe follow me',
    'uh where is uh my cup', 'um excuse me biron hello', 'wait for me here please', 'we are in the study',
    'we are now in the hallway', "we're now in the dining room", 'what are your skills',
    'what can you do biron', 'what else do you know how to do', 'where did i put my glasses', 'where is my cup',
    'where is the red cup', "where's my cup", "where's my phone", "yes that's right",
})


def test_no_new_tuning_row_is_a_near_duplicate_of_a_held_out_row():
    held = {_said(w) for name in ALL_HELD_OUT for w, _ in _rows(name)}
    deixis_free = {tuple("·" if w in _DEIXIS else w for w in h) for h in held}
    new = [w for w, _ in _rows("tuning.tsv") if len(s := _said(w)) >= 4 and w not in KNOWN_NEAR_DUPLICATES
           and (s in held or tuple("·" if x in _DEIXIS else x for x in s) in deixis_free)]
    assert new == [], "tuning rows that are one phrasing with a held-out row (rewrite or drop them)"


def _scene_says() -> dict[tuple[str, ...], str]:
    """Every line a scripted user says in the repository's scenes, as heard (deixis words alike), with its file."""
    from homesim.xmlio import parse_file

    root = CORPUS.parents[2]
    says: dict[tuple[str, ...], str] = {}
    for folder in ("scenarios", "tests/scenarios"):
        for path in sorted((root / folder).rglob("*.xml")):
            for el in parse_file(path).iter("say"):
                if text := el.get("text"):
                    says.setdefault(tuple("·" if w in _DEIXIS else w for w in _said(text)), str(path.relative_to(root)))
    return says


def test_no_held_out_row_is_a_line_a_scene_says():
    # A lane that fixes a failing scene reads its transcript; a held-out row a scene's user says word for word
    # would be tuned on unseen (review17 F1: 154 such rows were dropped on 28 Nov 2026, corpus README). Rows of
    # fewer than four heard words ("follow me") are everyday words every scene says and stay held out.
    says = _scene_says()
    shared = [(name, says[k]) for name in ALL_HELD_OUT for w, _ in _rows(name)
              if len(s := _said(w)) >= 4 and (k := tuple("·" if x in _DEIXIS else x for x in s)) in says]
    assert shared == [], "held-out rows a scene says (reword the scene's line or drop the row): " + repr(shared[:5])


@pytest.mark.parametrize("name", HELD_OUT)
def test_held_out_phrasings_are_understood_about_nine_times_in_ten(name):
    # heldout.tsv: 160/163 = 98.2 % when first measured (main before that work: 108/163 = 66.3 %);
    # heldout-2.tsv: 107/110 = 97.3 % when first run, 103/106 after 4 rows the users' bank uses were dropped;
    # heldout-3.tsv (lang5, committed before it was run): main 44c86f5 111/122 = 91.0 %, lang5 116/122 = 95.1 %;
    # heldout-4.tsv (lang6, committed before it was run): main b8ffc4b 22/60 = 36.7 %, lang6 54/60 = 90.0 %
    # (the README in the corpus folder)
    assert understood_share(_rows(name)) >= 0.9


def test_every_expected_frame_is_well_formed():
    for name in ("tuning.tsv", *ALL_HELD_OUT):
        for words, frame in _rows(name):
            if frame != "NOT_UNDERSTOOD":
                el = etree.fromstring(frame)
                assert el.tag == "SPEECH" and len(el) == 1, (name, words)
