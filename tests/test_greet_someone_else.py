"""A hello to someone else by name is no sure greeting for the robot (review17 F7): the words that go with a greeting
("how are you doing", "nice to meet you") raise a greeting's coverage when it names the robot or no one, never when
the hello names someone the robot does not know; then the coverage stays below the dialog's confirm-below, so it asks
("Did you say hello to me?") instead of greeting a phone call."""
import pytest

from robot.speech.grammar import Understander

CONFIRM_BELOW = 0.5  # robot/dialog/biron-dialogs.xml


@pytest.fixture(scope="module")
def u():
    return Understander()


@pytest.mark.parametrize("text", ["hi sara how are you doing", "hello sara, nice to meet you", "hey mum how are you"])
def test_hello_to_someone_else_by_name_is_unsure(u, text):
    r = u.understand(text)
    assert r.act != "GREETING" or r.coverage < CONFIRM_BELOW, (text, r.act, r.coverage)


@pytest.mark.parametrize("text", ["nice to meet you biron", "hello biron, how are you", "hello biron nice to meet you",
                                  "hi, how are you"])
def test_greeting_the_robot_with_such_words_is_sure(u, text):
    r = u.understand(text)
    assert r.act == "GREETING" and r.coverage >= CONFIRM_BELOW, (text, r.act, r.coverage)
