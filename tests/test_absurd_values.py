"""Absurd values are refused where they enter, with a clear error, never deep inside a run.

A sound level of 1e5 dB, an event lifetime of 10**400 ns, whether they come
from a scenario file (file:line), an event on the bus (a reported drop) or
the API (an error naming the value).
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest

from homesim.cli import main

ROOT = Path(__file__).resolve().parents[1]
SCENARIO = ROOT / "scenarios" / "two_people_radio.xml"
HUGE = 10**400


@pytest.mark.parametrize("value", ["1e5", "141", "-3", "1e308"])
@pytest.mark.parametrize("where", ["radio", "say"])
def test_an_absurd_loudness_is_refused_at_load_with_file_and_line(tmp_path, capsys, where, value):
    text = SCENARIO.read_text(encoding="utf-8")
    if where == "radio":
        text = text.replace('loudness="55"', f'loudness="{value}"', 1)
        marker = 'loudness="'
    else:
        text = text.replace('<say text="Hello BIRON"/>', f'<say text="Hello BIRON" loudness="{value}"/>', 1)
        marker = "<say text=\"Hello BIRON\""
    bad = tmp_path / "loud.xml"
    bad.write_text(text, encoding="utf-8")
    line = next(n for n, s in enumerate(text.splitlines(), 1) if marker in s and value in s)
    code = main(["run", str(bad), "--until", "2", "--quiet"])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1, err
    assert f"{bad}:{line}:" in err and "loudness" in err, err


def test_the_loudest_allowed_level_runs(tmp_path, capsys):
    bad = tmp_path / "loud.xml"
    bad.write_text(SCENARIO.read_text(encoding="utf-8").replace('loudness="55"', 'loudness="140"', 1), encoding="utf-8")
    assert main(["run", str(bad), "--until", "2", "--quiet"]) == 0, capsys.readouterr().err


@pytest.mark.parametrize("level", [1e5, 141.0, -1.0, float("nan"), float("inf")])
def test_the_sound_field_refuses_an_absurd_level_through_the_api(level):
    from homesim.world.acoustics import SoundField

    field = SoundField()
    with pytest.raises(ValueError, match="loudness"):
        field.say("radio", "hello", 0.0, loudness=level)
    assert len(field) == 0


def test_the_engine_refuses_an_absurd_lifetime_and_stays_as_it_was():
    from homesim.afsm.engine import Engine, Event
    from homesim.afsm.loader import load
    from homesim.errors import SupervisorError

    engine = Engine(load(ROOT / "robot" / "afsm" / "biron.scxml"))
    for lifetime in (HUGE, 3600 * 10**9 + 1, 0, -5, 1.5, True):
        with pytest.raises(SupervisorError, match="lifetime"):
            engine.queue(Event(f"e{lifetime!r:.10}", "greeting", "dialog", 0, lifetime), 0)
    assert engine.stats()["queued"] == 0 and engine.next_deadline() is None
    engine.queue(Event("ok", "greeting", "dialog", 0, 3600 * 10**9), 0)  # an hour is the longest


def test_a_machine_with_an_absurd_lifetime_is_invalid():
    from homesim.afsm.loader import load
    from homesim.afsm.model import validate

    m = load(ROOT / "robot" / "afsm" / "biron.scxml")
    name = next(iter(m.events))
    for bad in (replace(m, default_lifetime_ns=HUGE), replace(m, events={**m.events, name: replace(m.events[name], lifetime_ns=HUGE)})):
        assert any("lifetime" in p.message and "at most 3600 s" in p.message for p in validate(bad))


@pytest.mark.parametrize("lifetime", ["1" + "0" * 400, "1e400", "nan", "inf", "-1", "0", "3600.5", "abc"])
def test_an_event_with_an_absurd_lifetime_on_the_bus_is_a_reported_drop(lifetime):
    from homesim.sim import Simulation
    from robot.supervisor import ES_EVENTS, ExecutionSupervisor, event_xml

    with Simulation(seed=1, strict=False) as sim:  # an element built through the API: not validated
        trace = sim.record_trace()
        es = ExecutionSupervisor(sim, heartbeat=None)
        sim.start()
        dialog = sim.bus.participant("dialog")
        ev = event_xml("greeting")
        ev.set("lifetime", lifetime)
        dialog.publish(ES_EVENTS, ev)
        dialog.publish(ES_EVENTS, event_xml("greeting", lifetime=2.0))  # the ES goes on
        sim.run(until=1.0)
        drops = [r for r in trace.records() if r.get("kind") == "drop"]
        assert len(drops) == 1 and "lifetime" in drops[0]["reason"], drops
        assert es.engine.stats()["queued"] == 1


@pytest.mark.parametrize("created", [float("inf"), float("nan"), 1e300, 0.5])
def test_a_creation_time_not_finite_or_after_the_send_is_refused_and_nothing_is_sent(created):
    """publish(created=...) took any float: inf/NaN failed inside int() with no channel named, and an
    event 'created' 1e300 s in the future was queued by the ES ahead of everything and applied."""
    from homesim.errors import BusError
    from homesim.sim import Simulation

    sim = Simulation(seed=1, scenario="created")
    try:
        got: list[str] = []
        sim.bus.participant("sink").subscribe("/x", lambda m: got.append(m.id))
        sender = sim.bus.participant("sender")
        sim.run(until=0.25)
        with pytest.raises(BusError, match="/x: created="):
            sender.publish("/x", "<x/>", created=created)
        sender.publish("/x", "<x/>", created=0.25)  # at the send: fine
        sim.run(until=1.0)
        assert len(got) == 1  # only the good one arrives
    finally:
        sim.close()
