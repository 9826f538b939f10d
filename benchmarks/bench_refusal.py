"""How fast homesim refuses hostile inputs (issue 7): near-linear, bounded.

Run: ``python benchmarks/bench_refusal.py``. Not a test: wall-clock and CPU
figures belong here, never in the test suite.

Measures (CPU seconds, ``time.process_time``):

* ``afsm check`` of N states each holding an unknown element (N = 1k..10k):
  the schema pass used to resolve each problem by scanning every sibling
  (quadratic: 11 s for 5,000 states); it should now grow about linearly.
* one AFSM state with N unexpected children: bounded by MAX_SCHEMA_ROUNDS.
* the worst guard allowed (two nested descendant scans) on the largest
  payload allowed (MAX_PAYLOAD_ELEMENTS elements).
* a scenario with 20,000 pieces of furniture (refused by its size limit).
* a UTF-16 document with a DOCTYPE (refused before libxml2 sees it).
"""

from __future__ import annotations

import time
from pathlib import Path

from lxml import etree

from homesim.afsm.engine import MAX_PAYLOAD_ELEMENTS
from homesim.afsm.loader import check
from homesim.errors import InputError
from homesim.scenario.loader import load_scenario_text
from homesim.xmlio import parse_bytes

ROOT = Path(__file__).resolve().parents[1]
HEAD = '<scxml xmlns="http://www.w3.org/2005/07/scxml" version="1.0" initial="S0">\n'


def cpu(f, *args):  # type: ignore[no-untyped-def]
    t = time.process_time()
    out = f(*args)
    return time.process_time() - t, out


def main() -> None:
    for n in (1000, 2000, 5000, 10000):
        doc = HEAD + "".join(f'<state id="S{i}"><foo/><transition event="e" target="S{(i + 1) % n}"/></state>\n' for i in range(n)) + "</scxml>"
        s, problems = cpu(check, doc)
        print(f"afsm check, {n:>6} states with an unknown element: {s:6.2f} s CPU ({len(problems)} problems, {s / n * 1e6:.0f} us/state)")
    doc = HEAD + '<state id="S0">' + "<foo/>\n" * 5000 + "</state>\n</scxml>"
    s, problems = cpu(check, doc)
    print(f"afsm check, one state with 5000 unexpected children: {s:6.2f} s CPU ({len(problems)} problems, bounded rounds)")
    guard = etree.XPath("count(//*[count(//*) > 0]) > 0")
    payload = etree.Element("p")
    for _ in range(MAX_PAYLOAD_ELEMENTS - 1):
        etree.SubElement(payload, "x")
    s, _ = cpu(lambda: [guard(payload) for _ in range(10)])
    print(f"worst allowed guard on a {MAX_PAYLOAD_ELEMENTS}-element payload: {s / 10 * 1e3:6.2f} ms CPU per evaluation")
    example = (ROOT / "scenarios" / "two_people_radio.xml").read_text(encoding="utf-8")
    pieces = "".join(f'<furniture name="b{i}" type="box" points="1,4 1.05,4 1.05,4.05" height="0.1"/>\n' for i in range(20000))
    text = example.replace('<furniture name="sofa"', pieces + '<furniture name="sofa"', 1)
    t = time.process_time()
    try:
        load_scenario_text(text)
    except InputError as exc:
        print(f"scenario with 20000 pieces of furniture: refused in {time.process_time() - t:6.2f} s CPU ({exc.message[:60]})")
    data = '<?xml version="1.0" encoding="UTF-16"?><!DOCTYPE r SYSTEM "/etc/passwd"><r/>'.encode("utf-16")
    t = time.process_time()
    for _ in range(1000):
        try:
            parse_bytes(data)
        except InputError:
            pass
    print(f"UTF-16 document with a DOCTYPE: refused in {(time.process_time() - t) / 1000 * 1e6:6.1f} us CPU")


if __name__ == "__main__":
    main()
