"""An answer that says whose with "his", "her" or "their" keeps the owner the question named (long22).

tests/scenarios/perceive/hall_hub_long_tour.xml seed 0 on main 89146ce: "The green cup on the table is my
husband's" - "Is this your husband's green cup?" - "Yes, his cup" - "OK, I have learned His's green cup.", the
cup stored with the owner "his". Frames come from the real understanding (as test_dialog_confirm.py).
"""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from robot.dialog.manager import DialogManager
from tests.test_dialog_confirm import DOC, LOW, heard, says, sends


@pytest.fixture
def dm() -> DialogManager:
    m = DialogManager(DOC)
    m.es_state = "Interacting"
    return m


@pytest.mark.parametrize(("said", "question", "answer"), [
    ("the green cup on the table is my husband's", "Is this your husband's green cup?", "yes his cup"),
    ("this is my daughter's book", "Is this your daughter's book?", "yes her book"),
    ("that is my parents' radio", None, "yes their radio"),
])
def test_a_pronoun_in_the_answer_keeps_the_owner_named(dm, said, question, answer):
    asked = says(dm.on_frame(heard(said, LOW)))
    if question is not None:
        assert asked == [question]
    named = dm.top.slots["object"].value.find("OWNER").get("name")
    (s,) = sends(dm.on_frame(heard(answer)))
    owners = [o.get("name") for o in s.children[0].iter("OWNER")]
    assert owners == [named]
    assert not set(owners) & {"his", "her", "their"}


def test_an_answer_naming_another_owner_still_corrects_it(dm):
    dm.on_frame(heard("the green cup on the table is my husband's", LOW))
    (s,) = sends(dm.on_frame(heard("yes my daughter's cup")))
    assert [o.get("name") for o in s.children[0].iter("OWNER")] == ["daughter"]


@pytest.mark.parametrize("answer", ["yes his cup", "yes her cup", "yes their cup"])
def test_a_pronoun_answer_to_a_question_that_named_no_owner_stores_no_owner(dm, answer):
    """review22 R6: "Is this the green cup?" - "yes his cup" stored the owner "his" ("His's green cup")."""
    asked = says(dm.on_frame(heard("the green cup on the table", LOW)))
    assert asked and "your" not in asked[0]
    (s,) = sends(dm.on_frame(heard(answer)))
    assert [o.get("name") for o in s.children[0].iter("OWNER")] == []


@pytest.mark.parametrize(("said", "named"), [("the green cup on the table", None),
                                             ("the green cup on the table is my husband's", "husband"),
                                             ("this is my daughter's book", "daughter")])
@pytest.mark.parametrize("pronoun", ["his", "her", "their"])
def test_a_pronoun_in_a_correction_refers_to_the_owner_asked_about_or_to_none(dm, said, named, pronoun):
    """review22 R6, the correction: "Is this the green cup?" - "no, his mug" stored the mug as "his" (the corrected
    value replaced the old one whole); a pronoun names nobody: the owner the question named, else none."""
    dm.on_frame(heard(said, LOW))
    (s,) = sends(dm.on_frame(heard(f"no {pronoun} mug")))
    assert s.children[0].find("OBJECT/TITLE").get("name") == "mug"
    assert [o.get("name") for o in s.children[0].iter("OWNER")] == ([named] if named else [])


@pytest.mark.parametrize("pronoun", ["his", "her", "their"])
def test_a_pronoun_owner_said_unprompted_is_no_owner_name(dm, pronoun):
    """"This is his cup" with nobody named before: stored without owner, and never said back as "His's cup"."""
    (s,) = sends(dm.on_frame(heard(f"this is {pronoun} cup")))
    assert [o.get("name") for o in s.children[0].iter("OWNER")] == []
    dm2 = DialogManager(DOC)
    dm2.es_state = "Interacting"
    asked = says(dm2.on_frame(heard(f"this is {pronoun} cup", LOW)))
    assert asked == ["Is this the cup?"]


_OWNERS = ["my", "my husband's", "our", "the", "his", "her", "their"]
_THINGS = ["cup", "green cup", "book", "radio", "mug"]


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(st.sampled_from(["this is {o} {t}", "yes {o} {t}", "no {o} {t}", "{o} {t}", "yes", "no"]),
                          st.sampled_from(_OWNERS), st.sampled_from(_THINGS), st.sampled_from([0.3, 0.9])),
                min_size=1, max_size=4))
def test_no_owner_sent_is_ever_a_pronoun(turns):
    """Whatever she says and however well it is heard, no teaching the dialog sends names "his", "her" or "their" as
    an owner (review22 R6: a pronoun refers to an owner, it is none)."""
    m = DialogManager(DOC)
    m.es_state = "Interacting"
    for form, owner, thing, conf in turns:
        for s in sends(m.on_frame(heard(form.format(o=owner, t=thing), conf))):
            for c in s.children:
                assert not {(o.get("name") or "").lower() for o in c.iter("OWNER")} & {"his", "her", "their"}, (turns, s)
