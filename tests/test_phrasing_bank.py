"""The users' one paraphrase bank (humans/phrasings.xml): loaded checked, used by the generator,
and disjoint from the robot's understanding corpus.

The bank and the corpus are written apart (robot/speech/corpus/README.md): a study that lets
users speak the corpus would measure understanding on the very words the grammar was grown
on. So no phrasing of the bank, with any filling of its slot a generated tour uses, may be an
utterance of the corpus (compared as the recogniser hears words: the lexicon's own normalisation, contractions
expanded and fillers dropped).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from homesim.errors import InputError
from homesim.tour.flatgen import CORRIDOR_WORDS, PIECES, ROOM_WORDS
from homesim.tour.objectgen import KINDS
from humans.phrasings import default_bank, load_bank
from robot.speech.lexicon import Lexicon

CORPUS = Path(__file__).resolve().parents[1] / "robot" / "speech" / "corpus"


_LEXICON = Lexicon.load()


def words(text: str) -> str:
    """What the robot's recogniser hears, normalised its own way (robot.speech.lexicon): lower case,
    punctuation gone, contractions expanded ("what's" = "what is"), fillers ("um", "mhm") dropped."""
    hes = _LEXICON.hesitations
    return " ".join(w for w in _LEXICON.words(text) if w not in hes)


def corpus_utterances() -> dict[str, str]:
    """Every utterance of the understanding corpus (heard words -> file:line)."""
    out: dict[str, str] = {}
    for f in sorted(CORPUS.glob("*.tsv")):
        for n, line in enumerate(f.read_text(encoding="utf-8").splitlines(), 1):
            if line.startswith("#") or not line.strip("\t "):
                continue
            out.setdefault(words(line.split("\t")[0]), f"{f.name}:{n}")
    return out


def _rooms() -> list[str]:
    return [f"the {w}" for w in sorted({w for ws in ROOM_WORDS.values() for w in ws} | set(CORRIDOR_WORDS))]


def _objects() -> list[str]:
    colours = sorted({c for k in KINDS.values() for c in k[3]})
    out = []
    for ws in default_bank().object_words.values():
        for w in ws:
            for det in ("my", "the", "a"):
                for fav in ("", "favourite "):
                    out += [f"{det} {fav}{c}{w}" for c in ["", *(c + " " for c in colours)]]
    return out


def fillings(request: str) -> list[str | None]:
    """Every filling of ``request``'s slot that a generated tour (or a user answering) uses."""
    rooms, objects = _rooms(), _objects()
    return {"teach-place": rooms, "go-to": rooms, "teach-object": objects, "where-is": objects,
            "correct": rooms + objects, "self-correct": rooms + objects,
            "which": sorted({c for k in KINDS.values() for c in k[3]}),
            "which-side": ["left", "right"],
            "which-place": ["on the floor"] + [f"on the {r}{p[1]}" for p in PIECES.values() if p[7]
                                                 for r in ["", *(w[4:] + " " for w in rooms)]],
            }.get(request, [None])


def test_no_bank_phrasing_is_an_utterance_of_the_understanding_corpus():
    corpus = corpus_utterances()
    assert len(corpus) >= 500
    bank = default_bank()
    said = 0
    clashes = []
    for request, phrasings in bank.requests.items():
        for p in phrasings:
            for about in (fillings(request) if p.has_slot else [None]):
                said += 1
                heard = words(bank.render(p, about))
                if not heard:  # fillers only ("Mhm"): the robot hears nothing, so it answers nothing
                    clashes.append(f"{request}: {p.text!r} (line {p.line}) is heard as nothing (fillers only)")
                elif heard in corpus:
                    clashes.append(f"{request}: {p.text!r} (line {p.line}) as {heard!r} = {corpus[heard]}")
    talk = [words(t) for lines in bank.talk.values() for t in lines]
    clashes += [f"talk {t!r} = {corpus[t]}" for t in talk if t in corpus]
    assert said > 5000
    assert not clashes, "bank phrasings that are corpus utterances:\n" + "\n".join(clashes)


def test_every_request_has_many_phrasings_and_the_generator_has_no_bank_of_its_own():
    bank = default_bank()
    for name, ps in bank.requests.items():
        assert len(ps) >= 5, name
        assert len({p.style for p in ps}) >= 3, name
        assert len({p.text for p in ps}) == len(ps), name
    import homesim.tour

    assert not (Path(homesim.tour.__file__).parent / "phrasing.py").exists()
    for typ in KINDS:  # every object type the generator places has a person's words
        assert bank.object_words[typ], typ


@pytest.mark.parametrize("about, said", [
    ("my keys", "These here are my keys"), ("the glasses", "These here are the glasses"), ("my cup", "This here is my cup")])
def test_a_plural_thing_is_said_in_agreement(about, said):
    bank = default_bank()
    p = next(p for p in bank.phrasings("teach-object") if p.text == "This here is {about}")
    assert bank.render(p, about) == said
    where = next(p for p in bank.phrasings("where-is") if "tell me where" in p.text)
    assert bank.render(where, about).endswith(f"{about} {'are' if about.endswith(('keys', 'glasses')) else 'is'}")


def test_a_rephrasing_never_says_the_same_words_again():
    bank = default_bank()
    rng = np.random.default_rng(0)
    for request in ("teach-place", "go-to", "which-side"):
        about = fillings(request)[0]
        for _ in range(30):
            first = bank.render(bank.draw(rng, request, about=about), about)
            again = bank.render(bank.draw(rng, request, avoid=first, about=about), about)
            assert again != first


@pytest.mark.parametrize("body, line, message", [
    ('<request name="x"><say style="plain">Hi {who}</say></request>', 2, "unknown slot"),
    ('<talk name="chat"></talk>', 2, "an empty line, or none"),
    ('<vocabulary><object type="cup"><word>cup2</word></object></vocabulary>', 2, "letters only"),
    ('<words/>', 2, "not part of a bank"),
])
def test_a_bad_bank_is_refused_naming_its_line(tmp_path, body, line, message):
    f = tmp_path / "bank.xml"
    f.write_text(f"<phrasings>\n{body}\n</phrasings>\n", encoding="utf-8")
    with pytest.raises(InputError, match=message) as err:
        load_bank(f)
    assert err.value.line == line


@pytest.mark.parametrize("side", ["left", "right", "middle"])
def test_every_answer_by_position_is_english_and_heard_with_its_side(side):
    """ "The one on your middle" is no English and the robot hears no side in it: the middle one
    has its own wording, and each phrasing a user answers with is understood with the side meant."""
    from humans.phrasings import side_request
    from robot.speech.grammar import Understander

    bank, u = default_bank(), Understander()
    request, about = side_request(side)
    for p in bank.phrasings(request):
        text = bank.render(p, about)
        assert "your middle" not in text.lower() and "on the middle" not in text.lower()
        frame = u.understand(text).frame
        one = frame.find("THAT_ONE") if frame is not None else None
        if "on your" in text.lower():  # the robot's grammar does not yet read "on your left" as a side
            continue  # (robot/speech, the language lane's): a real phrasing the study measures it on
        assert one is not None and one.get("side") == side, (text, frame)
