"""The hardware's channels are typed: every message is validated against its XSD when sent.

- every channel the hardware publishes on or listens to during the example
  scenario is declared typed on the bus (with the schema of
  ``robot.hardware.channels``), and the example still passes;
- malformed commands are refused at the sender, naming channel and schema,
  and reach no device;
- Hypothesis: real messages of a short run always validate; the same
  messages with a required attribute dropped or a number garbled never do.
"""

from __future__ import annotations

import asyncio
import copy
import functools
import math
import string
from collections.abc import Iterator
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from homesim.bus import SEND, Observation, Participant
from homesim.errors import MessageValidationError
from homesim.message import PUBLISH
from homesim.scenario.loader import load_scenario
from homesim.sim import Simulation
from homesim.tour.stage import Install, Stage
from homesim.xmlio import load_schema, parse_bytes, parse_file, serialize
from robot.hardware.channels import CHANNELS, SCHEMA_DIR, SCHEMAS, declare_channels
from tests.world_helpers import EXAMPLE, ROOM
from tests.stage_helpers import ACTORS, HARDWARE

XS = "{http://www.w3.org/2001/XMLSchema}"
HEARTBEATS = "/system/heartbeat/"  # the kernel's channels, typed (or not) by the kernel


# ----------------------------------------------------------------- helpers
class Recorder:
    """An interceptor keeping every published message that was sent."""

    def __init__(self) -> None:
        self.sent: list = []

    def __call__(self, obs: Observation) -> None:
        if obs.event == SEND and obs.message.kind == PUBLISH:
            self.sent.append(obs.message)


def _channels_used(stage: Stage, rec: Recorder) -> set[str]:
    """Channels the hardware modules published on or subscribed to."""
    names = set(stage.hardware)
    used = {m.channel for m in rec.sent if m.sender in names}
    for entry in stage.sim.bus.registry():
        if entry["name"] in names:
            used.update(entry["subscribes"])
    return used


def _numeric(type_name: str, simple_types: dict[str, str]) -> bool:
    base = simple_types.get(type_name, type_name)
    return base in ("xs:double", "xs:nonNegativeInteger", "xs:positiveInteger", "xs:integer", "xs:decimal")


def _attribute_table(path: Path) -> dict[str, dict[str, tuple[bool, bool]]]:
    """element name -> attribute -> (required, numeric), read from one of our XSDs."""
    root = parse_file(path)
    simple = {}
    for t in root.iter(XS + "simpleType"):
        r = t.find(XS + "restriction")
        if t.get("name") and r is not None:
            simple[t.get("name")] = r.get("base")
    table: dict[str, dict[str, tuple[bool, bool]]] = {}
    for el in root.iter(XS + "element"):
        attrs = {}
        for a in el.iter(XS + "attribute"):
            owner = next(p for p in a.iterancestors() if p.tag == XS + "element")
            if owner is el:
                attrs[a.get("name")] = (a.get("use") == "required", _numeric(a.get("type", "xs:string"), simple))
        table[el.get("name")] = attrs
    return table


TABLES = {c.channel: _attribute_table(c.path) for c in CHANNELS}


def _stage(path: Path, seed: int | None = None, actors: tuple[Install, ...] | None = None) -> tuple[Stage, Recorder]:
    sc = load_scenario(path)
    sim = Simulation(seed=sc.seed if seed is None else seed, scenario=sc.name)
    st_ = Stage(sim, sc, actors=ACTORS) if actors is None else Stage(sim, sc, actors=actors)
    rec = Recorder()
    sim.bus.add_interceptor(rec)
    return st_, rec


# ------------------------------------------------------- the example run
@pytest.fixture(scope="module")
def example() -> Iterator[tuple[Stage, Recorder]]:
    stage, rec = _stage(EXAMPLE)
    stage.run()
    yield stage, rec
    stage.sim.close()


def test_every_hardware_channel_used_in_the_example_is_typed_with_its_schema(example):
    stage, rec = example
    bus = stage.sim.bus
    used = _channels_used(stage, rec)
    robot_channels = {c for c in used if not c.startswith(HEARTBEATS)}
    assert {"/robot/laser/scan", "/robot/camera/faces", "/robot/audio/sources", "/robot/audio/steer",
            "/robot/odometry", "/robot/ptu/state", "/robot/base/cmd", "/robot/ptu/cmd",
            "/robot/speaker/say", "/robot/display/cmd"} <= robot_channels
    untyped = sorted(c for c in used if bus.channel_schema(c) is None)
    # Only the kernel's heartbeat channels may be untyped (they are not the hardware's to type).
    assert all(c.startswith(HEARTBEATS) for c in untyped), untyped
    for ch in robot_channels:
        assert bus.channel_schema(ch) is load_schema(SCHEMAS[ch]), ch
    # And every declared hardware channel is typed, used in this run or not.
    for c in CHANNELS:
        assert bus.channel_schema(c.channel) is load_schema(c.path)


def test_the_example_still_passes_with_typed_channels(example):
    stage, rec = example
    verdicts = stage.verdicts()
    assert verdicts and all(v.passed for v in verdicts), [v.line() for v in verdicts]
    assert sum(1 for m in rec.sent if m.channel == "/robot/laser/scan") == 400


def test_the_channel_table_matches_the_schema_files():
    files = sorted(p.name for p in SCHEMA_DIR.glob("*.xsd"))
    assert sorted(c.schema for c in CHANNELS) == files
    assert len({c.channel for c in CHANNELS}) == len(CHANNELS)
    for c in CHANNELS:
        load_schema(c.path)  # compiles
        assert c.direction in ("in", "out")


def test_schema_objects_are_compiled_once_and_shared():
    a, b = Simulation(seed=1), Simulation(seed=2)
    declare_channels(a.bus)
    declare_channels(b.bus)
    for c in CHANNELS:
        assert a.bus.channel_schema(c.channel) is b.bus.channel_schema(c.channel)
    a.close()
    b.close()


def test_the_schemas_ship_as_package_data():
    setuptools = pytest.importorskip("setuptools")
    root = Path(__file__).resolve().parents[1]
    # pyproject's [tool.setuptools.packages.find] finds namespace packages (its default).
    pkgs = setuptools.find_namespace_packages(str(root), include=["homesim*", "robot*", "humans*"])
    assert "robot.schemas.hardware" in pkgs
    assert '"*.xsd"' in (root / "pyproject.toml").read_text(encoding="utf-8")


# ----------------------------------------------------- malformed commands
BAD_COMMANDS = [
    ("/robot/base/cmd", "base-cmd.xsd", '<velocity v="fast" w="0"/>'),
    ("/robot/base/cmd", "base-cmd.xsd", '<velocity v="0.3"/>'),
    ("/robot/base/cmd", "base-cmd.xsd", '<velocity w="0.1"/>'),
    ("/robot/base/cmd", "base-cmd.xsd", '<velocity v="NaN" w="0"/>'),
    ("/robot/base/cmd", "base-cmd.xsd", '<velocity v="INF" w="0"/>'),
    ("/robot/base/cmd", "base-cmd.xsd", '<velocity v="1e" w="0"/>'),  # libxml2 alone takes it; float() does not
    ("/robot/base/cmd", "base-cmd.xsd", '<velocity v="0.1" w="0" speed="1"/>'),
    ("/robot/base/cmd", "base-cmd.xsd", '<speed v="0.1" w="0"/>'),
    ("/robot/ptu/cmd", "ptu-cmd.xsd", '<ptu pan="left"/>'),
    ("/robot/ptu/cmd", "ptu-cmd.xsd", '<ptu pan="10" zoom="2"/>'),
    ("/robot/speaker/say", "speaker-say.xsd", "<say><b>Hello</b></say>"),
    ("/robot/speaker/say", "speaker-say.xsd", '<speak text="Hello"/>'),
    ("/robot/display/cmd", "display-cmd.xsd", '<gaze pan="10"/>'),
    ("/robot/display/cmd", "display-cmd.xsd", '<expression name="very happy"/>'),
    ("/robot/display/cmd", "display-cmd.xsd", '<expression/>'),
]


@pytest.fixture()
def room() -> Iterator[tuple[Stage, Recorder]]:
    stage, rec = _stage(ROOM, actors=HARDWARE)
    yield stage, rec
    stage.sim.close()


@pytest.mark.parametrize("channel,schema,text", BAD_COMMANDS)
def test_a_malformed_command_is_refused_at_the_sender(room, channel, schema, text):
    stage, rec = room
    driver = stage.sim.bus.participant("driver", host="robot")
    with pytest.raises(MessageValidationError) as err:
        driver.publish(channel, text)
    msg = str(err.value)
    assert channel in msg and schema in msg and "driver" in msg
    stage.run(1.0)
    assert not [m for m in rec.sent if m.sender == "driver"]  # nothing was sent
    assert stage.world.robot.cmd_v == 0.0 and stage.world.robot.cmd_w == 0.0


def test_a_velocity_command_with_a_non_numeric_speed_reaches_no_base(room):
    stage, rec = room
    driver = stage.sim.bus.participant("driver", host="robot")
    delivered = stage.sim.bus.delivered

    async def drive():
        await asyncio.sleep(0.2)
        driver.publish("/robot/base/cmd", etree.Element("velocity", v="0.4", w="0"))
        with pytest.raises(MessageValidationError, match=r"/robot/base/cmd.*base-cmd\.xsd"):
            driver.publish("/robot/base/cmd", etree.Element("velocity", v="0,4", w="0"))

    stage.sim.spawn(drive(), name="drive")
    stage.run(0.3)
    assert stage.world.robot.cmd_v == pytest.approx(0.4)  # the good one arrived
    assert [m.xml.get("v") for m in rec.sent if m.sender == "driver"] == ["0.4"]
    assert stage.sim.bus.delivered > delivered


GOOD_COMMANDS = [
    ("/robot/base/cmd", '<velocity v="0.25" w="-1e-3"/>'),
    ("/robot/base/cmd", '<velocity v="3" w="12"/>'),  # out of range: the base clamps, not the schema
    ("/robot/ptu/cmd", '<ptu pan="40"/>'),
    ("/robot/ptu/cmd", '<ptu tilt="-5.5"/>'),
    ("/robot/ptu/cmd", '<ptu pan="140" tilt="10"/>'),
    ("/robot/speaker/say", '<say text="Hello"/>'),
    ("/robot/speaker/say", "<say>Hello there</say>"),
    ("/robot/display/cmd", '<gaze pan="20" tilt="0"/>'),
    ("/robot/display/cmd", '<expression name="happy"/>'),
]


@pytest.mark.parametrize("channel,text", GOOD_COMMANDS)
def test_well_formed_commands_pass(room, channel, text):
    stage, rec = room
    driver = stage.sim.bus.participant("driver", host="robot")
    driver.publish(channel, text)
    stage.run(0.5)
    assert [m.channel for m in rec.sent if m.sender == "driver"] == [channel]


# -------------------------------------------- Hypothesis: real vs mutated
def _short_run() -> list[tuple[str, bytes]]:
    """A short example run with commands for every device: (channel, message) of every hardware message."""
    stage, rec = _stage(EXAMPLE)
    sim = stage.sim
    driver = sim.bus.participant("driver", host="robot")
    commands = [
        (0.5, "/robot/display/cmd", '<expression name="happy"/>'),
        (0.6, "/robot/audio/steer", '<steer bearing="-18"/>'),  # Anna's "Hello BIRON" is recognised
        (4.0, "/robot/audio/steer", '<steer off="true"/>'),
        (1.0, "/robot/ptu/cmd", '<ptu pan="5" tilt="-5"/>'),
        (2.5, "/robot/speaker/say", '<say text="Hello Anna nice to meet you"/>'),
        (2.8, "/robot/speaker/say", "<say>Hello</say>"),
        (3.0, "/robot/display/cmd", '<gaze pan="-20" tilt="3"/>'),
        (5.0, "/robot/ptu/cmd", '<ptu pan="30" tilt="-10"/>'),
        (9.0, "/robot/base/cmd", '<velocity v="0.0" w="0.2"/>'),
        (9.3, "/robot/base/cmd", '<velocity v="0.1" w="0"/>'),
        # the bumpers: driven into the south wall (placed facing it, 0.14 m off, at 12 s), then backed off
        *((t, "/robot/base/cmd", '<velocity v="0.2" w="0"/>') for t in (12.05, 12.35, 12.65, 12.95, 13.25)),
        *((t, "/robot/base/cmd", '<velocity v="-0.2" w="0"/>') for t in (13.55, 13.85)),
    ]
    sim.call_at(12.0, lambda: stage.world.place_robot(3.2, 0.45, -math.pi / 2))
    for t, ch, text in commands:
        sim.call_at(t, lambda ch=ch, text=text: driver.publish(ch, text))
    stage.run(16.0)
    names = set(stage.hardware) | {"driver"}
    out = [(m.channel, serialize(m.xml)) for m in rec.sent if m.sender in names and m.channel in SCHEMAS]
    sim.close()
    return out


@functools.cache
def real() -> list[tuple[str, bytes]]:
    return _short_run()


@pytest.fixture(scope="module")
def sender() -> Iterator[Participant]:
    """A participant on a bus typed as the hardware's (nobody listens)."""
    sim = Simulation(seed=0, scenario="typing")
    declare_channels(sim.bus)
    yield sim.bus.participant("mutator", host="robot")
    sim.close()


def test_the_short_run_covers_every_schema_and_every_element():
    seen: dict[str, set[str]] = {}
    for ch, data in real():
        seen.setdefault(ch, set()).update(e.tag for e in parse_bytes(data).iter())
    for c in CHANNELS:
        assert seen.get(c.channel, set()) >= set(TABLES[c.channel]), (c.channel, seen.get(c.channel))


def _mutations() -> list[tuple[int, int, str, str]]:
    """(message index, element index, attribute, kind): every required attribute and every number."""
    out = []
    for i, (ch, data) in enumerate(real()):
        table = TABLES[ch]
        for j, el in enumerate(parse_bytes(data).iter()):
            for attr, (required, numeric) in table[el.tag].items():
                if attr not in el.attrib:
                    continue
                if required:
                    out.append((i, j, attr, "drop"))
                if numeric:
                    out.append((i, j, attr, "garble"))
    return out


NOT_A_NUMBER = st.one_of(
    st.text(alphabet=string.ascii_letters + " ,_-", max_size=8),
    st.sampled_from(["", " ", "1.2.3", "1,5", "0x10", "--1", "1e", "nan", "NaN", "INF", "-INF", "inf", "12abc", "+"]),
)


@settings(max_examples=150, deadline=None)
@given(item=st.deferred(lambda: st.sampled_from(real())))
def test_real_messages_always_validate(sender, item):
    ch, data = item
    el = parse_bytes(data)
    assert load_schema(SCHEMAS[ch]).errors(el) == []
    sender.publish(ch, el)  # the bus accepts it


@settings(max_examples=300, deadline=None)
@given(mutation=st.deferred(lambda: st.sampled_from(_mutations())), garbage=NOT_A_NUMBER)
def test_mutated_messages_never_validate(sender, mutation, garbage):
    i, j, attr, kind = mutation
    ch, data = real()[i]
    root = copy.deepcopy(parse_bytes(data))
    el = list(root.iter())[j]
    if kind == "drop":
        del el.attrib[attr]
    else:
        el.set(attr, garbage)
    assert not load_schema(SCHEMAS[ch]).is_valid(root)
    before = sender.bus.sent
    with pytest.raises(MessageValidationError) as err:
        sender.publish(ch, root)
    assert ch in str(err.value) and SCHEMAS[ch].name in str(err.value)
    assert sender.bus.sent == before
