"""The study's social-navigation table (issue 26): each run summary's ``social`` figures, aggregated per condition."""

from __future__ import annotations

import statistics

from hypothesis import given, settings, strategies as st

from homesim.tour.socialtable import LABELS, social_navigation, social_table


def _row(cond: str, **m: float) -> dict:
    metrics = {"social.time_s": 100.0}
    metrics.update({f"social.{k.replace('__', '.')}": float(v) for k, v in m.items()})
    return {"condition": cond, "metrics": metrics}


def test_contacts_closest_person_and_go_to_success_are_aggregated_per_condition():
    rows = [
        _row("a", collisions_people=2, collisions_flat=0, min_person_distance_m=0.6, identity_switches=0, partner_kept=1,
             goto__episodes=2, goto__success_rate=0.5, goto__path_ratio=1.2, following__path_ratio=1.1, personal_space_s=3),
        _row("a", collisions_people=0, collisions_flat=1, min_person_distance_m=1.4, identity_switches=1, partner_kept=0,
             goto__episodes=1, goto__success_rate=1.0, goto__path_ratio=1.4, personal_space_s=1),
        _row("b", collisions_people=0, collisions_flat=0, min_person_distance_m=2.0, identity_switches=0, partner_kept=1),
        {"condition": "b", "metrics": {}},  # a run that measured nothing (an error) is not counted
    ]
    f = social_navigation(rows, ["a", "b"])
    a, b = f["a"], f["b"]
    assert a["runs"] == 2 and a["runs_touching_people"] == 1 and a["contacts_people"] == 2
    assert a["runs_touching_flat"] == 1 and a["contacts_flat"] == 1
    assert a["closest_person_m"] == 0.6 and a["closest_person_median_m"] == 1.0
    assert a["goto_episodes"] == 3 and a["goto_success_rate"] == round(2 / 3, 3)  # 1 of 2, then 1 of 1
    assert a["goto_path_ratio_median"] == 1.3 and a["following_path_ratio_median"] == 1.1
    assert a["runs_with_identity_switch"] == 1 and a["partner_kept_share"] == 0.5
    assert b["runs"] == 1 and b["goto_episodes"] == 0 and b["goto_success_rate"] is None
    text = social_table(f, ["a", "b"])
    assert "| go-to: share reaching the goal | 0.667 | - |" in text
    assert len(text.strip().splitlines()) == 2 + len(LABELS)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 3), st.integers(0, 3), st.floats(0.3, 5.0)), min_size=1, max_size=12))
def test_the_table_counts_every_contact_once_and_takes_the_true_minimum(runs):
    rows = [_row("c", collisions_people=p, collisions_flat=w, min_person_distance_m=d) for p, w, d in runs]
    f = social_navigation(rows, ["c"])["c"]
    assert f["runs"] == len(runs)
    assert f["contacts_people"] == sum(p for p, _, _ in runs) and f["contacts_flat"] == sum(w for _, w, _ in runs)
    assert f["runs_touching_people"] == sum(p > 0 for p, _, _ in runs) <= f["runs"]
    assert f["closest_person_m"] == round(min(d for _, _, d in runs), 3)
    assert f["closest_person_median_m"] == round(statistics.median(d for _, _, d in runs), 3)
