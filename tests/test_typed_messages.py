"""Typed messages (issue 25 item 1): a record on the bus, its XML built only when somebody reads it.

What a user relies on: a typed message's trace line is byte for byte the line of the same payload
sent as XML; receivers share the record but each gets an XML document of its own; nobody reading
means no XML is built at all; ``--strict`` still checks the record's XML against the channel's
schema and refuses an invalid one. And the records the robot and the kernel send now (tracks,
heartbeats, the pan-tilt state) write exactly what their senders wrote before.
"""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from homesim.errors import MessageValidationError
from homesim.bus import message_size
from homesim.heartbeat import BackstopMonitor, BeatForm, BeatRecord, Heartbeat, HeartbeatMonitor, _read_beat
from homesim.message import Frozen, Message, Typed, TypedMessage
from homesim.network import LinkModel
from homesim.sim import Simulation
from homesim.trace import MemoryTrace
from homesim.xmlio import hardened_parser, schema_from_text
from robot.attention.records import TrackRow, TracksRecord
from robot.percepts import FaceRow, PerceptForm, PerceptList, TorsoRow
from robot.sonar_packet import SonarPacket

POINT_XSD = """<xs:schema xmlns:xs="http://www.w3.org/2001/XMLSchema">
  <xs:element name="point">
    <xs:complexType>
      <xs:attribute name="x" type="xs:double" use="required"/>
      <xs:attribute name="label" type="xs:string"/>
    </xs:complexType>
  </xs:element>
</xs:schema>"""


class Point(Typed):
    """A test record that counts how often its XML is built."""

    __slots__ = ("x", "label")
    built = 0

    def __init__(self, x: float | str, label: str = "") -> None:
        object.__setattr__(self, "x", x)
        object.__setattr__(self, "label", label)

    def to_xml(self) -> etree._Element:
        Point.built += 1
        el = etree.Element("point", x=str(self.x))
        if self.label:
            el.set("label", self.label)
        return el


@pytest.fixture(autouse=True)
def _reset_count():
    Point.built = 0


def _sim(strict: bool = False) -> Simulation:
    return Simulation(seed=5, strict=strict)


def test_nobody_reading_builds_no_xml_and_the_message_still_counts():
    sim = _sim()
    a = sim.bus.participant("a")
    b = sim.bus.participant("b")
    got: list[Message] = []
    b.subscribe("/p", got.append)
    for i in range(5):
        msg = a.publish("/p", Point(i))
    sim.run()
    assert isinstance(msg, TypedMessage) and msg.id == "a#5"
    assert [m.data.x for m in got] == [0, 1, 2, 3, 4]
    assert Point.built == 0  # delivered, never read as XML
    assert sim.bus.sent == 5 and sim.bus.delivered == 5
    sim.close()


def test_receivers_share_the_record_but_each_reads_its_own_document():
    sim = _sim()
    a = sim.bus.participant("a")
    got: dict[str, Message] = {}
    for name in ("b", "c", "d"):
        sim.bus.participant(name).subscribe("/p", lambda m, n=name: got.__setitem__(n, m))
    a.publish("/p", Point(1.5, "here"))
    sim.run()
    assert got["b"].data is got["c"].data is got["d"].data
    docs = [got[n].xml for n in ("b", "c", "d")]
    assert len({id(d) for d in docs}) == 3
    assert got["b"].xml is docs[0]  # built once per receiver, then that receiver's own
    docs[0].set("x", "99")  # one receiver changing its document changes nobody else's
    assert [d.get("x") for d in docs] == ["99", "1.5", "1.5"]
    assert got["c"].data.x == 1.5
    sim.close()


def _trace_of(payloads: list) -> str:
    sim = _sim()
    trace = MemoryTrace(sim.bus, scenario="s", seed=5)
    a = sim.bus.participant("a")
    sim.bus.participant("b").subscribe("/p", lambda m: None)
    sim.bus.participant("c").subscribe("/p", lambda m: None)
    for p in payloads:
        a.publish("/p", p)
    sim.run()
    text = trace.text()
    sim.close()
    return text


@given(st.lists(st.tuples(st.floats(allow_nan=False, allow_infinity=False), st.sampled_from(["", "kitchen", "a&b"])),
                max_size=6))
@settings(max_examples=30, deadline=None)
def test_a_typed_message_traces_byte_for_byte_as_its_xml_would(points):
    typed = _trace_of([Point(x, label) for x, label in points])
    assert typed == _trace_of([Point(x, label).to_xml() for x, label in points])


def test_strict_validates_the_records_xml_at_send_and_refuses_an_invalid_one():
    sim = _sim(strict=True)
    sim.bus.declare_channel("/p", schema_from_text("point.xsd", POINT_XSD))
    a = sim.bus.participant("a")
    got: list[Message] = []
    sim.bus.participant("b").subscribe("/p", got.append)
    a.publish("/p", Point(2.0))
    assert Point.built == 1
    with pytest.raises(MessageValidationError, match="point.xsd"):
        a.publish("/p", Point("not a number"))
    assert Point.built == 2
    sim.run()
    assert [m.xml.get("x") for m in got] == ["2.0"]  # the invalid one reached nobody
    assert Point.built == 2  # the checked document is the one delivered, not built again
    sim.close()


def test_frozen_hands_out_copies_of_an_element_the_sender_keeps():
    template = etree.Element("ptu", pan="1.000", tilt="0.000")
    rec = Frozen(template)
    a, b = rec.to_xml(), rec.to_xml()
    assert a is not template and a is not b
    assert etree.tostring(a) == etree.tostring(template)


# ------------------------------------------------------------------ the senders' records
def _old_tracks_text(t: float, rows: list[TrackRow]) -> str:
    """What person attention wrote before the record (its f-strings, copied)."""
    parts = [f'<tracks time="{t:.6f}" frame="odom">']
    for r in rows:
        parts.append(
            f'<track id="{r.id}" x="{r.x:.3f}" y="{r.y:.3f}" vx="{r.vx:.3f}" vy="{r.vy:.3f}" cxx="{r.cxx:.5f}" cxy="{r.cxy:.5f}" cyy="{r.cyy:.5f}"'
            f' bearing="{r.bearing:.3f}" distance="{r.distance:.3f}" confirmed="{"true" if r.confirmed else "false"}"'
            f' speaking="{"true" if r.speaking else "false"}" facing="{"true" if r.facing else "false"}"/>'
        )
    parts.append("</tracks>")
    return "".join(parts)


_coord = st.floats(-500, 500, allow_nan=False)
_row = st.builds(TrackRow, st.integers(1, 10**6).map(lambda i: f"t{i}"), _coord, _coord, _coord, _coord,
                 st.floats(0, 50), st.floats(-50, 50), st.floats(0, 50), st.floats(-180, 180), st.floats(0, 40),
                 st.booleans(), st.booleans(), st.booleans())


@given(st.floats(0, 1e6), st.lists(_row, max_size=6))
@settings(max_examples=60, deadline=None)
def test_tracks_record_writes_what_person_attention_wrote(t, rows):
    rec = TracksRecord(t, tuple(rows))
    old = etree.fromstring(_old_tracks_text(t, rows).encode(), hardened_parser())
    assert etree.tostring(rec.to_xml()) == etree.tostring(old)
    with pytest.raises(AttributeError):
        rec.time = 1.0  # type: ignore[misc]


@given(st.floats(-1e9, 1e9, allow_nan=False))
def test_rounding_a_field_gives_the_value_an_xml_reader_parses(v):
    # The tracking metric reads the record's bearing and distance as round(v, 3): the same float,
    # sign of zero included, that float() of the contract's 3-decimal text gives.
    a, b = round(v, 3), float(f"{v:.3f}")
    assert a == b and math.copysign(1.0, a) == math.copysign(1.0, b)


@pytest.mark.parametrize("interval", [0.5, 2, 0.1 + 0.2])
def test_a_beat_is_read_as_its_xml_would_be_and_writes_the_same_bytes(interval):
    sim = _sim()
    p = sim.bus.participant("laser")
    hb = Heartbeat(p, interval)
    mon = HeartbeatMonitor(sim.bus.participant("monitor"))
    seen: list[Message] = []
    sim.bus.participant("watch").subscribe("/system/heartbeat/**", seen.append)
    assert hb.beat()
    sim.run()
    (m,) = seen
    assert isinstance(m.data, BeatRecord)
    assert mon.intervals == {"laser": float(interval)}
    old = etree.Element("heartbeat", module="laser", seq="0", interval=repr(interval))
    old.set("seq", "1")
    assert etree.tostring(m.xml) == etree.tostring(old)
    # An XML beat with the same text is read alike (the monitor's reading does not depend on the form).
    as_xml = Message(m.id, m.kind, m.sender, m.channel, old, m.created_ns, m.sent_ns)
    assert _read_beat(as_xml) == _read_beat(m)
    sim.close()


_deg_text = st.floats(-4, 4).map(lambda a: f"{math.degrees(a):.3f}")
_m_text = st.floats(0, 10).map(lambda v: f"{v:.3f}")


@given(st.booleans(), st.floats(0, 1e5), st.lists(st.tuples(_deg_text, _m_text, _m_text, _m_text), max_size=4))
@settings(max_examples=40, deadline=None)
def test_percept_list_writes_what_the_camera_wrote(faces, t, items):
    # The camera built each list as a copy of its per-pan-tilt template with the time set and a
    # SubElement per item (keyword attributes, in this order); the record must give the same bytes.
    template = etree.Element("faces" if faces else "torsos", {"time": "", "pan": "1.000", "tilt": "-2.500"})
    old = template.__copy__()
    old.set("time", f"{t:.6f}")
    rows: list = []
    for a, b, c, d in items:
        if faces:
            etree.SubElement(old, "face", bearing=a, distance=b, height=c)
            rows.append(FaceRow(a, b, c))
        else:
            etree.SubElement(old, "torso", bearing=a, r=b, g=c, b=d)
            rows.append(TorsoRow(a, b, c, d))
    form = PerceptForm(template.tag, "face" if faces else "torso", {"pan": "1.000", "tilt": "-2.500"})
    rec = PerceptList(form, f"{t:.6f}", tuple(rows))
    assert etree.tostring(rec.to_xml()) == etree.tostring(old)
    assert etree.tostring(rec.to_xml()) == etree.tostring(old)  # the form's template is never changed


# ------------------------------------------------------------------ shared records stay as sent
class _Sender:
    """Sends as the camera and a heartbeat do: one form, one Frozen record, one beat form shared by every message."""

    def __init__(self) -> None:
        self.form = PerceptForm("faces", "face", {"pan": "1.000", "tilt": "0.000"})
        self.ptu = Frozen(etree.Element("ptu", pan="1.000", tilt="0.000"))
        self.beat = BeatForm("cam", 0.5)

    def records(self, bearing: str, seq: int) -> dict[str, Typed]:
        return {
            "/faces": PerceptList(self.form, f"{seq:.6f}", (FaceRow(bearing, "2.000", "1.600"),)),
            "/ptu": self.ptu,
            "/system/heartbeat/cam": BeatRecord(self.beat, seq),
            "/sonar": SonarPacket(str(seq), f"{seq:.6f}", ("0.100", "5.000", "30.000", "0.200"),
                                  (("15", "-0.100", "-0.215", "-90.000", f"{1 + seq / 7:.4f}"),)),
        }


def _records(bearing: str, seq: int) -> dict[str, Typed]:
    return _Sender().records(bearing, seq)


_JUNK = {"rows": (), "time": "9.000000", "seq": 77, "interval": 0.001, "module": "x", "item": "x", "tag": "x"}


def _rude(msg: Message) -> None:
    """A receiver that tries every way to change a shared record; refusals are what must happen.

    The test then checks the effect (another receiver, later messages, the trace): a guard that
    lets a change through fails there too, not only here."""
    d = msg.data
    refused = 0
    names = (*type(d).__slots__, "module", "interval", "tag", "template", "element", "new_field")
    for target in (d, getattr(d, "form", None)):
        if target is None:
            continue
        for name in names + (type(target).__slots__ if target is not d else ()):
            try:
                setattr(target, name, _JUNK.get(name, None))
            except AttributeError:
                refused += 1
            try:
                delattr(target, name)
            except AttributeError:
                refused += 1
    for name in ("template", "element"):
        assert not hasattr(d, name)  # the sender's template is never handed out
    el = msg.xml  # its own document: changing it changes nobody else's
    el.set("pan", "99.000")
    el.set("interval", "0.001")
    for child in list(el):
        el.remove(child)
    d.to_xml().set("seq", "77")  # a fresh copy each call
    _REFUSED.append(refused)


_REFUSED: list[int] = []


def _run_shared(with_rude: bool, pans: list[str]) -> tuple[list, str]:
    sim = _sim()
    trace = MemoryTrace(sim.bus, scenario="s", seed=5)
    a = sim.bus.participant("cam")
    seen: list = []
    for name in ("rude", "other"):  # (the same receivers either way: the trace lists them)
        p = sim.bus.participant(name)
        for ch in ("/faces", "/ptu", "/system/heartbeat/cam", "/sonar"):
            p.subscribe(ch, (_rude if with_rude else lambda m: None) if name == "rude" else
                        lambda m: seen.append((m.channel, etree.tostring(m.xml), getattr(m.data, "interval", None),
                                               getattr(m.data, "rows", None),
                                               m.data.echoes() if isinstance(m.data, SonarPacket) else None)))
    sender = _Sender()
    for i, bearing in enumerate(pans):
        for ch, rec in sender.records(bearing, i + 1).items():
            a.publish(ch, rec)
        sim.run()
    text = trace.text()
    sim.close()
    return seen, text


@given(st.lists(st.floats(-180, 180).map(lambda v: f"{v:.3f}"), min_size=1, max_size=4))
@settings(max_examples=20, deadline=None)
def test_a_rude_receiver_changes_nothing_another_receiver_the_next_message_or_the_trace_sees(pans):
    polite, polite_trace = _run_shared(False, pans)
    _REFUSED.clear()
    rude, rude_trace = _run_shared(True, pans)
    assert rude == polite
    assert rude_trace == polite_trace
    assert len(_REFUSED) == 4 * len(pans) and all(_REFUSED)
    assert len(polite) == 4 * len(pans)


def test_a_sender_changing_its_element_after_sending_a_frozen_record_changes_nothing_sent():
    el = etree.Element("ptu", pan="1.000", tilt="0.000")
    rec = Frozen(el)
    el.set("pan", "99.000")
    assert rec.to_xml().get("pan") == "1.000"


def test_a_beat_says_in_its_xml_what_the_monitor_reads():
    # Module and interval come from one form: the fields and the XML cannot disagree.
    b = BeatRecord(BeatForm("laser", 2), 3)
    el = b.to_xml()
    assert (el.get("module"), float(el.get("interval")), el.get("seq")) == (b.module, b.interval, "3")


# ------------------------------------------------------------------ the backstop builds no beat XML
def test_the_backstop_monitor_reads_typed_beats_without_building_their_xml(monkeypatch):
    built = []
    orig = BeatRecord.to_xml
    monkeypatch.setattr(BeatRecord, "to_xml", lambda self: built.append(self.seq) or orig(self))
    sim = _sim()
    primary = HeartbeatMonitor(sim.bus.participant("watchdog"))
    backstop = BackstopMonitor(sim.bus.participant("kernel"), primary="watchdog")
    hb = Heartbeat(sim.bus.participant("laser"), 0.1)
    hb_w = Heartbeat(sim.bus.participant("watchdog-beat"), 0.1)
    for _ in range(5):
        hb.beat()
        hb_w.beat()
        sim.run(until=sim.bus.loop.now + 0.1)
    assert backstop.intervals["laser"] == 0.1 and primary.intervals["laser"] == 0.1
    assert built == []  # no trace, no XML reader: no beat's XML was built
    sim.close()


# ------------------------------------------------------------------ sizes from the record
_attr_text = st.text(st.characters(blacklist_categories=("Cs", "Cc")) | st.sampled_from("\t\n\r&<>\"'"), max_size=12)


@given(st.sampled_from(["faces", "torsos"]), _attr_text, st.dictionaries(st.sampled_from(["pan", "tilt", "x"]), _attr_text),
       st.lists(st.tuples(_attr_text, _attr_text, _attr_text, _attr_text), max_size=4))
@settings(max_examples=80, deadline=None)
def test_a_percept_lists_size_is_the_length_of_its_xml(kind, time, attrs, items):
    faces = kind == "faces"
    form = PerceptForm(kind, "face" if faces else "torso", attrs)
    rows = tuple(FaceRow(a, b, c) if faces else TorsoRow(a, b, c, d) for a, b, c, d in items)
    rec = PerceptList(form, time, rows)
    assert rec.size() == len(etree.tostring(rec.to_xml()))


@given(st.floats(0, 1e9) | st.just(0.0), st.lists(_row, max_size=5))
@settings(max_examples=60, deadline=None)
def test_a_tracks_records_size_is_the_length_of_its_xml(t, rows):
    rec = TracksRecord(t, tuple(rows))
    assert rec.size() == len(etree.tostring(rec.to_xml()))


@given(st.text(st.characters(blacklist_categories=("Cs", "Cc")), min_size=1, max_size=10),
       st.floats(0.001, 3600) | st.integers(1, 3600), st.integers(0, 10**12))
@settings(max_examples=60, deadline=None)
def test_a_beats_size_is_the_length_of_its_xml(module, interval, seq):
    rec = BeatRecord(BeatForm(module, interval), seq)
    assert rec.size() == len(etree.tostring(rec.to_xml()))


@given(_attr_text, _attr_text)
@settings(max_examples=40, deadline=None)
def test_a_frozen_records_size_is_the_length_of_its_xml(a, b):
    rec = Frozen(etree.Element("ptu", pan=a, tilt=b))
    assert rec.size() == len(etree.tostring(rec.to_xml()))
    assert Point(1.5, "x").size() == len(etree.tostring(Point(1.5, "x").to_xml()))  # the default: measured


def test_a_link_with_a_bandwidth_sizes_typed_messages_without_building_their_xml(monkeypatch):
    built = []
    for cls in (PerceptList, TracksRecord, BeatRecord, Frozen):
        orig = cls.to_xml
        monkeypatch.setattr(cls, "to_xml", lambda self, _o=orig: built.append(type(self)) or _o(self))
    sim = _sim()
    sim.network.set_link(LinkModel("slow", 0.001, 0.001, bandwidth_bps=1e5))
    sim.network.add_host("robot", link="slow")
    sim.network.add_host("laptop", link="slow")
    a = sim.bus.participant("cam", host="robot")
    got: list[Message] = []
    sim.bus.participant("far", host="laptop").subscribe("/c/**", got.append)
    recs = [*_records("1.000", 1).values(), TracksRecord(2.0, (TrackRow("t1", 1, 2, 0, 0, 0.1, 0, 0.1, 3, 2, True, False, True),))]
    for i, rec in enumerate(recs):
        a.publish(f"/c/{i}", rec)
    sim.run()
    assert len(got) == len(recs) and built == []
    sizes = [message_size(m) for m in got]
    assert sizes == [len(etree.tostring(r.to_xml())) for r in recs]
    sim.close()
