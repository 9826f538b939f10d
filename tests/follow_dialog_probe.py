"""A Dialog in Following that hears words from 60 degrees off the followed track (which is silent), after the
follower sent a given sequence of statuses: the probe of the dialog's stood-stop and searching-stop rules
(tests/test_follow_stood_deaf.py, tests/test_follow_searching_stop.py), written once."""

from __future__ import annotations

import math
from collections import deque
from types import SimpleNamespace

from lxml import etree

from robot.attention.fsm import AttentionFSM
from robot.attention.module import AttentionParams, PersonAttention
from robot.dialog.loader import BIRON_DIALOGS, load
from robot.dialog.manager import DialogManager
from robot.dialog.module import Dialog

DOC = load(BIRON_DIALOGS)


class _Clocked(Dialog):
    now = 0.0  # the rule only: a plain clock instead of the simulation's


def dialog_hearing_off_track(states: list[tuple[float, str]], said_at: float, act: str = "STOP",
                             words: str = "stop now") -> tuple[Dialog, list[str]]:
    """The dialog after the follower's ``states`` ((time, status) every 0.1 s) and words (``act``) that begin at
    ``said_at`` from 60 degrees left of the followed track (its heard span +-2 deg); returns it and the acts taken."""
    d = _Clocked.__new__(_Clocked)
    d.manager = DialogManager(DOC)
    d.manager.es_state = "Following"
    d._follow_state, d._waiting_since, d._searching_since = "", math.inf, math.inf
    d._approach_seen = -math.inf
    d._release_held = lambda: None
    d._queue = deque()  # nothing of its own waits to be said
    for t, state in states:
        d.now = t
        d._on_follow(SimpleNamespace(xml=etree.Element("follow", state=state)))
    d.now = said_at + 1.0
    d._partner_cues = deque([(said_at - 0.5 + 0.1 * i, "false", 0, (-2.0, 2.0)) for i in range(15)], maxlen=300)
    d._sources = deque([(said_at + 0.1 * i, (60.0,)) for i in range(6)], maxlen=300)
    d.barge_in_width = 9.0
    d.not_addressed = 0
    d._unanswered = None
    d._addressed_at = -math.inf
    taken: list[str] = []
    d._on_addressed = lambda msg: taken.append(msg.xml.find("SPEECH")[0].tag)
    msg = SimpleNamespace(id="m1", xml=etree.fromstring(
        f'<understood start="{said_at}" end="{said_at + 0.6}" confidence="0.9"><SPEECH><{act}/></SPEECH>'
        f'<words>{words}</words></understood>'))
    d._on_frame(msg)
    return d, taken


class _Attention(PersonAttention):
    now = 0.0


def attention_following(waiting_since: float | None = None, searching_since: float | None = None) -> PersonAttention:
    """A person attention following partner 1 (built without a bus, a plain clock): the follower said ``waiting``
    since ``waiting_since`` and ``searching`` since ``searching_since`` (None: not)."""
    a = _Attention.__new__(_Attention)
    a.params = AttentionParams()
    a.fsm = AttentionFSM()
    a.fsm.order("interact")
    a.fsm.order("follow")
    a._voice_turn = None
    a._dominant = None
    a._voices = None
    a.partner = 1
    a.partner_lost_sent = False
    a._caller = None
    a._follow_waiting = waiting_since
    a._follow_searching = searching_since
    return a
