"""A thing the camera saw as what she named only once in a look is never stored as it (obj19).

fresh8/terr_twin_cups_nonnative seeds 6, 9: no gesture seen for "this kettle"; the look's first
frames, caught while the camera still turned away from the kitchen table, held a white cup once
detected as a "kettle": that one detection was the only candidate of the named type and was stored
as the kettle 1.9 m from the real one (teaching precision 0.5)."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from robot.objects.attention import GLIMPSE, evidence, without_glimpses
from robot.objects.resolve import Candidate, Wanted, resolve

KETTLE = Wanted(type="kettle", name="kettle")
WHITE = (0.95, 0.95, 0.95)


def cand(x: float, y: float, types: dict[str, int]) -> Candidate:
    c = Candidate(x, y, 0.8)
    for t, k in types.items():
        for _ in range(k):
            c.add(t, x, y, 0.8, WHITE)
    return c


def test_one_kettle_detection_of_a_cup_is_not_the_kettle():
    cands = [cand(16.0, 2.4, {"kettle": 1}), cand(15.75, 2.4, {"cup": 1})]
    assert resolve(cands, KETTLE, None, (14.6, 3.4)).kind == "one"  # what the robot did before
    assert without_glimpses(resolve(cands, KETTLE, None, (14.6, 3.4)), cands, KETTLE, None, (14.6, 3.4)).kind == "none"


def test_a_cup_seen_once_as_kettle_and_once_as_cup_is_not_the_kettle():
    cands = [cand(15.74, 2.53, {"cup": 1, "kettle": 1})]
    res = resolve(cands, KETTLE, None, (14.6, 3.4))
    assert res.kind == "one" and without_glimpses(res, cands, KETTLE, None, (14.6, 3.4)).kind == "none"


def test_the_real_kettle_beside_a_glimpse_is_still_found():
    real = cand(15.2, 0.4, {"kettle": 6, "cup": 1})
    cands = [real, cand(13.0, 0.4, {"cup": 9})]
    res = without_glimpses(resolve(cands, KETTLE, None, (14.6, 3.4)), cands, KETTLE, None, (14.6, 3.4))
    assert res.kind == "one" and res.best is real
    # a glimpse beside it: never stored; asking between them (ambiguous) is left as it is
    cands = [cand(16.0, 2.4, {"kettle": 1}), real]
    res = without_glimpses(resolve(cands, KETTLE, None, (14.6, 3.4)), cands, KETTLE, None, (14.6, 3.4))
    assert not (res.kind == "one" and res.best is not real)


@settings(max_examples=60, deadline=None)
@given(named=st.integers(0, 12), other=st.integers(0, 12), x=st.floats(14.0, 17.0), y=st.floats(0.2, 4.8),
       said=st.sampled_from([KETTLE, Wanted()]))
def test_what_is_stored_was_seen_as_the_thing_named_at_least_twice(named, other, x, y, said):
    types = {k: v for k, v in (("kettle", named), ("cup", other)) if v}
    if not types:
        return
    cands = [cand(x, y, types)]
    res = without_glimpses(resolve(cands, said, None, (14.6, 3.4)), cands, said, None, (14.6, 3.4))
    if res.kind == "one":
        assert evidence(res.best, said) >= GLIMPSE
    # enough evidence of the thing named and nothing else: it stays found
    if named >= GLIMPSE and other == 0:
        assert res.kind == "one"


# ---- whose it is, said in the which-one answer (obj18's corr_nonnative_books seed 4)

def test_an_owner_said_again_in_the_which_one_answer_goes_to_the_object_attention():
    """"This red book is mine" heard without "mine" ("Is this the red book?" - yes), then said again
    whole, pointing, as the answer to "the book on the left or the one on the right?": the answer the
    object attention gets carries her OWNER with the deixis, and reads as hers."""
    from lxml import etree

    from robot.dialog.module import unchosen_answer
    from robot.objects.attention import wanted_from

    said = etree.fromstring('<OBJECT type="book"><GESTURE val="probably_pointing"/><TITLE name="book"/>'
                            '<COLOUR name="red"/><OWNER name="speaker"/></OBJECT>')
    ans = unchosen_answer(said)
    assert ans.get("deixis") == "true" and ans.find("OWNER").get("name") == "speaker"
    assert wanted_from(ans).owner == "partner"
    # said again without an owner: none is made up
    bare = etree.fromstring('<OBJECT type="book"><GESTURE val="probably_pointing"/><TITLE name="book"/></OBJECT>')
    assert unchosen_answer(bare).find("OWNER") is None and wanted_from(unchosen_answer(bare)).owner == ""
