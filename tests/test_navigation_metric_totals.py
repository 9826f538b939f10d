"""The navigation metric's totals over every go-to equal the figures of the whole list of
go-tos, while it lists only the first MAX_GOTOS (a run's memory does not grow with its length)."""

from __future__ import annotations

from types import SimpleNamespace

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import homesim.tour.metrics.navigation as nav
from tests.conftest import examples

maybe = st.one_of(st.none(), st.floats(0.0, 50.0))
episodes = st.lists(st.fixed_dictionaries({
    "outcome": st.sampled_from(["reached", "failed: blocked", "replanned", "cancelled"]),
    "time": st.floats(0.0, 100.0), "path_length": st.floats(0.0, 30.0),
    "ratio": maybe, "goal_error": maybe, "closest_person": maybe, "speed_near_person_max": st.floats(0.0, 1.0),
    "collisions": st.integers(0, 3), "replans": st.integers(0, 5), "replans_found": st.integers(0, 5),
}), max_size=12)


def whole_list_summary(eps):
    """The reference: the figures computed over the whole list of go-tos."""
    def worst(key, pick):
        vals = [e[key] for e in eps if e[key] is not None]
        return pick(vals) if vals else None

    return {
        "goto": list(eps), "episodes": len(eps),
        "reached": sum(e["outcome"] == "reached" for e in eps),
        "failed": sum(e["outcome"].startswith("failed") for e in eps),
        "time_s": round(sum(e["time"] for e in eps), 3),
        "path_length_m": round(sum(e["path_length"] for e in eps), 3),
        "ratio_max": worst("ratio", max), "goal_error_max_m": worst("goal_error", max),
        "closest_person_m": worst("closest_person", min),
        "speed_near_person_max": worst("speed_near_person_max", max),
        "replans": sum(e["replans"] for e in eps), "replans_found": sum(e["replans_found"] for e in eps),
        "collisions": sum(e["collisions"] for e in eps),
    }


def _metric(eps):
    m = nav.Navigation(SimpleNamespace(world=None))
    for e in eps:
        m._record(e)
    return m


@settings(max_examples=examples(60, 200), deadline=None)
@given(eps=episodes)
def test_running_totals_are_the_whole_lists_figures(eps):
    got = _metric(eps).summary()
    want = whole_list_summary(eps)
    assert got == want and [type(v) for v in got.values()] == [type(v) for v in want.values()]


@settings(max_examples=examples(20, 60), deadline=None)
@given(eps=episodes.filter(lambda e: len(e) > 3))
def test_a_long_run_lists_the_first_go_tos_and_counts_them_all(eps):
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(nav, "MAX_GOTOS", 3)
        got = _metric(eps).summary()
    want = whole_list_summary(eps)
    assert got.pop("goto") == eps[:3] and got.pop("goto_dropped") == len(eps) - 3
    want.pop("goto")
    assert got == want
