"""A trace as Chrome trace-event JSON for Perfetto: each module's work on its own thread, messages as flows.

One process (the run), one thread per module (named by the module). On a
module's thread:

* its **work** as complete slices (``X``, ``cat`` = what the span measures:
  "processing", "speech detection", "speech recognition", "ES
  reconfiguration", "robot speech"): a processing span runs from the delivery
  of a message's latest cause to the module to the message's send
  (:func:`homesim.traceview.walk`), named spans come from the run package's
  span markers (:func:`homesim.traceview.register_spans`: e.g. the robot's
  speech is a slice on the **speaker**'s thread from the start to the end of
  what it says). The slice is named by the message it made and carries it in
  ``args`` (id, channel, kind, receivers, causes, the XML's first 400 characters);
* every other message it sends as an **instant**: a zero-length slice at
  its send time (continuous streams too, ``args.stream``: true), never a
  made-up duration;
* each cause -> message link as a **flow** (``ph`` "s" right after the
  cause's slice or instant, "f" with ``bp`` "e" right after the message's), so
  one can click from the robot's speech on the speaker's thread back through
  the dialog, the supervisor and the understanding to the microphones'
  speech detection.

Phases (the papers' A-E, teaching, good-bye) are global instants. Heartbeats
are left out. Times are virtual microseconds.

What a viewer needs (Chrome trace-event format, as Perfetto imports it):
slices on one thread must nest, never partly overlap (a misplaced one is
dropped), and slices that start together nest only when the longer comes
first. A module's work rarely overlaps (two causes in flight at once); when a
slice would not nest on the module's thread it goes on the module's next
thread ("dialog (2)"), so nothing is cut or lost. A flow event binds to the
slice open on its thread when it is read, so each "s"/"f" is written right
after the slice of the message it belongs to. The file is written as the trace
is read, with bounded memory.
"""

from __future__ import annotations

import json
import os
from collections import OrderedDict, deque
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO, Any

from ..traceview import HEARTBEAT, PHASE_MARKERS, RECENT, SPAN_MARKERS, Delivery, Span, channel_stats, label_of, walk

PID = 1
#: How many of a thread's latest slices are remembered to keep its slices nested.
NEST_MEMORY = 64
#: How many recent messages wait for the flows that bind to them (about a minute of a home tour).
WINDOW = 8192


def _us(t: float) -> float:
    return round(t * 1e6, 3)


def _conflicts(s0: float, e0: float, s1: float, e1: float) -> bool:
    """Whether a slice [s1, e1] written after [s0, e0] on the same thread breaks the nesting."""
    if e1 <= s0 or e0 <= s1:
        return False  # apart (touching is fine)
    if s0 == s1:
        return e1 > e0 and e0 > s0  # same start: only the longer first nests
    return not (s0 < s1 and e1 <= e0 or s1 < s0 and e0 <= e1)


@dataclass
class _Module:
    """A module's threads: one per level of slices that would not nest on the ones before."""

    name: str
    tids: list[int] = field(default_factory=list)
    recent: list[deque[list[float]]] = field(default_factory=list)  # [start, end] of each level's latest slices


class _Writer:
    def __init__(self, fh: IO[str]) -> None:
        self.fh = fh
        self.n = 0
        self.tids = 0
        self.modules: dict[str, _Module] = {}

    def event(self, ev: dict[str, Any]) -> None:
        self.fh.write(("," if self.n else "") + "\n" + json.dumps(ev, ensure_ascii=False, separators=(",", ":"), sort_keys=True))
        self.n += 1

    def _new_thread(self, mod: _Module) -> int:
        self.tids += 1
        tid = self.tids
        level = len(mod.tids)
        mod.tids.append(tid)
        mod.recent.append(deque(maxlen=NEST_MEMORY))
        self.event({"ph": "M", "pid": PID, "tid": tid, "name": "thread_name",
                    "args": {"name": mod.name if level == 0 else f"{mod.name} ({level + 1})"}})
        # Threads sort by module (in order of appearance), a module's extra threads right under its first.
        self.event({"ph": "M", "pid": PID, "tid": tid, "name": "thread_sort_index",
                    "args": {"sort_index": 1000 * (list(self.modules).index(mod.name) + 1) + level}})
        return tid

    def thread(self, module: str, start: float, end: float) -> int:
        """The thread of ``module`` a slice [start, end] nests on (a new one if none)."""
        mod = self.modules.get(module)
        if mod is None:
            mod = self.modules[module] = _Module(module)
        for tid, recent in zip(mod.tids, mod.recent):
            if not any(_conflicts(s0, e0, start, end) for s0, e0 in recent):
                recent.append([start, end])
                return tid
        tid = self._new_thread(mod)
        mod.recent[-1].append([start, end])
        return tid

    def extend(self, module: str, tid: int, start: float, end: float, new_end: float) -> bool:
        """Lengthen the slice [start, end] on ``tid`` to ``new_end`` if it still nests; whether it did."""
        mod = self.modules[module]
        recent = mod.recent[mod.tids.index(tid)]
        mine = next((iv for iv in recent if iv[0] == start and iv[1] == end), None)
        if mine is None or any(_conflicts(s0, e0, start, new_end) for s0, e0 in (iv for iv in recent if iv is not mine)):
            return False
        mine[1] = new_end
        return True


def export_perfetto(trace: str | os.PathLike[str], out: str | os.PathLike[str], *,
                    progress: Callable[[float, float], None] | None = None) -> dict[str, int]:
    """Write ``trace`` as trace-event JSON to ``out``; return counts (threads, work slices, instants, flows, flows lost
    to the window's edge, phases).

    ``progress(t, end)``: told the virtual time reached while the trace is read."""
    header, streams = channel_stats(trace)
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    counts = {"threads": 0, "slices": 0, "instants": 0, "flows": 0, "flows_lost": 0, "phases": 0}
    span_markers = [factory() for factory in SPAN_MARKERS]
    phase_markers = [factory() for factory in PHASE_MARKERS]
    tmp = out.with_name(out.name + ".part")
    with open(tmp, "w", encoding="utf-8", newline="\n") as fh:
        fh.write('{"displayTimeUnit":"ms","otherData":' + json.dumps(
            {"scenario": header.get("scenario"), "seed": header.get("seed"), "homesim_version": header.get("homesim_version"),
             "time": "virtual"}, sort_keys=True) + ',"traceEvents":[')
        w = _Writer(fh)
        w.event({"ph": "M", "pid": PID, "tid": 0, "name": "process_name", "args": {"name": f"homesim {header.get('scenario')} (seed {header.get('seed')})"}})
        # Each message's slice or instant waits here, with the flow events that bind to it, until it falls out
        # of the window (by then the causes :func:`walk` can still link to it are past): a flow event is read
        # right after its slice, whatever else happens at the same time on that thread.
        pending: OrderedDict[str, list[dict[str, Any]]] = OrderedDict()  # message id -> [its X, flow events...]
        anchors: OrderedDict[str, tuple[int, float, str]] = OrderedDict()  # message id -> (tid, ts, the id its events wait under)
        same: OrderedDict[tuple[str, float, float], str] = OrderedDict()  # a span already written -> the message it went with
        work: OrderedDict[tuple[str, float], tuple[str, int, float, float]] = OrderedDict()  # (module, start) -> (message, tid, ts, end)
        flow_id = 0

        def flush_one() -> None:
            for e in pending.popitem(last=False)[1]:
                w.event(e)

        for ev in walk(trace, streams, progress=progress):
            if isinstance(ev, Delivery):
                continue
            rec = ev.rec
            ch = rec["channel"]
            for marker in phase_markers:
                for mark, label in marker(ch, rec):
                    w.event({"ph": "i", "s": "g", "cat": "phase", "name": f"{mark}: {label}", "pid": PID, "tid": 0, "ts": _us(rec["t"])})
                    counts["phases"] += 1
            span: Span | None = None if ev.continuous else ev.span
            for smarker in span_markers:
                named = smarker(ch, rec, span)
                if named is not None:
                    span = named
            if ch.startswith(HEARTBEAT):
                continue
            args = {"id": rec["id"], "channel": ch, "kind": rec["kind"], "receivers": rec.get("receivers", []),
                    "causes": rec.get("causes", []), "stream": ev.continuous, "xml": rec.get("xml", "")[:400]}
            name = label_of(rec) or ch
            key = None if span is None else (span.lane, span.start, span.end)
            if key is not None and key in same and same[key] in anchors:  # the same work once more (a speech's done status)
                tid, ts, home = anchors[same[key]]
            elif span is not None and (span.lane, span.start) in work and work[(span.lane, span.start)][0] in pending \
                    and w.extend(span.lane, *work[(span.lane, span.start)][1:], _us(span.end)):
                # More messages from the same work (a cause delivered, several sends): the slice runs to the last of
                # them, each of them an instant in it.
                first, tid, ts0, _ = work[(span.lane, span.start)]
                x = pending[first][0]
                x["dur"] = round(_us(span.end) - ts0, 3)
                x["args"]["messages"] = x["args"].get("messages", 1) + 1
                x["args"]["ms"] = round((span.end - span.start) * 1000, 3)
                work[(span.lane, span.start)] = (first, tid, ts0, _us(span.end))
                ts = _us(rec["t"])
                home = rec["id"]
                pending[home] = [{"ph": "X", "cat": "message", "name": name, "pid": PID, "tid": tid, "ts": ts, "dur": 0, "args": args}]
                counts["instants"] += 1
            elif span is not None:
                ts, end = _us(span.start), _us(span.end)
                tid = w.thread(span.lane, ts, end)
                if span.kind == "robot speech":
                    name = f'say "{name.split(" ", 1)[-1]}"'
                args["ms"] = round((span.end - span.start) * 1000, 3)
                home = rec["id"]
                pending[home] = [{"ph": "X", "cat": span.kind, "name": name, "pid": PID, "tid": tid, "ts": ts, "dur": round(end - ts, 3), "args": args}]
                counts["slices"] += 1
                same[key] = rec["id"]
                work[(span.lane, span.start)] = (rec["id"], tid, ts, end)
                for d in (same, work):
                    if len(d) > WINDOW:
                        d.popitem(last=False)
            else:
                ts = _us(rec["t"])
                tid = w.thread(rec["sender"], ts, ts)
                home = rec["id"]
                pending[home] = [{"ph": "X", "cat": "stream" if ev.continuous else "message", "name": name, "pid": PID, "tid": tid, "ts": ts,
                                  "dur": 0, "args": args}]
                counts["instants"] += 1
            for f in ev.flows:
                src = anchors.get(f.cause)
                if src is None or src[2] not in pending or home not in pending or (src[0], src[1]) == (tid, ts) or src[1] > ts:
                    counts["flows_lost"] += src is not None and (src[0], src[1]) != (tid, ts)
                    continue
                flow_id += 1
                pending[src[2]].append({"ph": "s", "cat": "cause", "name": "cause", "id": flow_id, "pid": PID, "tid": src[0], "ts": src[1]})
                pending[home].append({"ph": "f", "bp": "e", "cat": "cause", "name": "cause", "id": flow_id, "pid": PID, "tid": tid, "ts": ts})
                counts["flows"] += 1
            anchors[rec["id"]] = (tid, ts, home)
            if len(anchors) > WINDOW:
                anchors.popitem(last=False)
            while len(pending) > WINDOW:
                flush_one()
        while pending:
            flush_one()
        fh.write("\n]}\n")
        counts["threads"] = w.tids
    os.replace(tmp, out)
    return counts
