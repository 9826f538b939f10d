"""Her voice from a track in her clothes while her own track is silent and shows no clothes: that track is her (hear25).

Generated tour 9700-03 (main ad99049): following her into the bathroom, her track went over to a silent man she
walked up beside (their legs 0.5 m apart), and a new track was born on her 0.6 m in front of the robot. Face to face
from then on, each of her words came from that track's direction, 11 deg off her old track's, so the beam gate took
her for a bystander and turned the microphone beam off 0.3 s after she began: nothing she said reached the recogniser
to the end of the tour. The camera, looking at her old track, never gave it clothes, while it saw her red top on the
speaker. Face to face (Interaction, Object), a confirmed track near the robot that speaks in her clothes while the
partner's track is silent and shows none takes her place; a talker in other clothes, or whose clothes the camera has
not seen, never does, nor anyone while her track shows her clothes or speaks itself.
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from robot.attention.appearance import Colours
from robot.attention.cues import CueSpec, Hysteresis
from tests.test_attention_other_clothes import HERS, OTHER, _interacting



def _scene(partner_clothes, talker_clothes, partner_speaks: bool, state: str = "interact"):
    """Her track (the partner, 1 m ahead, still) and a confirmed talker 0.6 m in front of the robot, 0.5 m from it;
    the camera gave her clothes (``HERS``) to the partner's track when she became the partner; now it gives the
    partner's track ``partner_clothes`` and the talker ``talker_clothes`` (None: no blob), the talker speaks, and the
    partner's track speaks too when ``partner_speaks``. Returns the attention, the partner's and the talker's ids."""
    a, tid = _interacting(state)
    cues = CueSpec()
    a.speaking = Hysteresis(cues.speaking_on, cues.speaking_off)
    a.colours = Colours()
    a._her_clothes = HERS
    a.tracks._birth(0.0, np.array([(0.6, -0.05)], dtype=float), np.full(1, 0.01))
    other = a.tracks.tracks[-1]
    other.confirmed = True
    t = 10.0
    for k in range(12):  # 1.2 s of frames: the camera's blobs and the voice
        now = t + 0.1 * k
        for tk in a.tracks.tracks:
            tk.last_seen = now
        if partner_clothes is not None:
            a.colours.observe(tid, partner_clothes, now)
        if talker_clothes is not None:
            a.colours.observe(other.id, talker_clothes, now)
        ids = [tk.id for tk in a.tracks.tracks]
        a.speaking.feed(now, ids, {other.id} | ({tid} if partner_speaks else set()))
        a._top_down(now, {tid: 1, other.id: 1})
    return a, tid, other.id


def test_her_voice_from_a_track_in_her_clothes_moves_the_partner_there():
    a, tid, other = _scene(None, HERS, partner_speaks=False)
    assert a.partner == other
    assert a.events == []  # no loss: she never left


def test_also_while_she_shows_an_object():
    a, tid, other = _scene(None, HERS, partner_speaks=False, state="focus_object")
    assert a.partner == other


@settings(max_examples=60, deadline=None)
@given(partner_clothes=st.sampled_from([None, HERS]), talker_clothes=st.sampled_from([None, HERS, OTHER]),
       partner_speaks=st.booleans())
def test_a_talker_takes_her_place_only_in_her_clothes_with_her_track_silent_and_unclothed(partner_clothes, talker_clothes, partner_speaks):
    a, tid, other = _scene(partner_clothes, talker_clothes, partner_speaks)
    moved = partner_clothes is None and talker_clothes == HERS and not partner_speaks
    assert a.partner == (other if moved else tid)
