"""The study's social-navigation table: the ``social`` metric of every run, aggregated per condition.

Issue 26 asks for what the social-navigation benchmarks report (SocNavBench; Francis et al.,
2023) in the study table too, not only in each run's summary (:mod:`homesim.tour.metrics.social`
defines each figure). Per condition, over the runs that measured it:

* collisions: runs with a contact with a person / with the flat, and the contacts in all;
* the closest any person came (centre to centre, the smallest over the runs, and the median of
  the runs' minima) and the median time inside someone's personal space (s per run);
* following: the median path ratio (robot / partner path);
* go-to: episodes, the share reaching the goal, the median path and time ratios against the
  shortest path;
* identity: runs with an identity switch, and the share of runs that kept their partner.

A figure no run measured is "-". Rows are the run rows of :func:`homesim.tour.study.study`
(their ``metrics`` flattened, e.g. ``social.following.path_ratio``).
"""

from __future__ import annotations

import statistics
from collections.abc import Iterable
from typing import Any

Row = dict[str, Any]


def _values(rows: Iterable[Row], key: str) -> list[float]:
    return [float(r["metrics"][key]) for r in rows if key in r.get("metrics", {})]


def _median(xs: list[float]) -> float | None:
    return round(statistics.median(xs), 3) if xs else None


def social_navigation(rows: list[Row], conditions: list[str]) -> dict[str, dict[str, Any]]:
    """Per condition, the aggregated social-navigation figures (see the module docstring)."""
    out: dict[str, dict[str, Any]] = {}
    for cond in conditions:
        rs = [r for r in rows if r.get("condition") == cond and "social.time_s" in r.get("metrics", {})]
        people = _values(rs, "social.collisions_people")
        flat = _values(rs, "social.collisions_flat")
        closest = _values(rs, "social.min_person_distance_m")
        switches = _values(rs, "social.identity_switches")
        kept = _values(rs, "social.partner_kept")
        episodes = _values(rs, "social.goto.episodes")
        reached = sum(r["metrics"]["social.goto.episodes"] * r["metrics"].get("social.goto.success_rate", 0.0)
                      for r in rs if "social.goto.episodes" in r["metrics"])
        out[cond] = {
            "runs": len(rs),
            "runs_touching_people": sum(x > 0 for x in people),
            "contacts_people": int(sum(people)),
            "runs_touching_flat": sum(x > 0 for x in flat),
            "contacts_flat": int(sum(flat)),
            "closest_person_m": round(min(closest), 3) if closest else None,
            "closest_person_median_m": _median(closest),
            "personal_space_median_s": _median(_values(rs, "social.personal_space_s")),
            "following_path_ratio_median": _median(_values(rs, "social.following.path_ratio")),
            "goto_episodes": int(sum(episodes)),
            "goto_success_rate": round(reached / sum(episodes), 3) if sum(episodes) else None,
            "goto_path_ratio_median": _median(_values(rs, "social.goto.path_ratio")),
            "goto_time_ratio_median": _median(_values(rs, "social.goto.time_ratio")),
            "runs_with_identity_switch": sum(x > 0 for x in switches),
            "partner_kept_share": round(sum(kept) / len(kept), 3) if kept else None,
        }
    return out


LABELS = (
    ("runs", "runs measured"),
    ("runs_touching_people", "runs with a contact with a person"),
    ("contacts_people", "contacts with people, all runs"),
    ("runs_touching_flat", "runs with a contact with the flat"),
    ("contacts_flat", "contacts with walls and furniture, all runs"),
    ("closest_person_m", "closest any person came (m, centre to centre)"),
    ("closest_person_median_m", "median of each run's closest person (m)"),
    ("personal_space_median_s", "median time inside someone's personal space (s, < 0.45 m body to body)"),
    ("following_path_ratio_median", "following: median path ratio (robot / partner)"),
    ("goto_episodes", "go-to episodes"),
    ("goto_success_rate", "go-to: share reaching the goal"),
    ("goto_path_ratio_median", "go-to: median path ratio (driven / shortest)"),
    ("goto_time_ratio_median", "go-to: median time ratio (time / shortest at top speed)"),
    ("runs_with_identity_switch", "runs with a partner identity switch"),
    ("partner_kept_share", "share of runs that kept their partner (no switch, no loss)"),
)


def social_table(figures: dict[str, dict[str, Any]], conditions: list[str]) -> str:
    """The figures as a Markdown table, one column per condition."""
    lines = ["| social navigation | " + " | ".join(conditions) + " |", "|" + "---|" * (len(conditions) + 1)]
    for key, label in LABELS:
        cells = []
        for c in conditions:
            v = figures.get(c, {}).get(key)
            cells.append("-" if v is None else str(v))
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"
