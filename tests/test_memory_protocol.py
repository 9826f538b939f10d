"""The active memory on the bus (kernel only, no BIRON): requests and replies typed by memory.xsd,
attachments in and inline out, remove by XPath, subscriptions notified over the bus, refusals."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from homesim.memory import ActiveMemory
from homesim.memory.protocol import apply_request, decode_inline
from homesim.errors import MessageValidationError
from homesim.sim import Simulation

SCHEMA = Path("homesim/schemas/memory.xsd")


@pytest.fixture
def bus():
    sim = Simulation(seed=4)
    memory = ActiveMemory("things", indexes={"type": "@type"})
    server = sim.bus.participant("memory")
    server.serve("request", lambda msg: apply_request(memory, msg.xml, msg.attachments,
                                                     lambda ch, xml, att: server.publish(ch, xml, attachments=att)),
                 request_schema=SCHEMA, reply_schema=SCHEMA)
    client = sim.bus.participant("client", host="robot")
    yield sim, memory, client
    sim.close()


def test_requests_over_the_bus_change_and_query_the_memory(bus):
    sim, memory, client = bus
    notes = client.subscribe("/things/changes")
    hist = np.arange(6, dtype=np.float32).reshape(2, 3)

    async def talk():
        call = lambda xml, **kw: client.call("memory", "request", xml, **kw)
        sub = await call('<request op="subscribe" xpath="/*[@type=\'cup\']" actions="insert remove" channel="/things/changes"/>')
        a = await call('<request op="insert"><thing type="cup" n="1"/></request>', attachments={"hist": hist})
        await call('<request op="insert"><thing type="cup" n="2"/></request>')
        await call('<request op="insert"><thing type="plant" n="3"/></request>')
        await call('<request op="update" id="3"><thing type="plant" n="33"/></request>')
        q = await call('<request op="query" attachments="inline"><where index="type" value="cup"/></request>')
        rm = await call('<request op="remove" xpath="/*[@n=\'2\' or @n=\'33\']"/>')
        missing = await call('<request op="update" id="9"><thing/></request>')
        unsub = await call(f'<request op="unsubscribe" subscription="{sub.xml.get("subscription")}"/>')
        await call('<request op="insert"><thing type="cup" n="4"/></request>')
        return sub, a, q, rm, missing, unsub

    sub, a, q, rm, missing, unsub = sim.run_until_complete(talk())
    assert (sub.xml.get("ok"), a.xml.find("doc").get("id")) == ("true", "1")
    assert q.xml.get("count") == "2" and [d.get("id") for d in q.xml.iter("doc")] == ["1", "2"]
    att = q.xml.find("doc/attachment")
    assert (att.get("name"), att.get("dtype"), att.get("shape")) == ("hist", "<f4", "2 3")
    np.testing.assert_array_equal(decode_inline(att), hist)
    assert rm.xml.get("count") == "2" and memory.ids() == [1, 4]
    assert missing.xml.get("ok") == "false" and "no document 9" in missing.xml.get("reason")
    assert unsub.xml.get("ok") == "true"
    sim.run(until=sim.now + 0.1)
    got = [(m.xml.get("action"), m.xml.get("id"), m.xml[0].get("n")) for m in notes.drain()]
    assert got == [("insert", "1", "1"), ("insert", "2", "2"), ("remove", "2", "2")]  # nothing after unsubscribe


def test_bad_requests_are_refused_by_the_schema_or_answered_not_ok(bus):
    sim, memory, client = bus

    async def talk():
        with pytest.raises(MessageValidationError):
            await client.call("memory", "request", '<request op="drop_everything"/>')
        bad_channel = await client.call("memory", "request", '<request op="subscribe" channel="no/slash"/>')
        two_docs = await client.call("memory", "request", '<request op="insert"><a/><b/></request>')
        return bad_channel, two_docs

    bad_channel, two_docs = sim.run_until_complete(talk())
    assert bad_channel.xml.get("ok") == "false" and "channel" in bad_channel.xml.get("reason")
    assert two_docs.xml.get("ok") == "false" and "exactly one document" in two_docs.xml.get("reason")
    assert len(memory) == 0
