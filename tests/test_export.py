"""``homesim export``: Perfetto trace events with cause flows, and MCAP for Foxglove, read back."""

from __future__ import annotations

import json
import math

import pytest
from mcap.reader import make_reader

from homesim.cli import main
from homesim.export.foxglove import SCHEMA_NAMES, schema

from .viz_helpers import tour_trace


@pytest.fixture(scope="module")
def tour(tmp_path_factory):
    return tour_trace(tmp_path_factory.getbasetemp())


@pytest.fixture(scope="module")
def perfetto(tour, tmp_path_factory):
    out = tmp_path_factory.mktemp("pf") / "tour.json"
    assert main(["export", str(tour), "--perfetto", str(out)]) == 0
    return json.loads(out.read_text(encoding="utf-8"))


def _import(events):
    """What Perfetto's JSON importer does with slices and v1 flows, in short: events sorted by time (stable), a stack
    of open slices per thread (a slice that does not nest is misplaced), a flow event bound to the slice on top of
    its thread's stack when it is read. Returns the slices and, per flow id, the (start, end) slices it links."""
    order = sorted(range(len(events)), key=lambda i: events[i].get("ts", -1))
    stacks: dict[int, list[dict]] = {}
    ends: dict[int, list] = {}
    for i in order:
        e = events[i]
        if e["ph"] == "X":
            stack = stacks.setdefault(e["tid"], [])
            while stack and stack[-1]["ts"] + stack[-1]["dur"] <= e["ts"] and not (stack[-1]["dur"] > 0 and e["dur"] == 0 and
                                                                                  stack[-1]["ts"] + stack[-1]["dur"] == e["ts"] == stack[-1]["ts"]):
                stack.pop()
            assert not stack or e["ts"] + e["dur"] <= stack[-1]["ts"] + stack[-1]["dur"], ("misplaced", stack[-1], e)
            stack.append(e)
        elif e["ph"] in ("s", "f"):
            top = stacks.get(e["tid"], [None])[-1]
            assert top is not None and top["ts"] == e["ts"], ("flow bound elsewhere", e, top)
            ends.setdefault(e["id"], [None, None])[0 if e["ph"] == "s" else 1] = top
    return ends


def test_perfetto_follows_the_robots_speech_on_the_speaker_back_to_the_microphones(perfetto):
    events = perfetto["traceEvents"]
    threads = {e["tid"]: e["args"]["name"] for e in events if e["ph"] == "M" and e["name"] == "thread_name"}
    back: dict[str, list[str]] = {}  # message id -> the ids of its causes, read from the flows alone
    for cause, effect in _import(events).values():
        assert cause is not None and effect is not None and cause["ts"] <= effect["ts"]
        back.setdefault(effect["args"]["id"], []).append(cause["args"]["id"])
    slices = [e for e in events if e["ph"] == "X"]
    by_id = {e["args"]["id"]: e for e in slices}
    speech = next(e for e in slices if e["cat"] == "robot speech" and "Hello, I am BIRON" in e["name"])
    assert threads[speech["tid"]] == "speaker" and speech["name"].startswith('say "Hello, I am BIRON')
    assert speech["dur"] > 2_000_000  # microseconds: the whole sentence, as long as it is spoken
    chain, node = [], speech["args"]["id"]
    while node in back:
        chain.append(threads[by_id[node]["tid"]])
        node = back[node][0]
    chain.append(threads[by_id[node]["tid"]])
    assert chain == ["speaker", "dialog", "supervisor", "dialog", "understanding", "microphones"]
    recognition = next(e for e in slices if threads[e["tid"]] == "understanding" and e["cat"] == "speech recognition")
    assert recognition["dur"] > 200_000  # recognition takes longest, on the understanding's own thread
    assert not any(e["args"]["channel"].startswith("/system/heartbeat/") for e in slices)
    assert perfetto["otherData"]["scenario"] == "home_tour"
    assert any(e["ph"] == "i" and e["s"] == "g" and e["name"] == "B: greeting" for e in events)


def test_perfetto_has_work_slices_and_message_instants_not_a_flood_of_made_up_durations(perfetto):
    slices = [e for e in perfetto["traceEvents"] if e["ph"] == "X"]
    work = [e for e in slices if e["dur"] > 0]
    instants = [e for e in slices if e["dur"] == 0]
    assert work and all(e["dur"] >= 1000 or e["cat"] != "message" for e in work)  # no 1 us slice stands for a message
    assert all(e["cat"] in ("message", "stream", "processing") for e in instants)
    assert len(instants) > 10 * len(work)  # the streams: each message an instant at its send time
    assert {e["cat"] for e in work} >= {"speech detection", "speech recognition", "robot speech", "processing"}


def test_perfetto_slices_nest_and_each_flow_binds_to_its_messages_slice(perfetto):
    """What a viewer needs: a thread's slices never partly overlap (Perfetto drops a misplaced one), and each flow
    event is read while its own message's slice is on top of its thread (it binds to that one)."""
    ends = _import(perfetto["traceEvents"])
    assert len(ends) > 50


@pytest.fixture(scope="module")
def mcaps(tmp_path_factory):
    d = tmp_path_factory.mktemp("mcap")
    trace = tour_trace(tmp_path_factory.getbasetemp(), until=3.0)
    a, b = d / "a.mcap", d / "b.mcap"
    for out in (a, b):
        assert main(["export", str(trace), "--mcap", str(out)]) == 0
    return trace, a, b


def test_mcap_of_the_same_run_is_byte_identical(mcaps):
    _, a, b = mcaps
    assert a.read_bytes() == b.read_bytes()


def test_mcap_holds_every_bus_channel_and_the_foxglove_views(mcaps):
    trace, a, _ = mcaps
    sends = [json.loads(line) for line in trace.read_text(encoding="utf-8").split("\n")[1:] if line]
    sends = [r for r in sends if r["kind"] in ("publish", "request", "reply", "error")]
    with open(a, "rb") as fh:
        reader = make_reader(fh)
        summary = reader.get_summary()
        assert {s.name for s in summary.schemas.values()} == set(SCHEMA_NAMES)
        assert all(s.encoding == "jsonschema" and json.loads(s.data)["title"] == s.name for s in summary.schemas.values())
        got: dict[str, list] = {}
        last = -1
        for schema, channel, msg in reader.iter_messages(log_time_order=False):
            assert channel.message_encoding == "json" and msg.log_time >= last
            last = msg.log_time
            got.setdefault(channel.topic, []).append((schema.name, msg.log_time, json.loads(msg.data)))
    bus = [(t, m) for topic, ms in got.items() for name, t, m in ms if name == "homesim.BusMessage"]
    assert sorted(m["id"] for _, m in bus) == sorted(r["id"] for r in sends)  # every send, once
    by_id = {m["id"]: (t, m) for t, m in bus}
    for r in sends:
        t, m = by_id[r["id"]]
        assert t == round(r["t"] * 1e9) and m["xml"] == r["xml"] and m["causes"] == r["causes"]
    scans = got["/laser"]
    traced = [r for r in sends if r["channel"] == "/robot/laser/scan"]
    assert len(scans) == len(traced)
    import hashlib
    import numpy as np
    for (_, t, s), r in zip(scans, traced):
        assert len(s["ranges"]) == 361 and s["frame_id"] == "laser"
        assert math.isclose(s["end_angle"] - s["start_angle"], math.pi)
        digest = hashlib.sha256(np.asarray(s["ranges"], dtype="<f8").tobytes()).hexdigest()
        assert digest == r["attachments"]["ranges"]["sha256"]  # the very ranges the robot saw
    frames = {tr["child_frame_id"] for _, _, m in got["/tf"] for tr in m["transforms"]}
    assert frames >= {"base_link", "laser", "odom", "estimate"}
    people = got["/scene/people"][-1][2]["entities"]
    assert [e["id"] for e in people] == ["person/anna"] and people[0]["cylinders"][0]["size"]["z"] > 1.0
    walls = got["/scene/map"][0][2]["entities"][0]["lines"]
    assert len(walls) > 10
    tracks = [m for _, _, m in got["/scene/tracks"] if m["entities"]]
    assert tracks and tracks[-1]["entities"][0]["frame_id"] == "odom"
    assert all(e["id"].startswith("track/") for m in tracks for e in m["entities"])
    assert all(topic.startswith("/") for topic in got)  # ROS-style topics, RPC services included
    truth = [m for _, _, m in got["/poses/truth"]]
    assert len(truth) == len(got["/tf"]) - len(got["/poses/estimate"]) and truth[0]["frame_id"] == "map"
    said = [m for _, _, m in got["/transcript"]]
    assert said and said[0]["name"] == "anna" and said[0]["message"]  # she greets within 3 s


def test_every_mcap_message_is_valid_against_foxgloves_official_schema(mcaps):
    """Each message against the official @foxglove/schemas file of its schema name (tests/test_foxglove_schemas.py
    checks those files are Foxglove's, unmodified), and the MCAP carries that very schema."""
    import jsonschema  # in the test extra

    _, a, _ = mcaps
    checked: dict[str, int] = {}
    validators = {name: jsonschema.Draft7Validator(schema(name)) for name in SCHEMA_NAMES}
    with open(a, "rb") as fh:
        for sch, channel, msg in make_reader(fh).iter_messages():
            assert json.loads(sch.data) == schema(sch.name)
            errors = [f"{channel.topic} @ {msg.log_time}: {e.json_path}: {e.message}" for e in validators[sch.name].iter_errors(json.loads(msg.data))]
            assert not errors, errors[:5]
            checked[sch.name] = checked.get(sch.name, 0) + 1
    assert set(checked) == set(SCHEMA_NAMES)
    bad = {"timestamp": {"sec": -1, "nsec": 0}, "frame_id": "laser", "pose": {}, "start_angle": 0, "end_angle": 1, "ranges": []}
    with pytest.raises(jsonschema.ValidationError):  # the schemas do refuse what Foxglove would not read
        jsonschema.validate(bad, schema("foxglove.LaserScan"))
    trimmed = {"entities": [{"timestamp": {"sec": 0, "nsec": 0}, "frame_id": "map", "id": "x", "cubes": []}]}
    with pytest.raises(jsonschema.ValidationError):  # what the project's own trimmed copy used to let through
        jsonschema.validate(trimmed, schema("foxglove.SceneUpdate"))


def test_export_needs_something_to_write(mcaps, capsys):
    trace, _, _ = mcaps
    assert main(["export", str(trace)]) == 2
    assert "--perfetto" in capsys.readouterr().err


def test_mcap_refuses_a_trace_that_the_run_does_not_reproduce(mcaps, tmp_path, capsys):
    trace, _, _ = mcaps
    lines = trace.read_text(encoding="utf-8").split("\n")
    bad = tmp_path / "bad.jsonl"
    bad.write_text("\n".join(lines[:40] + [lines[40].replace('"seq":40', '"seq":4000')] + lines[41:]), encoding="utf-8")
    out = tmp_path / "x.mcap"
    assert main(["export", str(bad), "--mcap", str(out)]) == 2
    assert f"{bad}:41: the re-run departs from the trace" in capsys.readouterr().err
    assert not out.exists() and not (tmp_path / "x.mcap.part").exists()


def test_export_never_writes_over_the_trace_it_reads(tour, tmp_path, capsys):
    copy = tmp_path / "tour.jsonl"
    copy.write_bytes(tour.read_bytes())
    for opt in ("--perfetto", "--mcap"):
        assert main(["export", str(copy), opt, str(copy)]) == 2
        assert "is the trace being exported" in capsys.readouterr().err
    assert copy.read_bytes() == tour.read_bytes()
    assert main(["export", str(copy), "--perfetto", str(tmp_path / "x"), "--mcap", str(tmp_path / "x")]) == 2
    assert "two files" in capsys.readouterr().err


def test_the_transcripts_log_timestamps_are_its_log_and_publish_times(mcaps):
    """Foxglove's Log panel and its timeline agree: a line said at 2.747 s is logged at 2.747 s (not at the end of
    the world step that started it), as every other stamped message is; the file stays in log-time order."""
    _, a, _ = mcaps
    lines, stamped, last = [], 0, -1
    with open(a, "rb") as fh:
        for _, channel, msg in make_reader(fh).iter_messages(log_time_order=False):
            assert msg.log_time >= last and msg.publish_time == msg.log_time
            last = msg.log_time
            data = json.loads(msg.data)
            if isinstance(data.get("timestamp"), dict):
                stamped += 1
                assert data["timestamp"]["sec"] * 10**9 + data["timestamp"]["nsec"] == msg.log_time, (channel.topic, data)
            if channel.topic == "/transcript":
                lines.append(msg.log_time)
    assert lines and stamped > len(lines)
    assert any(t % 20_000_000 for t in lines)  # off the 20 ms world step: the utterance's own start


def test_an_exported_mcap_says_which_run_it_came_from(mcaps):
    trace, a, _ = mcaps
    header = json.loads(trace.read_text(encoding="utf-8").split("\n", 1)[0])
    with open(a, "rb") as fh:
        records = list(make_reader(fh).iter_metadata())
    meta = {r.name: r.metadata for r in records}["homesim"]
    assert meta["scenario"] == header["scenario"] == "home_tour" and meta["seed"] == str(header["seed"])
    assert meta["homesim_version"] == header["homesim_version"] and meta["exporter"].startswith("homesim ")
    assert meta["run.scenario_file"] == header["run"]["scenario_file"] and meta["run.scenario_digest"].startswith("sha256:")
    assert meta["run.profile"] == header["run"]["profile"] == "full" and meta["run.deployment"] == header["run"]["deployment"]
    assert meta["trace"] == trace.name


def test_trace_echo_finds_a_service_channel_by_either_spelling_in_the_trace_and_the_recording(tmp_path):
    """The trace names RPC services as the bus does (``map_server/map``), an MCAP gives every topic one leading
    slash (``/map_server/map``): ``trace echo`` takes either spelling on either file, with the same messages."""
    import io
    import re

    from homesim.tour.trace_cli import echo

    trace, rec = tmp_path / "t.jsonl", tmp_path / "t.mcap"
    assert main(["run", "scenarios/home_tour.xml", "--until", "2", "--quiet", "--trace", str(trace), "--record", str(rec)]) == 0
    traced = [r for r in map(json.loads, trace.read_text(encoding="utf-8").splitlines()[1:]) if r.get("channel") == "map_server/map"]
    assert traced  # the run asks the map server for its map at the start
    ids = sorted(r["id"] for r in traced)
    for f in (trace, rec):
        for name in ("map_server/map", "/map_server/map"):
            out = io.StringIO()
            assert echo(f, name, start=None, end=None, raw=False, limit=None, out=out) == len(traced), (f, name)
            assert sorted(re.findall(r"  id (\S+)", out.getvalue())) == ids
