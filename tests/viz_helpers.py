"""A short recorded home tour shared by the viz and export tests (recorded once per session)."""

from __future__ import annotations

from pathlib import Path

from homesim.cli import main

ROOT = Path(__file__).resolve().parents[1]
_made: dict[tuple[Path, float], Path] = {}


def tour_trace(base: Path, until: float = 12.0) -> Path:
    """The trace of ``scenarios/home_tour.xml`` run to ``until`` s (written under ``base`` once)."""
    key = (base, until)
    if key not in _made:
        trace = base / f"home_tour_{until:g}.jsonl"
        assert main(["run", str(ROOT / "scenarios/home_tour.xml"), "--until", f"{until:g}", "--quiet", "--trace", str(trace)]) == 0
        _made[key] = trace
    return _made[key]
