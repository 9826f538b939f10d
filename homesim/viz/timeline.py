"""The papers' Fig. 6: the time course of module communication, drawn from a trace.

One horizontal lane per module, grouped by the host it ran on (the run's
deployment; within a host sensors first, then by causal depth,
:func:`homesim.traceview.read_timeline`), time to the right. Messages over the
slow links (slower than the LAN: with the papers' deployment the WLAN) are
dashed and labelled with their latency, the legend naming the links; spans are
coloured by what they measure (speech detection, speech recognition, an event's
wait in the ES's queue, the ES's reconfiguration, other processing). A message is
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

from collections import Counter

from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import FancyArrowPatch, Patch, Rectangle
from matplotlib.text import Text

from ..traceview import Message, Timeline
from .placing import place_clear

EVENT = "#1f3b73"
REPLY = "#2ca02c"
STREAM = "#b0b0b0"
SPAN = "#f0a030"
PHASE = "#c0392b"
SLOW = "#8e44ad"
#: Span colours by what they measure (traceview.Span.kind).
SPAN_COLOURS = {"speech detection": "#9ecae1", "speech recognition": "#3182bd",
                "ES queue (waiting)": "#fdd9b5", "ES reconfiguration": "#e6550d",
                "robot speech": "#74c476", "processing": SPAN}
#: What a span kind measures, where its name does not say it (the legend).
SPAN_NOTES = {"processing": " (cause delivered -> message sent)",
              "ES queue (waiting)": " (event delivered -> decided: held until older events can no longer arrive)"}
#: At most this many event arrows are labelled (the rarest channels first: a word said before the 20th attention state).
LABEL_EVENTS = 60
#: Label a span with its duration from this length on (seconds).
LABEL_SPAN_S = 0.02
#: A burst: at least ``REPEAT_MIN`` events of one channel in a row, each at most ``REPEAT_GAP`` s after the one before.
#: Judged locally (not by the channel's average rate over the window, which a few bursts in a long run never reach):
#: a burst's arrows are drawn light and only its first is labelled (it does not eat the label budget).
REPEAT_MIN = 5
REPEAT_GAP = 2.0
REPEAT = "#7f93b8"


def slow_key(links: tuple[str, ...]) -> str:
    """The legend's line for the dashed arrows: the slow links by name (slowest first)."""
    if len(links) == 1:
        return f"over the slowest link ({links[0]}), with its latency"
    return f"over a slow link ({links[0]}, the slowest; {', '.join(links[1:])}), with its latency"


def _ms(d: float) -> str:
    return f"{d * 1000:.0f} ms" if d < 1.0 else f"{d:.2f} s"


def repeating(events: list[Message]) -> tuple[set[str], set[str]]:
    """Ids of the events in a burst (periodic attention states, object focus while teaching) and of each burst's first.

    ``events`` in send order. A channel that is quiet for most of a run and
    sends ten messages in two seconds repeats there, and only there.
    """
    runs: dict[tuple[str, str], list[Message]] = {}
    inside: set[str] = set()
    firsts: set[str] = set()

    def close(run: list[Message]) -> None:
        if len(run) >= REPEAT_MIN:
            inside.update(m.id for m in run)
            firsts.add(run[0].id)

    for m in events:
        k = (m.sender, m.channel)
        run = runs.get(k)
        if run and m.t - run[-1].t > REPEAT_GAP:
            close(run)
            run = None
        if run is None:
            run = runs[k] = []
        run.append(m)
    for run in runs.values():
        close(run)
    return inside, firsts


def _to_label(events: list[Message], inside: set[str], firsts: set[str]) -> set[str]:
    """Ids of the event arrows to label: each burst's first, then the rarest channels' other events, to the budget."""
    rest = [m for m in events if m.id not in inside]
    chosen = set(firsts)
    per_channel = Counter((m.sender, m.channel) for m in rest)
    budget = max(LABEL_EVENTS - len(chosen), 0)
    for m in sorted(rest, key=lambda m: (per_channel[(m.sender, m.channel)], m.t))[:budget]:
        chosen.add(m.id)
    return chosen


def _stack_labels(ax: Axes, texts: list[Text], base: float) -> None:
    """Put texts (in time order) into rows above ``base`` (data y) so that none overlaps another.

    Rows are chosen by the texts' pixel extents along x (fixed once the layout
    is); the figure grows taller when the rows need more room than the axes
    have, and the y limit is raised so that every row fits inside the axes.
    """
    if not texts:
        return
    fig = ax.figure
    renderer = fig.canvas.get_renderer()
    ends: list[float] = []  # each row's right edge (pixels)
    rows: list[int] = []
    height = 0.0
    for txt in texts:
        bb = txt.get_window_extent(renderer)
        height = max(height, bb.height)
        row = next((i for i, e in enumerate(ends) if bb.x0 > e + 3), len(ends))
        if row == len(ends):
            ends.append(bb.x1)
        else:
            ends[row] = bb.x1
        rows.append(row)
    pitch = height + 4  # pixels per row
    need = len(ends) * pitch
    axes_px = ax.get_window_extent(renderer).height
    if need > axes_px / 3:  # more rows than a third of the axes: the figure grows by what they need
        w, h = fig.get_size_inches()
        fig.set_size_inches(w, h + (3 * need - axes_px) / fig.dpi / 2)
        axes_px = ax.get_window_extent(renderer).height
    bottom = ax.get_ylim()[0]
    k = need / axes_px  # the rows' share of the axes height
    top = (base - bottom * k + 0.1) / (1 - k)  # top - base = k * (top - bottom), plus a little air
    ax.set_ylim(bottom, top)
    step = pitch * (top - bottom) / axes_px
    for txt, row in zip(texts, rows):
        txt.set_y(base + step * row)


def plot_timeline(tl: Timeline, *, width: float = 14.0) -> Figure:
    """The Fig. 6 picture of ``tl`` (one lane per module, messages, spans, phases)."""
    lanes = tl.lanes
    y = {name: len(lanes) - 1 - i for i, name in enumerate(lanes)}
    fig = Figure(figsize=(width, 1.2 + 0.42 * max(len(lanes), 3)))
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(1, 1, 1)
    dur = tl.end - tl.start
    ax.set_xlim(tl.start - dur * 0.01, tl.end + dur * 0.01)
    ax.set_ylim(-0.8, len(lanes) + 0.5)
    for name, yy in y.items():
        ax.axhline(yy, color="#dddddd", linewidth=0.8, zorder=0)
    min_w = dur / 600  # a zero-length span still shows
    # Lanes grouped by host (the run's deployment): a band, a rule between groups and the host's name per group.
    groups: dict[str, list[float]] = {}
    rules: list[Line2D] = []  # the rules between host groups: labels keep off them (a latency label sat on one)
    for name, yy in y.items():
        groups.setdefault(tl.hosts.get(name, ""), []).append(yy)
    for i, (host, ys) in enumerate(groups.items()):
        if not host:
            continue
        if i % 2 == 0:
            ax.axhspan(min(ys) - 0.5, max(ys) + 0.5, color="#f4f4fa", zorder=0)
        if i:
            rules.append(ax.axhline(max(ys) + 0.5, color="#9999bb", linewidth=0.8, zorder=1))
        ax.text(1.004, (min(ys) + max(ys)) / 2, host, transform=ax.get_yaxis_transform(), rotation=90, va="center", ha="left",
                fontsize=8, fontweight="bold", color="#555577")
    renderer = fig.canvas.get_renderer()
    span_texts: list[Text] = []
    for s in tl.spans:
        if s.lane not in y:
            continue
        x0 = max(s.start, tl.start)  # a span begun before the window is drawn from its edge ...
        x1 = min(s.end, tl.end)  # ... and one that goes on after it to its edge
        if x1 < x0:
            continue
        w = max(x1 - x0, min_w)
        ax.add_patch(Rectangle((x0, y[s.lane] - 0.18), w, 0.36, facecolor=SPAN_COLOURS.get(s.kind, SPAN),
                               edgecolor="#555555", linewidth=0.4, zorder=3))
        if s.end - s.start >= LABEL_SPAN_S and w / dur > 0.004:
            txt = ax.text(x0 + w / 2, y[s.lane] - 0.22, _ms(s.end - s.start) + ("\u2192" if s.end > tl.end else ""), ha="center", va="top",
                          fontsize=6, color="#8a520c", zorder=6)
            span_texts.append(txt)  # kept or dropped once the layout has fixed the axes (below)
    events = [m for m in tl.messages if not m.continuous]
    burst, burst_firsts = repeating(events)
    label = _to_label(events, burst, burst_firsts)
    labels: list[Text] = []
    latencies: list[Text] = []
    for m in tl.messages:
        if m.sender not in y:
            continue
        rep = m.id in burst
        colour = STREAM if m.continuous else REPEAT if rep else (REPLY if m.kind in ("reply", "error") else EVENT)
        light = m.continuous or rep
        for r, td in m.delivered.items():
            if r not in y or r == m.sender:
                continue
            slow = not light and tl.crosses_slow_link(m.sender, r)
            ax.add_patch(FancyArrowPatch((m.t, y[m.sender]), (td, y[r]), arrowstyle="-|>", mutation_scale=6 if light else 8,
                                         color=SLOW if slow else colour, linewidth=0.5 if light else 0.9,
                                         linestyle="--" if slow else "-",
                                         alpha=0.45 if m.continuous else 0.7 if rep else 0.9, zorder=2 if m.continuous else 3 if rep else 4))
            if slow and m.id in label:  # the latency over a slow link (the WLAN), at the arrow's middle
                latencies.append(ax.text((m.t + td) / 2, (y[m.sender] + y[r]) / 2, _ms(td - m.t) if td - m.t >= 0.001 else "<1 ms",
                        fontsize=5.5, color=SLOW, ha="center", va="center", zorder=7,
                        bbox={"facecolor": "white", "edgecolor": "none", "alpha": 0.7, "pad": 0.3}))
        if m.id in label:
            text = m.label if len(m.label) <= 32 else m.label[:31] + "\u2026"
            if rep:
                text += " (repeats)"
            labels.append(ax.text(m.t, y[m.sender] + 0.12, text, fontsize=5.5, ha="left", va="bottom", color=colour, zorder=7,
                                  bbox={"facecolor": "white", "edgecolor": "none", "alpha": 0.7, "pad": 0.5}))
    phase_texts = []
    for p in tl.phases:
        ax.axvline(p.t, color=PHASE, linestyle="--", linewidth=0.8, zorder=1)
        phase_texts.append(ax.text(p.t, len(lanes) - 0.45, f"{p.mark}: {p.label}", color=PHASE, fontsize=7, ha="left", va="bottom", zorder=7,
                                   bbox={"facecolor": "white", "edgecolor": "none", "alpha": 0.8, "pad": 0.3}))
    ax.set_yticks(list(y.values()), list(y.keys()), fontsize=7)
    ax.set_xlabel("virtual time [s]")
    ax.set_title(f"{tl.scenario} (seed {tl.seed}): module communication, {tl.start:g}-{tl.end:g} s "
                 f"({len(events)} messages, {len(tl.spans)} processing spans)", fontsize=9)
    # The legend names what this picture shows (a window without a burst does not promise "(repeats)" labels).
    keys = [(Line2D([], [], color=EVENT, marker=">", markersize=4), "message (sender -> receiver, send -> delivery)"),
            *([(Line2D([], [], color=SLOW, marker=">", markersize=4, linestyle="--"), slow_key(tl.slow_links))] if tl.slow_links else []),
            (Line2D([], [], color=REPLY, marker=">", markersize=4), "RPC reply")]
    if burst:
        keys.append((Line2D([], [], color=REPEAT, marker=">", markersize=4),
                     f"repeating ({REPEAT_MIN}+ in a row, < {REPEAT_GAP:g} s apart; first labelled \"(repeats)\")"))
    keys.append((Line2D([], [], color=STREAM, marker=">", markersize=4), "continuous stream (thinned)"))
    keys += [(Patch(facecolor=c, edgecolor="#555555"), k + SPAN_NOTES.get(k, "")) for k, c in SPAN_COLOURS.items()]
    keys.append((Line2D([], [], color=PHASE, linestyle="--"), "phase"))
    ax.legend([h for h, _ in keys], [t for _, t in keys], loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=7, frameon=False)
    fig.tight_layout()
    # Phase marks kept apart, in as many rows as they need (measured after the layout fixed the axes' width).
    right = ax.get_window_extent(fig.canvas.get_renderer()).x1
    for txt in phase_texts:  # a mark near the window's end reads to the left of its line (not out of the axes)
        if txt.get_window_extent(fig.canvas.get_renderer()).x1 > right:
            txt.set_horizontalalignment("right")
    _stack_labels(ax, phase_texts, len(lanes) - 0.45)
    # A span's duration only where it covers no other's (measured now that the layout is fixed).
    span_boxes: list = []
    kept: list[Text] = []
    renderer = fig.canvas.get_renderer()  # the figure may have grown: its renderer now
    frame = ax.get_window_extent(renderer)
    for txt in span_texts:
        bb = txt.get_window_extent(renderer)
        if bb.x0 < frame.x0 or bb.x1 > frame.x1 or any(bb.x0 <= o.x1 + 2 and o.x0 <= bb.x1 + 2 and bb.y0 <= o.y1 and o.y0 <= bb.y1 for o in span_boxes):
            txt.remove()
        else:
            span_boxes.append(bb)
            kept.append(txt)
    # message and latency labels off each other and inside the axes (not over the y axis or the host names);
    # arrows are everywhere in a timeline, so labels keep off labels and the rules between host bands only
    # (their white boxes keep them legible over arrows; over a rule they hid where one host ends)
    place_clear(ax, labels + latencies, avoid_marks=rules, avoid=phase_texts + kept)
    return fig
