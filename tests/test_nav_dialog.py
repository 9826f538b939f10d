"""What the robot says about navigation failures and module failures (the dialog's conditions)."""

from __future__ import annotations

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


def test_a_module_being_restarted_needs_no_technician_one_that_cannot_be_does():
    restarting = _dm().on_condition(cond("technical_failure", '<param name="module">player</param>',
                                         '<param name="still_failed">1</param>', '<param name="restarting">true</param>'))
    assert says(restarting) == ["My player stopped working. One moment please, I am restarting it."]
    down = _dm().on_condition(cond("technical_failure", '<param name="module">laser</param>',
                                   '<param name="still_failed">1</param>', '<param name="restarting">false</param>'))
    assert says(down) == ["I have a technical problem: my laser does not respond. Please call technical support."]
