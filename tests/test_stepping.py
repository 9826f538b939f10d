"""Stepping a run event by event (homesim.tour.stepping): live runs, recordings, the interactive view."""

from __future__ import annotations

import io
import json
from pathlib import Path

import pytest

from homesim.tour.runner import Run, RunOptions
from homesim.tour.stepping import Stepper

ROOT = Path(__file__).resolve().parents[1]
TOUR = ROOT / "scenarios" / "home_tour.xml"
UNTIL = 8.0
SENDS = ("publish", "request", "reply", "error")


@pytest.fixture(scope="module")
def trace_sends() -> list[dict]:
    """Every send of the tour's first seconds, from its trace."""
    buf = io.StringIO()
    with Run.from_file(TOUR, RunOptions(until=UNTIL, trace=buf)) as run:
        run.run()
    return [r for r in map(json.loads, buf.getvalue().splitlines()[1:]) if r["kind"] in SENDS]


def test_next_gives_every_message_of_the_trace_in_order_and_time(trace_sends):
    with Run.from_file(TOUR, RunOptions(until=UNTIL)) as run:
        st = Stepper(run)
        got = []
        for _ in range(400):
            s = st.next()
            assert s is not None and st.current is s
            assert run.sim.now == pytest.approx(s.t, abs=1e-6)  # the run stands at the message's time
            got.append(s)
    want = trace_sends[:400]
    assert [(s.t, s.seq, s.channel, s.sender, s.id, s.xml) for s in got] == [
        (r["t"], r["seq"], r["channel"], r["sender"], r["id"], r["xml"]) for r in want]  # seq: the trace's (deliveries count)


def test_next_on_a_channel_and_next_transition_skip_to_the_right_message(trace_sends):
    with Run.from_file(TOUR, RunOptions(until=UNTIL)) as run:
        st = Stepper(run)
        speech = st.next("/robot/audio/speech")
        first = next(r for r in trace_sends if r["channel"] == "/robot/audio/speech")
        assert (speech.t, speech.id, speech.xml) == (first["t"], first["id"], first["xml"])
        assert "hello biron" in speech.xml
        trans = [st.next_transition() for _ in range(2)]
        applied = [r for r in trace_sends if r["channel"] == "/robot/es/log" and 'kind="applied"' in r["xml"] and r["t"] > speech.t]
        assert [(s.t, s.id) for s in trans] == [(r["t"], r["id"]) for r in applied[:2]]
        assert trans[-1].transition() == ("greeting", "PotentialPartner", "Interacting")
        assert "supervisor: PotentialPartner -> Interacting on greeting" in str(trans[-1])
        fig = st.picture()
        assert "home_tour at t = " in fig.axes[0].get_title()


def test_stepping_stops_at_the_runs_end_and_after_a_manual_run(trace_sends):
    with Run.from_file(TOUR, RunOptions(until=UNTIL)) as run:
        st = Stepper(run)
        assert st.next(where=lambda s: False) is None
        assert run.sim.now == pytest.approx(UNTIL)
    with Run.from_file(TOUR, RunOptions(until=UNTIL)) as run:
        st = Stepper(run)
        st.next()
        run.sim.run(until=3.0)  # by hand: what the stepper held from before is stale
        s = st.next()
        assert s.t >= 3.0
        assert (s.t, s.id) == next((r["t"], r["id"]) for r in trace_sends if r["t"] >= 3.0)


def test_a_cursor_steps_a_recording_as_the_stepper_steps_the_run(tmp_path, trace_sends):
    pytest.importorskip("mcap")
    from homesim.cli import main
    from homesim.tour.stepping import Cursor

    rec = tmp_path / "tour.mcap"
    assert main(["run", str(TOUR), "--until", str(UNTIL), "--quiet", "--record", str(rec)]) == 0
    c = Cursor(rec)
    try:
        got = [c.next() for _ in range(300)]
        assert [(s.t, s.seq, s.id) for s in got] == [(r["t"], r["seq"], r["id"]) for r in trace_sends[:300]]
        c.seek(2.0)
        s = c.next("/robot/es/log")
        assert (s.t, s.id) == next((r["t"], r["id"]) for r in trace_sends if r["channel"] == "/robot/es/log" and r["t"] >= 2.0)
        tr = c.next_transition()
        assert tr.transition() is not None and tr.t >= s.t
        assert "at t = " in c.picture().axes[0].get_title()
    finally:
        c.close()
    pytest.importorskip("ipywidgets")
    from homesim.tour.stepping import interactive_view

    view = interactive_view(rec, window=2.0, dpi=40)
    try:
        first = view.flat.value
        assert first[:4] == b"\x89PNG" and view.timeline.value[:4] == b"\x89PNG"
        view.slider.value = 1.0  # moving the slider redraws at that time
        assert view.cursor.t == 1.0 and view.flat.value != first and "t = 1.000 s" in view.text.value
        s = view.step(transition=True)
        assert s.transition() is not None and view.slider.value == pytest.approx(s.t, abs=1e-6)
        view.slider.value = 1.0
        view.channel.value = "/robot/audio/speech"
        view.buttons["next message"].click()  # "hello biron" comes after 1 s and before UNTIL
        assert "/robot/audio/speech" in view.text.value and "hello biron" in view.text.value
        assert view.cursor.current.channel == "/robot/audio/speech" and view.slider.value == pytest.approx(view.cursor.t, abs=1e-6)
        while view.step("/robot/audio/speech") is not None:
            pass
        assert "no further message" in view.text.value
    finally:
        view.close()


@pytest.mark.parametrize("where", ["run", "recording"])
def test_an_unknown_channel_is_refused_with_the_closest_names_without_moving(tmp_path, where):
    """A typo ('/robot/es/staus') ran the live run to its end and returned None."""
    from homesim.tour.stepping import UnknownChannel

    with Run.from_file(TOUR, RunOptions(until=UNTIL)) as run:
        if where == "run":
            st = Stepper(run)
            st.next()
            before = run.sim.now
        else:
            pytest.importorskip("mcap")
            from homesim.tour.recording import record
            from homesim.tour.stepping import Cursor

            rec = record(run, tmp_path / "r.mcap")
            run.run()
            rec.close()
            st = Cursor(tmp_path / "r.mcap")
            st.next()
            before = st.t
        with pytest.raises(UnknownChannel, match=r"no channel '/robot/es/staus' in .*did you mean /robot/es/status"):
            st.next("/robot/es/staus")
        assert (run.sim.now if where == "run" else st.t) == before
        assert st.next("/robot/es/status").channel == "/robot/es/status"


def test_after_a_seek_the_next_message_is_the_first_at_or_after_that_time(tmp_path, trace_sends):
    pytest.importorskip("mcap")
    from homesim.cli import main
    from homesim.tour.stepping import Cursor

    rec = tmp_path / "tour.mcap"
    assert main(["run", str(TOUR), "--until", str(UNTIL), "--quiet", "--record", str(rec)]) == 0
    c = Cursor(rec)
    try:
        speech = next(r for r in trace_sends if r["channel"] == "/robot/audio/speech")
        for t in (0.0, speech["t"], 3.0, 5.25):
            c.seek(t)
            want = next(r for r in trace_sends if r["t"] >= t)
            s = c.next()
            assert (s.t, s.seq) == (want["t"], want["seq"])
        c.seek(speech["t"])  # "hello biron" at exactly the seek time
        assert c.next("/robot/audio/speech").id == speech["id"]
    finally:
        c.close()


def test_a_method_channel_is_stepped_and_echoed_from_a_recording_by_its_bus_name(tmp_path, trace_sends, capsys):
    """A request's bus channel (map_server/map) has no leading slash; its recording topic has one."""
    pytest.importorskip("mcap")
    from homesim.cli import main
    from homesim.tour.stepping import Cursor

    rec = tmp_path / "tour.mcap"
    assert main(["run", str(TOUR), "--until", str(UNTIL), "--quiet", "--record", str(rec)]) == 0
    want = [r for r in trace_sends if not r["channel"].startswith("/")]
    assert want
    c = Cursor(rec)
    try:
        s = c.next(want[0]["channel"])
        assert (s.t, s.seq, s.channel) == (want[0]["t"], want[0]["seq"], want[0]["channel"])
    finally:
        c.close()
    capsys.readouterr()
    assert main(["trace", "echo", str(rec), want[0]["channel"], "-n", "1"]) == 0
    assert f"seq {want[0]['seq']}" in capsys.readouterr().out
