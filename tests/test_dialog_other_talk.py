"""talk15: words said to someone else, then more words turned away (a phone call with nobody near her), and
the go-to's "OK, I am going" overtaken by a place it does not know (fresh5 row_phone_between)."""

from __future__ import annotations

import math
from collections import deque

from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from robot.dialog.loader import BIRON_DIALOGS, load
from robot.dialog.manager import DialogManager
from robot.dialog.module import ASIDE, OTHER_TALK_GAP, Dialog, _whole
from robot.speech.module import frame_message, shared_understander

DOC = load(BIRON_DIALOGS)


def _dialog(reports: list[tuple[float, str]], other_talk_end: float, faced_at: float = -math.inf) -> Dialog:
    d = Dialog.__new__(Dialog)
    d.manager = DialogManager(DOC)
    d.manager.es_state = "Interacting"
    d._partner_cues = deque([(t, f, 0, 0.0) for t, f in reports], maxlen=300)
    d._sources = deque(maxlen=300)
    d.barge_in_width = 9.0
    d._addressed_at = -math.inf
    d._aside_since = math.inf
    d._other_talk_end = other_talk_end
    d._faced_at = faced_at
    return d


def _frame(words: str) -> etree._Element:
    return frame_message(shared_understander().understand(words), 10.0, 11.0, 0.9)


CUES = st.lists(st.sampled_from(["true", "false", "unknown", ASIDE]), min_size=1, max_size=20)


@settings(max_examples=300, deadline=None)
@given(cues=CUES, gap=st.floats(0.0, 2 * OTHER_TALK_GAP), whole=st.booleans(), named=st.booleans())
def test_turned_away_words_after_words_to_someone_else_go_on_that_talk(cues, gap, whole, named):
    reports = [(10.0 + 0.1 * i, f) for i, f in enumerate(cues)]
    end = 10.0 + 0.1 * len(cues)
    heard = _dialog(reports, other_talk_end=10.0 - gap).addressed(10.0, end, named=named, whole=whole)
    before = _dialog(reports, other_talk_end=-math.inf).addressed(10.0, end, named=named, whole=whole)
    assert heard <= before  # the rule only ever drops words, never takes more
    if any(f == "true" for f in cues) or named or gap > OTHER_TALK_GAP:
        assert heard == before  # she faced the robot, called it by name, or the other talk is over
    elif not whole:
        assert not heard  # "no, the kitchen is fine, come over at six": her call goes on
    elif 2 * sum(f in ("false", ASIDE) for f in cues) >= len(cues) and cues[-1] in ("false", ASIDE):
        assert not heard  # seen turned away, even a whole request goes on the call


@settings(max_examples=100, deadline=None)
@given(cues=CUES, whole=st.booleans())
def test_once_she_faced_the_robot_the_other_talk_is_over(cues, whole):
    d = _dialog([(10.0 + 0.1 * i, f) for i, f in enumerate(cues)], other_talk_end=8.0, faced_at=9.0)
    alone = _dialog([(10.0 + 0.1 * i, f) for i, f in enumerate(cues)], other_talk_end=-math.inf)
    end = 10.0 + 0.1 * len(cues)
    assert d.addressed(10.0, end, whole=whole) == alone.addressed(10.0, end, whole=whole)


def test_a_whole_request_is_told_from_a_fragment_of_a_call():
    assert _whole(_frame("follow me please"))
    assert _whole(_frame("sorry, follow me please"))  # the apology turns back to the robot
    assert not _whole(_frame("no the kitchen is fine come over at six"))
    assert not _whole(_frame("hang on let me in the calendar"))


def test_the_call_itself_is_said_to_someone_else():
    for words in ("oh hello dad", "yes mum stop worrying i will call you back", "okay see you later bye dad",
                  "oh hi mum yes i am just showing the robot round the flat"):
        assert _frame(words).get("addressee") == "other", words


def test_a_welcome_naming_a_room_is_place_teaching_not_a_go_to():
    for words in ("welcome to my study", "welcome my study", "welcome to the kitchen", "welcome our living room"):
        speech = _frame(words).find("SPEECH")
        assert speech is not None and speech.find("PLACE") is not None and speech.find("GOTO") is None, words


def test_the_go_to_sentence_overtaken_by_an_unknown_place_is_never_said():
    # "OK, I am going to the study." made on entering Navigating, and the plan failed 0.06 s later (a place
    # it was never shown): only "Sorry, I do not know where the study is" may be said (fresh5 row_phone_between)
    from types import SimpleNamespace

    from robot.dialog.module import WITHDRAWN_BY

    d = Dialog.__new__(Dialog)
    d.sim = SimpleNamespace(now=26.0)
    d._queue, d._talking, d._repairs = deque(), True, frozenset()
    d._withdrawn = {WITHDRAWN_BY["unknown_place"]: 25.8}
    d._enqueue("OK, I am going to the study.", "dialog#1", frozenset({"goto"}), made=25.74)
    assert not d._queue
    d._enqueue("Sorry, I do not know where the study is.", "dialog#2", frozenset({"unknown_place"}), made=25.8)
    d._enqueue("OK, I am going to the kitchen.", "dialog#3", frozenset({"goto"}), made=30.0)  # a later go-to is said
    assert [q[0] for q in d._queue] == ["Sorry, I do not know where the study is.", "OK, I am going to the kitchen."]


def _says(outs) -> list[str]:
    from robot.dialog.manager import Say

    return [o.text for o in outs if isinstance(o, Say)]


def test_a_question_met_by_silence_is_put_once_more_then_left():
    # issue 26 item 7 (the lead's item 4): "Where shall I go?" and nothing heard: asked again once, then the
    # robot goes on politely; never the same question a third time, and no waiting on it for ever
    m = DialogManager(DOC)
    m.es_state = "Interacting"
    first = _says(m.on_frame(_frame("can you go")))
    assert first == ["Where shall I go?"]
    q = m.open_question()
    assert q is not None and q[1] == "Where shall I go?"
    assert _says(m.on_silence(*q)) == ["Where shall I go?"]
    assert m.open_question() == q
    last = _says(m.on_silence(*q))
    assert last and "Where shall I go?" not in last  # "Sorry, let us leave that for now."
    assert m.open_question() is None
    assert _says(m.on_silence(*q)) == []  # nothing open any more: silence is no question


def _unheard() -> etree._Element:
    return etree.fromstring('<not_understood confidence="0.2"/>')


def test_a_request_to_repeat_met_by_silence_is_put_once_more_then_left():
    # the reviewer's F4 (lang_silence seeds 10, 11): "Can you go" not understood, "Could you say that again?",
    # and she says nothing: the robot's most frequent question follows the same rule as a sub-dialog's
    m = DialogManager(DOC)
    m.es_state = "Interacting"
    first = _says(m.on_frame(_unheard()))
    assert first == [DOC.not_understood]
    q = m.open_question()
    assert q is not None and q[1] == DOC.not_understood
    assert _says(m.on_silence(*q)) == [DOC.not_understood]  # once more
    assert m.open_question() == q
    last = _says(m.on_silence(*q))
    assert last and DOC.not_understood not in last  # "Sorry, let us leave that for now."
    assert m.open_question() is None
    assert _says(m.on_silence(*q)) == []
    # not understood twice in a row: the request was put twice already, silence then leaves it (no third)
    m = DialogManager(DOC)
    m.es_state = "Interacting"
    m.on_frame(_unheard())
    m.on_frame(_unheard())
    q = m.open_question()
    assert q is not None
    last = _says(m.on_silence(*q))
    assert last and DOC.not_understood not in last and m.open_question() is None


def test_silence_after_a_request_to_repeat_answered_changes_nothing():
    m = DialogManager(DOC)
    m.es_state = "Interacting"
    m.on_frame(_unheard())
    q = m.open_question()
    m.on_frame(_frame("follow me"))
    assert m.open_question() != q
    assert _says(m.on_silence(*q)) == []
    m.on_frame(_unheard())
    q2 = m.open_question()
    m.on_frame(_unheard())  # said again, not understood again: a new request, the old watch is void
    assert m.open_question() != q2
    assert _says(m.on_silence(*q2)) == []


def test_words_to_someone_else_are_no_answer_to_the_robots_question():
    # the reviewer's F5: words not meant for the robot (a call to someone else, a television's) do not keep
    # the partner's silence after "Where shall I go?" from being met: the question is still put once more
    from types import SimpleNamespace

    d = _dialog([], other_talk_end=-math.inf)
    d.sim = SimpleNamespace(now=12.0)
    d.bus = SimpleNamespace(closed=False, hung=False)
    d._talking, d._queue = False, deque()
    d._heard_at, d._voice_at = -math.inf, -math.inf
    d.not_addressed = 0
    said: list[str] = []
    d._emit = lambda outs, cause: said.extend(_says(outs))
    d.manager.on_frame(_frame("can you go"))
    q = d.manager.open_question()
    assert q is not None
    other = etree.fromstring('<not_understood start="11.0" end="12.0" confidence="0.8" addressee="other">'
                             'tom can you put the kettle on</not_understood>')
    d._on_frame(SimpleNamespace(xml=other, id="u#1"))
    assert d.not_addressed == 1
    d.sim.now = 20.5
    d._on_silence(q, 10.0, "speaker#1")
    assert said == ["Where shall I go?"]


def test_a_question_put_again_is_left_only_after_silence_following_the_second_putting():
    # a watch set by an earlier sentence must not leave the question less than ask_timeout after it was put again
    from types import SimpleNamespace

    d = _dialog([], other_talk_end=-math.inf)
    timers: list[tuple] = []
    d.sim = SimpleNamespace(now=10.0, loop=SimpleNamespace(call_at_ns=lambda ns, f, *a: timers.append((ns, f, a))))
    d.ask_timeout = 10.0
    d.bus = SimpleNamespace(closed=False, hung=False)
    d._talking, d._queue = False, deque()
    d._heard_at, d._voice_at = -math.inf, -math.inf
    said: list[str] = []
    d._emit = lambda outs, cause: said.extend(_says(outs))
    d.manager.on_frame(_frame("can you go"))
    d._watch_silence("speaker#1")  # "Where shall I go?" said, done at 10 s
    d.sim.now = 12.0
    d._watch_silence("speaker#2")  # another sentence done at 12 s while the question is open
    d.sim.now = 20.0
    timers[0][1](*timers[0][2])  # the first watch (10 s + 10 s) gives way to the newer one
    assert said == []
    d.sim.now = 22.0
    timers[1][1](*timers[1][2])
    assert said == ["Where shall I go?"]


def test_silence_after_a_question_already_answered_changes_nothing():
    m = DialogManager(DOC)
    m.es_state = "Interacting"
    m.on_frame(_frame("can you go"))
    q = m.open_question()
    m.on_frame(_frame("to the kitchen"))
    assert _says(m.on_silence(*q)) == []
