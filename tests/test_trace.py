"""The trace: its format, and byte-identical runs across processes."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from homesim.bus import Observation
from homesim.message import Message
from homesim.sim import Simulation
from homesim.trace import observation_line, observation_record

from .conftest import examples


def test_header_and_record_format():
    with Simulation(seed=5, scenario="fmt") as sim:
        tr = sim.record_trace()
        a = sim.bus.participant("a")
        sim.bus.participant("b").subscribe("/img", lambda m: None)
        first = a.publish("/img", "<patch w='2'/>", attachments={"pixels": np.arange(6, dtype=np.uint8).reshape(2, 3)})
        a.publish("/img", "<patch/>", causes=(first.id,), created=0.0)
        sim.run()
        recs = tr.records()
    assert recs[0] == {"homesim_trace": 1, "scenario": "fmt", "seed": 5, "homesim_version": "0.1.0"}
    send = recs[1]
    assert list(send) == ["t", "seq", "kind", "sender", "channel", "receivers", "id", "causes", "created", "xml", "attachments"]
    assert send["attachments"]["pixels"]["dtype"] == "uint8"
    assert send["attachments"]["pixels"]["shape"] == [2, 3]
    assert len(send["attachments"]["pixels"]["sha256"]) == 64
    assert recs[2]["causes"] == [first.id]
    delivers = [r for r in recs if r.get("kind") == "deliver"]
    assert [r["id"] for r in delivers] == ["a#1", "a#2"]
    assert [r["seq"] for r in recs[1:]] == list(range(1, len(recs)))


def test_demo_trace_is_byte_identical_across_processes(tmp_path):
    paths = [tmp_path / "one.jsonl", tmp_path / "two.jsonl"]
    for p in paths:
        subprocess.run(
            [sys.executable, "-m", "homesim.cli", "demo", "--seed", "7", "--duration", "4", "--trace", str(p)],
            check=True,
            capture_output=True,
        )
    one, two = (p.read_bytes() for p in paths)
    assert one == two
    kinds = {json.loads(line).get("kind") for line in one.splitlines()[1:]}
    assert {"publish", "deliver"} <= kinds
    assert b"module_failed" in one


def test_different_seeds_give_different_traces(tmp_path):
    out = []
    for seed in (1, 2):
        with Simulation(seed=seed) as sim:
            tr = sim.record_trace()
            from homesim import demo

            demo.build(sim, duration=2.0)
            sim.run(until=2.0)
            out.append(tr.text())
    assert out[0] != out[1]


def test_realtime_pacing_changes_nothing_but_the_pace():
    from homesim import demo

    texts = []
    for realtime in (None, 2000.0):
        with Simulation(seed=3, scenario="rt", realtime=realtime) as sim:
            tr = sim.record_trace()
            demo.build(sim, duration=2.0)
            sim.run(until=2.0)
            texts.append(tr.text())
    assert texts[0] == texts[1]


def test_pacer_sleeps_so_virtual_time_tracks_the_wall_clock(monkeypatch):
    from homesim import realtime

    wall = [100.0]
    sleeps = []
    monkeypatch.setattr(realtime.time, "monotonic", lambda: wall[0])

    def fake_sleep(dt):
        sleeps.append(round(dt, 6))
        wall[0] += dt

    monkeypatch.setattr(realtime.time, "sleep", fake_sleep)
    pacer = realtime.RealtimePacer(scale=2.0)
    pacer.before_advance(0, 1_000_000_000)  # 1 virtual s at 2x: 0.5 s of wall time
    wall[0] += 0.2  # the simulation itself took 0.2 s
    pacer.before_advance(1_000_000_000, 2_000_000_000)
    assert sleeps == [0.5, 0.3]


def test_memory_trace_records_survive_unicode_line_separators():
    with Simulation(seed=1) as sim:
        tr = sim.record_trace()
        a = sim.bus.participant("a")
        a.publish("/x", "<say>Hello\u2028BIRON\u0085!</say>")
        assert tr.records()[1]["xml"] == "<say>Hello\u2028BIRON\u0085!</say>"


def test_random_streams_are_stable_and_distinct():
    a, b = Simulation(seed=4), Simulation(seed=4)
    # CRC32 would give these two names the same stream.
    assert a.rng("plumless").random() != a.rng("buckeroo").random()
    assert a.rng("laser").random() == b.rng("laser").random()
    assert a.rng("laser") is a.rng("laser")
    a.close()
    b.close()


# The recorder formats its lines itself (the hot path); they must be the bytes json.dumps writes.
_text = st.text(st.characters(blacklist_categories=("Cs",)), max_size=12)


@given(
    event=st.sampled_from(["send", "deliver", "drop"]),
    kind=st.sampled_from(["publish", "request", "reply", "error"]),
    t_ns=st.integers(0, 10**13),
    created_ns=st.integers(-(10**9), 10**13),
    seq=st.integers(1, 10**7),
    names=st.lists(_text, min_size=0, max_size=3),
    ident=_text,
    channel=_text,
    reason=_text,
    body=st.text(st.characters(blacklist_categories=("Cs", "Cc"), blacklist_characters="\ufffe\uffff"), max_size=12),
)
@settings(max_examples=examples(200, 60), deadline=None)
def test_a_trace_line_is_exactly_what_json_dumps_writes(event, kind, t_ns, created_ns, seq, names, ident, channel, reason, body):
    xml = etree.Element("m", a=body)
    xml.text = body
    msg = Message(ident, kind, ident, channel, xml, created_ns, t_ns, tuple(names))
    obs = Observation(t_ns, event, msg, tuple(sorted(names)) if event == "send" else tuple(names[:1]), reason if event == "drop" else "")
    want = json.dumps(observation_record(obs, seq), ensure_ascii=False, separators=(",", ":"), allow_nan=False)
    assert observation_line(obs, seq) == want


def test_file_and_memory_traces_batch_lines_but_lose_none(tmp_path):
    path = tmp_path / "t.jsonl"
    with Simulation(seed=1, scenario="batch") as sim:
        mem = sim.record_trace()
        sim.record_trace(path)
        a = sim.bus.participant("a")
        sim.bus.participant("b").subscribe("/x", lambda m: None)
        for i in range(700):  # several batches and a partial one
            a.publish("/x", f"<x i='{i}'/>")
        sim.run()
        middle = mem.text()  # read while the run is open: every line so far is there
        assert middle.count("\n") == 1 + 1400
    assert path.read_text(encoding="utf-8") == middle
