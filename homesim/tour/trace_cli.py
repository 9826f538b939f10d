"""``homesim trace info|echo``: what a trace or recording holds, in the spirit of ``ros2 bag info`` and ``ros2 topic echo``.

``homesim trace info FILE`` lists every channel with its message type, count, rate and time
span, and what the file says about its run (scenario, seed, profile, versions). ``homesim trace
echo FILE CHANNEL [--from T] [--to T]`` prints one channel's messages, oldest first. FILE is a
JSON Lines trace (``homesim run --trace``; the channels are the bus's, the type is the root
element of the messages' XML) or an MCAP recording (``homesim run --record``, or any MCAP file;
the channels are the file's, the type is the schema name). A file that is neither fails with one
line naming it (and the line, in a trace).
"""

from __future__ import annotations

import argparse
import difflib
import json
import os
import re
import sys
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO, Any

from .. import cliargs
from ..errors import HomesimError, InputError
from ..trace import read_trace
from ..traceview import SENDS, check_record

_ROOT = re.compile(r"\s*<([A-Za-z_][\w.:-]*)")
#: At most this many distinct types are named for one channel.
MAX_TYPES = 3


@dataclass
class ChannelInfo:
    """One channel as ``trace info`` shows it."""

    name: str
    types: list[str] = field(default_factory=list)
    count: int = 0
    first: float = 0.0
    last: float = 0.0
    senders: list[str] = field(default_factory=list)

    def add(self, t: float, kind: str | None = None, sender: str | None = None) -> None:
        if self.count == 0:
            self.first = t
        self.count += 1
        self.last = t
        if kind is not None and kind not in self.types and len(self.types) <= MAX_TYPES:
            self.types.append(kind)
        if sender is not None and sender not in self.senders and len(self.senders) <= MAX_TYPES:
            self.senders.append(sender)

    @property
    def rate(self) -> float | None:
        """Messages per second over the channel's own span (None for fewer than two, or one instant)."""
        return (self.count - 1) / (self.last - self.first) if self.count > 1 and self.last > self.first else None


@dataclass
class FileInfo:
    """What ``trace info`` reports on one file."""

    path: Path
    format: str
    about: list[tuple[str, str]]
    channels: list[ChannelInfo]
    start: float
    end: float
    totals: list[tuple[str, int]]


def _type_of(rec: dict[str, Any]) -> str:
    m = _ROOT.match(rec.get("xml") or "")
    root = m.group(1) if m else "?"
    return root if rec["kind"] == "publish" else f"{rec['kind']} <{root}>"


def _trace_records(path: Path) -> Iterator[tuple[int, dict[str, Any]]]:
    """(line, record) of a JSON Lines trace after its header (checked: a homesim trace, each record well-formed)."""
    for n, rec in enumerate(read_trace(path), 1):
        if n == 1:
            if "homesim_trace" not in rec:
                raise InputError("not a homesim trace (line 1 is no trace header) nor an MCAP recording", source=str(path), line=1)
            if "run" in rec:  # a run's header is checked whole, as replay, plot and export check it (a kernel trace has none)
                from .runheader import check_header

                check_header(rec, source=str(path))
            yield 1, rec
            continue
        check_record(path, n, rec)
        if not isinstance(rec.get("t"), (int, float)) or isinstance(rec.get("t"), bool):
            raise InputError(f"a record without a valid 't' (got {rec.get('t')!r:.60})", source=str(path), line=n)
        yield n, rec


def trace_info(path: Path) -> FileInfo:
    """Channels, counts, rates and span of a JSON Lines trace (one streaming pass; memory: one entry per channel)."""
    chans: dict[str, ChannelInfo] = {}
    header: dict[str, Any] = {}
    totals = {"sends": 0, "deliveries": 0, "drops": 0}
    start = end = None
    for n, rec in _trace_records(path):
        if n == 1:
            header = rec
            continue
        t = float(rec["t"])
        start = t if start is None else start
        end = t
        kind = rec.get("kind")
        if kind in SENDS:
            totals["sends"] += 1
            chans.setdefault(rec["channel"], ChannelInfo(rec["channel"])).add(t, _type_of(rec), rec["sender"])
        elif kind == "deliver":
            totals["deliveries"] += 1
        elif kind == "drop":
            totals["drops"] += 1
    if not header:
        raise InputError("empty file (no trace header)", source=str(path))
    run = header.get("run") if isinstance(header.get("run"), dict) else {}
    about = [("Scenario", f"{header.get('scenario')} ({run.get('scenario_file', '?')})"), ("Seed", str(header.get("seed"))),
             ("Profile", str(run.get("profile") or "the scenario's (default full)")), ("Deployment", str(run.get("deployment", "?"))),
             ("Stopped at", "the scenario's end" if run.get("until") is None else f"{run['until']:g} s"),
             ("homesim", str(header.get("homesim_version")))]
    return FileInfo(path, f"homesim JSON Lines trace (format {header.get('homesim_trace')})", about, sorted(chans.values(), key=lambda c: c.name),
                    start or 0.0, end or 0.0, list(totals.items()))


def recording_info(path: Path) -> FileInfo:
    """Channels (schema names, counts, rates, spans) and metadata of an MCAP file (one pass over its messages)."""
    from .recorded import Recording

    with Recording(path) as rec:
        chans = {topic: ChannelInfo(topic, [schema or f"({enc})"]) for topic, schema, enc, _ in rec.channels()}
        for topic, _, lt, _ in rec.messages():
            chans[topic].add(lt / 1e9)
        run = rec.run
        start, end = rec.span()
        about = []
        if run:
            about = [("Scenario", f"{run.get('scenario')} ({run.get('scenario_file') or '?'})"), ("Seed", run.get("seed", "?")),
                     ("Profile", run.get("profile", "?")), ("Deployment", run.get("deployment", "?")),
                     ("Stopped at", f"{float(run['until']):g} s" if run.get("until") else "the scenario's end"),
                     ("Versions", ", ".join(f"{k.split('.', 1)[1]} {v}" for k, v in sorted(run.items()) if k.startswith("version.")))]
        if "homesim.scenario" in rec.metadata:
            about.append(("Scenario text", f"embedded ({len(rec.metadata['homesim.scenario'].get('xml', ''))} characters)"))
        stopped = rec.metadata.get("homesim.stopped")
        if stopped is not None:
            about.append(("Partial", f"the run stopped at t = {float(stopped.get('t') or 0):.3f} s: {stopped.get('reason', '?')}"))
        others = sorted(set(rec.metadata) - {"homesim.run", "homesim.scenario", "homesim.trace", "homesim.stopped"})
        if others:
            about.append(("Other metadata", ", ".join(others)))
        n = sum(c.count for c in chans.values())
    return FileInfo(path, "MCAP" + (" recording (homesim run --record)" if run else ""), about, sorted(chans.values(), key=lambda c: c.name),
                    start, end, [("messages", n)])


def file_info(path: Path) -> FileInfo:
    from .recorded import is_mcap

    return recording_info(path) if is_mcap(path) else trace_info(path)


def _size(n: int) -> str:
    for unit in ("B", "KiB", "MiB", "GiB"):
        if n < 1024 or unit == "GiB":
            return f"{n:.0f} {unit}" if unit == "B" else f"{n:.1f} {unit}"
        n /= 1024  # type: ignore[assignment]
    return str(n)  # pragma: no cover


def print_info(info: FileInfo, out: IO[str]) -> None:
    """The ``ros2 bag info``-like report."""
    rows = [("File", str(info.path)), ("Format", info.format), ("Size", _size(os.path.getsize(info.path))), *info.about,
            ("Duration", f"{info.end - info.start:.3f} s (virtual time {info.start:.3f} to {info.end:.3f} s)"),
            ("Messages", ", ".join(f"{v} {k}" for k, v in info.totals)), ("Channels", str(len(info.channels)))]
    for k, v in rows:
        print(f"{k + ':':<15} {v}", file=out)
    if not info.channels:
        return
    w = max(len(c.name) for c in info.channels)
    tw = max(len(", ".join(c.types)) for c in info.channels)
    print(f"\n  {'channel':<{w}}  {'type':<{tw}}  {'count':>7}  {'rate':>9}  {'first':>9}  {'last':>9}  senders", file=out)
    for c in info.channels:
        rate = f"{c.rate:.2f} Hz" if c.rate is not None else "-"
        types = ", ".join(c.types[:MAX_TYPES]) + (", ..." if len(c.types) > MAX_TYPES else "")
        senders = ", ".join(c.senders[:MAX_TYPES]) + (", ..." if len(c.senders) > MAX_TYPES else "")
        print(f"  {c.name:<{w}}  {types:<{tw}}  {c.count:>7}  {rate:>9}  {c.first:>9.3f}  {c.last:>9.3f}  {senders}", file=out)


def _unknown_channel(path: Path, channel: str, known: list[str]) -> InputError:
    close = difflib.get_close_matches(channel, known, n=3, cutoff=0.5)
    hint = f"; did you mean {' or '.join(close)}?" if close else "; 'homesim trace info' lists them"
    return InputError(f"no channel {channel!r}{hint}", source=str(path))


def _bare(channel: str) -> str:
    """A channel's name without its leading slash: the trace names RPC services as the bus does ("map_server/map"),
    the MCAP gives every topic one ("/map_server/map"); either spelling finds the channel in either file."""
    return channel.lstrip("/")


def echo(path: Path, channel: str, *, start: float | None, end: float | None, raw: bool, limit: int | None, out: IO[str]) -> int:
    """Print ``channel``'s messages within [start, end]; return how many."""
    from .recorded import Recording, is_mcap

    n = 0
    if is_mcap(path):
        with Recording(path) as rec:
            chans = {c[0]: c[1] for c in rec.channels()}
            if channel not in chans:  # either spelling: map_server/map (the trace's) is the topic /map_server/map
                channel = next((k for k in chans if _bare(k) == _bare(channel)), channel)
            if channel not in chans:
                raise _unknown_channel(path, channel, sorted(chans))
            if chans[channel] == "homesim.BusMessage" and "homesim.trace" in rec.metadata:
                # A bus channel of a recording: from the trace it holds, so the echo is the JSONL trace's (seq too).
                for t, r in _recorded_sends(rec, channel, start, end):
                    if limit is not None and n >= limit:
                        break
                    n += 1
                    _print_record(out, t, r, raw)
                return n
            for topic, schema, lt, data in rec.messages([channel], start=start, end=end):
                if limit is not None and n >= limit:
                    break
                n += 1
                if raw:
                    out.write(data.decode("utf-8", errors="replace") + "\n")
                    continue
                msg = rec.decode(topic, data)
                if schema == "homesim.BusMessage" and isinstance(msg, dict):
                    _print_send(out, lt / 1e9, msg)
                else:
                    print(f"--- t={lt / 1e9:.6f} s  {schema}", file=out)
                    print(json.dumps(msg, ensure_ascii=False, sort_keys=True), file=out)
        return n
    seen: set[str] = set()
    want = _bare(channel)
    for line, rec in _trace_records(path):
        if line == 1 or rec.get("kind") not in SENDS:
            continue
        if len(seen) < 10_000:
            seen.add(rec["channel"])
        if _bare(rec["channel"]) != want:
            continue
        t = float(rec["t"])
        if (start is not None and t < start) or (end is not None and t > end):
            continue
        if limit is not None and n >= limit:
            break
        n += 1
        _print_record(out, t, rec, raw)
    if n == 0 and want not in {_bare(c) for c in seen}:
        raise _unknown_channel(path, channel, sorted(seen))
    return n


def _recorded_sends(rec: Any, channel: str, start: float | None, end: float | None) -> Iterator[tuple[float, dict[str, Any]]]:
    """(t, record) of each send on ``channel`` within [start, end] from a recording's trace (batches are logged at their
    last line's time, so the batches logged from ``start`` on hold every line from ``start`` on)."""
    from .recording import TRACE_CHANNEL

    for _, _, _, data in rec.messages([TRACE_CHANNEL], start=start):
        for line in rec.trace_batch(data):
            r = rec.decode(TRACE_CHANNEL, line)
            t = float(r["t"])
            if end is not None and t > end:
                return
            if r.get("kind") in SENDS and "/" + str(r.get("channel")).lstrip("/") == channel and (start is None or t >= start):
                yield t, r


def _print_record(out: IO[str], t: float, rec: dict[str, Any], raw: bool) -> None:
    if raw:
        out.write(json.dumps(rec, ensure_ascii=False, separators=(",", ":")) + "\n")
    else:
        _print_send(out, t, rec)


def _print_send(out: IO[str], t: float, rec: dict[str, Any]) -> None:
    seq = f"  seq {rec['seq']}" if "seq" in rec else ""
    receivers = ", ".join(rec.get("receivers") or []) or "nobody"
    print(f"--- t={t:.6f} s{seq}  {rec.get('kind')}  {rec.get('sender')} -> {receivers}  id {rec.get('id')}"
          + (f"  causes {', '.join(rec['causes'])}" if rec.get("causes") else ""), file=out)
    print(rec.get("xml", ""), file=out)
    for name, a in sorted((rec.get("attachments") or {}).items()):
        print(f"  attachment {name}: {a.get('dtype')} {a.get('shape')} sha256 {str(a.get('sha256'))[:16]}...", file=out)


# ------------------------------------------------------------ commands
def _needs_mcap(path: Path) -> None:
    from importlib.util import find_spec

    from .recorded import is_mcap

    if is_mcap(path) and find_spec("mcap") is None:
        raise HomesimError(f"{path} is an MCAP recording; reading it needs the mcap library: pip install 'homesim[export]'")


def info_command(a: argparse.Namespace) -> int:
    _needs_mcap(_existing(a.file))
    print_info(file_info(a.file), sys.stdout)
    return 0


def echo_command(a: argparse.Namespace) -> int:
    if a.start is not None and a.end is not None and a.end < a.start:
        raise cliargs.OptionError("--to", f"{a.end:g} s is before --from {a.start:g} s")
    _needs_mcap(_existing(a.file))
    echo(a.file, a.channel, start=a.start, end=a.end, raw=a.json, limit=a.count, out=sys.stdout)
    return 0


def _existing(path: Path) -> Path:
    """The file to read, or a one-line refusal (checked when the command runs, so help examples parse)."""
    if not path.exists():
        raise InputError("no such file", source=str(path))
    if not path.is_file():
        raise InputError("not a regular file", source=str(path))
    return path


def _count(text: str) -> int:
    if not text.isascii() or not text.isdigit() or int(text) < 1:
        raise argparse.ArgumentTypeError(f"{text!r} is not a count >= 1")
    return int(text)


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``homesim trace info`` and ``homesim trace echo``."""
    p = sub.add_parser("trace", help="list a trace's or recording's channels (info) or print one channel's messages (echo)",
                       description="Look into a JSON Lines trace (homesim run --trace) or an MCAP recording (homesim run --record), "
                                   "like 'ros2 bag info' and 'ros2 topic echo'.",
                       examples=["homesim trace info out/tour.mcap", "homesim trace echo out/tour.jsonl /robot/es/log --from 0 --to 5"])
    tsub = p.add_subparsers(dest="trace_command", metavar="ACTION")
    i = tsub.add_parser("info", help="channels with message types, counts, rates and time span; the run the file names",
                        examples=["homesim trace info out/tour.jsonl", "homesim trace info out/tour.mcap"])
    i.add_argument("file", type=Path, help="a trace or a recording, e.g. out/tour.jsonl or out/tour.mcap")
    i.set_defaults(func=info_command)
    e = tsub.add_parser("echo", help="print one channel's messages (optionally within --from/--to)",
                        examples=["homesim trace echo out/tour.mcap /robot/es/status --from 5 --to 12",
                                  "homesim trace echo out/tour.jsonl /robot/audio/speech --json -n 3"])
    e.add_argument("file", type=Path, help="a trace or a recording, e.g. out/tour.jsonl or out/tour.mcap")
    e.add_argument("channel", help="the channel, e.g. /robot/es/status (a bus channel; in a recording also /laser, /tf, /homesim/world, ...)")
    e.add_argument("--from", dest="start", type=cliargs.seconds(), default=None, metavar="SECONDS", help="first virtual time (default: the start)")
    e.add_argument("--to", dest="end", type=cliargs.seconds(), default=None, metavar="SECONDS", help="last virtual time (default: the end)")
    e.add_argument("-n", "--count", type=_count, default=None, metavar="N", help="print at most this many messages (default: all)")
    e.add_argument("--json", action="store_true", help="print each message as one line of JSON (the trace's record, the recording's message)")
    e.set_defaults(func=echo_command)
    p.set_defaults(func=lambda a: (p.print_help(), 2)[1])
