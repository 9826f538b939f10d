"""Confirmations that do not loop, corrections, the user's words as names (issue 26 items 6 and 7).

Frames come from the real understanding (words -> frame message), so these tests
follow what a user says, not hand-written XML.
"""

from __future__ import annotations

from collections import Counter

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from lxml import etree

from robot.dialog.loader import load
from robot.dialog.manager import MAX_SAME_QUESTION, DialogManager, Say, Send
from robot.speech.module import frame_message, shared_understander

DOC = load()


def heard(words: str, confidence: float = 0.9, start: float = 1.0) -> etree._Element:
    """What the understanding publishes for ``words`` heard with ``confidence``."""
    return frame_message(shared_understander().understand(words), start, start + 1.0, confidence)


def says(outs) -> list[str]:
    return [o.text for o in outs if isinstance(o, Say)]


def sends(outs) -> list[Send]:
    return [o for o in outs if isinstance(o, Send)]


@pytest.fixture
def dm() -> DialogManager:
    m = DialogManager(DOC)
    m.es_state = "Interacting"
    return m


LOW = 0.3  # below the document's confirm-below: the robot confirms


# ------------------------------------------------------------------ confirmations
@pytest.mark.parametrize("answer", ["yes", "right", "sure", "that's right", "exactly", "yes please", "of course",
                                    "yeah go ahead", "okay", "yes you can", "absolutely"])
def test_yes_and_its_everyday_variants_confirm(dm, answer):
    assert says(dm.on_frame(heard("follow me", LOW))) == ["Shall I follow you?"]
    (s,) = sends(dm.on_frame(heard(answer)))
    assert s.event == "follow"


@pytest.mark.parametrize("again", ["follow me", "could you follow me please", "come with me", "please follow me biron",
                                   "yes follow me", "walk with me"])
def test_a_repetition_or_paraphrase_of_the_request_confirms_it_even_heard_badly(dm, again):
    assert says(dm.on_frame(heard("follow me", LOW))) == ["Shall I follow you?"]
    out = dm.on_frame(heard(again, LOW))  # two hearings agree: no third question
    (s,) = sends(out)
    assert s.event == "follow" and says(out) == []
    assert dm.summary()["confirmed_by_repetition"] == 1


def test_place_confirmed_by_saying_it_again(dm):
    assert says(dm.on_frame(heard("this is the living room", LOW))) == ["Is this the living room?"]
    (s,) = sends(dm.on_frame(heard("yes this is the living room", LOW)))
    assert s.event == "place_teaching" and s.children[0].find("PLACE/TITLE").get("name") == "living room"


@pytest.mark.parametrize("correction", ["no, the kitchen", "no this is the kitchen", "the kitchen", "this is the kitchen"])
def test_a_correction_replaces_what_was_heard(dm, correction):
    assert says(dm.on_frame(heard("this is the living room", LOW))) == ["Is this the living room?"]
    (s,) = sends(dm.on_frame(heard(correction)))
    assert s.event == "place_teaching" and s.children[0].find("PLACE/TITLE").get("name") == "kitchen"


@pytest.mark.parametrize("statement", ["this is the kitchen", "no, this is the kitchen", "we are in the kitchen",
                                       "here we have the kitchen", "is the kitchen", "this room is the kitchen"])
def test_a_place_taught_while_a_misheard_goto_is_confirmed_is_taught_not_driven_to(dm, statement):
    # she said "this is the kitchen", the recogniser heard "to the kitchen": the robot asks
    # "Shall I go to the kitchen?" and she says it again. The same room is no repetition of the
    # go-to: a whole statement teaches the room (it drove off to the kitchen before)
    assert says(dm.on_frame(heard("to the kitchen", LOW))) == ["Shall I go to the kitchen?"]
    out = dm.on_frame(heard(statement))
    (s,) = sends(out)
    assert s.event == "place_teaching" and s.children[0].find("PLACE/TITLE").get("name") == "kitchen"
    assert says(out) == ["OK, I will stay here."]
    assert dm.summary()["confirmed_by_repetition"] == 0


def _corpus(acts: tuple[str, ...]) -> list[str]:
    from pathlib import Path

    rows = (Path(__file__).resolve().parents[1] / "robot" / "speech" / "corpus" / "tuning.tsv").read_text().splitlines()
    u = shared_understander()
    out = []
    for line in rows:
        if line.startswith("#") or not line.strip():
            continue
        words = line.split("\t")[0]
        r = u.understand(words)
        if r.act in acts and not r.answer:
            out.append(words)
    return out


STATEMENTS = [w for w in _corpus(("PLACE",)) if not shared_understander().understand(w).fragment]


@settings(max_examples=40, deadline=None)
@given(st.sampled_from(STATEMENTS), st.sampled_from([0.3, 0.6, 0.95]))
def test_no_place_statement_ever_confirms_a_goto(statement, conf):
    """Whatever words teach a room, said to "Shall I go to ...?", the robot does not drive: it teaches
    (or asks about) the room."""
    m = DialogManager(DOC)
    m.es_state = "Interacting"
    m.on_frame(heard("to the kitchen", LOW))
    out = m.on_frame(heard(statement, conf))
    assert all(s.event != "goto" for s in sends(out))
    assert m.summary()["confirmed_by_repetition"] == 0


@pytest.mark.parametrize("conf", [0.6, 0.8, 0.95])
def test_an_object_shown_with_its_this_lost_is_confirmed_never_taught_unasked(dm, conf):
    # "[this] is my cup" or "[where] is my cup": the robot asks before it stores anything
    out = dm.on_frame(heard("is my cup", conf))
    assert sends(out) == [] and says(out) == ["Is this your cup?"]
    long = DialogManager(DOC)
    long.es_state = "Interacting"
    assert says(long.on_frame(heard("is my favourite blue cup", conf))) == ["Is this your favourite blue cup?"]
    (s,) = sends(dm.on_frame(heard("yes")))
    assert s.event == "object_teaching"
    dm2 = DialogManager(DOC)
    dm2.es_state = "Interacting"
    dm2.on_frame(heard("is my cup", conf))
    (w,) = sends(dm2.on_frame(heard("no, where is my cup")))
    assert w.event == "query_object"


def test_a_place_statement_that_closes_a_goto_answers_the_teaching_question_below_it(dm):
    # lang_preamble seed 4: "Is this the study?" - (her repetition heard as a go-to) "Shall I go to
    # the study?" - "this is my study": the go-to is declined and the study confirmed, not asked
    # about twice more ("Is this the study? Is this the study?") and lost
    assert says(dm.on_frame(heard("this is my study", LOW))) == ["Is this the study?"]
    assert says(dm.on_frame(heard("to the study", LOW))) == ["Shall I go to the study?"]
    out = dm.on_frame(heard("this is my study", LOW))
    (s,) = sends(out)
    assert s.event == "place_teaching" and s.children[0].find("PLACE/TITLE").get("name") == "study"
    assert says(out) == ["OK, I will stay here."]


@pytest.mark.parametrize("answer", ["the kitchen", "kitchen", "yes the kitchen", "go to the kitchen",
                                    "to the kitchen please", "yes"])
def test_the_goal_alone_or_the_request_again_confirms_the_goto(dm, answer):
    assert says(dm.on_frame(heard("to the kitchen", LOW))) == ["Shall I go to the kitchen?"]
    (s,) = sends(dm.on_frame(heard(answer)))
    assert s.event == "goto" and s.children[0].find("PLACE/TITLE").get("name") == "kitchen"


@pytest.mark.parametrize("words,question", [("the study has a view", "Is this the study?"), ("the garden looks great", "Is this the garden?"),
                                            ("my cup over there", "Is this your cup?")])
def test_a_noun_phrase_said_unprompted_with_words_left_over_is_asked_about_first(dm, words, question):
    # "the study, go" taught the study where the robot stood, at full confidence (the grammar now
    # reads it as a go-to, the goal said first): a noun phrase with words the grammar could not use
    # says what, not what to do with it
    out = dm.on_frame(heard(words, 0.95))
    assert sends(out) == [] and says(out) == [question]
    (s,) = sends(dm.on_frame(heard("yes")))
    assert s.event in ("place_teaching", "object_teaching")


def test_a_clean_noun_phrase_is_taken_as_before(dm):
    # "this is the kitchen" often reaches the dialog as "the kitchen" (the recogniser drops short words)
    (s,) = sends(dm.on_frame(heard("the kitchen", 0.95)))
    assert s.event == "place_teaching"


def test_no_then_the_robot_asks_for_the_right_name(dm):
    dm.on_frame(heard("this is the living room", LOW))
    assert says(dm.on_frame(heard("no"))) == ["Sorry.", "Which room is this?"]
    (s,) = sends(dm.on_frame(heard("the dining room")))
    assert s.children[0].find("PLACE/TITLE").get("name") == "dining room"


def test_no_with_the_same_words_is_a_no(dm):
    dm.on_frame(heard("this is the living room", LOW))
    assert says(dm.on_frame(heard("no the living room"))) == ["Sorry.", "Which room is this?"]


def test_no_and_another_request_answers_then_does_the_request(dm):
    assert says(dm.on_frame(heard("follow me", LOW))) == ["Shall I follow you?"]
    out = dm.on_frame(heard("no, go to the kitchen"))
    assert "OK, I will stay here." in says(out)
    (s,) = sends(out)
    assert s.event == "goto" and s.children[0].find("PLACE/TITLE").get("name") == "kitchen"
    assert [i.d.id for i in dm.stack] == ["goto"]


def test_no_to_a_goto_confirmation_with_another_room_goes_there(dm):
    assert says(dm.on_frame(heard("go to the kitchen", LOW))) == ["Shall I go to the kitchen?"]
    (s,) = sends(dm.on_frame(heard("no, to the bedroom")))
    assert s.event == "goto" and s.children[0].find("PLACE/TITLE").get("name") == "bedroom"


def test_the_same_question_is_never_asked_a_third_time(dm):
    assert says(dm.on_frame(heard("this is the kitchen", LOW))) == ["Is this the kitchen?"]
    out = dm.on_frame(heard("blah blurb"))
    assert says(out)[-1] == "Is this the kitchen?"
    out = dm.on_frame(heard("blah blurb"))
    assert says(out) == ["Sorry, let us leave that for now."] and dm.stack == []


def test_the_same_confirmation_after_an_interruption_counts_too(dm):
    dm.on_frame(heard("this is the kitchen", LOW))
    dm.on_frame(heard("what can you do"))  # interrupts; the question comes again on resumption
    # (the Explain output stands for the robot's answer; the capabilities dialog is done)
    assert sum(1 for q in dm.stack[-1].asked.values()) == 1
    out = dm.on_frame(heard("blah blurb"))  # third time would be the re-ask: it gives up instead
    assert says(out) == ["Sorry, let us leave that for now."]


def test_the_same_request_again_after_its_dialog_gave_up_is_taken_not_asked_a_third_time(dm):
    # lang12: "Is this the kitchen?" asked twice, given up while the follow below resumed; her "this is the
    # kitchen" again started a new dialog that asked it a third time. Two hearings agree: it is taken.
    dm.on_frame(heard("follow me", 0.2))
    assert says(dm.on_frame(heard("this is the kitchen", 0.2))) == ["Is this the kitchen?"]
    dm.on_frame(heard("blah", 0.2))
    # (talk22: her teaching answered "Shall I follow you?" no, so no follow question resumes after the give-up)
    assert says(dm.on_frame(heard("blah", 0.2))) == ["Sorry, let us leave that for now."]
    out = dm.on_frame(heard("this is the kitchen", 0.2))
    (s,) = sends(out)
    assert s.event == "place_teaching" and "Is this the kitchen?" not in says(out)
    assert s.children[0].find("PLACE/TITLE").get("name") == "kitchen"


def test_another_value_after_a_given_up_dialog_is_asked_and_a_no_keeps_it_untaken(dm):
    dm.on_frame(heard("this is the kitchen", 0.2))
    dm.on_frame(heard("blah", 0.2))
    assert says(dm.on_frame(heard("blah", 0.2))) == ["Sorry, let us leave that for now."]
    assert says(dm.on_frame(heard("this is the bathroom", 0.2))) == ["Is this the bathroom?"]  # other content: asked
    m = DialogManager(DOC)
    m.es_state = "Interacting"
    for w in ("this is the kitchen", "blah", "blah"):
        m.on_frame(heard(w, 0.2))
    out = m.on_frame(heard("no, this is the kitchen", 0.2))  # the same words with a no: nothing taken, not asked again
    assert not sends(out) and "Is this the kitchen?" not in says(out)


def test_something_done_lets_a_given_up_question_be_asked_afresh(dm):
    for w in ("this is the kitchen", "blah", "blah"):
        dm.on_frame(heard(w, 0.2))
    (s,) = sends(dm.on_frame(heard("follow me")))  # done: a new topic
    assert s.event == "follow"
    assert says(dm.on_frame(heard("this is the kitchen", 0.2))) == ["Is this the kitchen?"]


# ------------------------------------------------------------------ names
@pytest.mark.parametrize("words,name", [("that's the study", "study"), ("this is the lounge", "lounge"),
                                        ("we are in the hallway", "hallway"), ("this is the sitting room", "sitting room"),
                                        ("this is the den", "den"), ("welcome to the office", "office")])
def test_the_users_word_is_the_places_name(dm, words, name):
    out = dm.on_frame(heard(words))
    (s,) = sends(out)
    assert s.children[0].find("PLACE/TITLE").get("name") == name
    out = dm.on_condition(etree.fromstring('<condition name="place_learned"/>'))
    assert says(out) == [f"OK, this is the {name}. I will remember it."]


def test_low_confidence_place_is_confirmed_in_the_users_word(dm):
    assert says(dm.on_frame(heard("that's the study", LOW))) == ["Is this the study?"]


def test_object_names_and_uses_are_said_back_as_said(dm):
    (s,) = sends(dm.on_frame(heard("this is my coffee mug")))
    obj = s.children[0].find("OBJECT")
    assert obj.get("type") == "cup" and obj.find("TITLE").get("name") == "mug" and obj.find("USE").get("name") == "coffee"
    out = dm.on_condition(etree.fromstring('<condition name="object_learned"><param><OBJECT type="cup" name="mug"/></param></condition>'))
    assert says(out) == ["OK, I have learned your coffee mug."]


def test_events_carry_the_utterances_timestamp(dm):
    (s,) = sends(dm.on_frame(heard("this is my cup", start=12.345)))
    assert s.children[0][0].tag == "TIMESTAMP" and s.children[0][0].get("val") == "12345"
    assert s.children[0][1].tag == "OBJECT"


def test_look_at_this_looks_where_she_points(dm):
    out = dm.on_frame(heard("look at this"))
    (s,) = sends(out)
    assert s.event == "object_teaching" and says(out) == ["Let me have a look."]
    obj = s.children[0].find("OBJECT")
    assert obj.find("GESTURE") is not None and obj.get("type") is None
    out = dm.on_condition(etree.fromstring('<condition name="object_learned"><param><OBJECT type="table" name="table"/></param></condition>'))
    assert says(out) == ["OK, I have learned the table."]


def test_where_is_never_teaching(dm):
    for words in ("where is my cup", "is my cup here", "have you seen my cup", "i can't find my cup",
                  "where did i leave my cup", "do you know where my cup is"):
        m = DialogManager(DOC)
        m.es_state = "Interacting"
        (s,) = sends(m.on_frame(heard(words)))
        assert s.event == "query_object", words


# ------------------------------------------------------------------ invariant
WORDS = ["follow me", "could you follow me", "yes", "no", "no the kitchen", "this is the kitchen", "that's the study",
         "go to the kitchen", "blah", "", "the left one", "this is my cup", "my cup", "what can you do", "stop",
         "where is my cup", "yes this is the kitchen", "look at this", "hmm"]


@settings(max_examples=300, deadline=None)
@given(st.lists(st.tuples(st.sampled_from(WORDS), st.sampled_from([0.2, 0.45, 0.9])), max_size=20))
@example([("no the kitchen", 0.2), ("blah", 0.2), ("no", 0.2), ("blah", 0.2), ("that's the study", 0.2), ("blah", 0.2)])
def test_no_question_is_ever_asked_more_than_twice_in_one_dialog(seq):
    dm = DialogManager(DOC)
    dm.es_state = "Interacting"
    asked: dict[int, Counter[str]] = {}
    for words, conf in seq:
        outs = dm.on_frame(heard(words, conf))
        for inst in dm.stack:
            asked.setdefault(inst.serial, Counter())
        questions = [o for o in outs if isinstance(o, Say) and o.text.endswith("?") and o.dialog]
        for q in questions:
            owner = next((i for i in dm.stack if i.d.id == q.dialog), None)
            if owner is not None:
                asked.setdefault(owner.serial, Counter())[q.text] += 1
    for per in asked.values():
        assert all(n <= MAX_SAME_QUESTION for n in per.values()), per


def test_no_right_after_a_learned_place_renames_it(dm):
    (s,) = sends(dm.on_frame(heard("this is the kitchen")))
    dm.on_condition(etree.fromstring('<condition name="place_learned"/>'))
    out = dm.on_frame(heard("no, this is the bedroom"))
    (s,) = sends(out)
    place = s.children[0].find("PLACE")
    assert place.find("TITLE").get("name") == "bedroom" and place.get("replaces") == "kitchen"
    # later, a new room named is no correction of the kitchen
    dm.on_condition(etree.fromstring('<condition name="place_learned"/>'))
    dm.on_frame(heard("follow me"))
    (s,) = sends(dm.on_frame(heard("this is the hall")))
    assert s.children[0].find("PLACE").get("replaces") is None


def test_the_knowledge_base_renames_a_corrected_place():
    from robot.knowledge.bases import PlaceBase

    kb = PlaceBase()
    pose = '<POSE x="1.0" y="2.0" theta="0" frame="map"/>'
    kb.store(etree.fromstring(f'<PLACE><TITLE name="living room"/>{pose}</PLACE>'), now=1.0)
    kb.store(etree.fromstring(f'<PLACE><TITLE name="kitchen"/><POSE x="5.0" y="2.0" theta="0" frame="map"/></PLACE>'), now=2.0)
    kb.store(etree.fromstring(f'<PLACE replaces="kitchen"><TITLE name="bedroom"/><POSE x="5.2" y="2.1" theta="0" frame="map"/></PLACE>'), now=3.0)
    names = [p.name for p in kb.taught()]
    assert names == ["living room", "bedroom"]
    # a "replaces" far from the wrong place renames nothing
    kb.store(etree.fromstring(f'<PLACE replaces="living room"><TITLE name="hall"/><POSE x="9.0" y="2.0" theta="0" frame="map"/></PLACE>'), now=4.0)
    assert [p.name for p in kb.taught()] == ["living room", "bedroom", "hall"]


def test_a_correction_heard_badly_is_confirmed_in_its_turn(dm):
    # "Is this the bathroom?" - "no, the kitchen" heard with low confidence: the robot asks about
    # the kitchen at once (it stayed silent: the slots' statuses had not changed, only the value)
    assert says(dm.on_frame(heard("this is the bathroom", LOW))) == ["Is this the bathroom?"]
    assert says(dm.on_frame(heard("no, the kitchen", LOW))) == ["Is this the kitchen?"]
    (s,) = sends(dm.on_frame(heard("exactly")))
    assert s.children[0].find("PLACE/TITLE").get("name") == "kitchen"


def test_a_lost_noun_is_asked_for_not_looked_at(dm):
    # "This is the kitchen" heard as "this is the": the robot asked nothing and learned the kettle
    # she happened to stand by
    out = dm.on_frame(heard("this is the"))
    assert says(out) == ["Sorry, I did not understand you. Could you say that again?"] and not sends(out)
    out = dm.on_frame(heard("look at this the"))  # words skipped: a partial frame asks
    assert says(out) == ["What is it?"] and not sends(out)


def test_after_two_requests_to_say_it_again_the_next_hearing_is_taken_without_a_third_question(dm):
    assert says(dm.on_frame(heard("blah blurb"))) == [DOC.not_understood]
    assert says(dm.on_frame(heard("blah blurb"))) == [DOC.not_understood]
    out = dm.on_frame(heard("this is the living room", 0.4))  # heard badly, but the third time
    (s,) = sends(out)
    assert s.event == "place_teaching" and dm.summary()["taken_after_repairs"] == 1
    # an utterance heard well in between starts the count again
    dm2 = DialogManager(DOC)
    dm2.es_state = "Interacting"
    dm2.on_frame(heard("blah blurb"))
    assert says(dm2.on_frame(heard("this is the living room", 0.4))) == ["Is this the living room?"]


@settings(max_examples=300, deadline=None)
@given(st.lists(st.tuples(st.sampled_from(WORDS), st.sampled_from([0.2, 0.45, 0.9])), max_size=20))
@example([("no the kitchen", 0.2), ("follow me", 0.2), ("no the kitchen", 0.2)])
@example([("no the kitchen", 0.2), ("what can you do", 0.2), ("follow me", 0.2), ("this is the kitchen", 0.2)])
@example([("blah", 0.2), ("blah", 0.2), ("blah", 0.2), ("hmm", 0.9), ("blah", 0.2), ("blah", 0.2)])
# a given-up sub-dialog's question resumed over by the one below, then the same request said again (lang12: the
# dev profile found it; the given-up dialog had left the stack, and the new one counted its question from zero)
@example([("follow me", 0.2), ("this is the kitchen", 0.2), ("blah", 0.2), ("blah", 0.2), ("this is the kitchen", 0.2)])
@example([("look at this", 0.2), ("blah", 0.2), ("blah", 0.2), ("blah", 0.2), ("look at this", 0.2), ("blah", 0.2)])
# a question of a request to act answered no by another request (talk22's rule) is still asked: the CI profile found it
@example([("follow me", 0.2), ("what can you do", 0.2), ("this is the kitchen", 0.2), ("follow me", 0.2)])
def test_no_question_is_said_a_third_time_in_a_row_across_dialogs(seq):
    """Item 7 over the whole interaction, not per sub-dialog: while the user neither answers yes/no nor
    gets anything done (an event sent) and every robot turn is a question, the same question is never
    said more than twice (a request said again starts a new sub-dialog, and a resumed dialog repeats
    its question: neither may make the robot ask it a third time; nor may "could you say that again?":
    the third turn in a row not understood is answered with what she can say)."""
    dm = DialogManager(DOC)
    dm.es_state = "Interacting"
    run: Counter[str] = Counter()
    for words, conf in seq:
        outs = dm.on_frame(heard(words, conf))
        questions = [o.text for o in outs if isinstance(o, Say) and o.text.endswith("?")]
        if sends(outs) or not questions or words.split()[:1] in (["yes"], ["no"]):
            run.clear()
        run.update(questions)
        assert all(n <= MAX_SAME_QUESTION for n in run.values()), (words, dict(run))


def test_words_around_a_yes_nobody_asked_for_are_not_met_with_silence(dm):
    # "alright you can stop there we have arrived" (generated tour 053) was heard as a bare yes with the
    # rest skipped, and with no question open the robot said nothing; the grammar now hears its stop, so
    # the same shape without a request: words around "alright" that say nothing the robot can act on
    out = dm.on_frame(heard("alright we have arrived at last", 0.6))
    assert says(out) == [DOC.not_understood] and not sends(out)
    assert not says(dm.on_frame(heard("yes")))  # a plain yes to nothing is still ignored


# ------------------------------------------------------------------ an answer that picks one out
_CHOICES = ["the one on the table", "the one on the counter", "the left one", "the red one", "the one in the middle",
            "the one on the shelf"]


@settings(max_examples=30, deadline=None)
@given(thing=st.sampled_from(["cup", "vase", "mug", "book", "kettle"]), choice=st.sampled_from(_CHOICES),
       conf=st.floats(0.3, 0.95))
@example(thing="cup", choice="the one on the table", conf=0.53)  # perceive/cups_on_table seed 2
def test_an_answer_that_says_which_one_confirms_the_object_and_keeps_the_choice(thing, choice, conf):
    # perceive/cups_on_table seed 2 (and 21 other library scenes at seed 2): "Is this cup?" - "the one
    # on the table" got "Sorry, I did not understand you. Is this cup?" and nothing was learned. An
    # answer that picks the thing out is a yes, and says which one: the teaching goes out with it.
    m = DialogManager(DOC)
    m.es_state = "Interacting"
    assert says(m.on_frame(heard(f"is my {thing}", 0.9))) == [f"Is this your {thing}?"]
    said_choice = heard(choice, conf)
    out = m.on_frame(said_choice)
    (s,) = sends(out)
    assert s.event == "object_teaching"
    obj = s.children[0].find("OBJECT")
    assert obj.find("TITLE").get("name") == thing and obj.find("OWNER") is not None
    picked = said_choice.find("SPEECH/THAT_ONE")
    for child in picked:  # every way she picked it out travels with the teaching
        assert obj.find(str(child.tag)) is not None
    if picked.get("side"):
        assert obj.get("side") == picked.get("side")
    assert not any("did not understand" in t for t in says(out))


def test_no_with_a_choice_is_a_no():
    m = DialogManager(DOC)
    m.es_state = "Interacting"
    m.on_frame(heard("is my cup", 0.9))
    out = m.on_frame(heard("no the one on the table"))
    assert sends(out) == [] and "Sorry." in " ".join(says(out))


@settings(max_examples=25, deadline=None)
@given(first=st.sampled_from(["this is my this", "this is my that", "that is my that"]),
       again=st.sampled_from(["this is my this", "this is my that", "that is my that"]),
       conf=st.floats(0.3, 0.95))
def test_what_is_it_is_asked_once_then_the_robot_looks(first, again, conf):
    # perceive/cups_across_10 seeds 4, 8, cups_on_table seed 4: "This is my cup" heard twice with its noun
    # lost ("this is my this", "this is my that"): "What is it?" twice, then nothing learned. Asked once,
    # the same loss again sends the teaching as a pointing (the camera says what it is), never a 2nd ask.
    m = DialogManager(DOC)
    m.es_state = "Interacting"
    assert says(m.on_frame(heard(first, conf))) == ["What is it?"]
    out = m.on_frame(heard(again, conf))
    assert "What is it?" not in says(out)
    (s,) = sends(out)
    assert s.event == "object_teaching" and s.children[0].find("OBJECT").get("type") is None


def test_what_is_it_answered_with_the_noun_still_teaches_that_noun(dm):
    assert says(dm.on_frame(heard("this is my this", 0.6))) == ["What is it?"]
    (s,) = sends(dm.on_frame(heard("a cup", 0.9)))
    assert s.children[0].find("OBJECT").get("type") == "cup"


@pytest.mark.parametrize("answer", ["yes that's my bag", "yes this is my bag", "yes my bag", "yes that one",
                                    "yes", "that's my brown bag"])
def test_a_confirmation_keeps_the_time_of_the_request_its_gesture_went_with(dm, answer):
    """"The brown bag on the bench behind me" (pointing) - "Is this the brown bag?" - "Yes, that's my bag": the
    event carries when the request was said, so the object attention looks back to the gesture that went with
    it. A deictic word in the yes is no new gesture, and one made with the yes is later, so also seen from there
    (fresh10 hall_wardrobe_bags: the yes's time lost the gesture, the robot asked her to step aside too late)."""
    out = dm.on_frame(heard("this is the brown bag", LOW, start=20.5))
    assert says(out) == ["Is this the brown bag?"]
    out = dm.on_frame(heard(answer, start=29.8))
    (s,) = sends(out)
    assert s.event == "object_teaching"
    assert s.children[0][0].tag == "TIMESTAMP" and s.children[0][0].get("val") == "20500"


@pytest.mark.parametrize("request_", ["this is my this", "this is my that", "that is my this"])
@pytest.mark.parametrize("answer", ["it is a teapot", "a teapot", "this is a teapot", "it's my teapot", "that is a teapot"])
def test_the_answer_to_what_is_it_keeps_the_time_of_the_request_its_gesture_went_with(dm, request_, answer):
    """"This is my teapot" (pointing behind her; the noun lost) - "What is it?" - "It is a teapot": the answer
    completes the request, so the event carries when the request was said and the object attention looks back
    to the gesture that went with it (flow/follow_while_looking seeds 2, 4: with the answer's time the gesture
    was lost, the robot searched round her and covered the room for 40 s before asking her to step aside).
    A gesture made with the answer is later, so it is seen from there too."""
    assert says(dm.on_frame(heard(request_, 0.6, start=9.7))) == ["What is it?"]
    (s,) = sends(dm.on_frame(heard(answer, start=14.1)))
    assert s.event == "object_teaching" and s.children[0].find("OBJECT").get("type") == "teapot"
    assert s.children[0][0].tag == "TIMESTAMP" and s.children[0][0].get("val") == "9700"


@pytest.mark.parametrize("request_, answer", [("this is your red cup", "no that cup"),
                                              ("this is your red cup", "no this cup"),
                                              ("this is my red cup", "no that cup")])
def test_a_correction_that_points_anew_keeps_its_own_time(dm, request_, answer):
    """"Is this your red cup?" - "No, that cup" (pointing at the other one): the correction points again, so
    the event carries the correction's time and the object attention looks at that gesture, not at the
    first one made at the wrong cup (review23 N2; issue 26 item 5: "this one" with pointing)."""
    out = dm.on_frame(heard(request_, LOW, start=20.5))
    assert says(out) and says(out)[0].startswith("Is this")
    (s,) = sends(dm.on_frame(heard(answer, start=29.8)))
    assert s.event == "object_teaching"
    assert s.children[0][0].tag == "TIMESTAMP" and s.children[0][0].get("val") == "29800"
