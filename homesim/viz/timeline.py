"""The papers' Fig. 6: the time course of module communication, drawn from a trace.

One horizontal lane per module, grouped by the host it ran on (the run's
deployment; within a host sensors first, then by causal depth,
:func:`homesim.traceview.read_timeline`), time to the right. Messages over the
slowest link (the WLAN) are dashed and labelled with their latency; spans are
coloured by what they measure (speech detection, speech recognition, the ES's
reconfiguration, other processing). A message is
an arrow from its sender's lane at the send time to each receiver's lane at
the delivery time; continuous streams (scans, odometry, tracks) are thinned
and drawn light grey, as the paper draws its brightening arrows; a
module's processing span (a cause delivered -> the message it caused sent)
is a bar on its lane, labelled with its duration when it is long enough to
read; phases (A start, B greeting, C follow request, D following, E stop,
T teaching, G good-bye) are vertical lines with their marks. Pure: takes a
:class:`~homesim.traceview.Timeline`, returns a ``Figure``.
"""

from __future__ import annotations

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import FancyArrowPatch, Patch, Rectangle

from ..traceview import Timeline
from .moment import place_labels

EVENT = "#1f3b73"
REPLY = "#2ca02c"
STREAM = "#b0b0b0"
SPAN = "#f0a030"
PHASE = "#c0392b"
SLOW = "#8e44ad"
#: Span colours by what they measure (traceview.Span.kind).
SPAN_COLOURS = {"speech detection": "#9ecae1", "speech recognition": "#3182bd", "ES reconfiguration": "#e6550d",
                "robot speech": "#74c476", "processing": SPAN}
#: Label event arrows only when the window holds at most this many events.
LABEL_EVENTS = 60
#: Label a span with its duration from this length on (seconds).
LABEL_SPAN_S = 0.02


def _ms(d: float) -> str:
    return f"{d * 1000:.0f} ms" if d < 1.0 else f"{d:.2f} s"


def plot_timeline(tl: Timeline, *, width: float = 14.0) -> Figure:
    """The Fig. 6 picture of ``tl`` (one lane per module, messages, spans, phases)."""
    lanes = tl.lanes
    y = {name: len(lanes) - 1 - i for i, name in enumerate(lanes)}
    fig = Figure(figsize=(width, 1.2 + 0.42 * max(len(lanes), 3)))
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(1, 1, 1)
    dur = tl.end - tl.start
    for name, yy in y.items():
        ax.axhline(yy, color="#dddddd", linewidth=0.8, zorder=0)
    min_w = dur / 600  # a zero-length span still shows
    # Lanes grouped by host (the run's deployment): a band and the host's name per group.
    groups: dict[str, list[float]] = {}
    for name, yy in y.items():
        groups.setdefault(tl.hosts.get(name, ""), []).append(yy)
    for i, (host, ys) in enumerate(groups.items()):
        if not host:
            continue
        if i % 2 == 0:
            ax.axhspan(min(ys) - 0.5, max(ys) + 0.5, color="#f4f4fa", zorder=0)
        ax.text(tl.end + dur * 0.012, (min(ys) + max(ys)) / 2, host, rotation=90, va="center", ha="left", fontsize=7,
                color="#555577")
    for s in tl.spans:
        if s.lane not in y:
            continue
        x0 = max(s.start, tl.start)  # a span begun before the window is drawn from its edge
        w = max(s.end - x0, min_w)
        ax.add_patch(Rectangle((x0, y[s.lane] - 0.18), w, 0.36, facecolor=SPAN_COLOURS.get(s.kind, SPAN),
                               edgecolor="#555555", linewidth=0.4, zorder=3))
        if s.end - s.start >= LABEL_SPAN_S and w / dur > 0.004:
            ax.text(x0 + w / 2, y[s.lane] - 0.22, _ms(s.end - s.start), ha="center", va="top", fontsize=6, color="#8a520c", zorder=6)
    events = [m for m in tl.messages if not m.continuous]
    label = len(events) <= LABEL_EVENTS
    labels = []
    for m in tl.messages:
        if m.sender not in y:
            continue
        colour = STREAM if m.continuous else (REPLY if m.kind in ("reply", "error") else EVENT)
        for r, td in m.delivered.items():
            if r not in y or r == m.sender:
                continue
            slow = not m.continuous and tl.crosses_slow_link(m.sender, r)
            ax.add_patch(FancyArrowPatch((m.t, y[m.sender]), (td, y[r]), arrowstyle="-|>", mutation_scale=6 if m.continuous else 8,
                                         color=SLOW if slow else colour, linewidth=0.5 if m.continuous else 0.9,
                                         linestyle="--" if slow else "-",
                                         alpha=0.45 if m.continuous else 0.9, zorder=2 if m.continuous else 4))
            if slow and label:  # the latency over the WLAN, at the arrow's middle
                ax.text((m.t + td) / 2, (y[m.sender] + y[r]) / 2, _ms(td - m.t) if td - m.t >= 0.001 else "<1 ms",
                        fontsize=5.5, color=SLOW, ha="center", va="center", zorder=7,
                        bbox={"facecolor": "white", "edgecolor": "none", "alpha": 0.7, "pad": 0.3})
        if label and not m.continuous:
            text = m.label if len(m.label) <= 32 else m.label[:31] + "\u2026"
            labels.append(ax.text(m.t, y[m.sender] + 0.12, text, fontsize=5.5, ha="left", va="bottom", color=colour, zorder=7,
                                  bbox={"facecolor": "white", "edgecolor": "none", "alpha": 0.7, "pad": 0.5}))
    for i, p in enumerate(tl.phases):
        ax.axvline(p.t, color=PHASE, linestyle="--", linewidth=0.8, zorder=1)
        ax.text(p.t, len(lanes) - 0.45 + 0.35 * (i % 2), f"{p.mark}: {p.label}", color=PHASE, fontsize=7, ha="left", va="bottom", zorder=7)
    ax.set_yticks(list(y.values()), list(y.keys()), fontsize=7)
    ax.set_ylim(-0.8, len(lanes) + 0.5)
    ax.set_xlim(tl.start - dur * 0.01, tl.end + dur * 0.01)
    ax.set_xlabel("virtual time [s]")
    ax.set_title(f"{tl.scenario} (seed {tl.seed}): module communication, {tl.start:g}-{tl.end:g} s "
                 f"({len(events)} messages, {len(tl.spans)} processing spans)", fontsize=9)
    ax.legend([Line2D([], [], color=EVENT, marker=">", markersize=4), Line2D([], [], color=SLOW, marker=">", markersize=4, linestyle="--"),
               Line2D([], [], color=REPLY, marker=">", markersize=4),
               Line2D([], [], color=STREAM, marker=">", markersize=4),
               *[Patch(facecolor=c, edgecolor="#555555") for c in SPAN_COLOURS.values()],
               Line2D([], [], color=PHASE, linestyle="--")],
              ["message (sender -> receiver, send -> delivery)", "over the slowest link (WLAN), with its latency",
               "RPC reply", "continuous stream (thinned)",
               *[k + (" (cause delivered -> message sent)" if k == "processing" else "") for k in SPAN_COLOURS], "phase"],
              loc="upper left", bbox_to_anchor=(1.005, 1.0), fontsize=7, frameon=False)
    fig.tight_layout()
    place_labels(ax, labels)  # message labels moved off each other
    return fig
