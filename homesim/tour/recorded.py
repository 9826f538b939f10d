"""Reading a recording (``homesim run --record``): metadata, channels, messages, a moment, the trace.

A recording stands alone: :meth:`Recording.moment` rebuilds what a top-down plot needs at time
``t`` from the file (the map, the world's truth, the robot's latest percepts), with no scenario
file and no re-run; :meth:`Recording.trace_lines` gives back the JSON Lines trace it holds, so
everything that reads a trace (the timeline, the Perfetto export, ``homesim trace``) reads a
recording too. A file that is not a whole MCAP recording fails with ``InputError`` naming it.
"""

from __future__ import annotations

import functools
import json
import math
import os
import stat
import struct
import zlib
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numpy as np

from ..errors import InputError
from ..world.world import Obstacle
from ..xmlio import open_regular, parse_bytes
from .percepts import CHANNELS, PerceptCollector
from .recording import MAP_CHANNEL, TRACE_CHANNEL, WORLD_CHANNEL

MAGIC = b"\x89MCAP0\r\n"
#: A moment looks this far back first for each channel's latest message (then from the start).
LOOK_BACK_NS = 3_000_000_000


def is_mcap(path: str | os.PathLike[str]) -> bool:
    """Does the file start with MCAP's magic bytes? (False for anything that is not a regular file one can read:
    a FIFO or a device is never opened blocking, and the trace reader then refuses it naming the file.)"""
    try:
        fd = os.open(os.fspath(path), os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0))
    except (OSError, ValueError):
        return False
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            return False
        return os.read(fd, len(MAGIC)) == MAGIC
    except OSError:
        return False
    finally:
        os.close(fd)


def is_recording(path: str | os.PathLike[str]) -> bool:
    """Is the file an MCAP recording of ``homesim run --record`` (one that has, or had, the ``homesim.run`` metadata)?

    An MCAP file that cannot be read whole counts as one: a damaged recording is not overwritten either.
    """
    if not is_mcap(path):
        return False
    try:
        with Recording(path) as rec:
            return "homesim.run" in rec.metadata or TRACE_CHANNEL in {c[0] for c in rec.channels()}
    except InputError:
        return True


@functools.cache
def _errors() -> tuple[type[BaseException], ...]:
    from mcap.exceptions import McapError

    errs: list[type[BaseException]] = [McapError, struct.error, ValueError, EOFError, KeyError, zlib.error, OSError]
    try:
        import zstandard

        errs.append(zstandard.ZstdError)
    except ImportError:  # pragma: no cover - mcap depends on it
        pass
    return tuple(errs)


class Recording:
    """An MCAP file opened for reading (use as a context manager, or :meth:`close`)."""

    def __init__(self, path: str | os.PathLike[str]) -> None:
        from mcap.reader import make_reader

        self.path = Path(path)
        self._errs = _errors()
        self.fh = os.fdopen(open_regular(path, error=InputError), "rb")
        head = self.fh.read(len(MAGIC))
        self.fh.seek(0)
        if head != MAGIC:
            self.fh.close()
            raise InputError("not an MCAP file (it does not start with MCAP's magic bytes)", source=str(path))
        try:
            with self._reading("cannot read its summary"):
                self.reader = make_reader(self.fh, validate_crcs=True)  # a damaged chunk fails, never reads as fewer messages
                self.summary = self.reader.get_summary()
            if self.summary is None:
                raise InputError("an MCAP file without a summary section (truncated, or still being written?)", source=str(path))
            with self._reading("cannot read its metadata"):
                self.metadata: dict[str, dict[str, str]] = {m.name: dict(m.metadata) for m in self.reader.iter_metadata()}
        except BaseException:
            self.fh.close()
            raise

    @contextmanager
    def _reading(self, what: str) -> Iterator[None]:
        try:
            yield
        except self._errs as exc:
            raise InputError(f"not a whole MCAP file: {what} ({type(exc).__name__}: {exc})", source=str(self.path)) from None

    def close(self) -> None:
        self.fh.close()

    def __enter__(self) -> Recording:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # ------------------------------------------------------------ summary
    @property
    def run(self) -> dict[str, str]:
        """The ``homesim.run`` metadata (scenario, seed, profile, versions); empty for another MCAP file."""
        return self.metadata.get("homesim.run", {})

    def channels(self) -> list[tuple[str, str, str, int]]:
        """(topic, schema name, message encoding, count) of every channel, by topic."""
        s = self.summary
        counts = s.statistics.channel_message_counts if s.statistics is not None else {}
        out = []
        for cid, ch in s.channels.items():
            schema = s.schemas.get(ch.schema_id)
            out.append((ch.topic, schema.name if schema is not None else "", ch.message_encoding, int(counts.get(cid, 0))))
        return sorted(out)

    def span(self) -> tuple[float, float]:
        """First and last log time (seconds)."""
        st = self.summary.statistics
        if st is None or st.message_count == 0:
            return 0.0, 0.0
        return st.message_start_time / 1e9, st.message_end_time / 1e9

    def require(self, topic: str, what: str) -> None:
        if topic not in {ch.topic for ch in self.summary.channels.values()}:
            raise InputError(f"has no {topic} channel, so it cannot {what} (not a recording of 'homesim run --record'?)", source=str(self.path))

    # ----------------------------------------------------------- messages
    def messages(self, topics: Sequence[str] | None = None, *, start: float | None = None,
                 end: float | None = None) -> Iterator[tuple[str, str, int, bytes]]:
        """(topic, schema name, log time ns, data) in log-time order, within [start, end] seconds."""
        kw: dict[str, Any] = {}
        if start is not None:
            kw["starting_at"] = max(0, int(round(start * 1e9)))
        if end is not None:
            kw["ending_at"] = max(0, int(round(end * 1e9)))
        with self._reading("a message cannot be read"):
            for schema, channel, msg in self.reader.iter_messages(topics=None if topics is None else list(topics), log_time_order=True, **kw):
                yield channel.topic, schema.name if schema is not None else "", msg.log_time, msg.data

    def decode(self, topic: str, data: bytes) -> Any:
        try:
            return json.loads(data)
        except (ValueError, UnicodeError) as exc:
            raise InputError(f"a message on {topic} is not JSON ({exc})", source=str(self.path)) from None

    def latest(self, topics: Sequence[str], t: float) -> dict[str, tuple[int, bytes]]:
        """The latest message (log time ns, data) of each topic at or before ``t`` (seconds)."""
        got: dict[str, tuple[int, bytes]] = {}
        for topic, _, lt, data in self.messages(topics, start=max(0.0, t - LOOK_BACK_NS / 1e9), end=t):
            got[topic] = (lt, data)
        missing = [tp for tp in topics if tp not in got]
        if missing and t > LOOK_BACK_NS / 1e9:
            for topic, _, lt, data in self.messages(missing, end=t):
                got[topic] = (lt, data)
        return got

    # -------------------------------------------------------------- trace
    def trace_header(self) -> dict[str, Any]:
        meta = self.metadata.get("homesim.trace")
        if meta is None or "header" not in meta:
            raise InputError("holds no homesim trace (no 'homesim.trace' metadata; not a recording of 'homesim run --record'?)", source=str(self.path))
        try:
            h = json.loads(meta["header"])
        except ValueError as exc:
            raise InputError(f"its trace header is not JSON ({exc})", source=str(self.path)) from None
        if not isinstance(h, dict):
            raise InputError("its trace header is not a JSON object", source=str(self.path))
        return h

    def trace_lines(self) -> Iterator[str]:
        """The JSON Lines trace the recording holds: the header line, then every record's line."""
        yield self.metadata["homesim.trace"]["header"] if "homesim.trace" in self.metadata else json.dumps(self.trace_header())
        for _, _, _, data in self.messages([TRACE_CHANNEL]):
            yield from self.trace_batch(data)

    def trace_batch(self, data: bytes) -> list[str]:
        """The trace lines one ``/homesim/trace`` message holds (``{"lines": [...]}``)."""
        batch = self.decode(TRACE_CHANNEL, data)
        lines = batch.get("lines") if isinstance(batch, dict) else None
        if not isinstance(lines, list) or not all(isinstance(line, str) for line in lines):
            raise InputError(f'a message on {TRACE_CHANNEL} is not a homesim.TraceRecords ({{"lines": [...]}})', source=str(self.path))
        return lines

    # ------------------------------------------------------------- moment
    def moment(self, t: float | None = None) -> tuple[RecordedWorld, Any, float]:
        """The world (truth), the robot's percepts and the time of the world state at ``t`` (default: the end)."""
        self.require(MAP_CHANNEL, "draw the flat")
        self.require(WORLD_CHANNEL, "draw the people")
        end = self.span()[1]
        if t is None:
            t = end
        if round(t, 3) > round(end, 3):  # the end as 'trace info' shows it (ms) is within the recording
            raise InputError(f"t = {t:g} s is after the end of the recording ({end:.3f} s)", source=str(self.path))
        t = min(t, end)
        got = self.latest([MAP_CHANNEL, WORLD_CHANNEL], t)
        if MAP_CHANNEL not in got or WORLD_CHANNEL not in got:
            raise InputError(f"holds no map or world state at or before t = {t:g} s", source=str(self.path))
        world = RecordedWorld(self.decode(MAP_CHANNEL, got[MAP_CHANNEL][1]), self.decode(WORLD_CHANNEL, got[WORLD_CHANNEL][1]))
        # The percepts of the same moment as the truth (the world state's time, on its 10 Hz grid), never later.
        t = world.time
        got = self.latest(["/laser", *CHANNELS], t)
        seen = PerceptCollector()
        laser = got.get("/laser")
        for ch in CHANNELS:
            if ch not in got:
                continue
            rec = self.decode(ch, got[ch][1])
            if not isinstance(rec, dict) or not isinstance(rec.get("xml"), str):
                raise InputError(f"a message on {ch} is not a homesim.BusMessage", source=str(self.path))
            attachments = {}
            if ch == "/robot/laser/scan" and laser is not None and laser[0] == got[ch][0]:
                attachments["ranges"] = np.asarray(self.decode("/laser", laser[1])["ranges"], dtype=float)
            seen(SimpleNamespace(channel=ch, xml=parse_bytes(rec["xml"], source=f"{self.path}:{ch}"), created=float(rec.get("created", 0.0)),
                                 attachments=attachments))
        return world, seen.percepts(t, world.robot.pose), world.time


@contextmanager
def as_trace(path: str | os.PathLike[str]) -> Iterator[Path]:
    """``path`` itself for a JSON Lines trace; for a recording, its trace written to a temporary file."""
    if not is_mcap(path):
        yield Path(path)
        return
    import tempfile

    with Recording(path) as rec, tempfile.TemporaryDirectory(prefix="homesim-trace-") as d:
        out = Path(d) / (Path(path).stem + ".jsonl")
        with open(out, "w", encoding="utf-8", newline="\n") as fh:
            for line in rec.trace_lines():
                fh.write(line + "\n")
        yield out


# ------------------------------------------------------------ the world
class _Person:
    def __init__(self, d: dict[str, Any]) -> None:
        self.name = d["name"]
        self.present = bool(d["present"])
        self.position = (float(d["x"]), float(d["y"]))
        self.heading = float(d["heading"])
        self.gaze = float(d["gaze"])
        self.height = float(d["height"])
        self.torso = tuple(d["torso"])
        self._legs = np.asarray(d["legs"], dtype=float)
        self.pointing = None if d.get("pointing") is None else SimpleNamespace(target=tuple(d["pointing"]))
        self.saying = d.get("saying")

    def leg_centres(self) -> np.ndarray:
        return self._legs

    def hand_point(self) -> tuple[float, float, float] | None:
        return None if self.pointing is None else self.pointing.target


class _Robot:
    def __init__(self, d: dict[str, Any]) -> None:
        self.pose = (float(d["x"]), float(d["y"]), float(d["theta"]))

    def world_point(self, forward: float, left: float = 0.0) -> tuple[float, float]:
        x, y, th = self.pose
        c, s = math.cos(th), math.sin(th)
        return x + c * forward - s * left, y + s * forward + c * left


class _Sound:
    def __init__(self, saying: dict[str, str]) -> None:
        self.saying = saying

    def speaking(self, name: str, t: float) -> Any:
        text = self.saying.get(name)
        return None if text is None else SimpleNamespace(text=text)


class RecordedWorld:
    """The world as :func:`homesim.viz.plot_moment` reads it, rebuilt from a recording's map and world state."""

    def __init__(self, flat: dict[str, Any], state: dict[str, Any]) -> None:
        try:
            self.scenario = SimpleNamespace(name=flat["scenario"], rooms=[SimpleNamespace(name=r["name"], polygon=r["polygon"]) for r in flat["rooms"]])
            self._bounds = tuple(float(b) for b in flat["bounds"])
            self.obstacles = [Obstacle(o["name"], o["kind"], np.asarray(o["polygon"], dtype=float), float(o["bottom"]), float(o["top"]))
                              for o in flat["obstacles"]]
            self.objects = {o["name"]: SimpleNamespace(x=o["x"], y=o["y"], size=o["size"], colour=tuple(o["colour"])) for o in flat["objects"]}
            self.time = float(state["t"])
            r = state["robot"]
            self.robot = _Robot(r)
            self.ptu = (float(r["pan"]), float(r["tilt"]))
            self.humans = {p["name"]: _Person(p) for p in state["people"]}
            self.sources = {s["name"]: (float(s["x"]), float(s["y"]), float(s["z"])) for s in state["sources"]}
            saying = {p["name"]: p["saying"] for p in state["people"] if p.get("saying")}
            saying.update({s["name"]: s["saying"] for s in state["sources"] if s.get("saying")})
        except (KeyError, TypeError, ValueError) as exc:
            raise InputError(f"a map or world state the recording holds is malformed ({type(exc).__name__}: {exc})") from None
        self.sound = _Sound(saying)

    def bounds(self) -> tuple[float, float, float, float]:
        return self._bounds  # type: ignore[return-value]

    def segments_at(self, z: float) -> tuple[np.ndarray, np.ndarray]:
        """Edges (a, b) of every obstacle whose vertical extent contains height ``z`` (as the world's)."""
        from ..geometry import polygon_edges

        pairs = [polygon_edges(o.polygon) for o in self.obstacles if o.bottom <= z <= o.top]
        if not pairs:
            return np.zeros((0, 2)), np.zeros((0, 2))
        return np.concatenate([p[0] for p in pairs]), np.concatenate([p[1] for p in pairs])
