"""Active-memory benchmark: query latency as the memory grows, write costs, the scene model's answer.

Run: ``python benchmarks/bench_memory.py [--sizes 100 1000 10000]``. For each size, a memory of
``OBJECT`` documents (20 types, 10 owners, unique names; the object base's indexes on type, name
and owner) is queried for one object:

- indexed: ``query_ids(where={"name": ...})`` (ids only) and ``query(where=...)`` (copies
  returned), and a two-index look-up (type + owner, ~1/200 of the memory);
- free XPath: ``query_ids("/OBJECT[@name=...]")``: one compiled ``etree.XPath`` evaluated per
  document (what the memory does), beside the same scan with ``element.xpath(text)`` per document
  (lxml re-compiling each time);
- the scene model's ``answer`` ("where is my cup?": find + locate with 8 taught places);
- writes: insert per document in memory only and with the SQLite store (one committed
  transaction each, ``synchronous=FULL``: the figure is the disk's fsync).

Not a test: wall-clock numbers belong here, never in the test suite.
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

from lxml import etree

from homesim.memory import ActiveMemory, SqliteStore
from robot.knowledge.bases import OBJECT_INDEXES
from robot.knowledge.scene_model import SceneModel
from homesim.sim import Simulation

TYPES = [f"type{i}" for i in range(20)]
OWNERS = [f"owner{i}" for i in range(10)]


def doc(i: int) -> str:
    return (f'<OBJECT type="{TYPES[i % 20]}" name="obj{i}" owner="{OWNERS[i % 10]}" colour="red" '
            f'x="{i % 97 * 0.1:.4f}" y="{i % 89 * 0.1:.4f}" size="0.1" frame="map" taught="{i}"/>')


def timed(fn, reps: int) -> float:
    """Median seconds per call over ``reps`` calls (in 5 batches)."""
    per = []
    batch = max(1, reps // 5)
    for _ in range(5):
        t0 = time.process_time()
        for _ in range(batch):
            fn()
        per.append((time.process_time() - t0) / batch)
    return statistics.median(per)


def bench_queries(n: int) -> dict[str, float]:
    m = ActiveMemory("objects", indexes=OBJECT_INDEXES)
    for i in range(n):
        m.insert(doc(i))
    target = f"obj{n // 2}"
    docs = [m._docs[i][0] for i in m.ids()]
    expr = f"/OBJECT[@name='{target}']"
    reps_free = max(5, 20000 // n)
    out = {
        "indexed ids": timed(lambda: m.query_ids(where={"name": target}), 20000),
        "indexed copies": timed(lambda: m.query(where={"name": target}), 20000),
        "two indexes": timed(lambda: m.query_ids(where={"type": "type3", "owner": "owner3"}), 2000),
        "free compiled": timed(lambda: m.query_ids(expr), reps_free),
        "free .xpath()": timed(lambda: [d for d in docs if d.xpath(expr)], reps_free),
    }
    assert m.query_ids(where={"name": target}) == m.query_ids(expr) == [n // 2 + 1]
    return out


def bench_answer(n: int) -> float:
    with Simulation(seed=0) as sim:
        scene = SceneModel(sim, map_server=None)
        for i in range(8):
            scene.places.store(etree.fromstring(f'<PLACE name="place{i}"><POSE x="{i}" y="1" theta="0"/></PLACE>'))
        mem = scene.objects.memory
        for i in range(n):
            mem.insert(doc(i))
        mem.insert('<OBJECT type="cup" name="cup" owner="speaker" x="3.5" y="1.8" frame="map" taught="0"/>')
        q = etree.fromstring('<OBJECT type="cup"><OWNER name="speaker"/></OBJECT>')
        assert scene.answer(q).get("found") == "true"
        return timed(lambda: scene.answer(q), 2000)


def bench_orders() -> tuple[float, float]:
    """CPU per store_object and store_place order's work (canonical form, XSD check, dedupe, insert/update)."""
    with Simulation(seed=0) as sim:
        scene = SceneModel(sim, map_server=None)
        k = iter(range(10**9))
        obj = lambda: etree.fromstring(f'<OBJECT type="cup" x="{next(k) % 50}" y="1" frame="map"><TITLE name="cup"/><OWNER name="o{next(k) % 7}"/></OBJECT>')
        place = lambda: etree.fromstring(f'<PLACE><TITLE name="p{next(k) % 20}"/><POSE x="1" y="2" theta="0.3" frame="map"/></PLACE>')
        return timed(lambda: scene.objects.store(obj()), 2000), timed(lambda: scene.places.store(place()), 2000)


def bench_writes(n: int) -> tuple[float, float]:
    m = ActiveMemory("objects", indexes=OBJECT_INDEXES)
    t0 = time.process_time()
    for i in range(n):
        m.insert(doc(i))
    mem = (time.process_time() - t0) / n
    with tempfile.TemporaryDirectory() as d:
        with SqliteStore(Path(d) / "bench.sqlite") as store:
            ms = ActiveMemory("objects", store=store, indexes=OBJECT_INDEXES)
            k = min(n, 200)
            t0 = time.process_time()
            for i in range(k):
                ms.insert(doc(i))
            disk = (time.process_time() - t0) / k
    return mem, disk


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[100, 1000, 10000])
    args = ap.parse_args()
    us = 1e6
    print(f"{'objects':>8} | {'indexed ids':>11} | {'indexed+copy':>12} | {'type+owner':>10} | "
          f"{'free XPath':>10} | {'free .xpath()':>13} | {'where-is':>9}   (µs per query)")
    for n in args.sizes:
        r = bench_queries(n)
        a = bench_answer(n)
        print(f"{n:>8} | {r['indexed ids'] * us:>11.2f} | {r['indexed copies'] * us:>12.2f} | {r['two indexes'] * us:>10.1f} | "
              f"{r['free compiled'] * us:>10.0f} | {r['free .xpath()'] * us:>13.0f} | {a * us:>9.1f}")
    mem, disk = bench_writes(max(args.sizes))
    so, sp = bench_orders()
    print(f"orders: store_object {so * us:.0f} µs, store_place {sp * us:.0f} µs (memory only)")
    print(f"insert: {mem * us:.1f} µs in memory, {disk * 1e3:.2f} ms with the SQLite store (one committed transaction)")


if __name__ == "__main__":
    main()
