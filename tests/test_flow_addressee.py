"""flow4: speech not addressed to the robot, and instructions the ES rejects at once.

The addressee rule (robot/dialog/module.py, docs/attention.md): an utterance during which the
partner never faced the robot, was mostly (and at its end) turned away, and ended in a group is the
group's chat, not a request. End to end in new flats with new people (scenarios/flow/; the rates
over seeds 0-9 are in the branch's report); the rule itself as Hypothesis properties."""

from __future__ import annotations

from collections import deque
from pathlib import Path

from hypothesis import given, settings
from hypothesis import strategies as st

from homesim.tour.runner import RunOptions, run_file
from robot.attention.module import AttentionParams, PersonAttention
from robot.dialog.manager import DialogManager
from robot.dialog.module import Dialog
from robot.dialog.loader import BIRON_DIALOGS, load

SCENES = Path(__file__).resolve().parent.parent / "scenarios" / "flow"
DOC = load(BIRON_DIALOGS)


def _run(name: str, seed: int = 0) -> dict:
    return run_file(SCENES / f"{name}.xml", RunOptions(seed=seed))


def _said(summary: dict) -> list[str]:
    return [u["text"] for u in summary["utterances"] if u.get("speaker") == "robot"]


def test_a_bystanders_good_bye_to_the_partner_in_their_group_does_not_end_the_interaction():
    s = _run("chat_group_bye", seed=2)  # main: the good-bye was applied at 19.5 s, "did not understand" at 16.7 s
    assert s["verdict"] == "PASS", [e for e in s["expectations"] if not e["passed"]]
    assert s["metrics"]["dialog"]["subdialogs"]["not_addressed"] >= 2


def test_a_request_while_following_is_answered_at_once_with_say_stop_first():
    s = _run("teach_while_following")
    assert s["verdict"] == "PASS", [e for e in s["expectations"] if not e["passed"]]
    assert any("say stop first" in t for t in _said(s))


def test_follow_me_while_the_robot_looks_at_an_object_is_refused_with_the_reason():
    s = _run("follow_while_looking")
    assert s["verdict"] == "PASS", [e for e in s["expectations"] if not e["passed"]]
    assert any("still looking at the object" in t for t in _said(s))


# ------------------------------------------------------------------- the rule itself
def _dialog(state: str, reports: list[tuple[float, str, int]], sources=(), bearing: float = 0.0) -> Dialog:
    d = Dialog.__new__(Dialog)  # the rule only: no bus
    d.manager = DialogManager(DOC)
    d.manager.es_state = state
    d._partner_cues = deque([(*r, bearing) for r in reports], maxlen=300)
    d._sources = deque(sources, maxlen=300)
    d.barge_in_width = 9.0
    return d


FACING = st.sampled_from(["true", "false", "unknown"])
REPORTS = st.lists(st.tuples(FACING, st.integers(0, 3)), max_size=30)
STATES = st.sampled_from(["Interacting", "ObjectTeaching", "Following"])


def _at(cues: list[tuple[str, int]], t0: float = 10.0) -> list[tuple[float, str, int]]:
    return [(t0 + 0.1 * i, f, c) for i, (f, c) in enumerate(cues)]


@settings(max_examples=300, deadline=None)
@given(cues=REPORTS, state=STATES)
def test_the_addressee_rule(cues, state):
    d = _dialog(state, _at(cues))
    end = 10.0 + 0.1 * max(0, len(cues) - 1)
    addressed = d.addressed(10.0, end)
    if state == "Following" or not cues or cues[-1][1] == 0 or cues[-1][0] != "false":
        assert addressed  # she leads, nothing known, nobody with her, or not turned away at the end
    faced = [i for i, (f, _) in enumerate(cues) if f == "true"]
    if state != "Following" and faced and 2 * (len(cues) - 1 - faced[-1]) < len(cues):
        assert addressed  # she faced it during the words and turned away (if at all) for less than half of them
    if state != "Following" and cues and all(f == "false" for f, _ in cues) and cues[-1][1] >= 1:
        assert not addressed  # turned away throughout, in a group: their chat
    # reports outside the utterance change nothing
    before = _dialog(state, [(1.0, "true", 0), *_at(cues), (99.0, "true", 0)])
    assert before.addressed(10.0, end) == addressed


AWAY = st.tuples(st.sampled_from(["false", "unknown"]), st.integers(0, 3))


@settings(max_examples=300, deadline=None)
@given(first=st.lists(st.tuples(FACING, st.integers(0, 3)), max_size=15), turn=st.lists(AWAY, min_size=1, max_size=30),
       company=st.integers(1, 3), state=st.sampled_from(["Interacting", "ObjectTeaching"]))
def test_turning_to_the_group_for_most_of_the_words_outweighs_an_older_facing(first, turn, company, state):
    # addr23 (docs/subsystems.md, the addressee rule): she faces the robot, then is seen turned away for at least
    # half the words, every report after the facing away from it and the last one with someone near her: the
    # group's chat, however she faced the robot at the start (chat_group_bye seed 2 with the camera raised for her
    # hands: Olga faced it 0.4 s as Rosa began "how was your holiday", then walked over). Stated one-sidedly from
    # the docs, not by the implementation's formula (review23 N5): the reports after the facing are all away here
    after = [("false", c) for _, c in turn[:-1]] + [("false", company)]
    first = first[:max(0, len(after) - 1)]  # the turn after the facing is at least half the words
    cues = [*first, ("true", 0), *after]
    d = _dialog(state, _at(cues))
    end = 10.0 + 0.1 * (len(cues) - 1)
    assert not d.addressed(10.0, end)
    # the words after the facing alone are no request either: every face seen then looked away, ending in a group
    only_away = _dialog(state, _at(after))
    assert not only_away.addressed(10.0, 10.0 + 0.1 * (len(after) - 1))
    # ... but calling the robot by its name is meant for it, and so is a request to follow her ("follow me"), said
    # as she turns to lead the way past the people by her (review23 N1)
    assert d.addressed(10.0, end, named=True)
    assert d.addressed(10.0, end, leads=True, to_robot=True)
    # ... and so is turning back to face it at the end
    back = _dialog(state, _at([*cues, ("true", company)]))
    assert back.addressed(10.0, 10.0 + 0.1 * len(cues))


@settings(max_examples=300, deadline=None)
@given(first=st.lists(st.tuples(FACING, st.integers(0, 3)), max_size=15), turn=st.lists(AWAY, max_size=15),
       state=st.sampled_from(["Interacting", "ObjectTeaching"]))
def test_a_facing_followed_by_a_short_turn_or_ending_alone_is_meant_for_the_robot(first, turn, state):
    # the other side of the rule: she faced the robot during the words and what she did after is short (fewer
    # reports than half the words), or she ended with nobody near her: the words are the robot's
    cues = [*first, ("true", 0), *turn]
    after = turn
    end = 10.0 + 0.1 * (len(cues) - 1)
    d = _dialog(state, _at(cues))
    if 2 * len(after) < len(cues) or not after or after[-1][1] == 0:
        assert d.addressed(10.0, end)
    alone = [*first, ("true", 0), *[(f, 0) for f, _ in turn]]
    assert _dialog(state, _at(alone)).addressed(10.0, 10.0 + 0.1 * (len(alone) - 1))


def test_follow_me_said_facing_the_robot_then_turning_to_lead_past_a_friend_is_a_request():
    # review23 N1: "please follow me into the kitchen", facing the robot for 0.8 s, then walking to the door past
    # her friend (walking away: facing "false"; the friend within the group radius: company 1) for the rest
    cues = [("true", 1)] * 8 + [("false", 1)] * 10
    d = _dialog("Interacting", _at(cues))
    assert d.addressed(10.0, 10.0 + 0.1 * (len(cues) - 1), leads=True, to_robot=True)
    # the same turn with words that are no request to follow her: the group's chat, as chat_group_bye seed 2
    assert not d.addressed(10.0, 10.0 + 0.1 * (len(cues) - 1))


@settings(max_examples=200, deadline=None)
@given(faced=st.integers(1, 9), turned=st.integers(10, 20), company=st.integers(1, 3), d0=st.floats(0.6, 2.5),
       walked=st.floats(0.0, 1.5), to_robot=st.booleans())
def test_a_follow_said_then_turned_to_a_friend_is_for_the_robot_only_when_she_leads_or_says_me(
        faced, turned, company, d0, walked, to_robot):
    # review24 F8: talk23 made "come and meet my sister" / "come and see the garden" a follow; said facing the robot,
    # then turned to a friend beside her for most of the words, it is for the robot only when she walks off (leads
    # the way: her distance grows by LEAD_WALK from her last facing) or its words ask the hearer along ("follow me",
    # "come with me": said facing the robot, the hearer is the robot)
    from robot.dialog.module import LEAD_WALK

    cues = [("true", company)] * faced + [("false", company)] * turned
    d = _dialog("Interacting", _at(cues))
    n = len(cues)
    d._partner_dists = deque([(10.0 + 0.1 * i, d0 + walked * max(0, i - faced + 1) / (n - faced)) for i in range(n)], maxlen=300)
    end = 10.0 + 0.1 * (n - 1)
    leads = walked >= LEAD_WALK + 1e-6
    if abs(walked - LEAD_WALK) > 1e-3:
        assert d.addressed(10.0, end, leads=True, to_robot=to_robot) == (to_robot or leads)
    # no follow at all: the turn to the friend is chat, walking or not
    assert not d.addressed(10.0, end, to_robot=to_robot)


def test_follow_me_and_come_with_me_address_the_hearer_come_and_meet_does_not():
    from lxml import etree

    from robot.dialog.module import _to_the_robot

    def frame(words: str):
        return etree.fromstring(f'<understood><SPEECH><FOLLOW/></SPEECH><words>{words}</words></understood>')

    for words in ("please follow me into the kitchen", "come with me", "Okay, come with us, BIRON", "follow me"):
        assert _to_the_robot(frame(words)), words
    for words in ("come and meet my sister", "come and see the garden", "come have a look at my study", "follow"):
        assert not _to_the_robot(frame(words)), words


def test_a_glance_at_the_robot_as_the_group_chat_begins_does_not_make_it_a_request():
    # the shape of chat_group_bye seed 2 (raise on): 5 reports facing, then 14 turned away, ending in a group of 2
    cues = [("true", 0)] * 5 + [("false", 0)] * 10 + [("false", 1), ("false", 1), ("false", 2), ("false", 2)]
    assert not _dialog("Interacting", _at(cues)).addressed(10.0, 10.0 + 0.1 * (len(cues) - 1))
    # misheard chat may parse as showing ("could you open the wine for us" heard as "it you open the wine": a
    # deictic, addr23's scene seed 8): as in the group test without a facing, that does not make it a request
    assert not _dialog("Interacting", _at(cues)).addressed(10.0, 10.0 + 0.1 * (len(cues) - 1), shows=True)
    # the same turn for less than half the words (she says most of it facing the robot): a request
    cues = [("true", 0)] * 12 + [("false", 0)] * 5 + [("false", 2)] * 2
    assert _dialog("Interacting", _at(cues)).addressed(10.0, 10.0 + 0.1 * (len(cues) - 1))
    # facing the robot again at the end: a request, whatever came between
    cues = [("true", 0)] * 3 + [("false", 2)] * 14 + [("true", 2)]
    assert _dialog("Interacting", _at(cues)).addressed(10.0, 10.0 + 0.1 * (len(cues) - 1))


@settings(max_examples=200, deadline=None)
@given(vx=st.floats(-1.5, 1.5), vy=st.floats(-1.5, 1.5), x=st.floats(-4, 4), y=st.floats(-4, 4))
def test_a_partner_walking_away_from_the_robot_counts_as_turned_away(vx, vy, x, y):
    pa = PersonAttention.__new__(PersonAttention)
    pa.params = AttentionParams()
    pa._odom = None  # the robot at the odometry origin
    d = (x * x + y * y) ** 0.5
    away = d > 1e-6 and (vx * x + vy * y) / d >= pa.params.leave_speed
    assert pa._walks_away(0.0, (x, y, vx, vy)) == away


# ------------------------------------------------------------- the rule while she leads
VOICES = st.lists(st.lists(st.floats(-90, 90), min_size=0, max_size=2), max_size=20)


@settings(max_examples=300, deadline=None)
@given(frames=VOICES, her=st.floats(-40, 40))
def test_while_following_words_are_hers_unless_every_voice_came_from_elsewhere(frames, her):
    """Following (her back turned, her face tells nothing): the words are not hers only when at least
    three sound frames during them heard a voice and none from within 9 degrees of her bearing (front
    and back folded); her "stop" is never dropped for want of evidence."""
    reports = [(10.0 + 0.1 * i, "false", 1) for i in range(21)]
    sources = [(10.0 + 0.1 * i, tuple(bs)) for i, bs in enumerate(frames) if bs]
    d = _dialog("Following", reports, sources, bearing=her)
    heard = d.addressed(10.0, 12.0)
    near = any(abs(b - her) <= 9.0 for _, bs in sources for b in bs)
    assert heard == (len(sources) < 3 or near)
    # from behind, the pair hears her at the mirrored bearing: the same answer (folded to the front)
    d2 = _dialog("Following", reports, sources, bearing=180.0 - her)
    assert d2.addressed(10.0, 12.0) == heard


def test_a_bystanders_remark_from_the_side_while_she_leads_is_not_taken_as_her_request():
    reports = [(10.0 + 0.1 * i, "false", 1) for i in range(21)]
    beside = [(10.0 + 0.1 * i, (62.0,)) for i in range(15)]
    assert not _dialog("Following", reports, beside, bearing=2.0).addressed(10.0, 12.0)
    hers = beside + [(11.6, (1.0,))]
    assert _dialog("Following", reports, hers, bearing=2.0).addressed(10.0, 12.0)
    assert _dialog("Following", [], beside, bearing=2.0).addressed(10.0, 12.0)  # where she is unknown: hers
