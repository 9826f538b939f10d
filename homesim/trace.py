"""The system-wide trace: every bus send, delivery and drop as JSON Lines.

Line 1 is a header ``{"homesim_trace": 1, "scenario", "seed",
"homesim_version"}`` plus what the writer adds (the runner: ``run`` with the
scenario file, its content digest and the options ``homesim replay`` needs). Each later line is one observation, in the order the
bus made them (``seq`` counts them):

* a send: ``{"t", "seq", "kind" (publish|request|reply|error), "sender",
  "channel", "receivers", "id", "causes", "created", "xml"}`` plus
  ``"attachments"`` (name -> sha256, dtype, shape; never inline);
* a delivery: ``{"t", "seq", "kind": "deliver", "id", "receivers": [name]}``;
* a drop: the same with ``"kind": "drop"`` and a ``"reason"``.

The recorder is an interceptor: it reads, never changes. Same scenario and
seed give a byte-identical file.

Cost: a trace line is written for every send and every delivery, so the
recorder formats the three record shapes itself (the same bytes as
``json.dumps(observation_record(...), ensure_ascii=False,
separators=(",", ":"))``, which the tests check) and, for a file or memory
trace it owns, writes lines in batches (everything is written by
:meth:`TraceRecorder.flush`, :meth:`~TraceRecorder.close` and
:meth:`MemoryTrace.text`).
"""

from __future__ import annotations

import io
import json
import math
import os
import re
from json.encoder import encode_basestring as _json_str
from collections.abc import Iterator
from pathlib import Path
from typing import IO, Any

from lxml import etree

from . import __version__
from .bus import DELIVER, DROP, SEND, Bus, Observation
from .errors import InputError
from .message import describe_attachment
from .vloop import NS_PER_S
from .xmlio import open_regular

TRACE_FORMAT = 1


_ENCODER = json.JSONEncoder(ensure_ascii=False, separators=(",", ":"), allow_nan=False)


def _dumps(obj: dict[str, Any]) -> str:
    """``json.dumps(obj, ensure_ascii=False, separators=(",", ":"), allow_nan=False)`` (one encoder, made once)."""
    return _ENCODER.encode(obj)


_float_repr = float.__repr__


def _finite(text: str) -> float:
    v = float(text)
    if v in (math.inf, -math.inf):
        raise ValueError(f"a number out of range ({text[:40]})")
    return v


def _no_constant(text: str) -> float:
    raise ValueError(f"{text} is not a number a trace holds")


#: Trace lines are read strictly: no NaN/Infinity, no number that overflows to infinity.
_DECODER = json.JSONDecoder(parse_float=_finite, parse_constant=_no_constant)
_DECODER_CHECK = json.JSONEncoder(ensure_ascii=False)
_SURROGATE_ESCAPE = re.compile(rb"\\u[dD][89a-fA-F]")


def _json_list(items: tuple[str, ...]) -> str:
    return "[" + ",".join(map(_json_str, items)) + "]"


def observation_line(obs: Observation, seq: int) -> str:
    """``_dumps(observation_record(obs, seq))``, formatted directly (the recorder's hot path).

    Floats as ``float.__repr__`` and strings as ``json.encoder.encode_basestring``: exactly what
    the JSON encoder writes. A send with attachments goes through :func:`observation_record`.
    """
    msg = obs.message
    event = obs.event
    t = _float_repr(obs.t_ns / NS_PER_S)
    if event == SEND:
        if msg.attachments:
            return _dumps(observation_record(obs, seq))
        return (
            f'{{"t":{t},"seq":{seq},"kind":{_json_str(msg.kind)},"sender":{_json_str(msg.sender)},'
            f'"channel":{_json_str(msg.channel)},"receivers":{_json_list(obs.receivers)},"id":{_json_str(msg.id)},'
            f'"causes":{_json_list(msg.causes)},"created":{_float_repr(msg.created_ns / NS_PER_S)},'
            f'"xml":{_json_str(etree.tostring(msg.xml, encoding="unicode"))}}}'
        )
    head = f'{{"t":{t},"seq":{seq},"kind":"{"deliver" if event == DELIVER else "drop"}","id":{_json_str(msg.id)},"receivers":{_json_list(obs.receivers)}'
    if event == DROP:
        return f'{head},"reason":{_json_str(obs.reason)}}}'
    return head + "}"


def observation_record(obs: Observation, seq: int) -> dict[str, Any]:
    """The JSON object for one observation (pure; used by the recorder and tests)."""
    msg = obs.message
    rec: dict[str, Any] = {"t": obs.t_ns / NS_PER_S, "seq": seq}
    if obs.event == SEND:
        rec["kind"] = msg.kind
        rec["sender"] = msg.sender
        rec["channel"] = msg.channel
        rec["receivers"] = list(obs.receivers)
        rec["id"] = msg.id
        rec["causes"] = list(msg.causes)
        rec["created"] = msg.created_ns / NS_PER_S
        rec["xml"] = etree.tostring(msg.xml, encoding="unicode")
        if msg.attachments:
            rec["attachments"] = {k: describe_attachment(v) for k, v in sorted(msg.attachments.items())}
    else:
        rec["kind"] = "deliver" if obs.event == DELIVER else "drop"
        rec["id"] = msg.id
        rec["receivers"] = list(obs.receivers)
        if obs.event == DROP:
            rec["reason"] = obs.reason
    return rec


def header_line(scenario: str, seed: int, header: dict[str, Any] | None = None) -> str:
    """A trace's first line (canonical JSON, no newline): format, scenario, seed, version and ``header``'s fields."""
    return _dumps({"homesim_trace": TRACE_FORMAT, "scenario": scenario, "seed": seed, "homesim_version": __version__, **(header or {})})


class TraceRecorder:
    """Writes the trace of a bus to a text stream (a file, or memory).

    ``batch``: how many lines to gather before one write (1: every line is
    written at once, as for a stream the caller gave and may read while the
    run goes on; the file and memory traces batch).
    """

    def __init__(self, bus: Bus, stream: IO[str], *, scenario: str, seed: int, header: dict[str, Any] | None = None,
                 batch: int = 1) -> None:
        self.bus = bus
        self.stream = stream
        self.seq = 0
        self.batch = max(1, int(batch))
        self._pending: list[str] = []
        stream.write(header_line(scenario, seed, header) + "\n")
        bus.add_interceptor(self)

    def __call__(self, obs: Observation) -> None:
        self.seq += 1
        pending = self._pending
        pending.append(observation_line(obs, self.seq))
        if len(pending) >= self.batch:
            self._write()

    def _write(self) -> None:
        # The lines leave the batch before the write: a stream that refuses them (the re-run
        # check of homesim.tour.tracerun raises on a departure) does not get them again at close.
        pending = self._pending
        pending.append("")
        text = "\n".join(pending)
        pending.clear()
        self.stream.write(text)

    def flush(self) -> None:
        """Write every gathered line to the stream and flush it."""
        if self._pending:
            self._write()
        self.stream.flush()

    def close(self) -> None:
        """Stop recording and flush (the stream is closed if we opened it)."""
        if self in self.bus._interceptors:
            self.bus.remove_interceptor(self)
        self.flush()


class FileTrace(TraceRecorder):
    """A trace written to a file path (opened and closed by the recorder)."""

    def __init__(self, bus: Bus, path: str | os.PathLike[str], *, scenario: str, seed: int, header: dict[str, Any] | None = None) -> None:
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        super().__init__(bus, open(self.path, "w", encoding="utf-8", newline="\n"), scenario=scenario, seed=seed, header=header,
                         batch=256)

    def close(self) -> None:
        super().close()
        self.stream.close()


class MemoryTrace(TraceRecorder):
    """A trace kept in memory (notebooks, tests)."""

    def __init__(self, bus: Bus, *, scenario: str, seed: int) -> None:
        super().__init__(bus, io.StringIO(), scenario=scenario, seed=seed, batch=256)

    def text(self) -> str:
        assert isinstance(self.stream, io.StringIO)
        self.flush()
        return self.stream.getvalue()

    def records(self) -> list[dict[str, Any]]:
        # Split on "\n" only: str.splitlines() also splits on U+2028 and
        # friends, which JSON leaves unescaped inside strings.
        return [json.loads(line) for line in self.text().split("\n") if line]


def read_trace(path: str | os.PathLike[str]) -> Iterator[dict[str, Any]]:
    """Iterate the records of a trace file (header first); regular files only (no FIFO or device).

    A trace is untrusted input: a line that is not a JSON object (a truncated
    or edited trace, bytes that are not UTF-8, JSON nested too deeply for the
    parser) fails with ``InputError`` naming the file and line.
    """
    with os.fdopen(open_regular(path, error=InputError), "rb") as fh:
        for n, raw in enumerate(fh, 1):  # binary files split on b"\n" only (not U+2028, which JSON leaves as is)
            if not raw.strip():
                continue
            try:
                rec = _DECODER.decode(raw.decode("utf-8"))
                if b"\\u" in raw and _SURROGATE_ESCAPE.search(raw):
                    _DECODER_CHECK.encode(rec).encode("utf-8")  # a lone surrogate is not text (no run writes one)
            except UnicodeError as exc:
                why = exc.reason if isinstance(exc, UnicodeDecodeError) else "a lone surrogate escape"
                raise InputError(f"not UTF-8 text ({why})", source=str(path), line=n) from None
            except ValueError as exc:
                if isinstance(exc, json.JSONDecodeError):
                    why = "the trace ends in the middle of a line (truncated?)" if not raw.endswith(b"\n") else f"not JSON ({exc.msg})"
                else:
                    why = str(exc)
                raise InputError(why, source=str(path), line=n) from None
            except RecursionError:
                raise InputError("JSON nested too deeply for a trace record", source=str(path), line=n) from None
            if not isinstance(rec, dict):
                raise InputError("not a trace record (a JSON object)", source=str(path), line=n)
            yield rec
