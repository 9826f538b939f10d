"""Saving a figure: the same figure gives the same bytes (no dates, fixed SVG ids), SVG text kept as text."""

from __future__ import annotations

from pathlib import Path


def save(fig, out: Path) -> None:  # noqa: ANN001 (a matplotlib Figure)
    """Save a figure as PNG or SVG; the same figure gives the same bytes (no dates, fixed SVG ids).

    SVG text stays ``<text>`` (``svg.fonttype`` "none"): searchable, selectable
    and editable in a paper's figure, and a fraction of the size of glyph paths.
    """
    import matplotlib

    with matplotlib.rc_context({"svg.hashsalt": "homesim", "svg.fonttype": "none"}):
        fig.savefig(out, dpi=120, metadata={"Software": None} if out.suffix.lower() == ".png" else {"Date": None, "Creator": None})
