"""Expectations checked after a run: each holds when it should and fails when it should."""

from __future__ import annotations

import math

import pytest

from homesim.errors import ScenarioError
from homesim.scenario.loader import load_scenario_text
from homesim.sim import Simulation
from homesim.tour.stage import Stage
from tests.world_helpers import ROOM
from tests.stage_helpers import PEOPLE

ROOM_TEXT = ROOM.read_text(encoding="utf-8")


def _run(people: str, expect: str, *, until: float = 10.0, drive: tuple[float, float] | None = None):
    text = ROOM_TEXT.replace('<human name="ann" x="3" y="3" heading="180" height="1.70" torso="yellow"/>', people)
    text = text.replace("</humans>", f"</humans>\n  <expect>\n    {expect}\n  </expect>")
    sc = load_scenario_text(text, source="expect.xml")
    sim = Simulation(seed=1, scenario=sc.name)
    st = Stage(sim, sc, actors=PEOPLE, truth_every=1)
    if drive is not None:
        st.world.robot.command(*drive)
    st.run(until)
    verdicts = st.verdicts()
    sim.close()
    return st, verdicts


def test_reached_a_moving_person_uses_where_they_were_at_that_moment():
    """The review's reached.py: bob passed where ann would end up, long before she got there;
    compared with her final position, 'reached' passed at t=0 though they were never within 1.2 m."""
    people = (
        '<human name="ann" x="3" y="3" heading="180" height="1.70" torso="yellow"><script><wait for="5"/><walk-to point="6 3.5"/></script></human>\n'
        '    <human name="bob" x="6" y="3"><script><walk-to point="1.5 5"/></script></human>'
    )
    st, (v,) = _run(people, '<reached who="bob" human="ann" within="1"/>')
    closest = min(math.hypot(a.x - b.x, a.y - b.y) for f in st.truth.frames for a in f.people for b in f.people if (a.name, b.name) == ("ann", "bob"))
    assert closest > 1.0
    assert not v.passed and f"{closest:.2f}" in v.detail


def test_reached_a_person_walking_up_to_them():
    people = (
        '<human name="ann" x="6" y="3" height="1.70" torso="yellow"><script><walk-to point="6 5"/></script></human>\n'
        '    <human name="bob" x="3" y="3"><script><wait for="1"/><walk-to human="ann" stop-at="0.8"/></script></human>'
    )
    st, (v,) = _run(people, '<reached who="bob" human="ann" within="0.9" by="8"/>')
    assert v.passed, v.detail
    t = float(v.detail.split("t=")[1].split(" ")[0])
    frame = st.truth.at(t)
    ann, bob = (next(p for p in frame.people if p.name == n) for n in ("ann", "bob"))
    assert math.hypot(ann.x - bob.x, ann.y - bob.y) <= 0.9


ANN = '<human name="ann" x="3" y="3" heading="180" height="1.70" torso="yellow"/>'


def test_no_collision_fails_when_the_robot_drives_into_a_wall():
    expect = '<no-collision/>\n    <no-collision with="wall"/>\n    <no-collision with="ann"/>\n    <no-collision with="wall" between="0 1"/>'
    st, verdicts = _run(ANN.replace('x="3" y="3"', 'x="3" y="5"'), expect, drive=(0.5, -math.pi / 4))
    hits = st.world.contacts
    assert hits and {w for _, w in hits} == {"wall"} and hits[0][0] > 1.0
    assert [v.passed for v in verdicts] == [False, False, True, True]
    assert f"the robot touched wall at t={hits[0][0]:.2f} s" in verdicts[0].detail


def test_no_collision_names_only_walls_furniture_or_people():
    text = ROOM_TEXT.replace("</humans>", '</humans>\n  <expect>\n    <no-collision with="bob"/>\n  </expect>')
    with pytest.raises(ScenarioError, match="with='bob': use 'wall', 'furniture' or the name of a human") as exc:
        load_scenario_text(text, source="expect.xml")
    assert exc.value.line == text[: text.index("<no-collision")].count("\n") + 1


def test_robot_near_never_fails_when_the_robot_drives_there():
    expect = '<robot-near point="5 3" within="1" never="true"/>\n    <robot-near point="5 3" within="1" never="true" by="1"/>\n    <robot-near point="5 3" within="1" after="2"/>'
    _, verdicts = _run(ANN.replace('x="3" y="3"', 'x="3" y="5"'), expect, drive=(0.5, 0.0), until=8)
    assert [v.passed for v in verdicts] == [False, True, True], [v.detail for v in verdicts]
    assert "where it should not" in verdicts[0].detail


@pytest.mark.parametrize(
    "expect,message",
    [
        ('<robot-says pattern="hi" after="5" by="3"/>', "after=5 is later than by=3"),
        ('<state-reached state="Following" between="2 8" by="1"/>', "the window is empty"),
        ('<robot-near room="room" between="5 8" after="9"/>', "the window is empty"),
        ('<robot-says pattern="hi" after="50"/>', "after the end of the run"),
        ('<event-applied event="goodbye" between="4 50"/>', "after the run"),
    ],
)
def test_an_expectation_whose_window_cannot_hold_is_refused_with_its_line(expect, message):
    text = ROOM_TEXT.replace("</humans>", f"</humans>\n  <expect>\n    {expect}\n  </expect>")
    with pytest.raises(ScenarioError, match=message) as exc:
        load_scenario_text(text, source="expect.xml")
    assert exc.value.line == text[: text.index(expect)].count("\n") + 1


def test_no_collision_counts_every_contact_beyond_the_worlds_log(monkeypatch):
    """The world keeps only its latest CONTACT_LOG contacts (bounded memory); no-collision
    counts its own as they begin, so its verdict names the first contact of the window and
    how many more there were however many the world has forgotten."""
    import homesim.world.world as world_mod

    monkeypatch.setattr(world_mod, "CONTACT_LOG", 1)
    text = ROOM_TEXT.replace("</humans>", '</humans>\n  <expect>\n    <no-collision with="wall"/>\n    <no-collision with="wall" between="3 10"/>\n  </expect>')
    sc = load_scenario_text(text, source="expect.xml")
    sim = Simulation(seed=1, scenario=sc.name)
    st = Stage(sim, sc, actors=(), truth_every=None)
    st.world.humans["ann"].remove()
    seen = []
    st.world.add_contact_listener(lambda t, what: seen.append((t, what)))
    for k in range(4):  # driven into the east wall four times over: four contacts begin
        st.world.place_robot(7.2, 3.0, 0.0)
        st.world.robot.command(0.5, 0.0)
        st.run(2.0 * (k + 1))
    whole, late = st.verdicts()
    sim.close()
    assert len(seen) == st.world.contact_count >= 4 and len(st.world.contacts) == 1
    assert not whole.passed and whole.detail == f"the robot touched wall at t={seen[0][0]:.2f} s (and {len(seen) - 1} more contacts)"
    in_late = [t for t, _ in seen if 3.0 - 1e-9 <= t <= 10.0 + 1e-9]
    assert in_late and not late.passed
    assert late.detail.startswith(f"the robot touched wall at t={in_late[0]:.2f} s")
