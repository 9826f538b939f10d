"""Stepping a run event by event, in a notebook: to the next message, the next on a channel, the next transition.

:class:`Stepper` steps a *live* run (:class:`homesim.tour.runner.Run`): ``next()`` runs the
virtual loop only until the bus has sent another message and returns it as a :class:`Step`
(time, sender, channel, receivers, causes, the XML); ``next("/robot/es/status")`` skips to the
next message on that channel; ``next_transition()`` to the next transition the execution
supervisor applied. ``picture()`` draws the flat at that moment with the robot's percepts.

:class:`Cursor` steps a *recording* (``homesim run --record``) the same way, without running
anything, and :func:`interactive_view` puts a cursor behind ipywidgets: a time slider over the
flat and the module timeline, and buttons for the next message / on a channel / transition
(ipywidgets is optional: ``pip install 'homesim[notebook]'``).

Several messages can be sent in one scheduling round of the loop; the stepper hands them out
one at a time (the world is then at the end of that round). Memory is bounded by what one round
sends.
"""

from __future__ import annotations

import difflib
import io
import weakref
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from lxml import etree

from ..bus import DELIVER, DROP, SEND, Observation
from ..xmlio import parse_bytes
from .percepts import CHANNELS, PerceptCollector

ES_LOG = "/robot/es/log"


@dataclass(frozen=True)
class Step:
    """One bus message as the stepper shows it."""

    t: float
    seq: int
    kind: str
    sender: str
    channel: str
    receivers: tuple[str, ...]
    id: str
    causes: tuple[str, ...]
    xml: str

    def element(self) -> etree._Element:
        """The message's XML as an element (parsed with the hardened parser)."""
        return parse_bytes(self.xml, source=f"<{self.channel}>")

    def transition(self) -> tuple[str, str, str] | None:
        """(event, from state, to state) when this is a transition the supervisor applied, else None."""
        if self.channel != ES_LOG:
            return None
        x = self.element()
        if x.get("kind") != "applied":
            return None
        return str(x.get("name")), str(x.get("state")), str(x.get("to"))

    def __str__(self) -> str:
        to = ", ".join(self.receivers) or "nobody"
        head = f"t = {self.t:.6f} s  {self.kind} {self.channel}  {self.sender} -> {to}  ({self.id}"
        head += f"; caused by {', '.join(self.causes)})" if self.causes else ")"
        tr = self.transition()
        if tr is not None:
            head += f"\n  supervisor: {tr[1]} -> {tr[2]} on {tr[0]}"
        return head + "\n  " + self.xml


def is_transition(step: Step) -> bool:
    return step.transition() is not None


class UnknownChannel(ValueError):
    """A channel nothing in the run or recording uses (a typo): refused before stepping, naming the closest."""

    def __init__(self, channel: str, known: list[str], where: str) -> None:
        close = difflib.get_close_matches(channel, known, n=3, cutoff=0.5)
        hint = f"; did you mean {' or '.join(close)}?" if close else ""
        super().__init__(f"no channel {channel!r} in {where}{hint}")


def _matches(channel: str, names: set[str]) -> bool:
    return channel in names or any(n.endswith("/**") and channel.startswith(n[:-2]) for n in names)


def run_channels(bus: Any) -> set[str]:
    """Every channel a run's modules publish on, subscribe to or declare, and every method (``server/method``)."""
    names = set(bus._channel_schemas)
    for p in bus.registry():
        names |= set(p["publishes"]) | set(p["subscribes"]) | {f"{p['name']}/{m}" for m in p["methods"]}
    return names


class Stepper:
    """Steps a live run to its next bus message (see the module docstring).

    A step's ``seq`` is the trace's: every send, delivery and drop counts, as in the JSON Lines
    trace and a recording's (the stepper is made before the run runs, or the run has a trace).
    """

    observes = (SEND, DELIVER, DROP)

    def __init__(self, run: Any) -> None:
        self.run = run
        self.pending: deque[Step] = deque()
        self.current: Step | None = None
        self._active = False
        trace = getattr(run, "trace", None)
        self._seq = trace.seq if trace is not None else 0
        self.seen = PerceptCollector()
        run.dispatcher.add(CHANNELS, self.seen)
        run.sim.bus.add_interceptor(self)
        weakref.finalize(self, _detach, weakref.ref(run.sim.bus), self)

    def __call__(self, obs: Observation) -> None:
        self._seq += 1
        if not self._active or obs.event != SEND:
            return
        m = obs.message
        self.pending.append(Step(obs.t_ns / 1e9, self._seq, m.kind, m.sender, m.channel, tuple(obs.receivers), m.id, tuple(m.causes),
                                 etree.tostring(m.xml, encoding="unicode")))

    def next(self, channel: str | None = None, *, where: Callable[[Step], bool] | None = None, timeout: float = 60.0) -> Step | None:
        """Run to the next message (on ``channel``, and for which ``where`` holds, if given) within ``timeout``
        virtual seconds and the run's end; return it (also as :attr:`current`), or None when none came."""
        sim = self.run.sim
        if channel is not None:
            known = run_channels(sim.bus)
            if not _matches(channel, known):  # a typo would otherwise run the live run to its end
                raise UnknownChannel(channel, sorted(n for n in known if not n.endswith("/**")), "this run (no module publishes, "
                                     "subscribes to or declares it)")
        # Messages of a round the user has since run past by hand are stale.
        while self.pending and self.pending[0].t < sim.now - 1e-9:
            self.pending.popleft()
        stop = min(sim.now + timeout, self.run.end)
        while True:
            while self.pending:
                s = self.pending.popleft()
                if (channel is None or s.channel == channel) and (where is None or where(s)):
                    self.current = s
                    return s
            left = stop - sim.now
            if left <= 0:
                return None
            self._active = True
            try:
                sim.run_until(lambda: bool(self.pending), timeout=left)
            finally:
                self._active = False
            if not self.pending:
                return None

    def next_transition(self, *, timeout: float = 60.0) -> Step | None:
        """Run to the next transition the execution supervisor applies (its log's ``applied`` records)."""
        return self.next(ES_LOG, where=is_transition, timeout=timeout)

    def show(self, step: Step | None = None) -> Step | None:
        """Print ``step`` (default: the current one) and return it."""
        step = self.current if step is None else step
        print(step if step is not None else "no message yet")
        return step

    def picture(self, **kw: Any) -> Any:
        """The flat now, with the robot's percepts over the truth (a matplotlib Figure)."""
        from ..viz.moment import plot_moment

        now = self.run.sim.now
        w = self.run.world
        title = f"{self.run.scenario.name} at t = {now:.3f} s" + (f" (after {self.current.channel})" if self.current else "")
        return plot_moment(w, percepts=self.seen.percepts(now, w.robot.pose), title=title, **kw)


def _detach(bus_ref: Any, stepper: Any) -> None:  # pragma: no cover - at garbage collection
    bus = bus_ref()
    if bus is not None and stepper in bus._interceptors:
        bus.remove_interceptor(stepper)


# ------------------------------------------------------------- recordings
class Cursor:
    """A position in a recording, stepped by message (no run: everything is read from the file)."""

    def __init__(self, path: str | Path) -> None:
        from .recorded import Recording

        self.rec = Recording(path)
        self.path = Path(path)
        self.start, self.end = self.rec.span()
        self.t = self.start
        self.current: Step | None = None
        # Which messages at time t are behind the cursor: those up to this trace seq (-1: none).
        self._seq = -1
        self._it: Any = None
        self.bus_channels = sorted(c[0] for c in self.rec.channels() if c[1] == "homesim.BusMessage")
        weakref.finalize(self, self.rec.close)

    def close(self) -> None:
        if self._it is not None:
            self._it.close()
            self._it = None
        self.rec.close()

    def seek(self, t: float) -> None:
        """Put the cursor at ``t``: the next message is the first sent at or after ``t``."""
        self.t = min(max(t, self.start), self.end)
        self.current = None
        self._seq = -1
        self._it = None

    def next(self, channel: str | None = None, *, where: Callable[[Step], bool] | None = None) -> Step | None:
        """The first bus message after the cursor (on ``channel``, for which ``where`` holds); the cursor moves there.

        Reads the recording's trace (``/homesim/trace``): its sequence numbers order the messages
        sent at one instant, so none is skipped or shown twice.
        """
        import json

        topic = None
        if channel is not None:
            topic = "/" + channel.lstrip("/")  # the recording's topic (a method's channel has no leading slash on the bus)
            if topic not in self.bus_channels:
                raise UnknownChannel(channel, self.bus_channels, str(self.path))
        if self._it is None:  # one reader pass, continued while the cursor moves forward
            self._it = self._lines()
        t_ns = round(self.t * 1e9)
        seq = self._seq
        for lt, line in self._it:
            if lt < t_ns:
                continue
            r = json.loads(line)
            if r.get("kind") not in ("publish", "request", "reply", "error") or (lt == t_ns and r["seq"] <= seq):
                continue
            if topic is not None and r["channel"] != channel and "/" + r["channel"].lstrip("/") != topic:
                continue
            s = Step(r["t"], r["seq"], r["kind"], r["sender"], r["channel"], tuple(r["receivers"]), r["id"], tuple(r["causes"]), r["xml"])
            if where is None or where(s):
                self.t, self.current, self._seq = s.t, s, s.seq
                return s
        self._it = None
        return None

    def next_transition(self) -> Step | None:
        return self.next(ES_LOG, where=is_transition)

    def _lines(self) -> Any:
        """(time ns, line) of the recording's trace from the first batch logged at or after the cursor (a batch is
        logged at its last line's time)."""
        import re

        from .recording import TRACE_CHANNEL

        t_of = re.compile(r'^\{"t":([^,]+),')
        for _, _, _, data in self.rec.messages([TRACE_CHANNEL], start=self.t):
            for raw in self.rec.trace_batch(data):
                m = t_of.match(raw)
                yield (round(float(m.group(1)) * 1e9) if m else 0), raw

    def picture(self, **kw: Any) -> Any:
        """The flat at the cursor, from the recording alone."""
        from ..viz.moment import plot_moment

        world, percepts, t = self.rec.moment(self.t)
        run = self.rec.run
        return plot_moment(world, percepts=percepts, title=f"{world.scenario.name} (seed {run.get('seed', '?')}) at t = {self.t:.3f} s", **kw)


def _png(fig: Any, dpi: int) -> bytes:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi)
    return buf.getvalue()


class InteractiveView:
    """The widgets of :func:`interactive_view` and what they show (kept as attributes for tests)."""

    def __init__(self, path: str | Path, *, window: float = 6.0, dpi: int = 70) -> None:
        import tempfile

        import ipywidgets as W

        from .recorded import as_trace

        self.cursor = Cursor(path)
        self.window = window
        self.dpi = dpi
        # The timeline reads a trace: the recording's, written once to a private file.
        self._tmp = tempfile.TemporaryDirectory(prefix="homesim-view-")
        self.trace = Path(self._tmp.name) / "trace.jsonl"
        with as_trace(path) as tr:
            self.trace.write_bytes(Path(tr).read_bytes())
        c = self.cursor
        self.slider = W.FloatSlider(value=c.t, min=c.start, max=c.end, step=0.1, description="t [s]", continuous_update=False,
                                    readout_format=".2f", layout=W.Layout(width="95%"))
        self.channel = W.Dropdown(options=["(any)"] + c.bus_channels, value="(any)", description="channel")
        self.buttons = {name: W.Button(description=name) for name in ("next message", "next transition")}
        self.text = W.HTML()
        self.flat = W.Image(format="png")
        self.timeline = W.Image(format="png")
        self.slider.observe(lambda ch: self._moved(ch["new"]), names="value")
        self.buttons["next message"].on_click(lambda _: self.step(None if self.channel.value == "(any)" else self.channel.value))
        self.buttons["next transition"].on_click(lambda _: self.step(transition=True))
        self.widget = W.VBox([self.slider, W.HBox([self.channel, *self.buttons.values()]), self.text, self.flat, self.timeline])
        self._drawing = False
        self.draw()

    def step(self, channel: str | None = None, *, transition: bool = False) -> Step | None:
        """Move to the next message (on ``channel``) or transition, and redraw."""
        s = self.cursor.next_transition() if transition else self.cursor.next(channel)
        if s is None:
            self.text.value = "<b>no further message</b>"
            return None
        self._drawing = True
        try:
            self.slider.value = round(s.t, 6)
        finally:
            self._drawing = False
        self.draw()
        return s

    def _moved(self, t: float) -> None:
        if self._drawing:
            return
        self.cursor.seek(t)
        self.draw()

    def draw(self) -> None:
        """Redraw the flat and the timeline (with a cursor line) at the cursor's time."""
        from html import escape

        from ..traceview import read_timeline
        from ..viz.timeline import plot_timeline

        c = self.cursor
        s = c.current
        self.text.value = f"<pre>{escape(str(s))}</pre>" if s is not None else f"<pre>t = {c.t:.3f} s</pre>"
        self.flat.value = _png(c.picture(size=6.0), self.dpi)
        lo = max(c.start, c.t - self.window / 2)
        hi = min(c.end, lo + self.window)
        tl = read_timeline(self.trace, start=lo, end=hi)
        fig = plot_timeline(tl, width=11.0)
        fig.axes[0].axvline(c.t, color="#d62728", linewidth=1.5, zorder=10)
        self.timeline.value = _png(fig, self.dpi)

    def close(self) -> None:
        self.cursor.close()
        self._tmp.cleanup()


def interactive_view(path: str | Path, **kw: Any) -> Any:
    """A time slider and step buttons over a recording's flat and timeline (an ipywidgets box; display it)."""
    try:
        import ipywidgets  # noqa: F401
    except ModuleNotFoundError as exc:
        raise ModuleNotFoundError("the interactive view needs ipywidgets: pip install 'homesim[notebook]'", name=exc.name) from exc
    return InteractiveView(path, **kw)
