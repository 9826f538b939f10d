"""The run header of a trace: one schema, checked whole before anything in it is used.

A trace is untrusted input (it may come from anyone), and its header line
tells ``homesim replay``, ``plot`` and ``export`` what to run again: which
scenario file, seed, stop time, knowledge store, robot subsystems and
metrics. Nothing in it may import code or touch the file system, so
:func:`check_header` checks every field against :data:`RUN_FIELDS` first and
refuses with one line (``TRACE:1: header field 'run.x': why``):

* ``subsystems`` and ``metrics`` only name members of the robot's own
  subsystem registry and of the metric registry (never a module to import);
* ``memory`` names an existing store directory holding a store, with the
  digest the run started from (a replay never creates a store);
* numbers are finite and in range, strings are strings, and a field this
  homesim does not know is refused (a newer trace, or an edited one).

:func:`check_subsystems` and :func:`check_metrics` are the same checks for
options given through the API (:class:`homesim.tour.runner.RunOptions`).
"""

from __future__ import annotations

import functools
import json
import math
import os
import re
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import robot.install as biron
from robot.profiles import PROFILES

from ..errors import InputError
from ..trace import TRACE_FORMAT
from ..xmlio import open_regular

#: Longest header line read (a header is a few hundred bytes).
MAX_HEADER_BYTES = 1 << 16
#: Largest seed a run accepts (numpy's SeedSequence takes any int >= 0; a trace keeps it sane).
MAX_SEED = 2**63 - 1
_DIGEST = re.compile(r"sha256:[0-9a-f]{64}\Z")


class HeaderError(InputError):
    """A trace header that cannot be used (names the trace, line 1, and the field)."""


def known_subsystems() -> tuple[str, ...]:
    """The robot's subsystem registry (``robot.install.SUBSYSTEMS``)."""
    return tuple(biron.SUBSYSTEMS)


@functools.cache
def known_metrics() -> tuple[str, ...]:
    """Every registered metric name (:func:`homesim.tour.metrics.registry`)."""
    from . import metrics

    return tuple(sorted(metrics.registry()))


def _names(kind: str, value: Any, known: Callable[[], Sequence[str]]) -> tuple[str, ...]:
    if not isinstance(value, (list, tuple)) or not all(isinstance(v, str) for v in value):
        raise ValueError(f"a list of {kind} names, not {_show(value)}")
    allowed = known()
    unknown = [v for v in value if v not in allowed]
    if unknown:
        raise ValueError(f"unknown {kind} {', '.join(map(_show, unknown[:5]))}; known: {', '.join(allowed)}")
    if len(set(value)) != len(value):
        raise ValueError(f"a {kind} is named twice")
    return tuple(value)


def check_subsystems(names: Any) -> tuple[str, ...]:
    """``names`` if each is in the robot's subsystem registry, else ``ValueError`` (nothing is imported)."""
    return _names("subsystem", names, known_subsystems)


def check_metrics(names: Any) -> tuple[str, ...]:
    """``names`` if each is a registered metric, else ``ValueError``."""
    return _names("metric", names, known_metrics)


def _show(v: Any) -> str:
    text = repr(v)
    return text if len(text) <= 60 else text[:57] + "..."


def _string(v: Any) -> str:
    if not isinstance(v, str) or not v or "\0" in v or len(v) > 4096:
        raise ValueError(f"a non-empty string (a path or name), not {_show(v)}")
    return v


def _digest(v: Any) -> str:
    if not isinstance(v, str) or not _DIGEST.match(v):
        raise ValueError(f"'sha256:' and 64 hex digits, not {_show(v)}")
    return v


def _seed(v: Any) -> int:
    if isinstance(v, bool) or not isinstance(v, int) or not 0 <= v <= MAX_SEED:
        raise ValueError(f"an integer from 0 to 2**63-1, not {_show(v)}")
    return v


def _seconds(v: Any) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v < 0:
        raise ValueError(f"a finite number of seconds >= 0, not {_show(v)}")
    return float(v)


def check_profile(v: Any) -> str:
    """``v`` if it names one of the robot's profiles, else ``ValueError``."""
    if not isinstance(v, str) or v not in PROFILES:
        raise ValueError(f"a robot profile ({', '.join(sorted(PROFILES))}), not {_show(v)}")
    return v


#: ``--rates`` presets: (laser Hz, camera Hz). "hardware": BIRON's PeopleBot, its SICK laser
#: sending 37.5 scans a second and its camera 25 frames.
RATES: dict[str, tuple[float, float]] = {"hardware": (37.5, 25.0)}


def check_rates(v: Any) -> str:
    """``v`` if it names a ``--rates`` preset, else ``ValueError``."""
    if not isinstance(v, str) or v not in RATES:
        raise ValueError(f"a rates preset ({', '.join(sorted(RATES))}), not {_show(v)}")
    return v


def _mapping(v: Any, check: Callable[[Any], Any]) -> dict[str, Any]:
    if not isinstance(v, dict) or len(v) > 256:
        raise ValueError(f"an object of at most 256 names, not {_show(v)}")
    return {_string(k): check(x) for k, x in v.items()}


def _optional(check: Callable[[Any], Any]) -> Callable[[Any], Any]:
    return lambda v: None if v is None else check(v)


#: The ``run`` object of a header: field -> its check (returns the value to use; ``ValueError`` says why not).
RUN_FIELDS: dict[str, Callable[[Any], Any]] = {
    "scenario_file": _string,
    "scenario_digest": _digest,
    "seed": _seed,
    "until": _optional(_seconds),
    "memory": _optional(_string),
    "memory_digest": _optional(_digest),
    "subsystems": _optional(check_subsystems),
    "metrics": _optional(check_metrics),
    "profile": _optional(lambda v: check_profile(v)),
    "deployment": _optional(_string),
    "hosts": _optional(lambda v: _mapping(v, _string)),
    "placement": _optional(lambda v: _mapping(v, _string)),
    "link_worst_ms": _optional(lambda v: _mapping(v, _seconds)),
    "uplinks": _optional(lambda v: _mapping(v, _string)),
    "routes": _optional(lambda v: _mapping(v, _string)),
    "rates": _optional(check_rates),
}
#: The header's own fields (besides ``run``).
TOP_FIELDS: dict[str, Callable[[Any], Any]] = {
    "homesim_trace": lambda v: v,  # checked first, with its own message
    "scenario": lambda v: v if isinstance(v, str) else _string(v),
    "seed": _seed,
    "homesim_version": _string,
}


def check_header(header: Any, *, source: str) -> dict[str, Any]:
    """The checked ``run`` object of a parsed header line (see the module docstring); :class:`HeaderError` if any field is bad."""
    def refuse(why: str) -> HeaderError:
        return HeaderError(why, source=source, line=1)

    if not isinstance(header, dict) or header.get("homesim_trace") != TRACE_FORMAT:
        raise refuse(f"not a homesim trace (no 'homesim_trace': {TRACE_FORMAT} header)")
    for key, value in header.items():
        if key == "run":
            continue
        if key not in TOP_FIELDS:
            raise refuse(f"unknown header field {_show(key)} (a trace of another homesim, or edited?)")
        try:
            TOP_FIELDS[key](value)
        except ValueError as exc:
            raise refuse(f"header field {key!r}: {exc}") from None
    run = header.get("run")
    if not isinstance(run, dict):
        raise refuse("the header does not name a run (write the trace with 'homesim run --trace')")
    extra = sorted(set(run) - set(RUN_FIELDS))
    if extra:
        raise refuse(f"unknown header field 'run.{_show(extra[0])[1:-1]}' (this homesim's run header has: {', '.join(RUN_FIELDS)})")
    out: dict[str, Any] = {}
    for key, check in RUN_FIELDS.items():
        if key not in run and key in ("scenario_file", "scenario_digest", "seed"):
            raise refuse(f"header field 'run.{key}' is missing")
        try:
            out[key] = check(run.get(key))
        except ValueError as exc:
            raise refuse(f"header field 'run.{key}': {exc}") from None
    if out["memory"] is not None:
        if out["memory_digest"] is None:
            raise refuse("header field 'run.memory' without 'run.memory_digest' (the store as the run found it)")
        store = Path(out["memory"])
        if not store.is_dir() or not any(p.is_file() for p in store.glob("*.sqlite")):
            raise refuse(f"the store directory {out['memory']} named in the header holds no store "
                         "(a run with --memory leaves one there; a replay never creates one)")
    return out


def parse_header_line(raw: bytes, *, source: str) -> Any:
    """A header line's JSON value (a clear error for bytes that are not UTF-8 JSON, however deep)."""
    if not raw.endswith(b"\n") and len(raw) >= MAX_HEADER_BYTES:
        raise HeaderError(f"not a homesim trace (its first line is longer than {MAX_HEADER_BYTES} bytes)", source=source, line=1)
    try:
        return json.loads(raw.decode("utf-8"))
    except UnicodeDecodeError as exc:
        raise HeaderError(f"not a homesim trace (not UTF-8 text: {exc.reason} at byte {exc.start})", source=source, line=1) from None
    except json.JSONDecodeError as exc:
        raise HeaderError(f"not a homesim trace (not JSON: {exc.msg})", source=source, line=1) from None
    except RecursionError:
        raise HeaderError("not a homesim trace (JSON nested too deeply)", source=source, line=1) from None
    except ValueError as exc:  # an integer of more digits than int() converts (sys.get_int_max_str_digits)
        raise HeaderError(f"not a homesim trace (a JSON value it cannot read: {str(exc)[:80]})", source=source, line=1) from None


def read_run_header(trace: str | os.PathLike[str]) -> dict[str, Any]:
    """The checked ``run`` object of ``trace``'s header (:func:`check_header`); regular files only."""
    with os.fdopen(open_regular(trace, error=InputError), "rb") as fh:
        raw = fh.readline(MAX_HEADER_BYTES)
    header = parse_header_line(raw, source=str(trace))
    return check_header(header, source=str(trace))
