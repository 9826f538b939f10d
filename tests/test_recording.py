"""Recordings that stand alone (``homesim run --record``) and ``homesim trace info|echo`` on both formats.

One short home tour (12 s) is run once with ``--trace`` and ``--record`` from a private copy of
the scenario; the tests then edit, move or delete that copy and look at the files from another
directory, as a user who shares a recording would.
"""

from __future__ import annotations

import json
import re
import shutil
from pathlib import Path

import pytest
from hypothesis import given, settings, strategies as st

pytest.importorskip("mcap")

from homesim.cli import main  # noqa: E402
from homesim.tour.recorded import Recording, as_trace  # noqa: E402
from homesim.tour.trace_cli import trace_info, recording_info  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
UNTIL = 12.0


@pytest.fixture(scope="module")
def recorded(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    d = tmp_path_factory.mktemp("recorded")
    scen = d / "my_tour.xml"
    shutil.copyfile(ROOT / "scenarios" / "home_tour.xml", scen)
    trace, rec = d / "tour.jsonl", d / "tour.mcap"
    assert main(["run", str(scen), "--until", str(UNTIL), "--quiet", "--trace", str(trace), "--record", str(rec)]) == 0
    return {"dir": d, "scenario": scen, "trace": trace, "recording": rec}


@pytest.fixture
def elsewhere(recorded: dict[str, Path], tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> dict[str, Path]:
    """The recording and trace copied to another directory, the scenario file edited, and the cwd there."""
    other = tmp_path / "other"
    other.mkdir()
    for k in ("trace", "recording"):
        shutil.copyfile(recorded[k], other / recorded[k].name)
    monkeypatch.chdir(other)
    return {"trace": Path(recorded["trace"].name), "recording": Path(recorded["recording"].name)}


def test_the_recording_holds_the_trace_byte_for_byte_and_names_its_run(recorded):
    with Recording(recorded["recording"]) as rec:
        assert "".join(line + "\n" for line in rec.trace_lines()) == recorded["trace"].read_text(encoding="utf-8")
        run = rec.run
        assert run["scenario"] == "home_tour" and run["seed"] == "0" and run["profile"] == "full"
        assert run["until"] == repr(UNTIL) and run["version.homesim"] and run["version.mcap"] and run["version.python"]
        assert rec.metadata["homesim.scenario"]["xml"] == (ROOT / "scenarios" / "home_tour.xml").read_text(encoding="utf-8")
        topics = {c[0]: c[1] for c in rec.channels()}
    assert topics["/homesim/world"] == "homesim.WorldState" and topics["/homesim/map"] == "homesim.Map"
    assert topics["/laser"] == "foxglove.LaserScan" and topics["/robot/laser/scan"] == "homesim.BusMessage"
    assert not list(recorded["dir"].glob("*.part"))


def test_recording_changes_nothing_in_the_run(recorded, tmp_path):
    """The recorder only reads: the trace of a run without --record is the same, line for line after the header."""
    plain = tmp_path / "plain.jsonl"
    assert main(["run", str(ROOT / "scenarios" / "home_tour.xml"), "--until", str(UNTIL), "--quiet", "--trace", str(plain)]) == 0
    assert plain.read_text().split("\n")[1:] == recorded["trace"].read_text().split("\n")[1:]


_text = st.text(st.characters(exclude_categories=("Cs",)), max_size=30)


@given(st.fixed_dictionaries({"kind": st.sampled_from(["publish", "request", "reply", "error"]), "sender": _text, "id": _text,
                              "receivers": st.lists(_text, max_size=4), "causes": st.lists(_text, max_size=3),
                              "created": st.floats(0, 1e6, allow_nan=False), "xml": _text}))
def test_bus_messages_are_formatted_as_the_canonical_json(obj):
    """The recorder's fast path writes the bytes the export's canonical JSON would."""
    from homesim.export.foxglove import dumps
    from homesim.tour.mcap_export import bus_message_json

    assert bus_message_json(obj) == dumps(obj)


def test_a_recording_is_byte_identical_for_the_same_run(tmp_path):
    scen = ROOT / "scenarios" / "two_people_radio.xml"
    outs = [tmp_path / f"r{i}.mcap" for i in range(2)]
    for out in outs:
        assert main(["run", str(scen), "--until", "3", "--quiet", "--record", str(out)]) == 0
    assert outs[0].read_bytes() == outs[1].read_bytes()


def test_plot_and_export_work_from_the_recording_alone_after_the_scenario_changed(recorded, elsewhere, capsys):
    with open(recorded["scenario"], "a", encoding="utf-8") as fh:  # the tutorial's step: edit the scenario
        fh.write("<!-- edited after the run -->\n")
    # The JSON Lines trace re-creates its run, and so refuses now ...
    assert main(["plot", str(elsewhere["trace"]), "--at", "10", "-o", "t.png"]) == 2
    err = capsys.readouterr().err
    assert "has changed since the trace was written" in err and "--record" in err
    # ... the recording does not need the scenario file.
    assert main(["plot", str(elsewhere["recording"]), "--at", "10", "-o", "moment.png"]) == 0
    out = capsys.readouterr().out
    assert "home_tour (seed 0) at t = 10.00 s" in out and "partner" in out
    assert Path("moment.png").stat().st_size > 10_000
    assert main(["plot", str(elsewhere["recording"]), "--timeline", "--from", "0", "--to", "12", "-o", "timeline.svg"]) == 0
    assert main(["export", str(elsewhere["recording"]), "--perfetto", "p.json", "--mcap", "x.mcap"]) == 0
    assert json.loads(Path("p.json").read_text())["traceEvents"]
    assert Path("x.mcap").read_bytes() == elsewhere["recording"].read_bytes()
    recorded["scenario"].unlink()  # and with the scenario file gone
    assert main(["plot", str(elsewhere["recording"]), "--at", "5", "-o", "gone.png"]) == 0
    assert "at t = 5.00 s" in capsys.readouterr().out


def test_the_recorded_moment_is_the_run_at_that_time(recorded):
    """The world state and percepts drawn at t come from the recording's messages at or before t."""
    with Recording(recorded["recording"]) as rec:
        world, percepts, t = rec.moment(10.0)
        states = [json.loads(d) for _, _, lt, d in rec.messages(["/homesim/world"], start=10.0, end=10.0)]
        assert len(states) == 1 and t == pytest.approx(10.0)
        assert world.robot.pose == (states[0]["robot"]["x"], states[0]["robot"]["y"], states[0]["robot"]["theta"])
        assert set(world.humans) == {p["name"] for p in states[0]["people"]}
        assert percepts.scan is not None and len(percepts.scan[1]) > 100  # the laser's ranges, from the file
        assert percepts.attention == "Interaction" and percepts.partner
        assert {o.name for o in world.obstacles} and world.bounds()[2] > world.bounds()[0]
        with pytest.raises(Exception, match="after the end of the recording"):
            rec.moment(UNTIL + 5)


def test_run_record_refuses_a_directory_and_writes_nothing_on_bad_input(tmp_path, capsys):
    assert main(["run", str(ROOT / "scenarios" / "home_tour.xml"), "--until", "1", "--record", str(tmp_path)]) == 2
    assert "--record" in capsys.readouterr().err
    same = tmp_path / "run.out"
    assert main(["run", str(ROOT / "scenarios" / "home_tour.xml"), "--until", "1", "--trace", str(same), "--record", str(same)]) == 2
    assert "also the --trace file" in capsys.readouterr().err and not same.exists()


# ---------------------------------------------------------------- trace info
def _rows(out: str) -> dict[str, list[str]]:
    """channel -> [channel, type, count, rate, first, last, senders] (columns are two or more spaces apart)."""
    rows = (re.split(r"\s{2,}", line.strip()) for line in out.splitlines() if line.startswith("  /"))
    return {r[0]: r for r in rows}


def test_trace_info_lists_channels_types_counts_rates_on_both_formats(recorded, capsys):
    assert main(["trace", "info", str(recorded["trace"])]) == 0
    jl = capsys.readouterr().out
    assert main(["trace", "info", str(recorded["recording"])]) == 0
    mc = capsys.readouterr().out
    assert "Scenario:" in jl and "home_tour" in jl and "Seed:" in jl
    assert "Versions:" in mc and "homesim" in mc and "MCAP recording" in mc
    a, b = _rows(jl), _rows(mc)
    scans = a["/robot/laser/scan"]
    assert scans[1] == "scan" and int(scans[2]) == int(b["/robot/laser/scan"][2]) == int(b["/laser"][2])
    assert float(scans[3].split()[0]) == pytest.approx(10.0, rel=0.02)  # the laser's 10 Hz
    assert b["/laser"][1] == "foxglove.LaserScan"
    # Every bus channel of the trace is a channel of the recording, with the same count.
    for name, row in a.items():
        assert int(b[name][2]) == int(row[2]), name


def test_trace_info_counts_add_up_to_the_sends(recorded):
    info = trace_info(recorded["trace"])
    sends = sum(1 for line in recorded["trace"].read_text().splitlines()[1:] if '"kind":"deliver"' not in line and '"kind":"drop"' not in line)
    assert sum(c.count for c in info.channels) == dict(info.totals)["sends"] == sends
    mc = recording_info(recorded["recording"])
    assert info.end - 0.1 <= mc.end <= info.end and sum(c.count for c in mc.channels) == dict(mc.totals)["messages"]  # trace lines go in 0.1 s batches


_T = re.compile(r"^--- t=([0-9.]+) s", re.M)


@settings(max_examples=15)
@given(a=st.floats(0, UNTIL), length=st.floats(0, 6))
def test_trace_echo_prints_exactly_the_window_on_both_formats(recorded, a, length):
    import io

    from homesim.tour.trace_cli import echo

    b = a + length
    want = [r["t"] for r in map(json.loads, recorded["trace"].read_text().splitlines()[1:])
            if r.get("channel") == "/robot/attention/state" and a <= r["t"] <= b]
    texts = []
    for f in (recorded["trace"], recorded["recording"]):
        out = io.StringIO()
        n = echo(f, "/robot/attention/state", start=a, end=b, raw=False, limit=None, out=out)
        got = [float(x) for x in _T.findall(out.getvalue())]
        assert n == len(want) and got == pytest.approx(want, abs=1e-6)
        texts.append(out.getvalue())
    assert texts[0] == texts[1]  # the same text, seq included, from either file


def test_trace_echo_of_a_bus_channel_is_the_same_from_both_formats(recorded, capsys):
    for raw in ([], ["--json"]):
        outs = []
        for f in (recorded["trace"], recorded["recording"]):
            assert main(["trace", "echo", str(f), "/robot/laser/scan", "--from", "3", "--to", "4", *raw]) == 0
            outs.append(capsys.readouterr().out)
        assert outs[0] == outs[1] and outs[0].count("seq" if not raw else '"seq":') >= 10


def test_trace_echo_json_and_count(recorded, capsys):
    assert main(["trace", "echo", str(recorded["trace"]), "/robot/es/log", "--json", "-n", "2"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == 2 and all(json.loads(x)["channel"] == "/robot/es/log" for x in lines)
    assert main(["trace", "echo", str(recorded["recording"]), "/homesim/world", "--from", "5", "--to", "5", "--json"]) == 0
    (state,) = capsys.readouterr().out.splitlines()
    assert json.loads(state)["t"] == pytest.approx(5.0)


def test_trace_echo_an_unknown_channel_names_the_closest(recorded, capsys):
    for f in (recorded["trace"], recorded["recording"]):
        assert main(["trace", "echo", str(f), "/robot/es/stat"]) == 2
        err = capsys.readouterr().err
        assert f"{f}: no channel '/robot/es/stat'; did you mean /robot/es/status" in err


def test_trace_refuses_bad_files_naming_file_and_line(recorded, tmp_path, capsys):
    lines = recorded["trace"].read_text().splitlines(keepends=True)
    cut = tmp_path / "cut.jsonl"
    cut.write_text("".join(lines[:5]) + lines[5][:40])
    assert main(["trace", "info", str(cut)]) == 2
    assert f"{cut}:6: the trace ends in the middle of a line" in capsys.readouterr().err
    bad = tmp_path / "bad.jsonl"
    bad.write_text(lines[0] + '{"t":1,"seq":1,"kind":"publish","sender":3}\n')
    assert main(["trace", "info", str(bad)]) == 2
    assert f"{bad}:2: a publish record without a valid" in capsys.readouterr().err
    other = tmp_path / "notes.txt"
    other.write_text('{"hello": 1}\n')
    assert main(["trace", "info", str(other)]) == 2
    assert f"{other}:1: not a homesim trace" in capsys.readouterr().err
    half = tmp_path / "half.mcap"
    data = recorded["recording"].read_bytes()
    half.write_bytes(data[: len(data) // 2])
    for cmd in (["trace", "info", str(half)], ["plot", str(half), "--at", "1", "-o", str(tmp_path / "x.png")]):
        assert main(cmd) == 2
        err = capsys.readouterr().err
        assert str(half) in err and "MCAP" in err
    assert not (tmp_path / "x.png").exists()


def test_trace_info_reads_any_mcap_file(tmp_path, capsys):
    from mcap.writer import Writer

    f = tmp_path / "foreign.mcap"
    with open(f, "wb") as fh:
        w = Writer(fh)
        w.start()
        sid = w.register_schema("demo.Ping", "jsonschema", b"{}")
        cid = w.register_channel("/ping", "json", sid)
        for i in range(5):
            w.add_message(cid, log_time=i * 500_000_000, publish_time=0, data=b'{"n":%d}' % i)
        w.finish()
    assert main(["trace", "info", str(f)]) == 0
    row = _rows(capsys.readouterr().out)["/ping"]
    assert row[1:4] == ["demo.Ping", "5", "2.00 Hz"]
    with Recording(f) as rec:
        with pytest.raises(Exception, match="holds no homesim trace"):
            rec.trace_header()


def test_export_never_writes_over_a_recording(recorded, tmp_path, capsys):
    """The README's old 'export tour.jsonl --mcap tour.mcap' after 'run --record tour.mcap' destroyed the recording."""
    rec = tmp_path / "tour.mcap"
    shutil.copyfile(recorded["recording"], rec)
    before = rec.read_bytes()
    for opt in ("--mcap", "--perfetto"):
        assert main(["export", str(recorded["trace"]), opt, str(rec)]) == 2
        err = capsys.readouterr().err
        assert f"{rec} is a recording of 'homesim run --record'" in err and opt in err
        assert rec.read_bytes() == before
    assert main(["plot", str(rec), "--at", "2", "-o", str(tmp_path / "m.png")]) == 0


def test_the_readme_never_exports_over_its_recording():
    """Each README command block: no 'export ... --mcap F' where an earlier 'run --record F' wrote F."""
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    recorded_files = set(re.findall(r"--record (\S+)", text))
    exported = set(re.findall(r"homesim export \S+.*?--mcap (\S+)", text))
    assert recorded_files and not recorded_files & exported


def _silently_damaged(path: Path) -> bytes:
    """The file with 16 bytes flipped inside a chunk where the chunk still decompresses (only its CRC tells)."""
    import io

    from mcap.reader import make_reader

    good = path.read_bytes()
    with Recording(path) as rec:
        chunks = rec.summary.chunk_indexes
    for ci in chunks[1:]:
        for frac in range(10, 90, 7):
            at = ci.chunk_start_offset + ci.chunk_length * frac // 100
            data = bytearray(good)
            for k in range(16):
                data[at + k] ^= 0xFF
            try:
                n = sum(1 for _ in make_reader(io.BytesIO(bytes(data))).iter_messages())
            except Exception:
                continue
            if n > 0:
                return bytes(data)
    raise AssertionError("no silent damage found")


def test_a_damaged_recording_is_refused_not_read_with_messages_missing(recorded, tmp_path, capsys):
    """Bytes flipped inside a chunk: every reader refuses the file, naming it (the chunk's CRC), never a shorter trace."""
    data = _silently_damaged(recorded["recording"])
    bad = tmp_path / "flip.mcap"
    bad.write_bytes(bytes(data))
    for cmd in (["trace", "info", str(bad)], ["trace", "echo", str(bad), "/robot/odometry"],
                ["plot", str(bad), "--timeline", "-o", str(tmp_path / "t.svg")],
                ["export", str(bad), "--perfetto", str(tmp_path / "p.json")]):
        assert main(cmd) == 2, cmd
        err = capsys.readouterr().err
        assert f"{bad}: not a whole MCAP file" in err, err
    assert not (tmp_path / "p.json").exists()


def test_ctrl_c_keeps_the_partial_recording_marked_as_stopped(tmp_path, monkeypatch, capsys):
    """As ros2 bag record: an interrupted run keeps what it recorded (the trace keeps its lines too), and says so."""
    from homesim.tour.runner import Run

    real = Run.run

    def interrupted(self, *a, **kw):
        self.sim.run_until(lambda: False, timeout=4.0)
        raise KeyboardInterrupt

    monkeypatch.setattr(Run, "run", interrupted)
    rec, trace = tmp_path / "int.mcap", tmp_path / "int.jsonl"
    with pytest.raises(KeyboardInterrupt):
        main(["run", str(ROOT / "scenarios" / "home_tour.xml"), "--quiet", "--trace", str(trace), "--record", str(rec)])
    monkeypatch.setattr(Run, "run", real)
    assert f"kept the partial recording {rec}" in capsys.readouterr().err
    with Recording(rec) as r:
        assert r.metadata["homesim.stopped"]["reason"] == "interrupted (Ctrl-C)"
        assert float(r.metadata["homesim.stopped"]["t"]) == pytest.approx(4.0)
        lines = list(r.trace_lines())
        assert 3.5 < r.span()[1] <= 4.0 and len(lines) > 1000
    assert trace.read_text().startswith("".join(line + "\n" for line in lines))  # what the trace holds, up to the stop
    assert main(["trace", "info", str(rec)]) == 0
    assert "the run stopped at t = 4.000 s: interrupted (Ctrl-C)" in capsys.readouterr().out
    assert main(["plot", str(rec), "--at", "3", "-o", str(tmp_path / "m.png")]) == 0
    assert not list(tmp_path.glob("*.part"))


@pytest.mark.parametrize("opt", ["--record", "--trace", "--summary"])
def test_run_refuses_an_output_that_is_the_scenario_or_the_memory_before_running(tmp_path, capsys, opt):
    scen = tmp_path / "s.xml"
    shutil.copyfile(ROOT / "scenarios" / "home_tour.xml", scen)
    before = scen.read_bytes()
    assert main(["run", str(scen), "--until", "1", "--quiet", opt, str(scen)]) == 2
    assert f"{scen} is the scenario file" in capsys.readouterr().err and scen.read_bytes() == before
    mem = tmp_path / "mem"
    for out in (mem, mem / "tour.out"):
        assert main(["run", str(scen), "--until", "1", "--quiet", "--memory", str(mem), opt, str(out)]) == 2
        assert "is the --memory directory" in capsys.readouterr().err
    assert not mem.exists() and sorted(p.name for p in tmp_path.iterdir()) == ["s.xml"]


def test_every_message_of_a_json_channel_is_one_json_document(recorded, capsys):
    """What a generic MCAP reader (Foxglove) does with a 'json' channel: json.loads each message."""
    from mcap.reader import make_reader

    with open(recorded["recording"], "rb") as fh:
        for schema, channel, msg in make_reader(fh).iter_messages():
            assert channel.message_encoding == "json"
            doc = json.loads(msg.data)
            if schema.name == "homesim.TraceRecords":
                assert set(doc) == {"lines"} and doc["lines"] and all(json.loads(line)["t"] <= msg.log_time / 1e9 for line in doc["lines"])
    assert main(["trace", "echo", str(recorded["recording"]), "/homesim/trace", "-n", "1"]) == 0
    assert '"lines"' in capsys.readouterr().out


@pytest.mark.parametrize("size", [8, 9, 20, 40])
def test_a_recording_cut_in_its_header_is_refused_naming_the_file(recorded, tmp_path, capsys, size):
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(recorded["recording"].read_bytes()[:size])
    for cmd in (["trace", "info", str(cut)], ["plot", str(cut), "--at", "1", "-o", str(tmp_path / "m.png")],
                ["export", str(cut), "--perfetto", str(tmp_path / "p.json")]):
        assert main(cmd) == 2
        err = capsys.readouterr().err
        assert f"{cut}: not a whole MCAP file" in err, err


def _same_percepts(a, b) -> bool:
    import pickle

    return pickle.dumps(a) == pickle.dumps(b)  # every field, arrays by value


def test_a_moment_between_world_states_draws_truth_and_percepts_of_one_time(recorded, capsys):
    """--at 10.07 draws the world state of 10.0 s: the percepts are those of 10.0 s too, not of 10.07 s."""
    with Recording(recorded["recording"]) as rec:
        world, percepts, t = rec.moment(10.07)
        _, at_state, t0 = rec.moment(10.0)
        assert t == t0 == pytest.approx(10.0) and _same_percepts(percepts, at_state)
        end = rec.span()[1]
    trace_end = json.loads(recorded["trace"].read_text().splitlines()[-1])["t"]
    assert end == pytest.approx(trace_end, abs=1e-9)  # the recording ends where its trace does
    assert main(["trace", "info", str(recorded["recording"])]) == 0
    shown = re.search(r"to ([0-9.]+) s\)", capsys.readouterr().out).group(1)
    assert float(shown) == pytest.approx(trace_end, abs=5e-4)
    assert main(["plot", str(recorded["recording"]), "--at", shown, "-o", str(recorded["dir"] / "end.png")]) == 0


def test_a_recording_holds_the_exports_foxglove_channels_with_the_same_schemas_and_messages(tmp_path):
    """Recorder and export share FoxgloveViews: the same topics, schema bytes and messages (the laser's ranges rounded)."""
    from mcap.reader import make_reader

    trace, recording, exported = tmp_path / "t.jsonl", tmp_path / "r.mcap", tmp_path / "export.mcap"
    assert main(["run", str(ROOT / "scenarios" / "home_tour.xml"), "--until", "4", "--quiet", "--trace", str(trace),
                 "--record", str(recording)]) == 0
    assert main(["export", str(trace), "--mcap", str(exported)]) == 0

    def read(path: Path) -> tuple[dict[str, tuple[str, bytes]], dict[str, list[tuple[int, bytes]]]]:
        schemas, msgs = {}, {}
        with open(path, "rb") as fh:
            for schema, channel, msg in make_reader(fh).iter_messages(log_time_order=False):
                schemas[channel.topic] = (schema.name, schema.data)
                msgs.setdefault(channel.topic, []).append((msg.log_time, msg.data))
        return schemas, msgs

    ex_schemas, ex_msgs = read(exported)
    rec_schemas, rec_msgs = read(recording)
    assert set(ex_schemas) <= set(rec_schemas)
    for topic, (name, data) in ex_schemas.items():
        assert rec_schemas[topic] == (name, data), topic
        if topic == "/laser":
            a, b = ex_msgs[topic], rec_msgs[topic]
            assert [t for t, _ in a] == [t for t, _ in b]
            for (_, x), (_, y) in zip(a, b):
                assert json.loads(y)["ranges"] == pytest.approx(json.loads(x)["ranges"], abs=5e-5)
        else:
            assert rec_msgs[topic] == ex_msgs[topic], topic


def test_closing_a_recorder_stops_every_hook_it_added(tmp_path):
    from homesim.tour.recording import record
    from homesim.tour.runner import Run, RunOptions

    with Run.from_file(ROOT / "scenarios" / "home_tour.xml", RunOptions(until=1.0)) as run:
        bus, world = run.sim.bus, run.world
        before = (list(bus._interceptors), list(world._listeners))
        rec = record(run, tmp_path / "r.mcap")
        assert len(bus._interceptors) > len(before[0]) and len(world._listeners) > len(before[1])
        run.run()
        rec.close()
        assert (list(bus._interceptors), list(world._listeners)) == before
