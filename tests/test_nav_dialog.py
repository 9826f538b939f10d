"""What the robot says about navigation failures and module failures (the dialog's conditions)."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from robot.dialog.manager import DialogManager
from tests.test_dialog_manager import DOC, cond, says


def _dm() -> DialogManager:
    m = DialogManager(DOC)
    m.es_state = "AskingForHelp"
    return m


def test_a_blocked_way_asks_for_help_naming_the_place():
    out = _dm().on_condition(cond("need_help", '<param name="reason">blocked</param>',
                                  '<param name="goal"><PLACE><TITLE name="kitchen"/></PLACE></param>'))
    assert says(out) == ["Could you please help me? I cannot get to the kitchen."]


def test_without_a_goal_the_help_request_is_general():
    out = _dm().on_condition(cond("need_help", '<param name="reason">blocked</param>', '<param name="goal"/>'))
    assert says(out) == ["I could not get there. Can somebody help me, please?"]


@settings(max_examples=30, deadline=None)
@given(st.lists(st.sampled_from(["front", "room", "snug", "scullery", "study", "bedroom", "my", "garage", "den"]),
                min_size=1, max_size=3).map(" ".join))
def test_an_unknown_place_is_named_and_the_talk_goes_on(name):
    # a go-to to a place it was never shown (or a misheard name): nobody can help, it tells her which
    # place it does not know and how to go on; it never calls for help (fresh5/row_phone_between)
    m = DialogManager(DOC)
    m.es_state = "Interacting"
    out = says(m.on_condition(cond("unknown_place", f'<param name="goal"><PLACE><TITLE name="{name}"/></PLACE></param>')))
    # and offers to be shown it (tests/test_unknown_place_offer.py)
    assert out == [f"Sorry, I do not know where the {name} is.", "Shall I follow you there?"]
    assert not any("help" in line for line in out)


def test_a_module_being_restarted_needs_no_technician_one_that_cannot_be_does():
    restarting = _dm().on_condition(cond("technical_failure", '<param name="module">player</param>',
                                         '<param name="still_failed">1</param>', '<param name="restarting">true</param>'))
    assert says(restarting) == ["My player stopped working. One moment please, I am restarting it."]
    down = _dm().on_condition(cond("technical_failure", '<param name="module">laser</param>',
                                   '<param name="still_failed">1</param>', '<param name="restarting">false</param>'))
    assert says(down) == ["I have a technical problem: my laser does not respond. Please call technical support."]
