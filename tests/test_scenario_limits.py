"""Absurd numbers and sizes in documents are refused at the boundary, with file and line.

Class: every number a scenario or an AFSM carries has a documented range
(seeds, repeat counts, coordinates in points and polygons, sensor rates
bounded by BIRON's hardware, event lifetimes) and a scenario has documented
size limits; targets lie inside the flat (never silently clamped) and
nobody starts on top of the robot or of someone else.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from homesim.errors import MessageValidationError, ScenarioError
from homesim.scenario.checks import MAX_COUNTS
from homesim.scenario.loader import load_scenario_text

from .conftest import examples

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = (ROOT / "scenarios" / "two_people_radio.xml").read_text(encoding="utf-8")


def _line_of(text: str, needle: str) -> int:
    return text[: text.index(needle)].count("\n") + 1


def _refused(text: str, needle: str, message: str) -> None:
    with pytest.raises(ScenarioError, match=message) as info:
        load_scenario_text(text, source="s.xml")
    assert info.value.line == _line_of(text, needle), str(info.value)
    assert str(info.value).startswith(f"s.xml:{info.value.line}: ")


@pytest.mark.parametrize("seed", ["9" * 19, "1" + "0" * 5000, "-1", "1e3"])
def test_absurd_seeds_are_refused_with_the_line(seed):
    text = EXAMPLE.replace('seed="7"', f'seed="{seed}"')
    _refused(text, "<scenario ", "seed")


def test_the_largest_seed_is_accepted():
    assert load_scenario_text(EXAMPLE.replace('seed="7"', 'seed="' + "9" * 18 + '"')).seed == 10**18 - 1


@pytest.mark.parametrize("times", ["100001", "9" * 5000, "0"])
def test_absurd_repeat_counts_are_refused_with_the_line(times):
    text = EXAMPLE.replace('<repeat times="2">', f'<repeat times="{times}">')
    _refused(text, "<repeat times=", "times")


@settings(max_examples=examples(30, 200))
@given(value=st.sampled_from(["1e308", "-1e308", "1001", "1e4", "123456789"]), where=st.sampled_from(["walk", "room", "furniture"]))
def test_coordinates_outside_the_documented_range_are_refused(value, where):
    if where == "walk":
        text, needle = EXAMPLE.replace('<walk-to point="7.0 1.0"/>', f'<walk-to point="{value} 1.0"/>'), "<walk-to point="
    elif where == "room":
        text, needle = EXAMPLE.replace('points="6,0 9.5,0 9.5,5 6,5"', f'points="6,0 {value},0 9.5,5 6,5"'), 'name="kitchen" points'
    else:
        text, needle = EXAMPLE.replace('points="0.3,0.3 2.5,0.3', f'points="{value},0.3 2.5,0.3'), 'name="sofa"'
    _refused(text, needle, "outside -1000 to 1000 m")


@pytest.mark.parametrize("point", ["20 20", "-3 2", "9.6 1.0"])
def test_a_walk_target_outside_the_flat_is_refused_not_clamped(point):
    text = EXAMPLE.replace('<walk-to point="7.0 1.0"/>', f'<walk-to point="{point}"/>')
    _refused(text, "<walk-to point=", "target point .* is not inside any room")


@pytest.mark.parametrize("xy", ['x="2.0" y="2.3"', 'x="2.3" y="2.5"', 'x="1.6" y="2.3"'])
def test_a_person_starting_on_the_robot_is_refused(xy):
    text = EXAMPLE.replace('<human name="anna" x="4.5" y="1.5"', f'<human name="anna" {xy}')
    _refused(text, '<human name="anna"', "on the robot")


def test_two_people_starting_on_each_other_are_refused():
    text = EXAMPLE.replace('<human name="tom" x="0.9" y="2.6"', '<human name="tom" x="4.6" y="1.5"')
    _refused(text, '<human name="tom"', "on top of 'anna'")


@pytest.mark.parametrize("attr,limit", [("laser-rate", 75), ("camera-rate", 30), ("odometry-rate", 50), ("audio-rate", 100)])
def test_sensor_rates_are_bounded_by_the_hardware(attr, limit):
    ok = EXAMPLE.replace('<robot x="2.0" y="2.3" heading="0"/>', f'<robot x="2.0" y="2.3" heading="0" {attr}="{limit}"/>')
    load_scenario_text(ok)
    for bad in (limit * 1.01, 1e6, 0):
        text = EXAMPLE.replace('<robot x="2.0" y="2.3" heading="0"/>', f'<robot x="2.0" y="2.3" heading="0" {attr}="{bad:g}"/>')
        _refused(text, "<robot x=", attr)


def test_too_much_furniture_is_refused_before_any_geometry():
    n = MAX_COUNTS["furniture"] + 1
    pieces = "".join(
        f'\n    <furniture name="box{i}" type="box" points="{0.1 + (i % 50) * 0.1:.2f},4.0 {0.15 + (i % 50) * 0.1:.2f},4.0 '
        f'{0.15 + (i % 50) * 0.1:.2f},4.05" height="0.1"/>'
        for i in range(n)
    )
    text = EXAMPLE.replace('    <furniture name="sofa"', pieces.lstrip("\n") + '\n    <furniture name="sofa"', 1)
    with pytest.raises(ScenarioError, match=f"at most {MAX_COUNTS['furniture']}") as info:
        load_scenario_text(text, source="s.xml")
    assert info.value.line == _line_of(text, f'name="box{MAX_COUNTS["furniture"]}"')


# ----------------------------------------------------------------- AFSM
AFSM = (
    '<scxml xmlns="http://www.w3.org/2005/07/scxml" xmlns:es="urn:homesim:afsm:1" version="1.0" es:default-lifetime="{dl}">\n'
    '<es:event name="e" lifetime="{lt}"/>\n<state id="A"><transition event="e" target="A"/></state>\n</scxml>'
)


@pytest.mark.parametrize("dl,lt,line", [("5", "1" + "0" * 400, 2), ("1" + "0" * 5000, "3", 1), ("3600.0000000001", "1", 1), ("5", "3601", 2)])
def test_absurd_lifetimes_are_refused_by_afsm_check_with_the_line(dl, lt, line):
    from homesim.afsm.loader import check

    problems = check(AFSM.format(dl=dl, lt=lt), source="m.scxml")
    assert problems and all(p.line == line for p in problems)
    assert all("lifetime" in str(p) for p in problems)


def test_the_longest_lifetime_is_accepted():
    from homesim.afsm.loader import check

    assert check(AFSM.format(dl="3600", lt="0.000000001")) == []


def test_an_event_with_an_absurd_lifetime_is_refused_at_the_sender():
    from homesim.sim import Simulation

    with Simulation(seed=1) as sim:
        sim.bus.declare_channel("/robot/es/events", ROOT / "robot" / "schemas" / "es-event.xsd")
        p = sim.bus.participant("evil")
        with pytest.raises(MessageValidationError, match="lifetime"):
            p.publish("/robot/es/events", etree.Element("event", name="greeting", lifetime="1" + "0" * 400))
        p.publish("/robot/es/events", etree.Element("event", name="greeting", lifetime="3.5"))
