"""Saving a figure: the same figure gives the same bytes (no dates, fixed SVG ids)."""

from __future__ import annotations

from pathlib import Path


def save(fig, out: Path) -> None:  # noqa: ANN001 (a matplotlib Figure)
    """Save a figure as PNG or SVG; the same figure gives the same bytes (no dates, fixed SVG ids)."""
    import matplotlib

    with matplotlib.rc_context({"svg.hashsalt": "homesim"}):
        fig.savefig(out, dpi=120, metadata={"Software": None} if out.suffix.lower() == ".png" else {"Date": None, "Creator": None})
