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
ALL_HELD_OUT = (*HELD_OUT, "heldout-5.tsv")


def test_the_corpus_has_500_utterances_and_a_fifth_held_out():
    tuning, held = _rows("tuning.tsv"), [r for name in ALL_HELD_OUT for r in _rows(name)]
    assert len(tuning) + len(held) >= 500
    assert len(held) / (len(tuning) + len(held)) >= 0.2


def test_the_held_out_slices_share_no_utterance_with_the_tuning_part_or_each_other():
    words = [{w for w, _ in _rows(name)} for name in ("tuning.tsv", *ALL_HELD_OUT)]
    assert sum(map(len, words)) == len(set().union(*words))


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
