"""flow7: a partner who walked off and turned her back talks to herself (issue 26 item 3).

The person attention marks the partner turned away in Interaction when her track walks away from the
robot (a walker faces where she goes) and clears it on her frontal face or when she walks back towards
it; the camera looks at her face meanwhile, so it sees her turn back. The dialog's addressee rule drops
words during which every report has her turned away 1.2 m or further off (docs/semantics.md §3).
End to end in a new flat (tests/scenarios/flow/mutter_at_window.xml: on main the robot answered the
muttered "where are my glasses"); the two rules as Hypothesis properties."""

from __future__ import annotations

import math
from collections import deque
from pathlib import Path
from types import SimpleNamespace

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from homesim.tour.runner import RunOptions, run_file
from robot.attention.module import AttentionParams, PersonAttention
from robot.dialog.manager import DialogManager
from robot.dialog.module import ASIDE, ASIDE_DISTANCE, Dialog
from robot.dialog.loader import BIRON_DIALOGS, load
from robot.speech.module import calls_robot, frame_message, shared_understander

SCENE = Path(__file__).resolve().parent / "scenarios" / "flow" / "mutter_at_window.xml"
DOC = load(BIRON_DIALOGS)


def test_muttering_at_the_window_is_not_answered_and_turning_back_is_heard():
    s = run_file(SCENE, RunOptions(seed=0))  # main: "Sorry, I don't know where to find your glasses." at 17.4 s
    assert s["verdict"] == "PASS", [e for e in s["expectations"] if not e["passed"]]
    assert s["metrics"]["dialog"]["subdialogs"]["not_addressed"] >= 1


# ------------------------------------------------------------------ the attention's flag
class _Tracks:
    def __init__(self, x: tuple[float, float, float, float] | None) -> None:
        self.tracks = [SimpleNamespace(id=1, x=x)] if x is not None else []

    def row(self, tid: int) -> int:
        return 0 if self.tracks and tid == 1 else -1


def _attention(state: str) -> PersonAttention:
    pa = PersonAttention.__new__(PersonAttention)  # the rule only: no bus
    pa.params = AttentionParams()
    pa._odom = None  # the robot at the odometry origin
    pa.partner = 1
    pa.turned_away = False
    pa.fsm = SimpleNamespace(state=state)
    return pa


OBS = st.lists(st.tuples(st.floats(0.3, 4.0), st.floats(-3.14, 3.14), st.floats(-1.2, 1.2), st.floats(-1.2, 1.2), st.booleans(),
                         st.booleans()), min_size=1, max_size=25)


@settings(max_examples=300, deadline=None)
@given(obs=OBS, state=st.sampled_from(["Interaction", "Follow", "Object"]))
def test_turned_away_is_the_last_decisive_evidence(obs, state):
    """Turned away = the latest decisive observation was her walking away (at leave_speed or faster)
    rather than her frontal face or her walking towards the robot; standing still changes nothing;
    outside Interaction (she leads in Follow; the robot looks at an object) never; no track, never."""
    pa = _attention(state)
    expect = False
    for d, b, vx, vy, face, tracked in obs:
        x, y = d * math.cos(b), d * math.sin(b)
        pa.tracks = _Tracks((x, y, vx, vy) if tracked else None)
        pa.facing = SimpleNamespace(on=lambda tid, f=face: f)
        pa._turning_away(0.0)
        radial = (vx * x + vy * y) / d
        if state != "Interaction" or not tracked or face or radial <= -pa.params.leave_speed:
            expect = False
        elif radial >= pa.params.leave_speed:
            expect = True
        assert pa.turned_away == expect


# ------------------------------------------------------------------ the dialog's rule
def _dialog(state: str, reports: list[tuple[float, str, int]]) -> Dialog:
    d = Dialog.__new__(Dialog)
    d.manager = DialogManager(DOC)
    d.manager.es_state = state
    d._partner_cues = deque([(*r, 0.0) for r in reports], maxlen=300)
    d._sources = deque(maxlen=300)
    d.barge_in_width = 9.0
    d._addressed_at = -math.inf  # no exchange with the robot yet
    d._aside_since = math.inf
    return d


CUES = st.lists(st.tuples(st.sampled_from(["true", "false", "unknown", ASIDE]), st.integers(0, 2)), min_size=1, max_size=30)


@settings(max_examples=300, deadline=None)
@given(cues=CUES, state=st.sampled_from(["Interacting", "ObjectTeaching"]))
def test_words_said_turned_aside_throughout_are_not_for_the_robot(cues, state):
    d = _dialog(state, [(10.0 + 0.1 * i, f, c) for i, (f, c) in enumerate(cues)])
    end = 10.0 + 0.1 * (len(cues) - 1)
    heard = d.addressed(10.0, end)
    if all(f == ASIDE for f, _ in cues):
        assert not heard  # turned aside the whole time: talking to herself, alone or not
    faced = [i for i, (f, _) in enumerate(cues) if f == "true"]
    if faced:
        # she faced it while speaking: hers, unless after her last facing she was turned away for at least half
        # the words and ended turned to someone near her (addr23: what she does after outweighs an older facing)
        # (stated one-sidedly, review23 N5: the property must not restate the implementation's formula)
        after = cues[faced[-1] + 1:]
        if 2 * len(after) < len(cues) or after[-1:] == [] or after[-1][1] == 0:
            assert heard  # she faced it and turned away only briefly, or ended with nobody near her
        if 2 * len(after) >= len(cues) and all(f in ("false", ASIDE) for f, _ in after) and after[-1][1] >= 1:
            assert not heard  # after the facing, turned away for at least half the words, ending by someone
    if any(f == "unknown" for f, _ in cues) and cues[-1][1] == 0:
        assert heard  # not turned aside throughout (she turned back, or the camera could not tell), alone


def _report(d: Dialog, facing: str, away: bool, distance: float) -> None:
    attrs = {"bearing": "10", "distance": f"{distance}", "facing": facing, "company": "0"}
    if away:
        attrs["away"] = "true"
    d._on_partner(SimpleNamespace(xml=etree.Element("partner", **attrs), created=d.now))


@settings(max_examples=200, deadline=None)
@given(facing=st.sampled_from(["true", "false", "unknown"]), away=st.booleans(), distance=st.floats(0.3, 3.5))
def test_a_report_is_kept_as_turned_aside_only_away_and_far_and_not_facing(facing, away, distance):
    d = Dialog.__new__(Dialog)
    d._partner_cues = deque(maxlen=300)
    d._pose = None
    d.sim = SimpleNamespace(now=5.0)  # Module.now reads the sim's clock
    d.partner_fresh = 2.0
    _report(d, facing, away, distance)
    kept = d._partner_cues[-1][1]
    assert (kept == ASIDE) == (away and distance >= ASIDE_DISTANCE and facing != "true")
    if kept == ASIDE:
        assert d._facing_now() == "false"  # her back turned: sides are taken as her own view's


@settings(max_examples=200, deadline=None)
@given(cues=CUES, state=st.sampled_from(["Interacting", "ObjectTeaching"]))
def test_words_that_call_the_robot_by_its_name_are_for_it_even_turned_aside(cues, state):
    # lang_names: Ben walks off to the lounge, turns round out of the camera's face range and says
    # "BIRON please go to the lounge": his name for the robot says whom the words are for
    d = _dialog(state, [(10.0 + 0.1 * i, f, c) for i, (f, c) in enumerate(cues)])
    end = 10.0 + 0.1 * (len(cues) - 1)
    if all(f == ASIDE for f, _ in cues):
        assert d.addressed(10.0, end, named=True)
    assert d.addressed(10.0, end) <= d.addressed(10.0, end, named=True)  # the name never makes words less addressed


@pytest.mark.parametrize("state", ["Interacting", "ObjectTeaching"])
def test_a_partner_turned_aside_throughout_is_heard_only_when_she_names_the_robot(state):
    # the case the property above reaches only when Hypothesis draws every cue turned aside
    d = _dialog(state, [(10.0 + 0.1 * i, ASIDE, 0) for i in range(8)])
    assert not d.addressed(10.0, 10.7)  # "where did I put that novel": to herself
    assert d.addressed(10.0, 10.7, named=True)  # "BIRON, go to the lounge": to the robot


@pytest.mark.parametrize(("words", "named"), [
    ("BIRON please go to the lounge", True), ("byron, follow me", True), ("hello biron", True),
    ("where did I put that novel", False), ("go to the lounge", False)])
def test_the_frame_says_when_the_words_call_the_robot_by_its_name(words, named):
    understander = shared_understander()
    el = frame_message(understander.understand(words), 1.0, 2.0, 0.9, calls_robot(words, understander.lexicon))
    assert (el.get("named") == "true") == named


@settings(max_examples=200, deadline=None)
@given(cues=CUES, state=st.sampled_from(["Interacting", "ObjectTeaching"]))
def test_showing_something_turned_aside_is_for_the_robot(cues, state):
    # fresh3 open_two_cups_rooms seeds 0-2: Nina walks on to the desk, her back to the robot 1.3 m
    # behind her, and says "and this one is my husband's cup" pointing at it: showing needs an onlooker
    d = _dialog(state, [(10.0 + 0.1 * i, f, c) for i, (f, c) in enumerate(cues)])
    end = 10.0 + 0.1 * (len(cues) - 1)
    if all(f == ASIDE for f, _ in cues):
        assert d.addressed(10.0, end, shows=True) and not d.addressed(10.0, end)
    else:  # the other rules as they were: showing never makes words less meant for the robot
        assert d.addressed(10.0, end, shows=True) or not d.addressed(10.0, end)


def test_once_she_has_talked_with_the_robot_turned_aside_she_goes_on_talking_to_it():
    """The rule's evidence is the whole exchange: words turned aside are her own only until the robot
    has taken a turn of hers since she turned aside (then "where is my cup" and "good bye" with her
    back still turned are meant for it: open_two_cups_rooms lost both)."""
    d = _dialog("Interacting", [(10.0 + 0.1 * i, ASIDE, 0) for i in range(20)])
    d._aside_since = 10.0
    assert not d.addressed(10.0, 11.9)  # muttering, nothing said to the robot since she turned aside
    d._addressed_at = 9.0  # an exchange before she turned aside says nothing about now
    assert not d.addressed(10.0, 11.9)
    d._addressed_at = 12.5  # the robot took a turn of hers after she turned aside
    d._partner_cues.extend((13.0 + 0.1 * i, ASIDE, 0, 0.0) for i in range(10))
    assert d.addressed(13.0, 13.9)


@settings(max_examples=200, deadline=None)
@given(other=st.floats(10.0, 80.0), n=st.integers(3, 40), hers=st.integers(0, 40), facing=st.sampled_from(["unknown", "false", "true"]))
def test_face_to_face_words_mostly_heard_from_elsewhere_are_another_talkers(other, n, hers, facing):
    # distractor seed 0 (obj12): Tom's "I need to find my keys now", 13 degrees off Anna, overlapping
    # the start of her next turn by 0.3 s, was taught as her keys
    hers = min(hers, n)
    d = _dialog("Interacting", [(10.0 + 0.1 * i, facing, 0) for i in range(n)])
    for i in range(n):
        d._sources.append((10.0 + 0.1 * i, (0.5,) if i < hers else (other,)))
    heard = d.addressed(10.0, 10.0 + 0.1 * (n - 1))
    if facing == "true":
        assert heard  # she faced the robot while the words were said
    else:
        assert heard == (hers >= 0.25 * n)
