"""Person tracking and attention on the scenarios of scenarios/attention/, scored against ground truth.

Aims (issue 10): MOTA >= 0.9 with one or two people, >= 0.8 with three crossing, at most one
identity switch per crossing; after the greeting the attention stays on the right person >= 95 %.
"""

from __future__ import annotations

import pytest
from lxml import etree

from robot.supervisor import event_xml
from tests.attention_helpers import ATTENTION_SCENARIOS, attention_run, channel, events


def _scores(name: str) -> dict:
    run = attention_run(ATTENTION_SCENARIOS / name)
    run.run()
    scores = run.metric_values()["tracking"]
    run.close()
    return scores


@pytest.mark.parametrize("name,mota,switches", [
    ("one_walker.xml", 0.9, 0),
    ("two_crossing.xml", 0.9, 2),  # they cross twice
    ("three_crossing.xml", 0.8, 6),  # three pairs cross, twice
])
def test_tracking_meets_the_aims(name, mota, switches):
    s = _scores(name)
    assert s["mota"] >= mota, s
    assert s["id_switches"] <= switches, s
    assert s["motp_m"] < 0.15, s


def test_a_person_walking_behind_the_table_keeps_her_track():
    s = _scores("behind_table.xml")
    assert s["track_ids"] == 1 and s["id_switches"] == 0 and s["false_positives"] == 0, s
    assert s["mota"] >= 0.85, s


@pytest.fixture(scope="module")
def distractor():
    """Ann greets (facing the robot); a stand-in for the dialog sends the greeting event; Bob talks
    without looking at the robot during the interaction."""
    run = attention_run(ATTENTION_SCENARIOS / "distractor.xml")
    dialog = run.sim.bus.participant("dialog_stub", host="robot")
    speech = etree.fromstring("<SPEECH><GREETING name=\"biron\"/></SPEECH>")
    run.sim.call_at(2.3, lambda: dialog.publish("/robot/es/events", event_xml("greeting", children=(speech,))))
    run.run()
    yield run
    run.close()


def test_the_greeting_meets_the_potential_partner_and_an_interaction_begins(distractor):
    run = distractor
    pp = [t for t, n in events(run) if n == "potential_partner"]
    assert pp and 1.0 < pp[0] < 2.1  # while Ann says "Hello BIRON", from sensor data alone
    orders = [m for m in channel(run, "/robot/es/orders/person_attention") if m.xml.get("name") == "interact"]
    assert orders and 2.3 < orders[0].created < 2.5
    states = [m for m in channel(run, "/robot/attention/state") if m.created > orders[0].created + 0.05]
    assert states and states[0].xml.get("state") == "Interaction" and states[0].xml.get("partner")


def test_a_distractor_talking_without_looking_never_takes_the_focus(distractor):
    run = distractor
    start = next(m.created for m in channel(run, "/robot/attention/state") if m.xml.get("state") == "Interaction")
    during = [m for m in channel(run, "/robot/attention/state") if start < m.created < 16.0]
    partners = {m.xml.get("partner") for m in during}
    assert len(partners) == 1 and partners != {""}
    assert {m.xml.get("selected") for m in during} == partners
    # The beam stays on Ann (-15 deg), never on Bob (+17 deg), though Bob talks from 3.5 s on
    # (while he talks and she does not, it is off: a bystander is not the partner).
    steer = [m for m in channel(run, "/robot/audio/steer") if m.created > 1.0]
    assert steer and steer[0].xml.get("bearing") is not None and steer[0].created < start
    assert all(m.xml.get("off") == "true" or float(m.xml.get("bearing")) < 5.0 for m in steer)
    assert all(m.created > 3.5 for m in steer if m.xml.get("off") == "true")
    assert not [t for t, n in events(run) if n == "potential_partner" and t > start]
    share = run.metric_values()["tracking"]["attention_on_partner_share"]
    assert share is not None and share >= 0.95


def test_talking_while_looking_away_makes_no_potential_partner():
    """Without the greeting: Ann's "Hello BIRON" (facing) makes her a potential partner, lost when she
    stops; Bob talking without looking, and Ann talking after she turned away, make none."""
    run = attention_run(ATTENTION_SCENARIOS / "distractor.xml")
    run.run()
    evs = events(run)
    pp = [t for t, n in evs if n == "potential_partner"]
    hello = next(u for u in run.world.sound.by("ann") if "hello" in u.text.lower())
    # while she speaks facing the robot (repeated every second): until her last sound direction
    # (the detector's hangover, 0.1 s) plus the speaking cue's hold (cues.speaking_off, 0.7 s) and a scan
    assert pp and all(hello.start < t <= hello.end + 0.9 for t in pp)
    # lost when the last potential_partner's validity (1.5 s, its AFSM lifetime) has run out
    assert any(n == "potential_partner_lost" and 1.5 - 1e-6 <= t - max(pp) < 1.65 for t, n in evs)
    run.close()


def test_the_beam_hears_the_unexplained_radio_not_the_talker_looking_away_and_the_new_speaker_gets_the_look():
    """scenarios/attention/radio_and_talkers.xml: where the recogniser listens (docs/semantics.md §2, §3)."""
    run = attention_run(ATTENTION_SCENARIOS / "radio_and_talkers.xml")
    run.run()
    try:
        sound = run.world.sound
        (radio,) = sound.by("radio")
        (ann_hello,) = sound.by("ann")
        speech = [(m.created, m.xml.text or "") for m in channel(run, "/robot/audio/speech")]
        # The radio's greeting comes from where nobody is: the beam turns to it, its words reach the robot.
        assert [w for t, w in speech if radio.start < t <= radio.end + 0.2] == ["hello biron"]
        # Bob talks while the robot sees him looking away: none of his words are recognised.
        assert not any(w in text for _, text in speech for w in ("keys", "kitchen", "somewhere", "put"))
        # Ann starts talking while Bob (selected, speaking) still talks: she takes the selection
        # at once, the camera finds her facing the robot, and she is the potential partner while
        # she greets; her greeting is recognised although the beam reached her during it.
        pp = [t for t, n in events(run) if n == "potential_partner"]
        assert pp and ann_hello.start < pp[0] < ann_hello.end
        assert [w for t, w in speech if ann_hello.start < t <= ann_hello.end + 0.2] == ["hello biron"]
        # the beam reaches her during her greeting, never before she speaks (attn17: a selected speaker whose face is
        # not yet in the image is listened to, so it turns 0.3 s in, not only once she is the potential partner)
        steer = [m for m in channel(run, "/robot/audio/steer") if ann_hello.start - 0.5 < m.created <= ann_hello.start]
        assert all(m.xml.get("off") == "true" or float(m.xml.get("bearing")) < 0 for m in steer)  # not yet on her (left)
        on_her = [m.created for m in channel(run, "/robot/audio/steer")
                  if ann_hello.start < m.created < ann_hello.end and m.xml.get("off") != "true" and float(m.xml.get("bearing")) > 0]
        assert on_her, "the beam never reached her while she greeted"
    finally:
        run.close()
