"""The composition root, streaming expectations, metrics, `homesim run` and `homesim replay`."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from homesim.tour import metrics
from homesim.cli import main
from homesim.errors import ScenarioError
from homesim.tour.metrics.stats import Running
from homesim.tour.runner import Run, RunOptions, element_dict
from homesim.tour.expect import matches
from homesim.scenario.loader import load_scenario_text
from homesim.sim import Simulation
from homesim.tour.stage import Stage
from tests.world_helpers import EXAMPLE, ROOM

ROOM_TEXT = ROOM.read_text(encoding="utf-8")


def _room(expect: str, *, extra: str = "", duration: float = 10) -> str:
    text = ROOM_TEXT.replace("</humans>", f"</humans>\n{extra}<expect>\n{expect}\n</expect>")
    return text.replace('duration="10"', f'duration="{duration:g}"')


def _stage(expect: str, *, robot: str = "", **kw: object) -> Stage:
    sc = load_scenario_text(_room(expect, **kw).replace("<robot ", f"<robot {robot} "), source="room.xml")
    sim = Simulation(seed=1, scenario=sc.name)
    return Stage(sim, sc, actors=())


def _publish_at(stage: Stage, t: float, sender: str, channel: str, el: etree._Element) -> None:
    p = stage.sim.bus._participants.get(sender) or stage.sim.bus.participant(sender)
    stage.sim.call_at(t, lambda: p.publish(channel, el))


def _log(kind: str, name: str, state: str, **attrs: str) -> etree._Element:
    return etree.Element("es_record", kind=kind, event="x#1", name=name, source=attrs.pop("source", "dialog"),
                         created="0", state=state, **attrs)


def _verdicts(stage: Stage, **context: object) -> dict[str, tuple[bool, str]]:
    stage.run()
    out = {v.name: (v.passed, v.detail) for v in stage.verdicts(context)}
    stage.sim.close()
    return out


# ------------------------------------------------------- robot-level expectations
def test_robot_says_passes_before_its_deadline_and_fails_after_it_with_file_and_line():
    stage = _stage('<robot-says pattern="hello|hi" by="3"/>\n<robot-says pattern="follow" by="3"/>\n'
                   '<robot-says pattern="stupid" never="true"/>\n<robot-says pattern="bye" never="true"/>')
    _publish_at(stage, 1.0, "dialog", "/robot/speaker/say", etree.Element("say", text="Hello, I am BIRON"))
    _publish_at(stage, 5.0, "dialog", "/robot/speaker/say", etree.Element("say", text="OK, I follow you"))
    _publish_at(stage, 6.0, "dialog", "/robot/speaker/say", etree.Element("say", text="Bye bye"))
    stage.run()
    v = {x.name: x for x in stage.verdicts()}
    assert v['<robot-says pattern="hello|hi" by="3"/>'].passed
    late = v['<robot-says pattern="follow" by="3"/>']
    assert not late.passed and "between 0 and 3 s" in late.detail and late.where == "room.xml:29"
    assert v['<robot-says pattern="stupid" never="true"/>'].passed
    bye = v['<robot-says pattern="bye" never="true"/>']
    assert not bye.passed and "t=6.00" in bye.detail and "Bye bye" in bye.detail
    assert "room.xml:" in bye.line() and bye.line().startswith("FAIL")


def test_state_reached_and_event_rejected_read_the_supervisors_log():
    stage = _stage('<state-reached state="Interacting" by="4"/>\n<state-reached state="Following" never="true"/>\n'
                   '<state-reached state="ObjectTeaching"/>\n'
                   '<event-rejected event="greeting" reason="expired"/>\n<event-rejected event="greeting" reason="inapplicable"/>')
    _publish_at(stage, 0.0, "supervisor", "/robot/es/status", etree.Element("es_status", state="LookingAround"))
    _publish_at(stage, 1.0, "supervisor", "/robot/es/log", _log("rejected", "greeting", "LookingAround", reason="expired", detail=""))
    _publish_at(stage, 2.0, "supervisor", "/robot/es/log", _log("applied", "potential_partner", "LookingAround", to="PotentialPartner"))
    _publish_at(stage, 3.0, "supervisor", "/robot/es/log", _log("applied", "greeting", "PotentialPartner", to="Interacting"))
    _publish_at(stage, 5.0, "supervisor", "/robot/es/log", _log("applied", "follow", "Interacting", to="Following"))
    v = _verdicts(stage)
    assert v['<state-reached state="Interacting" by="4"/>'][0]
    assert v['<state-reached state="Following" never="true"/>'] == (False, "the supervisor entered Following at t=5.00 s, where none should be")
    assert v['<state-reached state="ObjectTeaching"/>'] == (False, "no entry into state ObjectTeaching between 0 and 10 s")
    assert v['<event-rejected event="greeting" reason="expired"/>'][0]
    assert not v['<event-rejected event="greeting" reason="inapplicable"/>'][0]



def test_event_applied_reads_which_events_the_supervisor_applied_and_from_which_state():
    stage = _stage('<event-applied event="partner_lost" never="true"/>\n<event-applied event="greeting" state="PotentialPartner" by="4"/>\n'
                   '<event-applied event="greeting" state="Interacting"/>\n<event-applied event="partner_lost" never="true" by="5"/>')
    _publish_at(stage, 3.0, "supervisor", "/robot/es/log", _log("applied", "greeting", "PotentialPartner", to="Interacting"))
    _publish_at(stage, 6.0, "supervisor", "/robot/es/log", _log("rejected", "partner_lost", "Interacting", reason="expired", detail=""))
    _publish_at(stage, 7.0, "supervisor", "/robot/es/log", _log("applied", "partner_lost", "Following", to="Interacting"))
    v = _verdicts(stage)
    lost = v['<event-applied event="partner_lost" never="true"/>']
    assert not lost[0] and "t=7.00" in lost[1] and "Following -> Interacting" in lost[1]  # the rejected one at 6 s does not count
    assert v['<event-applied event="greeting" state="PotentialPartner" by="4"/>'][0]
    assert not v['<event-applied event="greeting" state="Interacting"/>'][0]
    assert v['<event-applied event="partner_lost" never="true" by="5"/>'][0]

def test_learned_checks_read_the_scene_models_answer():
    cup = etree.fromstring('<OBJECT type="cup" owner="speaker"><TITLE name="cup"/><COLOUR name="red"/><ATTRIBUTE name="favourite"/></OBJECT>')
    kitchen = etree.fromstring('<PLACE x="1" y="2"><TITLE name="kitchen"/></PLACE>')
    # knowledge handed in as if from an earlier run's store: names nobody in the room says
    stage = _stage('<object-learned type="cup" colour="red" attribute="favourite"/>\n<object-learned type="cup" colour="blue"/>\n'
                   '<place-learned name="kitchen"/>\n<place-learned name="bathroom"/>', robot='memory="required"')
    v = _verdicts(stage, knowledge={"objects": [cup], "places": [kitchen]})
    assert v['<object-learned type="cup" colour="red" attribute="favourite"/>'][0]
    assert not v['<object-learned type="cup" colour="blue"/>'][0]
    assert v['<place-learned name="kitchen"/>'][0] and not v['<place-learned name="bathroom"/>'][0]
    stage = _stage('<place-learned name="kitchen"/>', robot='memory="required"')
    (ok, detail), = _verdicts(stage).values()
    assert not ok and "no scene model" in detail


def test_metric_expectation_reads_dotted_paths_and_names_what_is_missing():
    stage = _stage('<metric name="following.mean_distance_m" min="0.8" max="2"/>\n<metric name="following.share_in_band" min="0.9"/>\n'
                   '<metric name="following.nothing_here" max="1"/>')
    v = _verdicts(stage, metrics={"following": {"mean_distance_m": 1.3, "share_in_band": 0.5}})
    assert v['<metric name="following.mean_distance_m" min="0.8" max="2"/>'][0]
    assert v['<metric name="following.share_in_band" min="0.9"/>'] == (False, "following.share_in_band = 0.5 (outside [0.9, inf])")
    ok, detail = v['<metric name="following.nothing_here" max="1"/>']  # a metric that is registered, a key it never wrote
    assert not ok and detail.startswith("the run has no metric 'following.nothing_here'")


def test_following_distance_counts_only_while_following():
    """Ann stands 2 m from the robot; the robot 'follows' from 2 s to 6 s: inside [1.5, 2.5], outside [0.5, 1]."""
    stage = _stage('<following-distance who="ann" min="1.5" max="2.5"/>\n<following-distance who="ann" min="0.5" max="1" settle="0"/>')
    _publish_at(stage, 2.0, "supervisor", "/robot/es/log", _log("applied", "follow", "Interacting", to="Following"))
    _publish_at(stage, 6.0, "supervisor", "/robot/es/log", _log("applied", "stop", "Following", to="Interacting"))
    v = _verdicts(stage)
    ok, detail = v['<following-distance who="ann" min="1.5" max="2.5"/>']
    assert ok and "100% of 100 steps" in detail  # 4 s - 2 s settle = 2 s at 50 Hz
    ok, detail = v['<following-distance who="ann" min="0.5" max="1" settle="0"/>']
    assert not ok and "0% of 200 steps" in detail and "closest 2.00 m" in detail


def test_following_distance_fails_when_the_robot_never_follows():
    (ok, detail), = _verdicts(_stage('<following-distance who="ann" min="0.5" max="3"/>')).values()
    assert not ok and "never followed ann" in detail


@pytest.mark.parametrize("bad, message", [
    ('<robot-says pattern="(unclosed"/>', "is not a regular expression"),
    ('<robot-says pattern="x" after="5" by="2"/>', "after=5 is later than by=2"),
    ('<robot-says pattern="x" by="99"/>', "after the end of the run"),
    ('<following-distance who="bob" min="1" max="2"/>', "no human named 'bob'"),
    ('<following-distance who="ann" min="2" max="1"/>', "max=1 is below min=2"),
    ('<metric name="a.b"/>', "needs min=, max= or both"),
    ('<event-rejected event="greeting" reason="boredom"/>', "scenario.xsd"),
    ('<object-learned/>', "needs at least one of"),
])
def test_bad_expectations_are_refused_with_file_and_line(bad, message):
    with pytest.raises(ScenarioError) as exc:
        load_scenario_text(_room(bad), source="room.xml")
    assert message in str(exc.value) and "room.xml:28" in str(exc.value)


def test_a_fault_in_a_module_that_is_not_there_names_its_line():
    sc = load_scenario_text(_room("", extra='<faults><crash module="dialog" at="3"/></faults>\n'), source="room.xml")
    with pytest.raises(ScenarioError) as exc:
        Run(sc, RunOptions(subsystems=()))
    assert "room.xml:27" in str(exc.value) and "no such module" in str(exc.value)


def test_a_crashed_module_is_reported_and_the_supervisor_goes_to_technical_failure():
    sc = load_scenario_text(_room('<state-reached state="TechnicalFailure" after="3" by="5"/>',
                                  extra='<faults><crash module="laser" at="3"/></faults>\n'), source="room.xml")
    lines: list[tuple[float, str, str]] = []
    with Run(sc, RunOptions(subsystems=()), on_line=lambda *a: lines.append(a)) as run:
        run.run()
        assert [v.passed for v in run.finish()] == [True]
        assert run.summary()["es"]["final_state"] == "TechnicalFailure"
    assert (3.0, "fault", "laser crashes") in lines
    assert any(who == "health" and text == "module_failed laser" for _, who, text in lines)
    assert any(who == "ES" and "-> TechnicalFailure (module_failed)" in text for _, who, text in lines)


# --------------------------------------------------------------- streaming memory
def test_a_run_keeps_no_messages_and_no_truth_frames():
    with Run.from_file(EXAMPLE, RunOptions(until=3, subsystems=())) as run:
        run.run()
        assert run.stage.messages == [] and run.stage.truth is None
        assert run.verdict() == "not checked"


@settings(max_examples=50, deadline=None)
@given(st.lists(st.floats(-1e6, 1e6, allow_nan=False), min_size=1, max_size=60))
def test_running_statistics_agree_with_the_batch_formulas(xs):
    r = Running()
    for x in xs:
        r.add(x)
    mean = sum(xs) / len(xs)
    assert r.n == len(xs) and math.isclose(r.mean, mean, rel_tol=1e-9, abs_tol=1e-6)
    assert math.isclose(r.std, math.sqrt(sum((x - mean) ** 2 for x in xs) / len(xs)), rel_tol=1e-6, abs_tol=1e-3)
    assert (r.lo, r.hi) == (min(xs), max(xs))


def test_metrics_registry_finds_the_builtin_metrics_and_refuses_unknown_names():
    known = metrics.registry()
    assert {"timing", "dialog", "following"} <= set(known)
    with pytest.raises(ValueError, match="unknown metric"):
        metrics.install(object(), ["no_such_metric"])


def test_matching_knowledge_is_case_insensitive_and_reads_children():
    doc = etree.fromstring('<OBJECT type="Cup"><TITLE name="cup"/><OWNER name="anna"/></OBJECT>')
    assert matches(doc, {"type": "cup", "name": "CUP", "owner": "anna"})
    assert not matches(doc, {"owner": "tom"})
    assert element_dict(doc) == {"kind": "OBJECT", "type": "Cup", "title": "cup", "owner": "anna"}


# ------------------------------------------------------------------- the commands
def test_homesim_run_writes_a_summary_and_replay_confirms_its_trace(tmp_path, capsys):
    trace, summary = tmp_path / "t.jsonl", tmp_path / "s.json"
    assert main(["run", str(EXAMPLE), "--trace", str(trace), "--summary", str(summary), "--until", "12"]) == 0
    out = capsys.readouterr().out
    assert "1.00          anna: Hello BIRON" in out and "verdict: not checked" in out
    s = json.loads(summary.read_text(encoding="utf-8"))
    assert {"scenario", "seed", "sim_time_s", "wall_time_s", "es", "utterances", "learned", "expectations", "metrics"} <= set(s)
    # Anna faced the robot and greeted it: potential partner (person attention) + greeting (dialog).
    assert s["seed"] == 7 and s["sim_time_s"] == 12.0 and s["es"]["final_state"] == "Interacting"
    assert s["utterances"][0] == {"t": 1.0, "end": pytest.approx(2.1, abs=0.2), "speaker": "anna", "text": "Hello BIRON"}
    assert set(s["metrics"]) >= {"timing", "dialog", "following", "tracking"}
    header = json.loads(trace.read_text(encoding="utf-8").split("\n", 1)[0])
    assert header["run"]["scenario_digest"].startswith("sha256:") and header["run"]["until"] == 12
    assert main(["replay", str(trace)]) == 0
    assert "identical" in capsys.readouterr().out
    # A tampered trace: one message changed.
    lines = trace.read_text(encoding="utf-8").split("\n")
    lines[200] = lines[200].replace('"seq":200', '"seq":201')
    trace.write_text("\n".join(lines), encoding="utf-8")
    assert main(["replay", str(trace)]) == 1
    out = capsys.readouterr().out
    assert f"{trace}:201 differs" in out and '"seq":201' in out


def test_replay_notices_a_changed_scenario_file(tmp_path, capsys):
    scenario = tmp_path / "example.xml"
    scenario.write_text(EXAMPLE.read_text(encoding="utf-8"), encoding="utf-8")
    trace = tmp_path / "t.jsonl"
    assert main(["run", str(scenario), "--trace", str(trace), "--until", "1", "--quiet"]) == 0
    scenario.write_text(EXAMPLE.read_text(encoding="utf-8").replace('seed="7"', 'seed="8"'), encoding="utf-8")
    assert main(["replay", str(trace)]) == 1
    assert "has changed since the trace was written" in capsys.readouterr().out


def test_replay_refuses_a_file_that_is_not_a_run_trace(tmp_path, capsys):
    bad = tmp_path / "x.jsonl"
    bad.write_text('{"homesim_trace": 1, "scenario": "x", "seed": 0}\n', encoding="utf-8")
    assert main(["replay", str(bad)]) == 2
    assert "does not name a run" in capsys.readouterr().err


def test_quiet_prints_the_verdict_only_and_a_failure_exits_one(tmp_path, capsys):
    # (The robot does answer Anna's greeting now that person attention and dialog run: ask for what it never says.)
    text = EXAMPLE.read_text(encoding="utf-8").replace('<no-collision/>', '<robot-says pattern="ballroom" by="5"/>')
    path = tmp_path / "needs_a_robot.xml"
    path.write_text(text, encoding="utf-8")
    assert main(["run", str(path), "--quiet"]) == 1
    out = capsys.readouterr().out.strip().split("\n")
    assert out[-1] == "verdict: FAIL (6/7 expectations hold)"
    assert out[0].startswith(f"FAIL {path}:102: <robot-says") and len(out) == 2


@pytest.mark.parametrize("args, message", [
    (["--until", "nan"], "--until"), (["--realtime", "0"], "--realtime"), (["--seed", "-1"], "--seed")])
def test_hostile_options_are_refused(args, message, capsys):
    assert main(["run", str(EXAMPLE), *args]) == 2
    assert message in capsys.readouterr().err


def test_replay_notices_a_changed_store(tmp_path, capsys):
    # a --memory run writes what it learned to its store, so its replay started from other
    # knowledge and diverged somewhere without saying why: the header pins the store's content
    from homesim.memory.sqlite import SqliteStore
    from homesim.tour.runner import store_digest

    store, trace = tmp_path / "store", tmp_path / "t.jsonl"
    assert main(["run", str(EXAMPLE), "--trace", str(trace), "--memory", str(store), "--until", "1", "--quiet"]) == 0
    header = json.loads(trace.read_text(encoding="utf-8").split("\n", 1)[0])
    assert header["run"]["memory_digest"] == store_digest(store)
    assert main(["replay", str(trace)]) == 0  # nothing learned in 1 s: the same store
    capsys.readouterr()
    (db,) = sorted(store.glob("*.sqlite"))
    with SqliteStore(db) as s:
        s.put("extra", 1, etree.fromstring('<OBJECT type="cup"/>'), {}, next_id=2)
    assert main(["replay", str(trace)]) == 1
    assert f"the store {store} has changed since the trace was written" in capsys.readouterr().out
    from homesim.errors import InputError
    from homesim.tour.tracerun import rerun

    with pytest.raises(InputError, match="the store .* has changed"):  # plot and export re-run it too
        rerun(trace)


def test_hardware_rates_run_the_laser_and_camera_at_the_peoplebots_rates_and_replay(tmp_path):
    """--rates hardware: 37.5 laser scans and 25 camera frames a simulated second (10 and 10 by
    default); the trace header names the preset so a replay runs at the same rates; a default
    run's header is as before (no "rates")."""
    from homesim.tour.runheader import read_run_header

    counts = {}
    for rates in (None, "hardware"):
        trace = tmp_path / f"{rates}.jsonl"
        with Run.from_file(EXAMPLE, RunOptions(until=2.0, subsystems=(), rates=rates, trace=trace)) as run:
            run.run()
            run.finish()
        lines = [json.loads(x) for x in trace.read_text().splitlines()]
        assert ("rates" in lines[0]["run"]) == (rates is not None)
        sent = [x["channel"] for x in lines[1:] if x.get("kind") == "publish"]
        counts[rates] = (sent.count("/robot/laser/scan"), sent.count("/robot/camera/faces"))
        if rates:
            assert read_run_header(trace)["rates"] == "hardware"
    assert counts[None] == (20, 20)
    assert counts["hardware"] == (75, 50)
    assert main(["replay", str(tmp_path / "hardware.jsonl")]) == 0
    with pytest.raises(Exception, match="rates"):
        Run.from_file(EXAMPLE, RunOptions(until=1, rates="fast"))


def test_place_learned_checks_where_the_place_was_stored():
    """A wrong user says "this is the study" in the kitchen and never corrects it: the name is
    stored, but in the kitchen; place-learned with room= fails and says where it was stored."""
    two_rooms = '<room name="kitchen" points="0,0 4,0 4,6 0,6"/>\n    <room name="study" points="4,0 8,0 8,6 4,6"/>'
    text = _room('<place-learned name="study" room="study"/>\n<place-learned name="study"/>\n'
                 '<place-learned name="study" room="kitchen"/>\n<place-learned name="study" point="1 3" within="1"/>\n'
                 '<place-learned name="study" room="study" never="true"/>')
    text = text.replace('<room name="room" points="0,0 8,0 8,6 0,6"/>', two_rooms).replace("<robot ", '<robot memory="required" ')
    sc = load_scenario_text(text, source="two.xml")
    stage = Stage(Simulation(seed=1, scenario=sc.name), sc, actors=())
    slip = etree.fromstring('<PLACE name="study" x="1.5" y="3" theta="0" frame="map"/>')  # stored in the kitchen
    v = _verdicts(stage, knowledge={"objects": [], "places": [slip]})
    ok, detail = v['<place-learned name="study" room="study"/>']
    assert not ok and "(1.50, 3.00) in the kitchen" in detail and "not in the study" in detail
    assert v['<place-learned name="study"/>'][0]  # without a target only the name is checked
    assert v['<place-learned name="study" room="kitchen"/>'][0]
    assert v['<place-learned name="study" point="1 3" within="1"/>'][0]
    assert v['<place-learned name="study" room="study" never="true"/>'][0]
    # at the doorway, 0.3 m outside the study's outline, still counts as the study (default margin 0.5 m)
    door = etree.fromstring('<PLACE name="study" x="3.7" y="3" theta="0" frame="map"/>')
    stage = Stage(Simulation(seed=1, scenario=sc.name), sc, actors=())
    assert _verdicts(stage, knowledge={"objects": [], "places": [door]})['<place-learned name="study" room="study"/>'][0]


def test_place_learned_target_must_name_a_room_of_the_flat(tmp_path):
    text = _room('<place-learned name="room" room="attic"/>')
    path = tmp_path / "bad.xml"
    path.write_text(text, encoding="utf-8")
    assert main(["check", str(path)]) != 0
