"""Questions about what she shows, rooms she names, and everyday forms (issue 26 items 6-8, lang7).

- "Is this the kitchen?", "is that my cup?": in a home tour the user shows and names her home; a
  question naming what she shows asks the robot to take that name up. It is understood as the
  statement it asks about ("this is the kitchen"), at half the coverage, so the dialog confirms it
  before anything is stored ("Is this the kitchen?" - "yes"). Questions about the robot's own things
  ("is this your cup", "are these keys yours") teach nothing (docs/semantics.md §4).
- A room she names with a noun, a use, a colour or a word the lexicon lacks before "room" ("the
  craft room", "my sewing room", "the blue room") is a place in her words; "a lovely room" is a remark.
- Everyday forms: "that red thing is my backpack", "right, [so→that] this room is the living room".
"""

from __future__ import annotations

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from lxml import etree

from robot.dialog.loader import load
from robot.dialog.manager import DialogManager, Say, Send
from robot.speech.lexicon import Lexicon
from robot.speech.module import frame_message, shared_understander

LEX = Lexicon.load()
#: single-word places and objects of the lexicon (the grammar's own word classes)
PLACES = sorted(k[0] for k, (t, _) in LEX.entries.items() if t == "PLACE" and len(k) == 1)
OBJECTS = sorted(k[0] for k, (t, _) in LEX.entries.items() if t == "OBJ" and len(k) == 1)


def frame(words: str) -> str | None:
    f = shared_understander().understand(words).frame
    return None if f is None else etree.tostring(f, encoding="unicode")


def _placed(statement: str) -> bool:
    """Whether ``statement`` is understood whole as a place or object teaching."""
    u = shared_understander().understand(statement)
    return u.frame is not None and not u.partial and u.act in ("PLACE", "OBJECT")


# ------------------------------------------------------------------ questions about what she shows
@pytest.mark.parametrize("question, statement", [
    ("is this the kitchen", "this is the kitchen"),
    ("is that the bathroom", "that is the bathroom"),
    ("is it the living room", "it is the living room"),
    ("is this room the study", "this room is the study"),
    ("is this my cup", "this is my cup"),
    ("is that the red book", "that is the red book"),
    ("are these my glasses", "these are my glasses"),
    ("is this the bathroom, right?", "this is the bathroom"),  # a tag asks for the same yes
    ("uh, is it, is this the bedroom", "this is the bedroom"),  # the question said again
])
def test_a_question_naming_what_she_shows_is_the_statement_it_asks_about(question, statement):
    # on main 2e607e0 every one of these was "a question, not a request or a teaching": not understood
    assert frame(question) == frame(statement) is not None
    asked, said = shared_understander().understand(question), shared_understander().understand(statement)
    assert asked.coverage <= 0.5 * said.coverage  # confirmed before anything is stored


@given(deixis=st.sampled_from(["this", "that", "it"]), det=st.sampled_from(["the", "my", "our"]),
       place=st.sampled_from(PLACES))
@settings(max_examples=60, deadline=None)
@example(deixis="this", det="the", place="kitchen")
def test_any_question_about_a_place_gives_the_place_at_half_the_coverage_at_most(deixis, det, place):
    statement = f"{deixis} is {det} {place}"
    if not _placed(statement):
        return  # the statement itself is not a whole teaching ("this is the corner"): nothing to ask about
    u = shared_understander().understand(f"is {deixis} {det} {place}")
    assert u.frame is not None and etree.tostring(u.frame) == etree.tostring(
        shared_understander().understand(statement).frame)
    assert u.coverage <= 0.5


@given(obj=st.sampled_from(OBJECTS), how=st.sampled_from(["is this your {}", "is that your {}", "are these {}s yours",
                                                          "is this {} yours"]))
@settings(max_examples=60, deadline=None)
def test_a_question_about_the_robots_own_things_teaches_nothing(obj, how):
    u = shared_understander().understand(how.format(obj))
    assert u.act not in ("OBJECT", "PLACE", "FOLLOW", "STOP", "WAIT", "GOTO")


@pytest.mark.parametrize("words", ["is this the", "is this my", "is it", "is this with me", "is that mine"])
def test_a_question_naming_nothing_is_still_not_understood(words):
    assert frame(words) is None


def test_a_question_about_the_room_is_confirmed_then_taught():
    dm = DialogManager(load())
    dm.es_state = "Interacting"
    u = shared_understander().understand("is this the kitchen")
    out = dm.on_frame(frame_message(u, 1.0, 2.0, 0.9))  # even heard well: a question is confirmed
    assert [o.text for o in out if isinstance(o, Say)] == ["Is this the kitchen?"]
    assert not [o for o in out if isinstance(o, Send)]
    out = dm.on_frame(frame_message(shared_understander().understand("yes"), 3.0, 4.0, 0.9))
    (sent,) = [o for o in out if isinstance(o, Send)]
    assert sent.event == "place_teaching"


def test_her_question_said_back_to_the_robots_own_confirms_it():
    dm = DialogManager(load())
    dm.es_state = "Interacting"
    out = dm.on_frame(frame_message(shared_understander().understand("this is the kitchen"), 1.0, 2.0, 0.3))
    assert [o.text for o in out if isinstance(o, Say)] == ["Is this the kitchen?"]
    out = dm.on_frame(frame_message(shared_understander().understand("is this the kitchen"), 3.0, 4.0, 0.9))
    assert [o.event for o in out if isinstance(o, Send)] == ["place_teaching"]


# ------------------------------------------------------------------ rooms she names
@given(word=st.sampled_from(OBJECTS + ["craft", "boot", "powder", "sewing", "games", "blue"]),
       det=st.sampled_from(["the", "my", "our", "anna's"]))
@settings(max_examples=80, deadline=None)
@example(word="drawing", det="the")
def test_a_word_before_room_after_an_article_names_a_room_in_her_words(word, det):
    u = shared_understander().understand(f"this is {det} {word} room")
    if word in LEX.hesitations or (word,) in LEX.entries and LEX.entries[(word,)][0] not in ("OBJ", "USE", "COLOUR"):
        return  # a filler or another word class ("the living room" is a phrase of its own)
    assert u.act == "PLACE"
    assert u.frame[0].find("TITLE").get("name") == f"{word} room"


@pytest.mark.parametrize("words, title", [("this is the study room", "study room"),
                                          ("this is the reading room", "reading room"),
                                          ("here is my sleeping room", "sleeping room"),
                                          ("go to the drawing room", "drawing room"),
                                          ("this is the room of my daughter", "room")])
def test_the_room_keeps_the_words_she_said(words, title):
    assert shared_understander().understand(words).frame.find(".//TITLE").get("name") == title


@pytest.mark.parametrize("words", ["this is a lovely room", "this is a big room", "what a nice room"])
def test_a_remark_about_the_room_teaches_nothing(words):
    assert frame(words) is None


# ------------------------------------------------------------------ everyday forms
@pytest.mark.parametrize("words, expected", [
    ("that red thing is my backpack", '<OBJECT type="bag"><GESTURE val="probably_pointing"/><TITLE name="backpack"/>'
                                      '<OWNER name="speaker"/><COLOUR name="red"/></OBJECT>'),
    ("this one is my bedroom", '<PLACE><TITLE name="bedroom"/><OWNER name="speaker"/></PLACE>'),
    ("you are in the kitchen now", '<PLACE><TITLE name="kitchen"/></PLACE>'),
    ("that is the lamp of my wife", '<OBJECT type="lamp"><GESTURE val="probably_pointing"/><TITLE name="lamp"/>'
                                    '<OWNER name="wife"/></OBJECT>'),
    ("by the way do you know where my kettle is", '<WHERE><OBJECT type="kettle"><TITLE name="kettle"/>'
                                                  '<OWNER name="speaker"/></OBJECT></WHERE>'),
    ("you follow me now", "<FOLLOW/>"),
    ("that is exactly right", "<YES/>"),
    ("that's wrong", "<NO/>"),
    ("left", '<THAT_ONE side="left"/>'),
    ("where could my cup be", '<WHERE><OBJECT type="cup"><TITLE name="cup"/><OWNER name="speaker"/></OBJECT></WHERE>'),
])
def test_everyday_forms(words, expected):
    assert frame(words) == f"<SPEECH>{expected}</SPEECH>"


def test_a_misheard_word_after_an_answer_does_not_hide_the_statement_after_it():
    # hall_everyday seed 0: "Right, so this room here is the living room" heard as "right that this room is the
    # living room" was a plain yes; the rest is a whole statement of its own
    u = shared_understander().understand("right that this room is the living room")
    assert u.act == "PLACE" and u.answer == "yes" and u.partial


@pytest.mark.parametrize("words", ["you kitchen", "you come i show you kitchen"])
def test_you_alone_before_a_place_teaches_nothing(words):
    assert shared_understander().understand(words).act != "PLACE"


_WORDS = ["the", "my", "a", "kitchen", "cup", "red", "here", "there", "one", "room", "go", "to", "follow", "me", "stop",
          "your", "yours", "mine", "right", "yes", "is", "this", "where", "study", "favourite", "of", "anna's"]


@given(lead=st.sampled_from(["is this", "is that", "is it", "are these", "are those"]),
       rest=st.lists(st.sampled_from(_WORDS), min_size=0, max_size=6))
@settings(max_examples=300, deadline=None)
@example(lead="is this", rest=["the", "kitchen"])
def test_a_question_is_never_a_command_and_a_teaching_it_names_is_always_confirmed(lead, rest):
    u = shared_understander().understand(" ".join([lead, *rest]))
    assert u.act not in ("FOLLOW", "STOP", "WAIT", "GOTO")
    if u.act in ("PLACE", "OBJECT"):
        assert u.coverage <= 0.5  # below the dialog's confirm-below (0.5) at any recogniser confidence short of 1


@pytest.mark.parametrize("words, title", [("no no is bathroom", "bathroom"), ("no, is my cup", "cup")])
def test_a_correction_with_its_this_lost_is_a_guess_to_confirm(words, title):
    u = shared_understander().understand(words)  # on main 2e607e0: a plain no
    assert u.answer == "no" and u.frame.find(".//TITLE").get("name") == title and u.coverage <= 0.5


@pytest.mark.parametrize("words", ["this is the room", "this is the uh room", "uh is the room", "this the the uh room"])
def test_a_room_whose_name_was_lost_is_a_place_without_a_name(words):
    # studio_confirm_repeat seeds 7 and 9: "This is the living room" heard as "this is the room": on main not
    # understood ("say that again"); a place with no name makes the dialog ask "Which room is this?"
    u = shared_understander().understand(words)
    assert u.act == "PLACE" and u.frame[0].find("TITLE") is None and u.partial


def test_which_room_is_asked_when_the_name_was_lost():
    dm = DialogManager(load())
    dm.es_state = "Interacting"
    out = dm.on_frame(frame_message(shared_understander().understand("this is the room"), 1.0, 2.0, 0.8))
    assert [o.text for o in out if isinstance(o, Say)] == ["Which room is this?"]


@pytest.mark.parametrize("words", ["the room is the kitchen", "the room here is the kitchen"])
def test_the_room_before_its_name_still_names_it(words):
    assert shared_understander().understand(words).frame.find(".//TITLE").get("name") == "kitchen"


@pytest.mark.parametrize("words, title", [("where is uh kettle sorry the bowl", "bowl"),
                                          ("this is kitchen sorry the bathroom", "bathroom"),
                                          ("go to kitchen sorry the bathroom", "bathroom")])
def test_a_repair_replaces_the_noun_phrase_even_when_its_article_was_lost(words, title):
    # lang_everyday seed 1: "Where is the kettle, sorry, the bowl" heard as "where is uh kettle sorry the bowl" kept
    # the kettle on main 2e607e0 (no article to align the repair's "the" with)
    assert shared_understander().understand(words).frame.find(".//TITLE").get("name") == title
