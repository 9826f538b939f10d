"""A study's per-capability rates with their 95 % intervals, one bar per condition (PNG or SVG).

Reads the ``study.json`` document (:mod:`homesim.tour.study`): for each capability
a horizontal bar of the pass rate with the Wilson interval as an error bar and the
number of runs next to it; conditions side by side. Uses matplotlib's object API
(no pyplot state), so it is safe in worker processes and tests.
"""

from __future__ import annotations

import textwrap
from pathlib import Path
from typing import Any

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.backends.backend_svg import FigureCanvasSVG
from matplotlib.figure import Figure

COLOURS = ("#3b75af", "#ef8636", "#519e3e", "#c53a32", "#8d69b8", "#84584e")


def plot_rates(doc: dict[str, Any], path: str | Path) -> Path:
    """Draw the rates of ``doc`` (a study.json) into ``path`` (.png or .svg); returns the path."""
    path = Path(path)
    fig = rates_figure(doc)
    canvas = FigureCanvasSVG(fig) if path.suffix.lower() == ".svg" else FigureCanvasAgg(fig)
    path.parent.mkdir(parents=True, exist_ok=True)
    if path.suffix.lower() == ".svg":
        canvas.print_svg(str(path), metadata={"Date": None})  # no date: same study, same file
    else:
        canvas.print_png(str(path), metadata={"Software": None})
    return path


#: Legend text per row of the figure (7.5 in wide, 8 pt type: about 100 characters with the
#: colour patches and gaps); a longer condition name is wrapped onto lines of WRAP characters
#: (after a comma between options where it can).
LEGEND_CHARS = 110
WRAP = 48


def legend_layout(conditions: list[str]) -> tuple[list[str], int]:
    """Legend labels (long names wrapped) and the number of columns that fit the figure's width,
    so that with many or long condition names the legend takes more rows instead of being clipped."""
    labels = [textwrap.fill(c.replace(",", ", "), WRAP, break_on_hyphens=False).replace(", ", ",") if len(c) > WRAP else c
              for c in conditions]
    widest = max((max(len(line) for line in lb.split("\n")) for lb in labels), default=1)
    per_entry = widest + 6  # the colour patch and the gap to the next entry, in characters
    return labels, max(1, min(len(labels), 4, LEGEND_CHARS // per_entry))


def rates_figure(doc: dict[str, Any]) -> Figure:
    """The figure of :func:`plot_rates` (a legend of the conditions above the axes when there are several)."""
    conditions = list(doc["study"]["conditions"])
    rows = [("every expectation", doc["overall"])] + list(doc["capabilities"].items())
    n, k = len(rows), max(1, len(conditions))
    names, ncols = legend_layout(conditions)
    legend_rows = -(-k // ncols)
    # constrained layout: the legend sits outside the axes, above them, so it never covers a bar,
    # an interval or a count (inside "lower right" it hid the bars of rates near 100 %)
    fig = Figure(figsize=(7.5, 0.5 + 0.42 * n * (1 + 0.35 * (k - 1)) + ((0.2 + 0.16 * legend_rows * max(nm.count("\n") + 1 for nm in names)) if k > 1 else 0)),
                 layout="constrained")
    ax = fig.add_subplot(1, 1, 1)
    height = 0.8 / k
    for j, cond in enumerate(conditions):
        ys, xs, lo, hi, labels = [], [], [], [], []
        for i, (_, cell) in enumerate(rows):
            c = cell["by_condition"].get(cond) if "by_condition" in cell else cell
            if not c or not c["runs"]:
                continue
            y = n - 1 - i + (k - 1) / 2 * height - j * height
            ys.append(y)
            xs.append(100 * c["rate"])
            lo.append(100 * (c["rate"] - c["ci95"][0]))
            hi.append(100 * (c["ci95"][1] - c["rate"]))
            labels.append(f"{c['passed']}/{c['runs']}")
        ax.barh(ys, xs, height=height * 0.9, color=COLOURS[j % len(COLOURS)], label=names[j], alpha=0.85)
        ax.errorbar(xs, ys, xerr=[lo, hi], fmt="none", ecolor="black", elinewidth=1, capsize=3)
        for y, label in zip(ys, labels):
            ax.text(101, y, label, va="center", fontsize=7)
    ax.set_yticks(range(n))
    ax.set_yticklabels([name for name, _ in reversed(rows)])
    ax.set_xlim(0, 112)
    ax.set_xlabel("runs passing (%), with 95 % Wilson interval")
    runs = doc["study"]["runs"]
    ns, nn = doc['study']['scenarios'], len(doc['study']['seeds'])
    ax.set_title(f"{ns} scenario{'s' * (ns != 1)} x {nn} seed{'s' * (nn != 1)}: {runs} runs", fontsize=10)
    if k > 1:
        fig.legend(loc="outside upper center", ncols=ncols, fontsize=8, frameon=False)
    ax.grid(axis="x", alpha=0.3)
    return fig
