"""review18's findings on the chat18 rules (fixrev19).

F1: the voice-level rule takes a quieter voice from the partner's direction as another person's only when the
robot sees someone else besides her (the attention's ``others``: a person right behind her is hidden from the
laser by her legs, so not only someone seen in line behind her), and never words she says
again after getting no answer. F6: the level references are cleared when an interaction ends."""

from __future__ import annotations

import math
from collections import deque
from types import SimpleNamespace

from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from robot.dialog.module import FARTHER_DB, VOICE_FRAMES, Dialog

from tests.test_chat18 import CHAT, _dialog, _frame, _turn


def _face_to_face(her_levels, frames, dist=1.2, others=0):
    d = _dialog("Interacting")
    d._partner_cues = deque([(10.0 + 0.1 * i, "true", 0, 1.0) for i in range(40)], maxlen=300)
    d._others_cues = deque([(10.0 + 0.1 * i, others) for i in range(40)], maxlen=300)
    d._sources = deque([(t, (b,)) for t, b, _ in frames], maxlen=300)
    d._levels = deque(frames, maxlen=600)
    d._partner_dist = (dist, 14.0)
    d._partner_dists = deque(maxlen=300)
    d._her_levels = deque(her_levels, maxlen=5)
    d._her_turns = deque(maxlen=5)
    return d


# ---------------------------------------------------------------- F1
def test_her_own_softer_words_are_answered_when_nobody_else_is_seen():
    ref = 60.0 + 20 * math.log10(1.2)
    soft = 60.0 - 5.0  # 5 dB under her voice, at the same distance (across a counter, a quieter line)
    assert _face_to_face([ref], _turn(soft)).addressed(10.5, 12.0)
    # the same voice with someone else in the room is his
    assert not _face_to_face([ref], _turn(soft), others=1).addressed(10.5, 12.0)
    # ... unless she says it again after it got no answer
    assert _face_to_face([ref], _turn(soft), others=1).addressed(10.5, 12.0, repeated=True)


@settings(max_examples=200, deadline=None)
@given(ref=st.floats(45.0, 70.0), delta=st.floats(-25.0, 20.0), dist=st.floats(0.5, 3.0), n=st.integers(0, 20),
       others=st.integers(0, 2), repeated=st.booleans(), named=st.booleans())
def test_a_quieter_voice_is_dropped_only_with_someone_else_seen(ref, delta, dist, n, others, repeated, named):
    level = ref + delta - 20 * math.log10(dist)
    d = _face_to_face([ref], _turn(level, n=n), dist=dist, others=others)
    dropped = not d.addressed(10.5, 10.5 + 0.1 * max(n, 1), named=named, repeated=repeated)
    if others == 0 or repeated or named or n < VOICE_FRAMES or delta > -FARTHER_DB + 1.6:
        assert not dropped  # she faces the robot the whole time: only the level rule could drop it
    if others >= 1 and not (repeated or named) and n >= VOICE_FRAMES and delta < -FARTHER_DB - 1.6:
        assert dropped


def test_alone_softer_scene_seed_1_her_quieter_request_is_answered(capsys) -> None:
    from pathlib import Path

    from homesim.cli import main

    scene = Path(__file__).resolve().parent / "scenarios" / "flow" / "fixrev19_alone_softer.xml"
    code = main(["run", str(scene), "--seed", "1"])
    out = capsys.readouterr().out
    assert code == 0, out


# ---------------------------------------------------------------- F6
def test_the_level_references_are_cleared_when_the_interaction_ends():
    d = _face_to_face([50.0], [])
    d._her_turns.append((1.0, 2.0))
    d._queue = deque()
    d._goodbye_held = None
    d._emit = lambda outs, cause: None
    d._on_status(SimpleNamespace(xml=etree.Element("status", state="Interacting"), id="s1"))
    assert list(d._her_levels) == [50.0]  # still hers
    d._on_status(SimpleNamespace(xml=etree.Element("status", state="LookingAround"), id="s2"))
    assert not d._her_levels and not d._her_turns  # the next partner's voice is learned from her own turns

