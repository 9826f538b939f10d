"""Understanding and dialog on the bus with the supervisor: greetings synchronised, rejections explained,
timing in virtual time, self-explanation, clarification, barge-in."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from homesim.scenario.loader import load_scenario
from homesim.sim import Simulation
from homesim.tour.stage import Stage
from robot.contract import FOLLOW_STATUS
from robot.dialog.module import Dialog
from robot.dialog.transcript import transcript
from robot.speech.module import RobotSentence, SpeechUnderstanding, is_own_voice
from robot.supervisor import ES_EVENTS, ExecutionSupervisor, event_xml
from tests.world_helpers import ROOM
from tests.stage_helpers import HARDWARE

PERSON = etree.fromstring('<PERSON id="t1" bearing="0" distance="1.2" speaking="true" facing="true"/>')


class Robot:
    """Supervisor, understanding and dialog; the microphones and the person attention are played by the test."""

    def __init__(self, seed: int = 1, **dialog_options) -> None:
        self.sim = Simulation(seed=seed, scenario="dialog")
        self.trace = self.sim.record_trace()
        self.es = ExecutionSupervisor(self.sim)
        self.understanding = SpeechUnderstanding(self.sim)
        self.dialog = Dialog(self.sim, **dialog_options)
        self.mic = self.sim.bus.participant("microphones")
        self.attention = self.sim.bus.participant("person_attention")
        self.probe = self.sim.bus.participant("probe")
        self.said = self.probe.subscribe("/robot/speaker/say")
        self.speaker = self.sim.bus.participant("speaker")
        self.speaker.subscribe("/robot/speaker/say", self._speak)
        self.sim.start()

    def _speak(self, msg) -> None:
        """The loudspeaker's status reports (its duration model: 0.3 s + 0.4 s a word)."""
        text = msg.xml.get("text", "")
        if not text:
            return
        now = self.sim.now
        end = now + 0.3 + 0.4 * len(text.split())
        self.speaker.publish("/robot/speaker/status", etree.Element("speaking", text=text, start=f"{now:.6f}", end=f"{end:.6f}"))
        self.sim.call_at(end, lambda: self.speaker.publish("/robot/speaker/status", etree.Element("done", text=text)))

    def utter(self, words: str, start: float, end: float, *, confidence: float = 0.9, level: float = 60.0) -> None:
        def go() -> None:
            el = etree.Element("utterance", start=f"{start:.3f}", end=f"{end:.3f}", bearing="0", level=f"{level}",
                               confidence=f"{confidence}")
            el.text = words
            self.mic.publish("/robot/audio/speech", el, created=end)
        self.sim.call_at(end, go)

    def partner_at(self, bearing: float, start: float, end: float, distance: float = 1.0) -> None:
        """The person attention's /robot/attention/partner every 0.1 s from ``start`` to ``end``."""
        def beat(t: float) -> None:
            el = etree.Element("partner", id="t1", bearing=f"{bearing}", distance=f"{distance}", x="1", y="0", vx="0", vy="0",
                               visible="true", lost_for="0")
            self.attention.publish("/robot/attention/partner", el)
            if t + 0.1 <= end:
                self.sim.call_at(t + 0.1, lambda: beat(t + 0.1))
        self.sim.call_at(start, lambda: beat(start))

    def sound(self, t: float, bearing: float, level: float) -> None:
        """One /robot/audio/sources frame with one direction."""
        def go() -> None:
            el = etree.Element("sources", time=f"{self.sim.now:.6f}")
            etree.SubElement(el, "source", tdoa="0", bearing=f"{bearing}", level=f"{level}")
            self.mic.publish("/robot/audio/sources", el)
        self.sim.call_at(t, go)

    def partner(self, t: float) -> None:
        self.sim.call_at(t, lambda: self.attention.publish(ES_EVENTS, event_xml("potential_partner", children=(PERSON,))))

    def sentences(self) -> list[str]:
        return [m.xml.get("text") for m in self.said.drain()]

    def records(self, channel: str) -> list[dict]:
        return [r for r in self.trace.records() if r.get("kind") == "publish" and r.get("channel") == channel]

    def greet(self) -> None:
        self.utter("hello biron", 0.3, 1.0)
        self.partner(1.1)


def test_hello_biron_with_a_potential_partner_gets_the_spoken_answer(robot):
    robot.greet()
    robot.sim.run(until=4.0)
    assert robot.sentences() == ["Hello, I am BIRON. What can I do for you?"]
    assert robot.es.state == "Interacting"
    # the answer comes only after the supervisor's synchronisation (condition partner_found)
    found = [r for r in robot.records("/robot/es/conditions/dialog") if 'name="partner_found"' in r["xml"]]
    (say,) = robot.records("/robot/speaker/say")
    assert found and found[0]["t"] < say["t"]


def test_a_greeting_the_supervisor_rejects_is_explained_in_words(robot):
    robot.utter("hello biron", 0.3, 1.0)  # a radio: nobody faces the robot
    robot.sim.run(until=6.0)
    assert robot.sentences() == ["I can't see you. Please look at me."]
    (rej,) = robot.records("/robot/es/rejected/dialog")
    assert 'reason="expired"' in rej["xml"] and robot.es.state == "LookingAround"
    assert robot.dialog.summary()["rejections_explained"] == 1


def test_a_greeting_that_comes_too_late_for_a_person_seen_is_no_i_cant_see_you(robot):
    # she speaks facing the robot (potential partner at 0.5 s, lost again at 2.5 s), but the greeting
    # reaches the supervisor only at 6 s (a slow dialog host): it expires, and the robot says why
    robot.partner(0.5)
    robot.sim.call_at(2.5, lambda: robot.attention.publish(ES_EVENTS, event_xml("potential_partner_lost")))
    robot.utter("hello biron", 0.3, 1.0)
    robot.dialog.dialog_cost = 5.0  # understanding done at once, the dialog host takes 5 s
    robot.sim.run(until=20.0)
    (rej,) = robot.records("/robot/es/rejected/dialog")
    assert 'reason="expired"' in rej["xml"]
    assert robot.sentences() == ["Sorry, I was too slow. Please look at me and say hello again."]


def test_a_greeting_expiring_in_a_technical_failure_is_told_as_the_failure(robot):
    robot.sim.call_at(0.5, lambda: robot.attention.publish(ES_EVENTS, event_xml("module_failed", attrs={"module": "camera", "still_failed": "1"})))
    # the greeting arrives after its lifetime (a congested WLAN: wlan_congested), in TechnicalFailure
    greeting = etree.fromstring('<event name="greeting"><SPEECH><TIMESTAMP val="300"/><GREETING name="biron"/></SPEECH></event>')
    robot.sim.call_at(4.5, lambda: robot.dialog.bus.publish(ES_EVENTS, greeting, created=1.2))
    robot.sim.run(until=8.0)
    (rej,) = robot.records("/robot/es/rejected/dialog")
    assert 'reason="expired"' in rej["xml"] and 'state="TechnicalFailure"' in rej["xml"]
    said = robot.sentences()
    assert said and all("can't see you" not in s for s in said), said


def test_transcript_shows_the_answer_and_the_explained_rejection():
    r = Robot()
    try:
        r.utter("hello biron", 0.3, 1.0)  # nobody there: rejected
        r.utter("hello biron", 6.0, 6.8)  # now someone faces the robot
        r.partner(6.9)
        r.sim.run(until=10.0)
        text = "\n".join(transcript(r.trace.records()))
    finally:
        r.sim.close()
    assert 'user        "hello biron"' in text
    assert "ES          rejected greeting (expired) in LookingAround" in text
    assert 'BIRON       "I can\'t see you. Please look at me."' in text
    assert "ES          greeting: PotentialPartner -> Interacting" in text
    assert 'BIRON       "Hello, I am BIRON. What can I do for you?"' in text
    assert text.index("look at me") < text.index("I am BIRON")


def test_answer_starts_about_200_ms_after_understanding_ends(robot):
    robot.greet()
    robot.utter("follow me", 7.0, 7.8)  # after the robot's greeting ended (at 6.04 s)
    robot.sim.run(until=10.0)
    frames = robot.records("/robot/speech/frames")
    says = robot.records("/robot/speaker/say")
    assert len(frames) == 2 and len(says) == 2
    for f, s in zip(frames, says):
        delay = s["t"] - f["t"]
        # dialog processing + generation (0.2 s) plus the supervisor's reconfiguration and the messages
        assert 0.2 <= delay <= 0.25, delay


def test_answer_delay_follows_the_parameters():
    r = Robot(dialog_cost=0.05, generation_time=0.45)
    try:
        r.greet()
        r.sim.run(until=4.0)
        (f,) = r.records("/robot/speech/frames")
        (s,) = r.records("/robot/speaker/say")
        # the frame and the supervisor's condition each cost the dialog 50 ms, then 450 ms of generation
        assert 0.55 <= s["t"] - f["t"] <= 0.57
    finally:
        r.sim.close()


def test_recognition_time_grows_with_the_utterance_length(robot):
    robot.utter("stop", 0.5, 1.0)
    robot.utter("this is my favourite red cup at the window", 5.0, 8.0)
    robot.sim.run(until=12.0)
    short, long_ = robot.records("/robot/speech/frames")
    lag_short = short["t"] - 1.0
    lag_long = long_["t"] - 8.0
    u = robot.understanding
    assert lag_short == pytest.approx(u.recognition_time(1) + u.understanding_cost, abs=1e-6)
    assert lag_long == pytest.approx(u.recognition_time(9) + u.understanding_cost, abs=1e-6)
    assert lag_long > lag_short


def _speaking(robot, text: str, start: float, end: float, level: str | None = "62.0") -> None:
    attrs = dict(text=text, start=f"{start}", end=f"{end}", **({"level": level} if level else {}))
    robot.sim.call_at(start, lambda: robot.speaker.publish("/robot/speaker/status", etree.Element("speaking", attrs)))


def _heard(robot) -> list[str]:
    """The words of every utterance the understanding passed on (understood or not)."""
    out = []
    for r in robot.records("/robot/speech/frames"):
        el = etree.fromstring(r["xml"])
        out.append((el.findtext("words") if el.tag == "understood" else el.text) or "")
    return out


def test_the_robots_own_voice_is_not_understood(robot):
    # The robot says a sentence; its echo leaks through (72 dB: the loudspeaker 0.3 m from the microphones).
    _speaking(robot, "I am listening to you. Now you can ask me to follow you.", 0.5, 4.9)
    robot.utter("i am listening to you now you can ask me to follow you", 0.52, 4.85, level=72.0)
    robot.sim.run(until=7.0)
    assert _heard(robot) == [] and robot.understanding.counts["own_voice"] == 1


def test_a_partner_talking_over_the_robot_is_understood_however_close(robot):
    # The partner a hand's breadth away is as loud as the loudspeaker (the old rule dropped
    # every overlapping utterance of 68 dB or more); neither saying the robot's words ("stop",
    # "follow") nor the level makes it the robot's own voice.
    _speaking(robot, "I am still following you; say stop first.", 0.5, 3.7)
    robot.utter("stop", 1.2, 1.6, level=72.0)
    _speaking(robot, "OK, I am following you.", 5.0, 7.3)
    robot.utter("hello biron", 5.6, 6.4, level=70.0)
    robot.utter("ok i am following you", 5.0, 7.2, level=95.0)  # louder than any echo: somebody shouting it
    robot.sim.run(until=10.0)
    assert _heard(robot) == ["stop", "hello biron", "ok i am following you"]
    assert robot.understanding.counts["own_voice"] == 0


def test_a_cut_sentences_echo_is_its_spoken_part(robot):
    _speaking(robot, "one two three four five six seven eight", 0.5, 4.0)
    robot.sim.call_at(1.3, lambda: robot.speaker.publish(
        "/robot/speaker/status", etree.Element("interrupted", text="one two three four five six seven eight")))
    robot.utter("one two", 0.5, 1.3, level=72.0)  # what was said before the cut
    robot.utter("four", 2.0, 2.4, level=60.0)  # after the cut: the robot is silent, this is somebody
    robot.sim.run(until=5.0)
    assert _heard(robot) == ["four"] and robot.understanding.counts["own_voice"] == 1


SAID = st.lists(st.sampled_from(["i", "am", "following", "you", "say", "stop", "first", "the", "cup", "hello"]),
                min_size=1, max_size=10)


@settings(max_examples=150, deadline=None)
@given(robot_words=SAID, heard=SAID, offset=st.floats(-3.0, 3.0), level=st.floats(30.0, 100.0))
def test_own_voice_rule_properties(robot_words, heard, offset, level):
    said = [RobotSentence(tuple(robot_words), 10.0, 10.0 + 0.4 * len(robot_words), 62.0)]
    own = is_own_voice(" ".join(heard), 10.0 + offset, level, said)
    # Only what starts with a robot sentence can be its echo, and never louder than the loudspeaker can make it.
    if abs(offset) > 0.5 or level > 62.0 + 10.5 + 6.0:
        assert not own
    # The robot's own sentence, heard as said when it said it at the loudspeaker's level, is always its own.
    assert is_own_voice(" ".join(robot_words), 10.0 + max(-0.5, min(0.3, offset)), 72.0, said)
    # Without anything the robot said, nothing is its own voice.
    assert not is_own_voice(" ".join(heard), 10.0, level, [])


def test_what_can_you_do_is_answered_from_the_supervisors_state(robot):
    robot.greet()
    robot.utter("what can you do", 7.0, 7.8)
    robot.sim.run(until=10.0)
    _, answer = robot.sentences()
    assert answer.startswith("I am listening to you. Now you can ")
    assert "ask me to follow you" in answer and "greet me" not in answer
    r2 = Robot()
    try:
        r2.partner(0.5)
        r2.utter("what can you do", 0.3, 1.0)
        r2.sim.run(until=3.0)
        (answer2,) = r2.sentences()
    finally:
        r2.sim.close()
    assert answer2.startswith("I can see you.") and "greet me" in answer2 and "follow you" not in answer2


def test_what_can_you_do_is_not_answered_with_nobody_engaged(robot):
    # A radio (nobody faces the robot): like every other request, it needs a partner.
    robot.utter("what can you do", 0.3, 1.0)
    robot.sim.run(until=4.0)
    assert robot.sentences() == [] and robot.es.state == "LookingAround"
    assert robot.dialog.summary()["ignored_frames"] == 1


def test_place_teaching_sends_the_latest_pose(robot):
    loc = robot.sim.bus.participant("localiser")
    robot.sim.call_at(2.0, lambda: loc.publish("/robot/localisation/pose", etree.Element(
        "pose", time="2", x="1.5", y="2.0", theta="0.3", cxx="0.01", cyy="0.01", ctt="0.001", frame="map")))
    robot.greet()
    robot.utter("this is the kitchen", 7.0, 8.0)
    robot.sim.run(until=15.0)
    ev = [r for r in robot.records(ES_EVENTS) if 'name="place_teaching"' in r["xml"]]
    assert ev and '<POSE x="1.5" y="2.0" theta="0.3" frame="map"/>' in ev[0]["xml"]
    assert robot.sentences()[-1] == "OK, this is the kitchen. I will remember it."
    orders = [r for r in robot.records("/robot/es/orders/scene_model") if "store_place" in r["xml"]]
    assert orders and "<POSE " in orders[0]["xml"]


def _approaching(robot, start: float, stop: float) -> None:
    """The follower's status: "approaching" every 0.1 s from ``start``, then "stopped" at ``stop``."""
    fol = robot.sim.bus.participant("follower")
    def beat(t: float) -> None:
        fol.publish(FOLLOW_STATUS, etree.Element(
            "follow", distance="1.5", speed="0.2", at_limit="false", state="approaching"))
        if t + 0.1 < stop:
            robot.sim.call_at(t + 0.1, lambda: beat(t + 0.1))
    robot.sim.call_at(start, lambda: beat(start))
    robot.sim.call_at(stop, lambda: fol.publish(FOLLOW_STATUS, etree.Element(
        "follow", distance="1.0", speed="0", at_limit="false", state="stopped")))


def test_every_request_made_during_an_approach_is_handled_in_order_when_it_ends(robot):
    """Two requests while the robot comes up to her: both reach the ES / are answered, in order, after
    the approach (issue 23 item 4: every understood instruction goes to the ES; none is overwritten)."""
    loc = robot.sim.bus.participant("localiser")
    robot.sim.call_at(2.0, lambda: loc.publish("/robot/localisation/pose", etree.Element(
        "pose", time="2", x="1.5", y="2.0", theta="0.3", cxx="0.01", cyy="0.01", ctt="0.001", frame="map")))
    robot.greet()
    _approaching(robot, 6.0, 14.0)
    robot.utter("this is the kitchen", 7.0, 8.0)
    robot.utter("what can you do", 10.0, 11.0)
    robot.sim.run(until=30.0)
    teach = [r for r in robot.records(ES_EVENTS) if 'name="place_teaching"' in r["xml"]]
    assert len(teach) == 1 and teach[0]["t"] >= 14.0
    said = robot.sentences()
    assert "OK, this is the kitchen. I will remember it." in said
    assert any(s.startswith("I am listening to you.") for s in said)
    assert said.index("OK, this is the kitchen. I will remember it.") < next(
        i for i, s in enumerate(said) if s.startswith("I am listening to you."))


def test_teaching_while_following_is_explained_when_it_expires(robot):
    robot.greet()
    robot.utter("follow me", 7.0, 7.6)
    robot.utter("this is my favourite cup", 12.0, 13.5)
    robot.sim.run(until=30.0)
    said = robot.sentences()
    assert said[:2] == ["Hello, I am BIRON. What can I do for you?", "OK, I am following you."]
    # an object shown while it follows is asked about once she stops (talk13, fresh12 item 5)
    assert said[-1] == "I am following you. When you stop, please show it to me again."


def test_clarification_question_from_the_object_attention(robot):
    robot.greet()
    obj = robot.sim.bus.participant("object_attention")
    replies = []

    async def ask() -> None:
        req = etree.fromstring('<ask timeout="8"><option index="0" text="red cup"/><option index="1" text="blue cup"/></ask>')
        replies.append(await obj.call("dialog", "ask", req, timeout=10.0))

    robot.sim.call_at(7.0, lambda: robot.sim.spawn(ask(), name="asker"))
    robot.utter("the blue one", 11.0, 11.8)
    robot.sim.run(until=15.0)
    assert robot.sentences()[1:] == ["Do you mean the red cup or the blue one?", "Thank you."]
    assert replies and replies[0].xml.get("index") == "1"


@pytest.mark.parametrize("side, index", [("left", "0"), ("right", "1")])
def test_a_side_said_in_answer_to_the_confirmation_answers_the_which_one_question(robot, side, index):
    # perceive/cups_across_10 seed 2: "Is this your cup?" - "the left one" was taken as a yes, and then the
    # robot asked "Do you mean the cup on the left or the one on the right?", a question she had answered
    robot.greet()
    obj = robot.sim.bus.participant("object_attention")
    replies = []

    async def ask() -> None:
        req = etree.fromstring('<ask timeout="8"><option index="0" text="the cup on the left"/>'
                               '<option index="1" text="the one on the right"/></ask>')
        replies.append(await obj.call("dialog", "ask", req, timeout=10.0))

    robot.utter("is my cup", 6.0, 7.0)
    robot.utter(f"the {side} one", 10.0, 10.8)
    robot.sim.call_at(13.0, lambda: robot.sim.spawn(ask(), name="asker"))
    robot.sim.run(until=16.0)
    said = robot.sentences()
    assert "Is this your cup?" in said and not any(s.startswith("Do you mean") for s in said)
    assert replies and replies[0].xml.get("index") == index


def _ask_red_or_blue_cup(robot) -> list:
    """Greeted, an object teaching at 7 s and the object attention's clarification "red cup or blue cup?" at 7.5 s,
    through the ES; returns the list the object attention's orders are collected in."""
    robot.greet()
    obj = robot.sim.bus.participant("object_attention")
    orders: list = []
    obj.subscribe("/robot/es/orders/object_attention", orders.append)

    def teach_and_ask() -> None:
        frame = etree.fromstring('<event name="object_teaching"><SPEECH><OBJECT type="cup"/></SPEECH></event>')
        robot.sim.bus.get("dialog").publish(ES_EVENTS, frame)
        ev = etree.fromstring('<event name="clarification"><OPTIONS timeout="8"><option index="0" text="red cup"/>'
                              '<option index="1" text="blue cup"/></OPTIONS></event>')
        robot.sim.call_at(7.5, obj.publish, ES_EVENTS, ev)

    robot.sim.call_at(7.0, teach_and_ask)
    return orders


def test_a_question_routed_through_the_supervisor_is_asked_and_answered_as_an_event(robot):
    """The object attention asks through the ES: event clarification -> condition ask -> the dialog asks ->
    event clarified -> order clarified to the object attention (robot/afsm/biron.scxml, ObjectTeaching)."""
    orders = _ask_red_or_blue_cup(robot)
    robot.utter("the blue one", 11.0, 11.8)
    robot.sim.run(until=15.0)
    assert "Do you mean the red cup or the blue one?" in robot.sentences()
    answers = [o for o in orders if o.xml.get("name") == "clarified"]
    assert answers and answers[0].xml.find("param/ANSWER").get("index") == "1"


def test_an_answer_that_picks_no_option_says_how_often_the_question_was_put(robot):
    """talk14 (issue 26 item 7): "the one on the sofa" picks neither the red nor the blue cup; the answer goes back
    with ``asked="1"``, so the asker may put the question once more (and never a third time)."""
    orders = _ask_red_or_blue_cup(robot)
    robot.utter("the one on the sofa", 11.0, 12.0)
    robot.sim.run(until=16.0)
    answers = [o for o in orders if o.xml.get("name") == "clarified"]
    ans = answers[0].xml.find("param/ANSWER")
    assert ans.get("none") == "true" and ans.get("asked") == "1" and ans.find("POSITION/TITLE").get("name") == "sofa"


def _teach_then_occluded(robot) -> list:
    """Greeted, an object teaching at 7 s and the object attention's ``occluded`` at 7.5 s, through the ES; returns
    the list the object attention's orders are collected in."""
    robot.greet()
    obj = robot.sim.bus.participant("object_attention")
    orders: list = []
    obj.subscribe("/robot/es/orders/object_attention", orders.append)

    def teach_and_occlude() -> None:
        frame = etree.fromstring('<event name="object_teaching"><SPEECH><OBJECT type="plant"/></SPEECH></event>')
        robot.sim.bus.get("dialog").publish(ES_EVENTS, frame)
        robot.sim.call_at(7.5, obj.publish, ES_EVENTS, etree.Element("event", name="occluded"))

    robot.sim.call_at(7.0, teach_and_occlude)
    return orders


def test_the_occlusion_question_goes_through_the_supervisor_and_is_answered_once_said(robot):
    """The object attention cannot see past the partner: event occluded -> condition step_aside -> the
    dialog asks her to step aside -> event asked_aside (said) -> order asked_aside to the object attention,
    after the question has been said (not before: the object attention then waits for her to move)."""
    orders = _teach_then_occluded(robot)
    robot.sim.run(until=20.0)
    assert any("step aside" in s for s in robot.sentences())
    conds = [r for r in robot.records("/robot/es/conditions/dialog") if 'name="step_aside"' in r["xml"]]
    (said,) = [o for o in orders if o.xml.get("name") == "asked_aside"]
    assert conds and said.xml.find("param[@name='said']").text == "true"
    done = [r["t"] for r in robot.records("/robot/speaker/status") if r["xml"].startswith("<done") and "step aside" in r["xml"]]
    assert done and said.created >= done[0]


def test_an_occlusion_report_outside_object_teaching_asks_nothing(robot):
    """Stale: the partner is no longer showing an object; the ES consumes the event, the dialog says nothing."""
    robot.greet()
    obj = robot.sim.bus.participant("object_attention")
    robot.sim.call_at(7.0, obj.publish, ES_EVENTS, etree.Element("event", name="occluded"))
    robot.sim.run(until=12.0)
    assert not any("step aside" in s for s in robot.sentences())
    assert not [r for r in robot.records("/robot/es/conditions/dialog") if 'name="step_aside"' in r["xml"]]


def test_clarification_without_an_answer_times_out_to_none(robot):
    obj = robot.sim.bus.participant("object_attention")
    replies = []

    async def ask() -> None:
        req = etree.fromstring('<ask timeout="2"><option index="0" text="cup"/><option index="1" text="plant"/></ask>')
        replies.append(await obj.call("dialog", "ask", req, timeout=15.0))

    robot.sim.call_at(1.0, lambda: robot.sim.spawn(ask(), name="asker"))
    robot.sim.run(until=15.0)
    assert replies and replies[0].xml.get("none") == "true"
    assert robot.dialog.manager.stack == []
    # The 2 s to answer run from the end of the question (5 words: 2.3 s said), not from the request.
    done = [r["t"] for r in robot.records("/robot/speaker/status") if r["xml"].startswith("<done")]
    assert done and replies[0].created >= done[0] + 2.0 - 1e-6


def test_same_seed_same_trace():
    def run() -> list[str]:
        r = Robot(seed=4)
        try:
            r.greet()
            r.utter("uh this is my red no blue cup", 7.0, 9.0, confidence=0.4)
            r.utter("yes", 11.0, 11.5)
            r.sim.run(until=16.0)
            return [f"{x['t']}|{x.get('channel')}|{x.get('xml')}" for x in r.trace.records() if x.get("kind") == "publish"]
        finally:
            r.sim.close()

    a = run()
    assert a == run()
    assert any("Is this cup?" in line or "Is this" in line for line in a)


def test_barge_in_cuts_the_robots_sentence_in_the_world():
    # Real microphones and loudspeaker: a radio on the robot's left plays while the robot talks
    # (louder at the robot than the partner) and does not cut it off; the partner in front does.
    sc = load_scenario(ROOM)
    sim = Simulation(seed=3, scenario=sc.name)
    stage = Stage(sim, sc, actors=HARDWARE)
    stage.world.sources["radio"] = (1.5, 5.2, 1.0)  # about 77 degrees left of the robot at (1, 3)
    dialog = Dialog(sim)
    status: list[str] = []
    sim.bus.participant("probe").subscribe("/robot/speaker/status", lambda m: status.append(m.xml.tag))
    attention = sim.bus.participant("person_attention")

    def partner() -> None:  # the person attention's report of ann, straight ahead
        el = etree.Element("partner", id="t1", bearing="0.0", distance="2.0", x="2", y="0", vx="0", vy="0",
                           visible="true", lost_for="0")
        attention.publish("/robot/attention/partner", el)
        sim.call_at(sim.now + 0.1, partner)

    try:
        long_text = "I am BIRON and I can follow you, learn your objects and places and tell you where things are."
        sim.call_at(0.2, partner)
        sim.call_at(0.5, lambda: dialog._enqueue(long_text, "test"))
        sim.call_at(1.0, lambda: stage.world.sound.say("radio", "and now the weather for tomorrow", 1.0, loudness=70.0))
        sim.call_at(3.5, lambda: stage.world.sound.say("ann", "stop talking please", 3.5))
        stage.run(7.0)
        (robot_u,) = stage.world.sound.by("robot")
        assert robot_u.cut and 3.5 < robot_u.end < 4.0 and robot_u.text != long_text
        assert dialog.summary()["barge_ins"] == 1
        assert status == ["speaking", "interrupted"]
    finally:
        sim.close()


def test_introspection_lists_what_the_current_state_accepts(robot):
    robot.sim.run(until=0.5)
    st = robot.es.status_xml()
    accepts = {e.get("name"): e.get("status") for e in st.iterfind("accepts/event")}
    assert accepts["potential_partner"] == "applies" and accepts["greeting"] == "waits"
    assert "follow" not in accepts
    assert robot.es.status_xml(history=0).find("accepts") is None  # the status channel stays small


def test_an_empty_say_silences_the_speaker_without_a_new_utterance():
    sc = load_scenario(ROOM)
    sim = Simulation(seed=3, scenario=sc.name)
    st = Stage(sim, sc, actors=HARDWARE)
    p = sim.bus.participant("dialog")
    try:
        sim.call_at(0.5, lambda: p.publish("/robot/speaker/say", etree.Element("say", text="one two three four five six")))
        sim.call_at(1.0, lambda: p.publish("/robot/speaker/say", etree.Element("say")))
        st.run(4.0)
        (u,) = st.world.sound.by("robot")
        assert u.cut and u.end == pytest.approx(1.0, abs=0.11) and u.text == "one"
        assert st.world.sound.cut("robot", 3.0) is None  # nothing left to cut
    finally:
        sim.close()


def test_a_partner_close_to_the_robot_barges_in(robot):
    # The microphones' echo cancellation already removes the robot's own voice from
    # /robot/audio/sources: a loud direction from the partner's bearing while the robot talks
    # is the partner, e.g. 0.6 m away (65 dB at 1 m -> about 69 dB), and cuts the sentence.
    robot.greet()
    robot.partner_at(8.0, 1.5, 3.0)  # the person attention's partner, 8 degrees left
    robot.sim.run(until=2.5)  # the greeting's answer is being spoken
    robot.sound(2.6, 0.0, 69.5)
    robot.sim.run(until=3.0)
    assert robot.sentences()[-1] == ""  # the empty <say/> that cuts the robot's sentence
    assert robot.dialog.summary()["barge_ins"] == 1


@pytest.mark.parametrize("partner,bearing", [
    (0.0, 55.0),  # the radio on the left, the partner in front
    (-30.0, 30.0),  # mirrored: a different direction, however loud
    (None, 0.0),  # no partner reported (nobody engaged, or the attention lost them): nobody to barge in
])
def test_only_sound_from_the_partners_bearing_barges_in(robot, partner, bearing):
    robot.greet()
    if partner is not None:
        robot.partner_at(partner, 1.5, 3.0)
    robot.sim.run(until=2.5)
    robot.sound(2.6, bearing, 75.0)
    robot.sim.run(until=3.0)
    assert "" not in robot.sentences() and robot.dialog.summary()["barge_ins"] == 0


def test_a_talker_behind_the_robot_does_not_cut_it_off_beside_the_partners_bearing(robot):
    # distractor seed 2: Tom talks to himself 4 m behind the robot (about 158 degrees), which the pair
    # hears at the mirrored 22 +- 2 degrees; Anna stands straight ahead. A direction 19-21 degrees off
    # the partner's is not her (the pair resolves a voice in front to about 1.5 degrees): "OK, I
    # stopped." was cut and she never heard it.
    robot.greet()
    robot.partner_at(0.3, 1.5, 3.0)
    robot.sim.run(until=2.5)  # the greeting's answer is being spoken
    for k, bearing in enumerate((21.3, 20.0, 20.9, 19.6)):
        robot.sound(2.6 + 0.1 * k, bearing, 50.0)
    robot.sim.run(until=3.2)
    assert "" not in robot.sentences() and robot.dialog.summary()["barge_ins"] == 0


def test_a_partner_beside_the_robot_barges_in_where_the_pair_hears_her():
    # A partner 1.7 m away, 76 degrees to the side: her mouth above the pair shortens the path
    # difference, so the pair hears her about 7 degrees nearer the front (perceive2's cue).
    from robot.dialog.module import heard_bearing
    from robot.attention.cues import CueSpec, sound_bearings_from
    import math
    spec = CueSpec()
    (expect,) = sound_bearings_from([(1.7 * math.cos(math.radians(76)), 1.7 * math.sin(math.radians(76)))], spec)
    assert heard_bearing(76.0, 1.7) == pytest.approx(math.degrees(expect), abs=1e-9)
    assert (spec.mic_offset, spec.mic_spacing, spec.mic_height, spec.mouth_height) == (0.10, 0.281, 1.06, 1.6)
    robot = Robot()
    try:
        robot.greet()
        robot.partner_at(76.0, 1.5, 3.0, distance=1.7)
        robot.sim.run(until=2.5)
        robot.sound(2.6, math.degrees(expect) - 2.5, 60.0)  # 9.3 degrees off her track bearing
        robot.sim.run(until=3.0)
        assert robot.dialog.summary()["barge_ins"] == 1
    finally:
        robot.sim.close()


def test_the_dialogs_partner_direction_is_the_attentions():
    # One rule for "this sound is the partner's": the dialog's barge-in window is the person
    # attention's sound-to-track tolerance (the track's "speaking" cue).
    import math

    from robot.attention.cues import CueSpec
    assert Dialog.__init__.__kwdefaults__["barge_in_width"] == pytest.approx(math.degrees(CueSpec().sound_tolerance))


def test_the_partner_behind_the_robot_is_heard_at_the_mirrored_bearing(robot):
    # The pair's directions lie in the front half-plane: a partner at 170 degrees sounds at 10.
    robot.greet()
    robot.partner_at(170.0, 1.5, 3.0)
    robot.sim.run(until=2.5)
    robot.sound(2.6, 10.0, 60.0)
    robot.sim.run(until=3.0)
    assert robot.dialog.summary()["barge_ins"] == 1


def test_a_sound_frame_recorded_before_the_robot_began_its_sentence_does_not_barge_in(robot):
    """Over a slow link the microphones' frames arrive late: one recorded while the partner was still
    finishing her turn, delivered once the robot has begun its answer, is not an interruption; a frame
    recorded after the robot began is (wlan_reorder's queued downlink cut every farewell this way)."""
    robot.greet()
    robot.partner_at(0.0, 1.5, 3.5)
    robot.sim.run(until=2.5)  # the greeting's answer is being spoken
    start = robot.dialog._talk_start
    assert 0.0 < start < 2.5

    def late(recorded: float) -> None:
        el = etree.Element("sources", time=f"{recorded:.6f}")
        etree.SubElement(el, "source", tdoa="0", bearing="0", level="70")
        robot.mic.publish("/robot/audio/sources", el)

    robot.sim.call_at(2.6, lambda: late(start - 0.3))
    robot.sim.run(until=2.8)
    assert robot.dialog.summary()["barge_ins"] == 0
    robot.sim.call_at(2.9, lambda: late(2.85))
    robot.sim.run(until=3.2)
    assert robot.dialog.summary()["barge_ins"] == 1


def test_a_stale_partner_bearing_does_not_barge_in(robot):
    robot.greet()
    robot.partner_at(0.0, 1.0, 1.2)  # reported, then no more (the partner left)
    robot.sim.run(until=2.5)
    robot.sound(2.6, 0.0, 70.0)
    robot.sim.run(until=3.0)
    assert robot.dialog.summary()["barge_ins"] == 0


def test_no_robot_module_asks_the_dialog_directly():
    """The papers route every question a reactive or intermediate module has for the user through the ES
    (an event to it, a condition to the dialog): no robot module calls the dialog's RPCs (``dialog/ask`` is
    for tools)."""
    import ast
    from pathlib import Path

    root = Path(__file__).resolve().parents[1] / "robot"
    direct = []
    for path in sorted(root.rglob("*.py")):
        if path.parent.name == "dialog":
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "call" \
                    and node.args and isinstance(node.args[0], ast.Constant) and node.args[0].value == "dialog":
                direct.append(f"{path.relative_to(root.parent)}:{node.lineno}")
    assert direct == []


def _voices(robot, bearing: float, start: float, end: float, level: float = 58.0) -> None:
    """A voice from ``bearing`` in every microphone frame (10 Hz) from ``start`` to ``end``."""
    k = 0
    while start + 0.1 * k <= end + 1e-9:
        robot.sound(start + 0.1 * k, bearing, level)
        k += 1


def _answer_time(voices_until: float | None) -> tuple[float | None, dict]:
    """When the answer to "what can you do" (said 7.0-7.8 s) is begun, with a voice where she stands
    from 7.9 s until ``voices_until`` (None: no voice), and the dialog's summary."""
    r = Robot()
    try:
        r.greet()
        r.partner_at(0.0, 1.5, 16.0)
        r.sim.run(until=6.5)
        r.utter("what can you do", 7.0, 7.8)
        if voices_until is not None:
            _voices(r, 2.0, 7.9, voices_until)
        r.sim.run(until=16.0)
        said = [x for x in r.records("/robot/speaker/say") if x["t"] > 7.0]
        return (said[0]["t"] if said else None), r.dialog.summary()
    finally:
        r.sim.close()


def test_the_robot_does_not_begin_to_talk_while_someone_talks_where_she_stands():
    # fresh3 passage_talk_aside: Sara and Tom talk to each other in turns; the robot began its answer
    # between their overlapping turns and was cut off at once, eight times. It waits for a pause.
    ready, _ = _answer_time(None)
    assert ready is not None
    # a voice that ends just before the answer is ready: the answer waits for the pause after it
    t, summary = _answer_time(ready - 0.15)
    assert t is not None and t >= ready - 0.15 + 0.5 - 0.1 and summary["held_for_a_pause"] == 1
    assert summary["barge_ins"] == 0
    # a voice that goes on after the answer was ready: begun, it would have been cut at once; it is
    # not said at all (no words over hers, no empty <say/>), her words are her next turn
    t, summary = _answer_time(ready + 2.0)
    assert t is None and summary["barge_ins"] == 1


def test_a_repair_for_words_after_which_the_talk_went_on_is_dropped(robot):
    robot.greet()
    robot.partner_at(0.0, 1.5, 14.0)
    robot.sim.run(until=6.5)
    robot.sentences()
    robot.utter("gorble flimp", 7.0, 7.8)  # not understood
    _voices(robot, -3.0, 8.2, 10.0)  # the next turn, another voice where she stands
    robot.sim.run(until=13.0)
    assert robot.sentences() == []  # no "Could you say that again?" to a talk that went on
    assert robot.dialog.summary()["stale_repairs_dropped"] == 1


def test_with_a_pause_the_repair_is_said_and_voices_elsewhere_hold_nothing(robot):
    robot.greet()
    robot.partner_at(0.0, 1.5, 14.0)
    robot.sim.run(until=6.5)
    robot.sentences()
    robot.utter("gorble flimp", 7.0, 7.8)
    _voices(robot, 60.0, 7.9, 10.0)  # a radio to the left: not where she stands
    robot.sim.run(until=10.0)
    assert robot.sentences() == ["Sorry, I did not understand you. Could you say that again?"]
    assert robot.dialog.summary()["held_for_a_pause"] == 0


def _radio(robot, bearing: float, start: float, end: float, level: float = 58.0) -> None:
    """A radio reading on from ``bearing``: 4 s of voice, a 0.3 s breath, again, from ``start`` to ``end``."""
    t = start
    while t < end:
        _voices(robot, bearing, t, min(t + 4.0, end), level)
        t += 4.3


def test_a_radio_where_she_stands_that_never_pauses_does_not_silence_the_robot(robot):
    # review12 item 5: a radio behind her, on her bearing, reading the news with 0.3 s breaths held every
    # sentence up to HOLD_MAX s and cut every answer off; a voice with no pause for VOICE_RUN_MAX s is no turn
    from robot.dialog.module import VOICE_RUN_MAX
    robot.greet()
    robot.partner_at(0.0, 1.5, 40.0)
    robot.sim.run(until=2.0)
    robot.sentences()
    _radio(robot, 2.0, 2.0, 40.0)
    at = 2.0 + VOICE_RUN_MAX + 1.0
    robot.sim.run(until=at)
    robot.sentences()
    cut = robot.dialog.summary()["barge_ins"]  # the greeting's end, cut as the radio began: it could not know
    robot.utter("what can you do", at, at + 0.8)
    robot.sim.run(until=at + 3.0)
    (answer,) = robot.sentences()  # answered within 2.2 s, not held, and not cut off
    assert answer.startswith("I am listening to you.")
    assert robot.dialog.summary()["barge_ins"] == cut


def test_a_repair_is_never_dropped_twice_in_a_row(robot):
    robot.greet()
    robot.partner_at(0.0, 1.5, 20.0)
    robot.sim.run(until=6.5)
    robot.sentences()
    robot.utter("gorble flimp", 7.0, 7.8)
    _voices(robot, -3.0, 8.2, 10.0)  # the talk went on: this repair is dropped
    robot.utter("gorble flimp", 10.4, 11.2)
    _voices(robot, -3.0, 11.6, 13.0)  # and on again: the second one is said in the next pause
    robot.sim.run(until=16.0)
    assert robot.sentences() == ["Sorry, I did not understand you. Could you say that again?"]
    assert robot.dialog.summary()["stale_repairs_dropped"] == 1


def test_a_good_bye_said_while_it_looks_waits_until_the_object_is_learned(robot):
    # talk13 (fresh4 loft_teach_walking_past): "thanks bye" right after "Let me have a look" ended the look and the
    # kettle was never stored; now the look ends first, then the good-bye
    robot.greet()
    robot.utter("this is my cup", 6.0, 7.0)
    robot.utter("thanks bye", 9.0, 9.6)
    objects = robot.sim.bus.participant("object_attention")
    cup = etree.fromstring('<OBJECT type="cup" name="cup" owner="partner" x="1" y="0" z="0.8" frame="map"/>')
    robot.sim.call_at(12.0, lambda: objects.publish(ES_EVENTS, event_xml("object_recognized", children=(cup,))))
    robot.sim.run(until=11.5)
    said = robot.sentences()
    assert "Let me have a look." in said and not any("Good-bye" in s for s in said)  # still looking: no good-bye yet
    robot.sim.run(until=20.0)
    said = robot.sentences()
    learned = next(i for i, s in enumerate(said) if s.startswith("OK, I have learned"))
    assert any(i > learned for i, s in enumerate(said) if "Good-bye" in s)


def test_a_step_aside_question_cut_by_her_voice_is_asked_again_and_reported_said_only_then(robot):
    """review22 R2 (fresh10 hall_wardrobe_bags): her voice cut the step-aside question after three words and the
    dialog still told the ES it had been said; the object attention then waited for a step she never heard of. A
    question cut by a barge-in is not said: it is put again once she pauses, and ``asked_aside`` comes after that."""
    robot.partner_at(0.0, 1.5, 40.0)
    orders = _teach_then_occluded(robot)
    asked = None
    while asked is None and robot.sim.now < 20.0:
        robot.sim.run(until=robot.sim.now + 0.1)
        asked = next((m for m in robot.said.drain() if "step aside" in (m.xml.get("text") or "")), None)
    assert asked is not None
    for k in range(5):  # she talks over it right away, from where she stands
        robot.sound(robot.sim.now + 0.2 + 0.1 * k, 0.0, 70.0)
    robot.sim.run(until=robot.sim.now + 0.8)
    assert robot.dialog.summary()["barge_ins"] >= 1
    cut_at = robot.sim.now
    assert not [o for o in orders if o.xml.get("name") == "asked_aside"]  # not reported said when it was cut
    robot.sim.run(until=cut_at + 30.0)
    asks = [r["t"] for r in robot.records("/robot/speaker/say") if "step aside" in r["xml"]]
    assert len(asks) == 2 and asks[1] > cut_at  # put again once she paused
    done = [r["t"] for r in robot.records("/robot/speaker/status")
            if r["xml"].startswith("<done") and "step aside" in r["xml"] and r["t"] > asks[1]]
    (said,) = [o for o in orders if o.xml.get("name") == "asked_aside"]
    assert done and said.xml.find("param[@name='said']").text == "true" and said.created >= done[0]
