"""The Fig. 6 timeline: lanes, messages, processing spans read from causes, phases; ``homesim plot --timeline``."""

from __future__ import annotations

import json

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from homesim.cli import main
from homesim.traceview import read_timeline

from .conftest import examples
from .viz_helpers import tour_trace

MODULES = ["mic", "asr", "dlg", "es", "spk"]


@st.composite
def traces(draw):
    """A synthetic trace: messages between a few modules, each caused by an earlier delivered one (or none)."""
    records = []
    t = 0.0
    delivered: list[tuple[str, str, float]] = []  # (id, receiver, delivery time)
    n = draw(st.integers(1, 25))
    seq = 0
    for i in range(n):
        t += draw(st.floats(0.0, 0.5))
        cause = draw(st.sampled_from(delivered)) if delivered and draw(st.booleans()) else None
        sender = cause[1] if cause else draw(st.sampled_from(MODULES))
        t_send = max(t, cause[2] + draw(st.floats(0.0, 0.4))) if cause else t
        receiver = draw(st.sampled_from([m for m in MODULES if m != sender]))
        mid = f"{sender}#{i}"
        seq += 1
        records.append({"t": t_send, "seq": seq, "kind": "publish", "sender": sender, "channel": f"/c/{sender}",
                        "receivers": [receiver], "id": mid, "causes": [cause[0]] if cause else [], "created": t_send,
                        "xml": f'<m name="n{i}"/>'})
        lat = draw(st.floats(0.0, 0.05))
        seq += 1
        records.append({"t": t_send + lat, "seq": seq, "kind": "deliver", "id": mid, "receivers": [receiver]})
        delivered.append((mid, receiver, t_send + lat))
        t = t_send
    records.sort(key=lambda r: (r["t"], r["seq"]))
    return records


def write(path, records):
    head = {"homesim_trace": 1, "scenario": "synthetic", "seed": 0, "homesim_version": "0"}
    path.write_text("\n".join(json.dumps(r) for r in [head, *records]) + "\n", encoding="utf-8")
    return path


@settings(max_examples=examples(40, 100))
@given(records=traces())
def test_spans_run_from_a_cause_delivered_to_the_sender_until_its_message(tmp_path_factory, records):
    path = write(tmp_path_factory.mktemp("tl") / "t.jsonl", records)
    tl = read_timeline(path, end=max(r["t"] for r in records) + 1.0)
    sends = {r["id"]: r for r in records if r["kind"] == "publish"}
    deliveries = {(r["id"], r["receivers"][0]): r["t"] for r in records if r["kind"] == "deliver"}
    for s in tl.spans:
        effect = sends[s.effect]
        assert s.lane == effect["sender"] and s.end >= effect["t"] >= s.start
        assert s.start == deliveries[(s.cause, s.lane)]
    caused = [m for m in sends.values() if m["causes"] and (m["causes"][0], m["sender"]) in deliveries
              and deliveries[(m["causes"][0], m["sender"])] <= m["t"]]
    for m in caused:  # each message made from a delivered cause lies in a span of its sender from that delivery
        start = deliveries[(m["causes"][0], m["sender"])]
        assert any(s.lane == m["sender"] and s.start == start and s.end >= m["t"] for s in tl.spans), m["id"]
    for f in tl.flows:
        assert f.cause_t <= f.effect_t and sends[f.cause]["sender"] == f.cause_sender
    assert set(tl.lanes) >= {r["sender"] for r in sends.values()}
    for m in tl.messages:
        for r, td in m.delivered.items():
            assert td == deliveries[(m.id, r)] and td >= m.t


@pytest.fixture(scope="module")
def tour(tmp_path_factory):
    return tour_trace(tmp_path_factory.getbasetemp())


def test_the_greeting_shows_recognition_then_a_fast_supervisor(tour):
    tl = read_timeline(tour, start=0, end=12)
    assert [p.mark for p in tl.phases][:2] == ["A", "B"]
    greeting = next(m for m in tl.messages if m.label == "event greeting")
    assert any(p.mark == "B" and 0 <= p.t - greeting.t < 0.02 for p in tl.phases)  # where the ES applied it
    heard = next(m for m in tl.messages if m.label == "utterance hello biron")
    recognising = next(s for s in tl.spans if s.cause == heard.id)
    assert recognising.lane == "understanding" and recognising.end - recognising.start > 0.2  # speech takes longest
    assert recognising.kind == "speech recognition"
    detecting = next(s for s in tl.spans if s.effect == heard.id)  # while she spoke: speech detection
    assert detecting.kind == "speech detection" and detecting.lane == "microphones" and detecting.end == heard.t
    es = [s for s in tl.spans if s.lane == "supervisor" and s.cause == greeting.id]
    assert es and all(s.end - s.start < 0.02 and s.kind == "ES reconfiguration" for s in es)  # under 20 ms (Fig. 6)
    # lanes grouped by host (the papers' deployment): pc1's modules, then pc2's, then the laptop's
    hosts = [tl.hosts[name] for name in tl.lanes]
    assert hosts == sorted(hosts, key=["pc1", "pc2", "laptop"].index) and tl.hosts["dialog"] == "laptop"
    # the greeting crosses the WLAN (laptop -> pc1), a potential-partner event does not
    assert tl.crosses_slow_link("dialog", "supervisor") and not tl.crosses_slow_link("person_attention", "supervisor")
    # the greeting chain runs down the lanes: microphones (pc1), understanding, dialog (the laptop)
    assert tl.lanes.index("microphones") < tl.lanes.index("understanding") < tl.lanes.index("dialog")
    assert any(m.continuous and m.channel == "/robot/laser/scan" for m in tl.messages)
    assert not any(m.channel.startswith("/system/heartbeat/") for m in tl.messages)


def test_plot_timeline_writes_png_and_the_same_svg_twice(tour, tmp_path, capsys):
    a, b, png = tmp_path / "a.svg", tmp_path / "b.svg", tmp_path / "t.png"
    for out in (a, b, png):
        assert main(["plot", str(tour), "--timeline", "--from", "0", "--to", "12", "--out", str(out)]) == 0
    assert "processing spans" in capsys.readouterr().out
    svg = a.read_text(encoding="utf-8")
    assert a.read_bytes() == b.read_bytes()
    for text in ("B: greeting", "understanding", "continuous stream", "processing (cause delivered", "speech recognition",
                 "over the slowest link (wlan)", "laptop"):
        assert text in svg, text
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_an_empty_window_is_refused(tour, tmp_path, capsys):
    assert main(["plot", str(tour), "--timeline", "--from", "5", "--to", "5", "--out", str(tmp_path / "x.png")]) == 2
    assert "window 5-5 s is empty" in capsys.readouterr().err


def test_a_file_that_is_not_a_trace_is_refused(tmp_path, capsys):
    bad = tmp_path / "x.jsonl"
    bad.write_text('{"hello": 1}\n', encoding="utf-8")
    assert main(["plot", str(bad), "--timeline", "--out", str(tmp_path / "x.png")]) == 2
    assert "not a homesim trace" in capsys.readouterr().err


@pytest.mark.parametrize("damage, says", [
    (lambda text: text[: len(text) - 25], "ends in the middle of a line (truncated?)"),
    (lambda text: text.replace('"sender": "mic"', '"sender": 7', 1), "without a valid 'sender'"),
    (lambda text: text.replace('"receivers": ["', '"receivers": [3, "', 1), "'receivers' is not a list of names"),
    (lambda text: text.replace('{"t":', '[{"t":', 1), "not JSON"),
    (lambda text: text + "[1, 2]\n", "not a trace record"),
])
@pytest.mark.parametrize("command", [["plot", "--timeline", "--out", "x.png"], ["export", "--perfetto", "x.json"]])
def test_a_damaged_trace_is_one_line_naming_file_and_line(tmp_path, capsys, damage, says, command):
    """A truncated or edited trace: 'file:line: what', exit 2, no traceback and no output file."""
    records = [{"t": 0.1 * i, "seq": i, "kind": "publish", "sender": "mic", "channel": "/c/mic", "receivers": ["asr"],
                "id": f"mic#{i}", "causes": [], "created": 0.1 * i, "xml": "<m/>"} for i in range(1, 4)]
    path = write(tmp_path / "t.jsonl", records)
    path.write_text(damage(path.read_text(encoding="utf-8")), encoding="utf-8")
    out = tmp_path / command[-1]
    argv = [command[0], str(path), *command[1:-1], str(out)]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert says in err and err.startswith(f"homesim: error: {path}:") and len(err.strip().splitlines()) == 1, err
    assert not out.exists()


def _texts(fig):
    return [t.get_text() for t in fig.axes[0].texts]


def test_the_tutorials_window_labels_what_was_said_and_decided(tour):
    """The README's 0-12 s window: 1 Hz attention messages do not use up the labels; each repeating channel is
    labelled once, and the words, the greeting and the robot's answer are labelled."""
    from homesim.viz.timeline import plot_timeline

    tl = read_timeline(tour, start=0, end=12)
    texts = _texts(plot_timeline(tl))
    for want in ("utterance hello biron", "event greeting", "say Hello, I am BIRON"):
        assert any(t.startswith(want) for t in texts), (want, texts)
    repeats = [t for t in texts if t.endswith("(repeats)")]
    assert repeats and len(repeats) == len(set(repeats))


def test_spans_are_cut_at_the_windows_edge(tour):
    from matplotlib.patches import Rectangle

    from homesim.viz.timeline import plot_timeline

    tl = read_timeline(tour, start=0, end=5)  # the robot's first sentence runs past 5 s
    assert any(s.end > 5 for s in tl.spans)
    bars = [p for p in plot_timeline(tl).axes[0].patches if isinstance(p, Rectangle) and p.get_height() == 0.36]
    assert bars and all(b.get_x() + b.get_width() <= 5 + 1e-9 for b in bars)


def test_phase_labels_never_cover_each_other():
    """A whole run has many phases close together: their marks go into rows, none over another."""
    from homesim.traceview import Phase, Timeline
    from homesim.viz.timeline import plot_timeline

    phases = [Phase(0.5 * i, "CDET"[i % 4], ["follow request", "following (driving)", "teaching an object", "stop"][i % 4]) for i in range(16)]
    tl = Timeline("synthetic", 0, 0.0, 100.0, ["a", "b"], [], [], [], phases, {})
    fig = plot_timeline(tl)
    r = fig.canvas.get_renderer()
    boxes = [t.get_window_extent(r) for t in fig.axes[0].texts if ":" in t.get_text()]
    assert len(boxes) == 16
    assert not any(boxes[i].overlaps(boxes[j]) for i in range(16) for j in range(i + 1, 16))
    top = fig.axes[0].get_window_extent(r).y1
    assert all(b.y1 <= top + 1 for b in boxes)  # all inside the axes


def test_a_whole_run_timeline_thins_each_stream_to_a_readable_number(tour):
    from homesim.traceview import STREAM_SAMPLES

    tl = read_timeline(tour)  # the whole recorded run (12 s here: 2 per second)
    per = {}
    for m in tl.messages:
        if m.continuous:
            per[(m.sender, m.channel)] = per.get((m.sender, m.channel), 0) + 1
    assert per and max(per.values()) <= max(STREAM_SAMPLES, 2 * (tl.end - tl.start)) + 1

def test_the_slow_arrows_follow_a_link_per_direction_and_a_route():
    """The header's uplinks and routes: a message takes the pair's route, else the slower of the
    sender's uplink and the receiver's link, as the network does."""
    from types import SimpleNamespace

    from homesim.traceview import _deployment

    run = {"hosts": {"pc1": "lan", "pc2": "lan", "laptop": "wlan_down"}, "uplinks": {"laptop": "wlan"},
           "routes": {"pc2->laptop": "lan"}, "placement": {"default": "pc1", "dialog": "laptop", "camera": "pc2"},
           "link_worst_ms": {"lan": 4.0, "wlan": 30.0, "wlan_down": 700.0}}
    msgs = [SimpleNamespace(sender="attention", delivered=["dialog"]), SimpleNamespace(sender="dialog", delivered=["attention"]),
            SimpleNamespace(sender="camera", delivered=["dialog"])]
    _, _, slow, links = _deployment({"run": run}, {"attention", "dialog", "camera"}, msgs)
    # to the laptop over its queued downlink; back over wlan (slower than the LAN too); pc2's route is the LAN
    assert slow == {("attention", "dialog"): "wlan_down", ("dialog", "attention"): "wlan"}
    assert links == ("wlan_down", "wlan")  # slowest first: the legend names them


def test_the_legend_names_the_slow_links_the_run_used():
    from homesim.viz.timeline import slow_key

    assert slow_key(("wlan",)) == "over the slowest link (wlan), with its latency"
    assert slow_key(("wlan_down", "wlan")) == "over a slow link (wlan_down, the slowest; wlan), with its latency"


def test_a_label_names_the_root_element_not_a_child():
    """es_status's state, not the name of the event inside it (the review: "es_status greeting")."""
    from homesim.traceview import label_of

    xml = '<es_status state="Interacting" at="3.2"><last event="dialog#4" name="greeting"/></es_status>'
    assert label_of({"xml": xml}) == "es_status Interacting"
    assert label_of({"xml": '<event name="greeting"><SPEECH text="hi"/></event>'}) == "event greeting"
    assert label_of({"xml": '<order target="dialog"><param name="place"/></order>'}) == "order"


def test_an_events_wait_in_the_es_queue_is_not_drawn_as_the_es_working(tmp_path):
    """wlan_reorder: the greeting waits ~0.27 s in the ES's queue for the older potential-partner event
    still on the WLAN. That wait (delivered -> the ES's record that applies it) is its own span kind,
    not the ES working (the review: "es_record greeting 266 ms" drawn as processing)."""
    from homesim.tour.phases import ES_QUEUE

    trace = tmp_path / "wr.jsonl"
    assert main(["run", "scenarios/wlan_reorder.xml", "--seed", "0", "--until", "4.5", "--quiet", "--trace", str(trace)]) == 0
    tl = read_timeline(trace, start=0, end=4.5)
    greeting = next(m for m in tl.messages if m.label == "event greeting" and m.sender == "dialog")
    es = [s for s in tl.spans if s.lane == "supervisor" and s.cause == greeting.id]
    waits = [s for s in es if s.kind == ES_QUEUE]
    assert len(waits) == 1 and waits[0].end - waits[0].start > 0.1
    assert [s.kind for s in es if s is not waits[0]] and all(
        s.kind == "ES reconfiguration" and s.end - s.start < 0.02 for s in es if s is not waits[0])
    assert not any(s.kind == "processing" for s in tl.spans if s.lane == "supervisor")


@pytest.fixture(scope="module")
def long_tour(tmp_path_factory):
    """A real home tour to 100 s: greeting, following, two object teachings (each a burst of object focus)."""
    return tour_trace(tmp_path_factory.getbasetemp(), until=100.0)


def test_a_whole_run_draws_the_teaching_bursts_light_and_labels_each_once(long_tour):
    """Object focus sends ~10 messages in 2 s twice in 100 s: far below any average rate, but a burst where it
    happens. Its arrows are the light repeating colour (not dark event arrows) and each burst is labelled once."""
    from matplotlib.patches import FancyArrowPatch

    from homesim.viz.timeline import EVENT, plot_timeline, repeating

    tl = read_timeline(long_tour)
    events = [m for m in tl.messages if not m.continuous]
    end = max(m.t for m in tl.messages)
    focus = [m for m in events if m.channel == "/robot/objects/focus" and m.t < end - 2.0]  # bursts the window holds whole
    assert len(focus) >= 10
    inside, firsts = repeating(events)
    assert all(m.id in inside for m in focus)
    bursts = len([m for m in focus if m.id in firsts])
    assert bursts >= 1  # each teaching's burst, labelled once
    said = [m for m in events if m.channel == "/robot/speaker/say"]
    assert said and not any(m.id in inside for m in said)  # what the robot says, seconds apart, is no burst
    fig = plot_timeline(tl)
    from matplotlib.colors import to_hex
    dark = [p for p in fig.axes[0].patches if isinstance(p, FancyArrowPatch) and to_hex(p.get_edgecolor()) == EVENT]
    lanes = {name: len(tl.lanes) - 1 - i for i, name in enumerate(tl.lanes)}
    focus_dark = [p for p in dark if any(abs(p._posA_posB[0][0] - m.t) < 1e-9 and p._posA_posB[0][1] == lanes["object_attention"]
                                         for m in focus)]
    assert not focus_dark
    texts = _texts(fig)
    assert sum(t.endswith("(repeats)") and "focus" in t for t in texts) == bursts, texts


def test_the_legend_promises_repeats_labels_only_where_the_picture_has_them(long_tour):
    """On a real run's 0-12 s no channel bursts (the attention's states are a stream over the run): no "(repeats)"
    promise in the legend; the teaching window has a burst, its label and the legend entry."""
    from homesim.viz.timeline import plot_timeline

    def legend(fig):
        return [t.get_text() for t in fig.axes[0].get_legend().get_texts()]

    fig = plot_timeline(read_timeline(long_tour, start=0, end=12))
    assert not any("repeats" in t for t in legend(fig)) and not any(t.endswith("(repeats)") for t in _texts(fig))
    fig = plot_timeline(read_timeline(long_tour, start=70, end=80))
    assert any("(repeats)" in t for t in legend(fig))
    assert any(t.endswith("(repeats)") for t in _texts(fig))


@pytest.mark.parametrize("window", [(0.0, 15.0), (None, None)])
def test_no_timeline_label_covers_another_or_leaves_the_axes_on_a_real_run(long_tour, window):
    """The review's pictures: WLAN latencies at 2.1-2.6 s on top of each other, "map_request" over the y axis,
    replies at the run's end running into the host's name. Every label (messages, latencies, span durations,
    phases) now has its own place inside the axes; an understood frame is labelled with its words."""
    from homesim.viz.timeline import plot_timeline

    start, end = window
    fig = plot_timeline(read_timeline(long_tour, start=start, end=end))
    fig.canvas.draw()
    ax = fig.axes[0]
    r = fig.canvas.get_renderer()
    frame = ax.get_window_extent(r)
    hosts = {"pc1", "pc2", "laptop"}
    texts = [t for t in ax.texts if t.get_text() and t.get_text() not in hosts]
    assert len(texts) > 30
    boxes = [t.get_window_extent(r) for t in texts]
    for i, (t, bb) in enumerate(zip(texts, boxes)):
        assert frame.x0 - 0.5 <= bb.x0 and bb.x1 <= frame.x1 + 0.5, t.get_text()  # inside the axes, left to right
        clash = [texts[j].get_text() for j, o in enumerate(boxes) if j != i and bb.overlaps(o)]
        assert not clash, (t.get_text(), clash)
    if start == 0.0:
        assert any(t.get_text() == "understood what can you do" for t in texts)


@pytest.mark.parametrize("window", [(0.0, 15.0), (None, None)])
def test_no_message_or_latency_label_lies_across_a_rule_between_host_bands(long_tour, window):
    """The review: WLAN latency labels sat on the rule between two hosts' bands (an arrow from pc1 to the laptop
    crosses it at its middle), hiding where one host ends. Message and latency labels now keep off the rules."""
    from homesim.viz.timeline import SLOW, plot_timeline

    start, end = window
    fig = plot_timeline(read_timeline(long_tour, start=start, end=end))
    fig.canvas.draw()
    ax = fig.axes[0]
    r = fig.canvas.get_renderer()
    rules = [ln for ln in ax.lines if ln.get_color() == "#9999bb"]
    assert len(rules) == 2  # pc1 | pc2 | laptop
    rule_y = [ax.transData.transform((0.0, ln.get_ydata()[0]))[1] for ln in rules]
    placed = [t for t in ax.texts if t.get_text() and t.get_fontsize() == 5.5]  # message and latency labels
    assert any(t.get_color() == SLOW for t in placed)  # latencies over the WLAN are among them
    for t in placed:
        bb = t.get_window_extent(r)
        assert not any(bb.y0 < yr < bb.y1 for yr in rule_y), (t.get_text(), bb, rule_y)
