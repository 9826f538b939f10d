"""Honest audio: the mixture, not the sources; walls; one steered recognition stream with a confidence."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from homesim.scenario.loader import load_scenario_text
from homesim.sim import Simulation
from homesim.tour.stage import Stage
from robot.hardware.microphones import SPEED_OF_SOUND, MicSpec, OnsetTracker, Peak, mixture_peaks, path_loss_db, recognise_scored
from tests.world_helpers import ROOM
from tests.stage_helpers import ACTORS

SPEC = MicSpec()


def _dt(bearing_deg: float) -> float:
    return -SPEC.spacing * math.sin(math.radians(bearing_deg)) / SPEED_OF_SOUND


def test_sources_closer_than_the_pair_resolves_merge_into_one_direction():
    peaks = mixture_peaks(np.array([_dt(10.0), _dt(14.0)]), np.array([60.0, 58.0]), SPEC)
    assert len(peaks) == 1
    b = math.degrees(math.asin(-peaks[0].tdoa * SPEED_OF_SOUND / SPEC.spacing))
    assert 10.0 < b < 14.0  # power-weighted, nearer the louder one
    assert peaks[0].level == pytest.approx(10 * math.log10(10**6 + 10**5.8))


def test_far_apart_sources_are_two_directions_and_a_loud_one_masks_a_quiet_one():
    assert len(mixture_peaks(np.array([_dt(-40.0), _dt(30.0)]), np.array([60.0, 57.0]), SPEC)) == 2
    assert len(mixture_peaks(np.array([_dt(-40.0), _dt(30.0)]), np.array([60.0, 45.0]), SPEC)) == 1
    three = mixture_peaks(np.array([_dt(-60.0), _dt(0.0), _dt(60.0)]), np.array([60.0, 59.0, 58.0]), SPEC)
    assert len(three) == SPEC.max_peaks


@settings(max_examples=100, deadline=None)
@given(b=st.lists(st.floats(-80, 80), min_size=1, max_size=5), lv=st.lists(st.floats(36, 80), min_size=5, max_size=5))
def test_the_mixture_never_shows_more_directions_than_sources_or_peaks_and_never_invents_one(b, lv):
    dts = np.array([_dt(x) for x in b])
    levels = np.array(lv[: len(b)])
    peaks = mixture_peaks(dts, levels, SPEC)
    assert 1 <= len(peaks) <= min(len(b), SPEC.max_peaks)
    for p in peaks:
        assert dts.min() - 1e-12 <= p.tdoa <= dts.max() + 1e-12  # a weighted mean of real directions
    loudest = int(np.argmax(levels))
    assert any(abs(p.tdoa - dts[loudest]) < SPEC.resolution_tdoa for p in peaks)  # the loudest is always heard


def test_onsets_are_delayed_and_offsets_hang_over():
    tr = OnsetTracker(MicSpec(onset_frames=2, onset_jitter=0.0, hangover_frames=2))
    rng = np.random.default_rng(0)
    pk = [Peak(1e-4, 50.0)]
    assert tr.update(pk, rng) == []
    assert len(tr.update(pk, rng)) == 1
    assert len(tr.update([], rng)) == 1 and len(tr.update([], rng)) == 1
    assert tr.update([], rng) == []


def test_each_wall_crossed_costs_its_loss_and_an_open_door_none():
    walls = (np.array([[5.0, 0.0], [5.1, 0.0], [5.1, 2.0], [5.0, 2.0]]), np.array([[5.1, 0.0], [5.1, 2.0], [5.0, 2.0], [5.0, 0.0]]))  # x=5..5.1, y 0..2
    none = (np.zeros((0, 2)), np.zeros((0, 2)))
    loss = path_loss_db(np.array([[8.0, 1.0], [8.0, 3.0]]), (1.0, 1.0), walls, none, SPEC)
    assert loss[0] == SPEC.wall_loss_db  # through the wall
    assert loss[1] == 0.0  # past its end (the door gap)


def test_confidence_falls_with_the_errors_it_never_sees():
    rng = np.random.default_rng(3)
    words = tuple(f"w{i}" for i in range(6))
    errs, confs = [], []
    for wer in np.linspace(0.0, 0.8, 400):
        out, conf = recognise_scored(words, float(wer), rng)
        errs.append(sum(1 for w in words if w not in out) / len(words))
        confs.append(conf)
    assert np.corrcoef(errs, confs)[0, 1] < -0.6


TWO = ROOM.read_text(encoding="utf-8").replace(
    '<human name="ann" x="3" y="3" heading="180" height="1.70" torso="yellow"/>',
    '<human name="ann" x="3" y="3" heading="180" height="1.70" torso="yellow"><script><wait for="0.5"/>'
    '<say text="one two three four five six seven eight nine ten"/></script></human>'
    '<human name="bob" x="4.5" y="3.4" heading="180" height="1.80" torso="green"><script><wait for="0.5"/>'
    '<say text="alpha beta gamma delta epsilon zeta eta theta iota kappa"/></script></human>',
)


def test_two_people_talking_at_once_in_nearly_the_same_direction_are_heard_as_one_direction():
    sc = load_scenario_text(TWO, source="two.xml")
    sim = Simulation(seed=4, scenario=sc.name)
    st_ = Stage(sim, sc, actors=ACTORS, keep_messages=True)
    st_.run(4.0)
    frames = [m for m in st_.messages if m.channel == "/robot/audio/sources" and 1.2 < m.created < 4.0]
    assert frames and all(len(m.xml) == 1 for m in frames)  # ann at 0 deg, bob at 7 deg: one direction
    bearings = [float(m.xml[0].get("bearing")) for m in frames]
    assert 0.0 < float(np.mean(bearings)) < 7.0
    sim.close()


def test_the_recogniser_only_hears_where_its_beam_points():
    sc = load_scenario_text(TWO.replace('<human name="bob" x="4.5" y="3.4"', '<human name="bob" x="2.5" y="5.0"'), source="two.xml")
    sim = Simulation(seed=4, scenario=sc.name)
    st_ = Stage(sim, sc, actors=ACTORS, keep_messages=True)
    steer = sim.bus.participant("attention", host="robot")
    sim.call_at(0.1, lambda: steer.publish("/robot/audio/steer", etree.Element("steer", bearing="0")))
    st_.run(6.0)
    heard = [m.xml.text for m in st_.messages if m.channel == "/robot/audio/speech"]
    assert len(heard) == 1 and "alpha" not in heard[0]  # ann's words (ahead), never bob's (53 deg left)
    sim.close()
