"""The XCF-like bus: delivery, FIFO, latency, typed channels, RPC, faults."""

from __future__ import annotations

import asyncio
from collections import defaultdict

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from lxml import etree

from homesim.errors import (
    BusError,
    MessageValidationError,
    RemoteCallFailed,
    RemoteCallTimeout,
    UnknownParticipantError,
    XMLInputError,
)
from homesim.network import LinkModel
from homesim.sim import Simulation
from homesim.xmlio import schema_from_text

from .conftest import examples

PERSON_XSD = """<xs:schema xmlns:xs="http://www.w3.org/2001/XMLSchema">
  <xs:element name="person">
    <xs:complexType>
      <xs:sequence>
        <xs:element name="bearing" type="xs:double"/>
        <xs:element name="distance" type="xs:double" minOccurs="0"/>
      </xs:sequence>
      <xs:attribute name="id" type="xs:positiveInteger" use="required"/>
      <xs:attribute name="speaking" type="xs:boolean" use="required"/>
    </xs:complexType>
  </xs:element>
</xs:schema>"""
VALID_PERSON = '<person id="3" speaking="true"><bearing>0.5</bearing><distance>1.2</distance></person>'


@pytest.fixture
def sim():
    s = Simulation(seed=3)
    yield s
    s.close()


def test_publish_reaches_exact_and_subtree_subscribers_only(sim):
    a = sim.bus.participant("a")
    b = sim.bus.participant("b")
    c = sim.bus.participant("c")
    got = defaultdict(list)
    b.subscribe("/robot/attention/persons", lambda m: got["b"].append(m.channel))
    c.subscribe("/robot/attention/**", lambda m: got["c"].append(m.channel))
    a.publish("/robot/attention/persons", "<p/>")
    a.publish("/robot/attention/state", "<s/>")
    a.publish("/robot/attentionx", "<x/>")
    sim.run()
    assert got == {"b": ["/robot/attention/persons"], "c": ["/robot/attention/persons", "/robot/attention/state"]}


def test_latency_follows_the_link_between_hosts(sim):
    sim.network.add_host("pc1", link="lan")
    sim.network.add_host("pc2", link="lan")
    sim.network.add_host("laptop", link="wlan")
    src = sim.bus.participant("src", host="pc1")
    delays = defaultdict(list)
    for name, host in (("same", "pc1"), ("lan", "pc2"), ("wlan", "laptop")):
        sim.bus.participant(name, host=host).subscribe("/x", lambda m, n=name: delays[n].append(sim.now - m.sent))

    async def send():
        for _ in range(200):
            src.publish("/x", "<x/>")
            await asyncio.sleep(0.05)

    sim.run_until_complete(send())
    sim.run()
    assert all(0.00005 <= d <= 0.0002 + 1e-9 for d in delays["same"])
    assert all(0.001 <= d <= 0.003 + 1e-9 for d in delays["lan"])
    assert all(d >= 0.005 for d in delays["wlan"])
    assert sum(delays["wlan"]) / 200 > 3 * sum(delays["lan"]) / 200


def test_invalid_message_is_refused_and_delivered_to_nobody(sim):
    sim.bus.declare_channel("/robot/persons", schema_from_text("person.xsd", PERSON_XSD))
    a = sim.bus.participant("a")
    got = []
    sim.bus.participant("b").subscribe("/robot/persons", got.append)
    with pytest.raises(MessageValidationError, match=r"/robot/persons.*person\.xsd.*speaking"):
        a.publish("/robot/persons", '<person id="3"><bearing>0.5</bearing></person>')
    a.publish("/robot/persons", VALID_PERSON)
    sim.run()
    assert len(got) == 1 and sim.bus.sent == 1


def test_doctype_is_refused_on_the_bus(sim):
    a = sim.bus.participant("a")
    with pytest.raises(XMLInputError, match="DOCTYPE"):
        a.publish("/x", '<!DOCTYPE x [<!ENTITY e "boom">]><x>&e;</x>')


# Mutations that each make VALID_PERSON invalid by construction.
MUTATIONS = {
    "drop required attribute": lambda el, v: el.attrib.pop("speaking"),
    "non-integer id": lambda el, v: el.set("id", v or "x"),
    "non-boolean flag": lambda el, v: el.set("speaking", "maybe" + v),
    "unknown child": lambda el, v: el.append(etree.Element("legs" + v.replace(" ", ""))),
    "missing required child": lambda el, v: el.remove(el.find("bearing")),
    "text where number is due": lambda el, v: setattr(el.find("bearing"), "text", "north" + v),
    "renamed root": lambda el, v: setattr(el, "tag", "human"),
    "children swapped": lambda el, v: el.insert(0, el.find("distance")),
    "unknown attribute": lambda el, v: el.set("colour", v),
}


@settings(max_examples=examples(60, 300))
@given(st.sampled_from(sorted(MUTATIONS)), st.text(alphabet="abcxyz -", max_size=5))
def test_validation_refuses_every_mutated_invalid_message(mutation, value):
    with Simulation(seed=0) as s:
        s.bus.declare_channel("/robot/persons", schema_from_text("person.xsd", PERSON_XSD))
        sender = s.bus.participant("a")
        got = []
        s.bus.participant("b").subscribe("/robot/persons", got.append)
        el = etree.fromstring(VALID_PERSON)
        MUTATIONS[mutation](el, value)
        with pytest.raises(MessageValidationError):
            sender.publish("/robot/persons", el)
        s.run()
        assert got == [] and s.bus.sent == 0


sends = st.lists(
    st.tuples(st.integers(0, 2), st.integers(0, 3), st.integers(0, 20)),
    min_size=1,
    max_size=40,
)


@settings(max_examples=examples(80, 300))
@given(sends, st.integers(0, 2**32 - 1))
def test_nothing_lost_or_duplicated_and_fifo_per_link(plan, seed):
    """Each (message, subscriber) is delivered exactly once, in send order per pair."""
    with Simulation(seed=seed) as s:
        s.network.add_host("robot", link="lan")
        s.network.add_host("laptop", link="wlan")
        senders = [s.bus.participant(f"s{i}", host=("robot", "laptop")[i % 2]) for i in range(3)]
        received = defaultdict(list)
        channels = ["/a", "/b", "/a/c", "/d"]
        for j, host in enumerate(("robot", "laptop", "robot")):
            p = s.bus.participant(f"r{j}", host=host)
            p.subscribe(channels[j] if j < 2 else "/a/**", lambda m, j=j: received[j].append(m.id))
        expected = defaultdict(list)
        sent_ids = []

        def send(si, ci):
            m = senders[si].publish(channels[ci], "<m/>")
            sent_ids.append((si, ci, m.id))

        for si, ci, tick in plan:
            s.call_at(tick * 0.001, send, si, ci)
        s.run()
        for si, ci, mid in sent_ids:
            ch = channels[ci]
            for j in range(3):
                if (j < 2 and ch == channels[j]) or (j == 2 and ch.startswith("/a")):
                    expected[j].append((si, mid))
        for j in range(3):
            assert sorted(received[j]) == sorted(mid for _, mid in expected[j])
            for si in range(3):
                got = [mid for mid in received[j] if mid.startswith(f"s{si}#")]
                want = [mid for sj, mid in expected[j] if sj == si]
                assert got == want, "per-link FIFO violated"


def test_loss_drops_messages_and_every_drop_is_observed(sim):
    sim.network.set_link(LinkModel("lossy", 0.005, 0.02, loss=0.3))
    sim.network.add_host("laptop", link="lossy")
    a = sim.bus.participant("a", host="robot")
    got = []
    sim.bus.participant("b", host="laptop").subscribe("/x", got.append)
    drops = []
    sim.bus.add_interceptor(lambda o: drops.append(o) if o.event == "drop" else None)
    for i in range(1000):
        sim.call_at(i * 0.001, a.publish, "/x", "<x/>")
    sim.run()
    assert len(got) + len(drops) == 1000
    assert 200 < len(drops) < 400
    assert {d.reason for d in drops} == {"lost"}


def test_rpc_reply_error_timeout_and_unknown_server(sim):
    sim.network.add_host("laptop", link="wlan")
    server = sim.bus.participant("scene_model", host="robot")
    client = sim.bus.participant("dialog", host="laptop")

    def query(msg):
        if msg.xml.get("fail"):
            raise ValueError("no such object")
        return etree.Element("objects", n="2")

    async def slow(msg):
        await asyncio.sleep(5.0)
        return etree.Element("late")

    server.serve("query", query)
    server.serve("slow", slow)

    async def main():
        reply = await client.call("scene_model", "query", "<q/>", timeout=1.0)
        assert reply.xml.get("n") == "2" and reply.causes[0].startswith("dialog#")
        with pytest.raises(RemoteCallFailed, match="ValueError: no such object"):
            await client.call("scene_model", "query", '<q fail="1"/>')
        t0 = sim.now
        with pytest.raises(RemoteCallTimeout, match="scene_model/slow.*0.5 s"):
            await client.call("scene_model", "slow", "<q/>", timeout=0.5)
        assert sim.now - t0 == pytest.approx(0.5)
        with pytest.raises(UnknownParticipantError, match="no server 'planner'"):
            await client.call("planner", "plan", "<q/>")
        with pytest.raises(UnknownParticipantError, match="has no method 'store'.*query"):
            client.call_nowait("scene_model", "store", "<q/>")

    sim.run_until_complete(main())


def test_typed_method_refuses_invalid_request_and_reply(sim):
    xsd = schema_from_text("person.xsd", PERSON_XSD)
    server = sim.bus.participant("pta")
    client = sim.bus.participant("es")
    server.serve("who", lambda m: etree.Element("nobody"), request_schema=xsd, reply_schema=xsd)

    async def main():
        with pytest.raises(MessageValidationError, match="pta/who"):
            await client.call("pta", "who", "<q/>")
        with pytest.raises(RemoteCallFailed, match="MessageValidationError"):
            await client.call("pta", "who", VALID_PERSON)

    sim.run_until_complete(main())


def test_runtime_registration_and_removal(sim):
    a = sim.bus.participant("a")
    got = []
    b = sim.bus.participant("b")
    sub = b.subscribe("/x", got.append)
    a.publish("/x", "<one/>")
    sim.run()
    sub.close()
    a.publish("/x", "<two/>")
    sim.run()
    assert [m.xml.tag for m in got] == ["one"]
    assert [p["name"] for p in sim.bus.registry()] == ["a", "b", "simulator"]
    b.close()
    assert [p["name"] for p in sim.bus.registry()] == ["a", "simulator"]
    with pytest.raises(BusError, match="already registered"):
        sim.bus.participant("a")
    sim.bus.participant("b")  # the name is free again


def test_subscription_queue_and_overflow(sim):
    a = sim.bus.participant("a")
    sub = sim.bus.participant("b").subscribe("/scan", maxlen=2)
    for i in range(5):
        a.publish("/scan", etree.Element("scan", n=str(i)))
    sim.run()
    assert [m.xml.get("n") for m in sub.drain()] == ["3", "4"]


def test_crash_and_hang_faults(sim):
    from homesim.module import Module

    class Server(Module):
        async def run(self):
            self.bus.serve("ping", lambda m: etree.Element("pong"))
            while True:
                self.beat()
                await asyncio.sleep(0.1)

    Server(sim, "crashy")
    Server(sim, "hangy")
    client = sim.bus.participant("client")
    sim.start()
    sim.run(until=0.5)
    sim.inject_fault("crashy", "crash")
    sim.inject_fault("hangy", "hang")

    async def main():
        with pytest.raises(UnknownParticipantError):
            await client.call("crashy", "ping", "<p/>")
        with pytest.raises(RemoteCallTimeout):
            await client.call("hangy", "ping", "<p/>", timeout=0.3)

    sim.run_until_complete(main())
    assert [p["name"] for p in sim.bus.registry() if p["hung"]] == ["hangy"]


# --------------------------------------------------------------------------
# Regressions found in review: each of these failed before its fix.
# --------------------------------------------------------------------------


def test_a_cancelled_reader_does_not_swallow_the_wake_up(sim):
    a = sim.bus.participant("a")
    sub = sim.bus.participant("b").subscribe("/x")
    got = []

    async def reader(tag):
        got.append((tag, (await sub.get()).id))

    ta = sim.spawn(reader("A"), name="A")
    sim.spawn(reader("B"), name="B")
    sim.run(until=0.1)
    a.publish("/x", "<m/>")
    sim.run_until(lambda: sub.qsize() == 1)
    ta.cancel()
    sim.run(until=5)
    assert got == [("B", "a#1")]


def test_closing_a_subscription_ends_async_iteration(sim):
    a = sim.bus.participant("a")
    sub = sim.bus.participant("b").subscribe("/x")
    got = []

    async def consume():
        async for m in sub:
            got.append(m.id)
        got.append("end")

    sim.spawn(consume(), name="consumer")
    sim.call_at(0.5, a.publish, "/x", "<m/>")
    sim.call_at(1.0, sub.close)
    sim.run(until=2)
    assert got == ["a#1", "end"]


def test_async_subscription_handlers_run(sim):
    a = sim.bus.participant("a")
    got = []

    async def handler(msg):
        await asyncio.sleep(0.5)
        got.append((msg.id, sim.now))

    sim.bus.participant("b").subscribe("/x", handler)
    a.publish("/x", "<m/>")
    sim.run(until=2)
    assert len(got) == 1 and got[0][0] == "a#1" and got[0][1] > 0.5


def test_message_ids_stay_unique_across_re_registration(sim):
    p = sim.bus.participant("laser")
    first = p.publish("/scan", "<s/>")
    p.close()
    second = sim.bus.participant("laser").publish("/scan", "<s/>")
    assert (first.id, second.id) == ("laser#1", "laser#2")


def test_sender_cannot_change_what_receivers_get(sim):
    sim.bus.declare_channel("/robot/persons", schema_from_text("person.xsd", PERSON_XSD))
    scene = etree.fromstring(f"<scene>{VALID_PERSON}tail<secret/></scene>")
    person = scene[0]
    a = sim.bus.participant("a")
    got = []
    sim.bus.participant("b").subscribe("/robot/persons", got.append)
    tr = sim.record_trace()
    a.publish("/robot/persons", person)
    person.set("speaking", "maybe")  # after validation: must not reach anyone
    person.append(etree.Element("junk"))
    sim.run()
    msg = got[0]
    assert msg.xml.get("speaking") == "true" and msg.xml.find("junk") is None
    assert msg.xml.getparent() is None and msg.xml.tail is None
    assert msg.xml.xpath("/person") == [msg.xml]
    assert "tail" not in tr.text() and "secret" not in tr.text()


def test_receivers_get_payloads_of_their_own(sim):
    a = sim.bus.participant("a")
    seen = []

    def greedy(msg):  # moves a node out of its payload, as an ES copying parameters might
        etree.SubElement(etree.Element("order"), "x").append(msg.xml[0])

    sim.bus.participant("b").subscribe("/x", greedy)
    sim.bus.participant("c").subscribe("/x", lambda m: seen.append(len(m.xml)))
    a.publish("/x", "<e><who/></e>")
    sim.run()
    assert seen == [1]


def test_attachments_are_read_only_copies_and_object_arrays_refused(sim):
    import numpy as np

    a = sim.bus.participant("a")
    got = []
    sim.bus.participant("b").subscribe("/img", got.append)
    img = np.zeros((2, 2))
    a.publish("/img", "<i/>", attachments={"px": img})
    img[0, 0] = 9
    sim.run()
    px = got[0].attachments["px"]
    assert px[0, 0] == 0 and not px.flags.writeable
    with pytest.raises(BusError, match="object arrays are refused"):
        a.publish("/img", "<i/>", attachments={"px": np.array([object()])})


def test_a_doctype_cannot_travel_inside_an_element(sim):
    a = sim.bus.participant("a")
    el = etree.fromstring(b'<!DOCTYPE x [<!ENTITY e "boom">]><x>&e;</x>')
    with pytest.raises(XMLInputError, match="DOCTYPE"):
        a.publish("/x", el)


def test_hung_server_sends_no_error_replies_and_odd_errors_travel(sim):
    server = sim.bus.participant("db")
    client = sim.bus.participant("client")

    async def failing(msg):
        await asyncio.sleep(0.5)
        raise RuntimeError("db down")

    server.serve("slow", failing)
    server.serve("odd", lambda m: (_ for _ in ()).throw(ValueError("bad \x1b[31m colour \x00")))

    async def main():
        with pytest.raises(RemoteCallFailed, match="bad \ufffd\\[31m colour \ufffd"):
            await client.call("db", "odd", "<q/>")
        call = asyncio.ensure_future(client.call("db", "slow", "<q/>", timeout=2.0))
        await asyncio.sleep(0.1)
        server.hung = True
        with pytest.raises(RemoteCallTimeout):
            await call

    sim.run_until_complete(main())


def test_maxlen_zero_is_refused(sim):
    with pytest.raises(BusError, match="maxlen must be >= 1"):
        sim.bus.participant("b").subscribe("/x", maxlen=0)


def test_loss_of_either_host_applies():
    with Simulation(seed=1) as s:
        s.network.set_link(LinkModel("lossy-lan", 0.001, 0.003, loss=0.5))
        s.network.add_host("pc", link="lossy-lan")
        s.network.add_host("laptop", link="wlan")
        lost = sum(s.network.delay_ns("pc", "laptop") is None for _ in range(2000))
        assert 800 < lost < 1200


def test_transfer_skips_the_copy_but_keeps_isolation_rules(sim):
    a = sim.bus.participant("a")
    got = []
    sim.bus.participant("b").subscribe("/x", got.append)
    fresh = etree.Element("order", name="interact")
    m = a.publish("/x", fresh, transfer=True)
    assert m.xml is fresh  # handed over, not copied
    parent = etree.fromstring("<scene><order/>tail</scene>")
    m2 = a.publish("/x", parent[0], transfer=True)
    assert m2.xml is not parent[0] and m2.xml.getparent() is None and m2.xml.tail is None
    sim.run()
    assert [g.xml.tag for g in got] == ["order", "order"]


# ------------------------------------------------------- validation policy
# The suite runs strict (conftest); these build the product's default explicitly.


def test_default_policy_validates_text_from_outside_and_trusts_built_elements():
    with Simulation(seed=3, strict=False) as s:
        assert s.bus.validation == "edges"
        s.bus.declare_channel("/robot/persons", schema_from_text("person.xsd", PERSON_XSD))
        a = s.bus.participant("a")
        got = []
        s.bus.participant("b").subscribe("/robot/persons", got.append)
        with pytest.raises(MessageValidationError, match="speaking"):
            a.publish("/robot/persons", '<person id="3"><bearing>0.5</bearing></person>')
        # A module's own element is trusted: delivered as built (--strict finds such a bug).
        a.publish("/robot/persons", etree.fromstring('<person id="3"><bearing>0.5</bearing></person>'))
        s.run()
        assert [m.xml.get("id") for m in got] == ["3"] and s.bus.sent == 1


def test_strict_policy_refuses_an_invalid_element_too():
    with Simulation(seed=3, strict=True) as s:
        assert s.bus.validation == "all"
        s.bus.declare_channel("/robot/persons", schema_from_text("person.xsd", PERSON_XSD))
        a = s.bus.participant("a")
        with pytest.raises(MessageValidationError, match="speaking"):
            a.publish("/robot/persons", etree.fromstring('<person id="3"><bearing>0.5</bearing></person>'))
        assert s.bus.sent == 0


@pytest.mark.parametrize("strict", [False, True])
def test_every_policy_refuses_elements_built_from_a_doctype_or_holding_entities(strict):
    """The default policy skips the schema for a module's element, never the look for a DTD or entities."""
    hostile = b'<!DOCTYPE x [<!ENTITY e "boom">]><x><y>&e;</y></x>'
    parser = etree.XMLParser(resolve_entities=False)
    entity = etree.Element("x")
    etree.SubElement(entity, "y").append(etree.Entity("e"))
    with Simulation(seed=3, strict=strict) as s:
        got = []
        s.bus.participant("b").subscribe("/x", got.append)
        a = s.bus.participant("a")
        for el, why in ((etree.fromstring(hostile, parser), "DOCTYPE"), (etree.fromstring(hostile, parser)[0], "DOCTYPE"),
                        (etree.fromstring(hostile), "DOCTYPE"), (entity, "entity"), (entity[0], "entity"),
                        (etree.fromstring(b'<!DOCTYPE x SYSTEM "x.dtd"><x><y/></x>', parser), "DOCTYPE")):
            with pytest.raises(XMLInputError, match=why):
                a.publish("/x", el)
            with pytest.raises(XMLInputError, match=why):
                a.publish("/x", el, transfer=True)
        a.publish("/x", etree.fromstring(b"<x><y>boom</y></x>"))  # the same without them travels
        s.run()
        assert [etree.tostring(m.xml) for m in got] == [b"<x><y>boom</y></x>"]


@pytest.mark.parametrize("strict", [False, True])
def test_a_lazy_payload_is_built_only_when_someone_will_see_it(strict):
    built = []

    def payload() -> etree._Element:
        built.append(1)
        return etree.Element("note", n=str(len(built)))

    with Simulation(seed=3, strict=strict) as s:
        a = s.bus.participant("a")
        first = a.publish("/nobody", payload)  # no subscriber, no interceptor
        assert (first.xml is None) == (not strict) and len(built) == (1 if strict else 0)
        got = []
        s.bus.participant("b").subscribe("/heard", got.append)
        second = a.publish("/heard", payload)
        before = len(built)
        rec = s.record_trace()  # the trace sees every send: from now on, always built
        third = a.publish("/nobody", payload)
        s.run()
        assert len(built) == before + 1 and third.xml is not None
        # Sent either way: ids and counters do not depend on who listens.
        assert [first.id, second.id, third.id] == ["a#1", "a#2", "a#3"]
        assert s.bus.sent == 3 and s.bus.unheard == 2
        assert [m.xml.tag for m in got] == ["note"]
        assert '"channel":"/nobody"' in rec.text()


def test_an_unseen_lazy_payload_counts_as_sent_and_a_closed_sender_still_cannot_send_it():
    with Simulation(seed=3, strict=False) as s:
        a = s.bus.participant("a")
        msg = a.publish("/nobody", lambda: etree.Element("note"), causes=["x#1"], created=0.5)
        assert msg.xml is None and msg.causes == ("x#1",) and msg.created_ns == 500_000_000
        assert "/nobody" in a.published and (s.bus.sent, s.bus.unheard, s.bus.delivered) == (1, 1, 0)
        a.close()
        with pytest.raises(BusError, match="closed"):
            a.publish("/nobody", lambda: etree.Element("note"))
        assert s.bus.sent == 1


def test_a_lazy_payload_reaches_a_dispatcher_only_on_the_channels_it_watches():
    from homesim.observe import Dispatcher

    built = []

    def payload() -> etree._Element:
        built.append(1)
        return etree.Element("note")

    with Simulation(seed=3, strict=False) as s:
        seen = []
        Dispatcher(s.bus).add("/watched", seen.append)
        a = s.bus.participant("a")
        a.publish("/other", payload)
        a.publish("/watched/x", payload)
        assert len(built) == 1 and [m.channel for m in seen] == ["/watched/x"]


_CHANNELS = ("/a", "/a/x", "/b", "/system/heartbeat/m")


@settings(max_examples=examples(40, 200), deadline=None)
@given(ops=st.lists(st.one_of(
    st.tuples(st.just("publish"), st.sampled_from(_CHANNELS), st.booleans()),
    st.tuples(st.just("handler"), st.sampled_from(("/a", "/b", "/system/", "/"))),
    st.tuples(st.just("watcher"), st.sets(st.sampled_from(_CHANNELS))),
    st.tuples(st.just("remove"),),
), max_size=25))
@example(ops=[("publish", "/a", False), ("handler", "/a"), ("publish", "/a", True)])  # a route asked before its handler
@example(ops=[("watcher", {"/b"}), ("publish", "/b", False), ("remove",), ("publish", "/b", False),
              ("watcher", {"/b"}), ("publish", "/b", True)])  # watchers coming and going
def test_every_interceptor_sees_every_send_it_wants_in_order_however_watchers_change(ops):
    """An interceptor with ``wants`` is shown only the publishes on channels it wants (the bus asks once
    per channel and keeps the answer), so whoever changes what it wants must say so: a dispatcher's
    handler added after its channel was used, a watcher added or removed mid-run, still see exactly
    the sends a reference that looks at every send would give them, in send order, and an
    interceptor without ``wants`` sees every send."""
    from homesim.observe import Dispatcher

    with Simulation(seed=3, strict=False) as s:
        a = s.bus.participant("a")
        s.bus.participant("r").subscribe("/a/**", lambda m: None)
        everything: list[str] = []
        s.bus.add_interceptor(lambda o: everything.append(o.message.id) if o.event == "send" else None)
        disp = Dispatcher(s.bus)
        handlers: list[tuple[str, list[str]]] = []  # (prefix, ids seen)
        watchers: list[tuple[frozenset[str], list[str], object]] = []
        sent: list[tuple[str, str]] = []
        want_handlers: list[list[str]] = []
        want_watchers: list[list[str]] = []

        class Watcher:
            observes = ("send",)

            def __init__(self, channels: frozenset[str], seen: list[str]) -> None:
                self.channels, self.seen = channels, seen

            def wants(self, channel: str) -> bool:
                return channel in self.channels

            def __call__(self, obs) -> None:  # records everything it is shown
                self.seen.append(obs.message.id)

        for op in ops:
            if op[0] == "publish":
                _, channel, lazy = op
                msg = a.publish(channel, (lambda: etree.Element("n")) if lazy else etree.Element("n"))
                sent.append((msg.id, channel))
                for (prefix, _), want in zip(handlers, want_handlers):
                    if channel.startswith(prefix):
                        want.append(msg.id)
                for (chs, _, _), want in zip(watchers, want_watchers):
                    if channel in chs:
                        want.append(msg.id)
            elif op[0] == "handler":
                seen: list[str] = []
                disp.add(op[1], lambda m, seen=seen: seen.append(m.id))
                handlers.append((op[1], seen))
                want_handlers.append([])
            elif op[0] == "watcher":
                seen = []
                w = Watcher(frozenset(op[1]), seen)
                s.bus.add_interceptor(w)
                watchers.append((frozenset(op[1]), seen, w))
                want_watchers.append([])
            elif watchers:  # remove the latest watcher: it sees nothing more
                chs, seen, w = watchers.pop()
                s.bus.remove_interceptor(w)
                assert seen == want_watchers.pop()
        s.run()
        assert everything == [i for i, _ in sent]
        assert [seen for _, seen in handlers] == want_handlers
        assert [seen for _, seen, _ in watchers] == want_watchers


def test_the_suite_runs_strict(sim):
    assert sim.bus.validation == "all"


def test_an_unknown_validation_policy_is_refused(sim):
    from homesim.bus import Bus

    with pytest.raises(BusError, match="validation policy 'some'"):
        Bus(sim.loop, network=sim.network, validation="some")


@settings(max_examples=examples(10, 30))
@given(st.integers(1, 10**6), st.booleans(), st.floats(-4, 4, allow_nan=False), st.booleans())
def test_a_valid_message_is_delivered_identically_under_both_policies(pid, speaking, bearing, as_text):
    """The policy decides only whether an invalid element is refused; valid traffic is the same."""
    doc = f'<person id="{pid}" speaking="{str(speaking).lower()}"><bearing>{bearing!r}</bearing></person>'
    delivered = []
    for strict_mode in (True, False):
        with Simulation(seed=5, strict=strict_mode) as s:
            s.bus.declare_channel("/robot/persons", schema_from_text("person.xsd", PERSON_XSD))
            got: list = []
            s.bus.participant("b").subscribe("/robot/persons", got.append)
            s.bus.participant("a").publish("/robot/persons", doc if as_text else etree.fromstring(doc))
            s.run()
            delivered.append([(m.id, m.sent_ns, etree.tostring(m.xml)) for m in got])
    assert delivered[0] == delivered[1] and len(delivered[0]) == 1


def test_scenario_runs_in_the_suite_are_strict_and_the_product_default_is_not():
    from pathlib import Path

    from homesim.tour.runner import Run, RunOptions

    scen = Path(__file__).resolve().parents[1] / "scenarios" / "two_people_radio.xml"
    with Run.from_file(scen, RunOptions(until=0.1)) as run:
        assert run.sim.bus.validation == "all"
    with Run.from_file(scen, RunOptions(until=0.1, strict=False)) as run:
        assert run.sim.bus.validation == "edges"


@pytest.mark.parametrize("strict", [False, True])
def test_a_payload_function_that_returns_no_element_is_refused_at_the_sender(strict):
    # None is also the bus's mark of an unbuilt payload: it must not be sent as one.
    with Simulation(seed=3, strict=strict) as s:
        got = []
        s.bus.participant("b").subscribe("/x", got.append)
        a = s.bus.participant("a")
        with pytest.raises(BusError, match=r"/x.*returned NoneType"):
            a.publish("/x", lambda: None)
        with pytest.raises(BusError, match=r"/x.*returned int"):
            a.publish("/x", lambda: 3)
        s.run()
        assert got == [] and s.bus.sent == 0


# Ops for the delivery-plan property below: (kind, a, b) at one-second ticks (longer than any delay).
plan_ops = st.lists(
    st.one_of(
        st.tuples(st.just("publish"), st.integers(0, 2), st.integers(0, 3)),
        st.tuples(st.just("subscribe"), st.integers(0, 2), st.integers(0, 4)),
        st.tuples(st.just("unsubscribe"), st.integers(0, 2), st.integers(0, 4)),
        st.tuples(st.just("move"), st.integers(0, 2), st.sampled_from(["lan", "slow", "robot"])),
        st.tuples(st.just("relink"), st.just(0), st.sampled_from([0.2, 0.4])),
    ),
    min_size=1,
    max_size=30,
)


def _plan_run(ops, *, strict):
    """Run ``ops``; return (what reached whom with its delay, the trace text)."""
    from homesim.trace import MemoryTrace

    channels = ["/a", "/b", "/a/c", "/d"]
    patterns = ["/a", "/b", "/a/**", "/d", "/b/**"]
    with Simulation(seed=5, strict=strict) as s:
        s.network.set_link(LinkModel("slow", 0.3, 0.35))
        for h in ("h0", "h1", "h2"):
            s.network.add_host(h, link="lan")
        senders = [s.bus.participant(f"s{i}", host="h0") for i in range(3)]
        receivers = [s.bus.participant(f"r{j}", host=f"h{j}") for j in range(3)]
        trace = MemoryTrace(s.bus, scenario="plans", seed=5)
        got = []
        subs: dict[tuple[int, int], object] = {}
        expected = []

        def handler(j):
            return lambda m: got.append((j, m.id, s.loop.now_ns - m.sent_ns))

        def do(kind, a, b):
            if kind == "publish":
                m = senders[a].publish(channels[b], "<m/>")
                for (j, pi), _ in sorted(subs.items()):
                    pat = patterns[pi]
                    if pat == channels[b] or (pat.endswith("/**") and (channels[b] + "/").startswith(pat[:-2])):
                        expected.append((j, m.id))
            elif kind == "subscribe" and (a, b) not in subs:
                subs[(a, b)] = receivers[a].subscribe(patterns[b], handler(a))
            elif kind == "unsubscribe" and (a, b) in subs:
                subs.pop((a, b)).close()
            elif kind == "move":  # the receiver's host changes its link kind (or joins the robot's host)
                s.network.add_host(f"h{a}", link=b if b != "robot" else "local")
            elif kind == "relink":
                s.network.set_link(LinkModel("slow", b, b + 0.05))

        for k, op in enumerate(ops):
            s.call_at(float(k), do, *op)
        s.run()
        text = trace.text()
        return sorted(got), sorted(expected), text


@settings(max_examples=examples(60, 200), deadline=None)
@given(plan_ops)
def test_deliveries_follow_subscriptions_and_links_as_they_change(ops):
    """The bus's cached delivery plans never outlive a change: each message reaches exactly the
    subscriptions open when it was sent, once, with a delay from the current link kinds; and the
    run is the same under both validation policies (same trace, byte for byte)."""
    got, expected, text = _plan_run(ops, strict=False)
    assert [(j, mid) for j, mid, _ in got] == expected
    bounds = [(50_000, 200_000), (1_000_000, 3_000_000), (200_000_000, 450_000_000)]  # local, lan, any slow
    for _, _, delay in got:
        assert any(lo <= delay <= hi for lo, hi in bounds), delay
    got_strict, _, text_strict = _plan_run(ops, strict=True)
    assert got_strict == got and text_strict == text
