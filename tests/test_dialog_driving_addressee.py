"""The addressee rule while the robot drives on its own (Navigating; goto_l_flat: a bystander on the
phone in the corridor said "See you later then" facing the robot as it passed, and the good-bye
cancelled a go-to 0.15 m from its goal). The person attention sleeps there, so the microphones decide:
words are the partner's unless several sound frames heard voices and none came from where she was
last reported; a stop is always taken."""

from __future__ import annotations

import math
from collections import deque

from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from robot.dialog.loader import BIRON_DIALOGS, load
from robot.dialog.manager import DialogManager
from robot.dialog.module import VOICE_FRAMES, Dialog, front_bearing, heard_bearing, heard_span, span_off

DOC = load(BIRON_DIALOGS)


def _dialog(place, pose, sources) -> Dialog:
    d = Dialog.__new__(Dialog)  # the rule only: no bus
    d.manager = DialogManager(DOC)
    d.manager.es_state = "Navigating"
    d._partner_cues = deque(maxlen=300)
    d._partner_place = place
    d._pose = etree.Element("pose", x=f"{pose[0]}", y=f"{pose[1]}", theta=f"{pose[2]}", frame="map")
    d._sources = deque(sources, maxlen=300)
    d.barge_in_width = 9.0
    return d


def _her(place, pose) -> float:
    dx, dy = place[0] - pose[0], place[1] - pose[1]
    b = math.degrees(math.remainder(math.atan2(dy, dx) - pose[2], 2 * math.pi))
    return front_bearing(heard_bearing(b, max(math.hypot(dx, dy), 0.3)))


@settings(max_examples=200, deadline=None)
@given(st.tuples(st.floats(-6, 6), st.floats(-6, 6)), st.floats(-math.pi, math.pi),
       st.lists(st.floats(-89, 89), min_size=0, max_size=8))
def test_words_are_hers_unless_enough_voices_none_from_her_place(place, theta, voices):
    pose = (0.0, 0.0, theta)
    if math.hypot(*place) < 0.5:
        place = (place[0] + 1.0, place[1])
    frames = [(10.0 + 0.1 * i, (b,)) for i, b in enumerate(voices)]
    d = _dialog(place, pose, frames)
    her = _her(place, pose)
    # where she may be heard: a span over the mouth heights a person may have (heard_span)
    b_deg = math.degrees(math.remainder(math.atan2(place[1], place[0]) - theta, 2 * math.pi))
    span = heard_span(b_deg, max(math.hypot(*place), 0.3))
    assert span[0] - 1e-9 <= her <= span[1] + 1e-9
    near = any(span_off(b, span) <= 9.0 for b in voices)
    assert d.addressed(10.0, 11.0) == (len(voices) < VOICE_FRAMES or near)


def test_the_corridor_bystanders_good_bye_is_not_hers_but_a_voice_from_her_place_is():
    # she stayed in the living room 5 m behind-left; the bystander stands 1 m ahead-right of the robot
    place, pose = (-4.0, 3.0), (0.0, 0.0, 0.0)
    bystander = [(10.0 + 0.1 * i, (-40.0,)) for i in range(6)]
    assert not _dialog(place, pose, bystander).addressed(10.0, 10.6)
    hers = [(10.0 + 0.1 * i, (_her(place, pose),)) for i in range(6)]
    assert _dialog(place, pose, hers).addressed(10.0, 10.6)
    # nothing known about her place: hers
    assert _dialog(None, pose, bystander).addressed(10.0, 10.6)


def test_a_stop_while_driving_is_always_taken():
    d = _dialog((-4.0, 3.0), (0.0, 0.0, 0.0), [(10.0 + 0.1 * i, (-40.0,)) for i in range(6)])
    taken: list[str] = []
    d._on_addressed = lambda msg: taken.append(msg.xml.find("SPEECH")[0].tag)
    d.not_addressed = 0

    class Msg:
        def __init__(self, act: str) -> None:
            self.xml = etree.fromstring(f'<understood start="10.0" end="10.6" confidence="0.9"><SPEECH><{act}/></SPEECH><words>w</words></understood>')
    d._on_frame(Msg("STOP"))
    d._on_frame(Msg("GOODBYE"))
    assert taken == ["STOP"] and d.not_addressed == 1
