"""An answer that says whose with "his", "her" or "their" keeps the owner the question named (long22).

tests/scenarios/perceive/hall_hub_long_tour.xml seed 0 on main 89146ce: "The green cup on the table is my
husband's" - "Is this your husband's green cup?" - "Yes, his cup" - "OK, I have learned His's green cup.", the
cup stored with the owner "his". Frames come from the real understanding (as test_dialog_confirm.py).
"""

from __future__ import annotations

import pytest

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
