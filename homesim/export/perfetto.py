"""A trace as Chrome trace-event JSON for Perfetto: modules as threads, processing spans, cause -> message flows.

One process (the run), one thread per module (named by the module). Each
message is a slice on its sender's thread at its send time (``cat`` "bus";
``args``: id, channel, kind, receivers, the XML's first 400 characters),
lasting until its last delivery (at least 1 us). Each processing span
(:func:`homesim.traceview.walk`: a cause delivered to the module -> the
message it made) is an async slice (``cat`` "processing") under the
module's name, so spans that overlap never break the threads' nesting. Each
cause -> message link is a flow (``ph`` "s" on the cause's slice, "f" with
``bp`` "e" on the message's), so one can click from the microphones'
utterance through the understanding, the supervisor and the dialog to the
speaker. Continuous streams are exported too (``args.stream``: true);
heartbeats are not. Times are virtual microseconds.

The file is written as it is read (bounded memory: a message's slice is
written when its last delivery is seen or when it falls out of the bounded
table of recent messages).

What a viewer needs (Chrome trace-event format, as Perfetto imports it):
complete slices ("X") on one thread must nest, never partly overlap (a
slice that starts inside another and ends after it is dropped as misplaced),
so a message slice is cut at the end of the slice it starts in (its true
last delivery stays in ``args.delivered_until_us``); and a flow event binds
to the slice open on its thread when it is read, so each "s"/"f" is written
right after the "X" of the message it belongs to, never before it.
"""

from __future__ import annotations

import json
import os
from collections import OrderedDict, deque
from collections.abc import Callable
from pathlib import Path
from typing import IO, Any

from ..traceview import HEARTBEAT, RECENT, Delivery, channel_stats, label_of, walk

PID = 1
#: How many of a thread's latest slices are remembered to keep its slices nested.
NEST_MEMORY = 64


def _us(t: float) -> float:
    return round(t * 1e6, 3)


class _Writer:
    def __init__(self, fh: IO[str]) -> None:
        self.fh = fh
        self.n = 0

    def event(self, ev: dict[str, Any]) -> None:
        self.fh.write(("," if self.n else "") + "\n" + json.dumps(ev, ensure_ascii=False, separators=(",", ":"), sort_keys=True))
        self.n += 1


def export_perfetto(trace: str | os.PathLike[str], out: str | os.PathLike[str], *,
                    progress: Callable[[float, float], None] | None = None) -> dict[str, int]:
    """Write ``trace`` as trace-event JSON to ``out``; return counts (slices, spans, flows, threads).

    ``progress(t, end)``: told the virtual time reached while the trace is read."""
    header, streams = channel_stats(trace)
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    tids: dict[str, int] = {}
    counts = {"slices": 0, "spans": 0, "flows": 0, "threads": 0}
    pending: OrderedDict[str, dict[str, Any]] = OrderedDict()  # message id -> its slice, until delivered
    tmp = out.with_name(out.name + ".part")
    with open(tmp, "w", encoding="utf-8", newline="\n") as fh:
        fh.write('{"displayTimeUnit":"ms","otherData":' + json.dumps(
            {"scenario": header.get("scenario"), "seed": header.get("seed"), "homesim_version": header.get("homesim_version"),
             "time": "virtual"}, sort_keys=True) + ',"traceEvents":[')
        w = _Writer(fh)
        w.event({"ph": "M", "pid": PID, "tid": 0, "name": "process_name", "args": {"name": f"homesim {header.get('scenario')} (seed {header.get('seed')})"}})

        def tid(name: str) -> int:
            if name not in tids:
                tids[name] = len(tids) + 1
                w.event({"ph": "M", "pid": PID, "tid": tids[name], "name": "thread_name", "args": {"name": name}})
                w.event({"ph": "M", "pid": PID, "tid": tids[name], "name": "thread_sort_index", "args": {"sort_index": tids[name]}})
                counts["threads"] += 1
            return tids[name]

        written: dict[int, deque[tuple[float, float]]] = {}  # tid -> (start, end) of its latest written slices

        def flush(mid: str) -> None:
            sl = pending.pop(mid)
            flows = sl.pop("_flows")
            start, end = sl["ts"], sl["ts"] + sl["dur"]
            sl["args"]["delivered_until_us"] = end
            recent = written.setdefault(sl["tid"], deque(maxlen=NEST_MEMORY))
            for s0, e0 in recent:  # cut at the end of a written slice it starts in, so the thread's slices nest
                if s0 <= start < e0 < end:
                    end = e0
            sl["dur"] = round(end - start, 3)
            recent.append((start, end))
            w.event(sl)
            for f in flows:
                w.event(f)
            counts["slices"] += 1

        exported: OrderedDict[str, tuple[int, float]] = OrderedDict()  # id -> (tid, ts) of exported slices
        for ev in walk(trace, streams, progress=progress):
            rec = ev.rec
            if isinstance(ev, Delivery):
                sl = pending.get(rec["id"])
                if sl is not None:
                    sl["dur"] = max(1.0, round(_us(rec["t"]) - sl["ts"], 3))
                    sl["args"]["delivered"] += len(rec.get("receivers", ()))
                    if sl["args"]["delivered"] >= len(sl["args"]["receivers"]):
                        flush(rec["id"])
                continue
            if rec["channel"].startswith(HEARTBEAT):
                continue
            me = tid(rec["sender"])
            ts = _us(rec["t"])
            pending[rec["id"]] = {"_flows": [], "ph": "X", "cat": "bus", "name": label_of(rec) or rec["channel"], "pid": PID, "tid": me, "ts": ts, "dur": 1.0,
                                  "args": {"id": rec["id"], "channel": rec["channel"], "kind": rec["kind"], "receivers": rec.get("receivers", []),
                                           "delivered": 0, "causes": rec.get("causes", []), "stream": ev.continuous, "xml": rec.get("xml", "")[:400]}}
            exported[rec["id"]] = (me, ts)
            if len(exported) > RECENT:
                exported.popitem(last=False)
            for f in ev.flows:
                src = exported.get(f.cause)
                if src is None:
                    continue
                counts["flows"] += 1
                fid = counts["flows"]
                start = {"ph": "s", "cat": "bus", "name": "cause", "id": fid, "pid": PID, "tid": src[0], "ts": src[1]}
                if f.cause in pending:  # after the cause's slice, when that is written
                    pending[f.cause]["_flows"].append(start)
                else:
                    w.event(start)
                pending[rec["id"]]["_flows"].append({"ph": "f", "bp": "e", "cat": "bus", "name": "cause", "id": fid, "pid": PID, "tid": me, "ts": ts})
            if not rec.get("receivers"):
                flush(rec["id"])
            while len(pending) > RECENT:
                flush(next(iter(pending)))
            if ev.span is not None and not ev.continuous:
                counts["spans"] += 1
                sid = f"span{counts['spans']}"
                name = f"{ev.span.lane} processing"
                args = {"cause": ev.span.cause, "message": ev.span.effect, "ms": round((ev.span.end - ev.span.start) * 1000, 3)}
                w.event({"ph": "b", "cat": "processing", "name": name, "id": sid, "pid": PID, "tid": me, "ts": _us(ev.span.start), "args": args})
                w.event({"ph": "e", "cat": "processing", "name": name, "id": sid, "pid": PID, "tid": me, "ts": _us(ev.span.end)})
        while pending:
            flush(next(iter(pending)))
        fh.write("\n]}\n")
    os.replace(tmp, out)
    return counts
