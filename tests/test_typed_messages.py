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
from homesim.heartbeat import BeatRecord, Heartbeat, HeartbeatMonitor, _read_beat
from homesim.message import Frozen, Message, Typed, TypedMessage
from homesim.sim import Simulation
from homesim.trace import MemoryTrace
from homesim.xmlio import hardened_parser, schema_from_text
from robot.attention.records import TrackRow, TracksRecord
from robot.percepts import FaceRow, PerceptList, TorsoRow

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
        self.x = x
        self.label = label

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
    rec = PerceptList(template, f"{t:.6f}", "face" if faces else "torso", tuple(rows))
    assert etree.tostring(rec.to_xml()) == etree.tostring(old)
    assert template.get("time") == "" and len(template) == 0  # the sender's template is never changed
