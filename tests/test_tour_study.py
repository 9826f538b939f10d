"""``homesim study``: Wilson intervals, capability mapping, failure grouping, conditions, and a tiny study end to end."""

from __future__ import annotations

import json

import pytest
from hypothesis import given
from hypothesis import strategies as st

from homesim.cli import main
from homesim.cliargs import OptionError
from homesim.scenario.loader import load_scenario
from homesim.scenario.model import Expectation
from homesim.tour.capabilities import capability_of, cause_of, wilson
from homesim.tour.study import analyse, parse_condition


@given(st.integers(1, 5000).flatmap(lambda n: st.tuples(st.integers(0, n), st.just(n))))
def test_wilson_bounds_lie_in_0_1_and_contain_the_rate(pn):
    passed, runs = pn
    lo, hi = wilson(passed, runs)
    assert 0.0 <= lo <= passed / runs <= hi <= 1.0
    assert hi - lo > 0  # a finite sample never pins a rate down exactly


@given(st.integers(1, 2000))
def test_wilson_narrows_with_more_runs_and_is_symmetric(n):
    lo, hi = wilson(n // 2, n)
    lo4, hi4 = wilson(2 * (n // 2), 2 * n)
    assert hi4 - lo4 < hi - lo
    a, b = wilson(n // 3, n)
    c, d = wilson(n - n // 3, n)
    assert a == pytest.approx(1 - d) and b == pytest.approx(1 - c)


def test_wilson_known_values_and_no_runs():
    assert wilson(0, 0) == (0.0, 1.0)
    lo, hi = wilson(8, 10)  # textbook: 0.490 .. 0.943
    assert (round(lo, 3), round(hi, 3)) == (0.490, 0.943)
    lo, hi = wilson(0, 40)
    assert lo == 0.0 and round(hi, 3) == 0.088
    with pytest.raises(ValueError):
        wilson(3, 2)


def E(kind: str, line: int = 1, **attrs) -> Expectation:
    return Expectation(kind, tuple(attrs.items()), line)


def test_every_library_expectation_has_a_capability_and_the_home_tour_maps_as_a_reader_would():
    sc = load_scenario("scenarios/home_tour.xml")
    caps = {e.describe(): capability_of(e, sc.expectations) for e in sc.expectations}
    assert caps['<robot-says pattern="hello|hi" by="25"/>'] == "greeting"
    assert caps['<robot-says pattern="ask me to follow you|show me objects"/>'] == "self-explanation"
    assert caps['<state-reached state="Following"/>'] == "following"
    assert caps['<robot-near room="kitchen"/>'] == "following"  # nobody sends the robot anywhere here
    assert caps['<place-learned name="kitchen"/>'] == "place teaching"
    assert caps['<object-learned type="kettle"/>'] == "object teaching"
    assert caps['<robot-says pattern="^good-?bye"/>'] == "good-bye"
    assert caps['<event-applied event="partner_lost" never="true"/>'] == "partner kept"
    assert caps["<no-collision/>"] == "no collision"
    goto = load_scenario("scenarios/goto.xml")
    near = next(e for e in goto.expectations if e.kind == "robot-near")
    assert capability_of(near, goto.expectations) == "go-to"
    assert capability_of(E("metric", name="navigation.reached"), ()) == "go-to"
    assert capability_of(E("robot-says", pattern=r"\b(cup) is\b"), ()) == "where-is"


def test_causes_group_the_same_failure_in_different_flats():
    a = cause_of("robot-near", "the robot never entered kitchen between 0 and 140 s", ["kitchen", "anna"])
    b = cause_of("robot-near", "the robot never entered guest room between 0 and 230.5 s", ["guest room"])
    assert a == b == "robot-near: the robot never entered … between N and N"
    c = cause_of("place-learned", "none of the 2 places in the scene model matches {'name': 'study'}")
    assert c == "place-learned: none of the N places in the scene model matches …"
    assert cause_of("no-collision", "the robot touched wall at t=3.2 s") != a


def test_analyse_counts_capabilities_per_run_and_groups_failures():
    exps = [E("state-reached", 10, state="Interacting"), E("object-learned", 11, type="cup"),
            E("object-learned", 12, type="book"), E("no-collision", 13)]
    rows = []
    for seed, failed in enumerate([[], [11], [11, 12], [13]]):
        rows.append({"file": "f.xml", "scenario": "f", "seed": seed, "condition": "default",
                     "verdict": "PASS" if not failed else "FAIL",
                     "failed": [{"name": "x", "where": f"f.xml:{ln}", "detail": f"none of the {seed} objects matches {{'type': 'cup'}}"
                                 if ln != 13 else "the robot touched wall at t=1 s"} for ln in failed]})
    rows.append({"file": "f.xml", "scenario": "f", "seed": 9, "condition": "default", "verdict": "ERROR", "failed": [], "error": "boom"})
    out = analyse(rows, {"f.xml": exps}, {"f.xml": []}, ["default"])
    caps = out["capabilities"]
    assert (caps["object teaching"]["runs"], caps["object teaching"]["passed"]) == (5, 2)  # a run passes it only if both hold
    assert (caps["greeting"]["runs"], caps["greeting"]["passed"]) == (5, 4)  # the errored run counts as a failure
    assert (caps["no collision"]["runs"], caps["no collision"]["passed"]) == (5, 3)
    assert (out["overall"]["runs"], out["overall"]["passed"]) == (5, 1)
    assert rows[2]["first_failed"] == '<object-learned type="cup"/>' and rows[2]["first_failed_capability"] == "object teaching"
    teach = next(g for g in out["failures"] if g["capability"] == "object teaching")
    assert teach["runs"] == 2  # two runs, three failed expectations: grouped by cause, counted per run
    assert any(g["kind"] == "error" for g in out["failures"])


def test_runs_that_checked_nothing_are_counted_apart_not_as_failures():
    """A scenario without expectations ("no expectations") neither passed nor failed: it stays out
    of every rate and the table shows it in its own row."""
    from homesim.tour.study import table

    exps = [E("state-reached", 10, state="Interacting")]
    rows = [{"file": "f.xml", "scenario": "f", "seed": 0, "condition": "default", "verdict": "PASS", "failed": []},
            {"file": "g.xml", "scenario": "g", "seed": 0, "condition": "default", "verdict": "no expectations", "failed": []},
            {"file": "g.xml", "scenario": "g", "seed": 1, "condition": "default", "verdict": "no expectations", "failed": []}]
    out = analyse(rows, {"f.xml": exps, "g.xml": []}, {"f.xml": [], "g.xml": []}, ["default"])
    assert (out["overall"]["runs"], out["overall"]["passed"], out["overall"]["rate"]) == (1, 1, 1.0)
    assert out["nothing_checked"] == {"runs": 2, "by_condition": {"default": 2}}
    assert "| nothing checked (runs, in no rate) | 2 |" in table(out, ["default"])


def test_conditions_parse_and_refuse_unknown_keys():
    c = parse_condition("slow=robot.max-speed=0.3,option.follow-distance=1.4,strict=true")
    assert c.name == "slow" and c.robot == (("max-speed", "0.3"),) and c.options == (("follow-distance", "1.4"),)
    assert c.run == (("strict", True),)
    assert parse_condition("plain").text() == "(as written)"
    for bad in ("x=colour=red", "=a=b", "x=seed=3", "x=strict=maybe", "x=robot.max-speed"):
        with pytest.raises(OptionError):
            parse_condition(bad)


def test_tiny_study_end_to_end_with_two_conditions(tmp_path, capsys):
    """Two short library scenarios, two conditions (as written, and a robot too slow to follow): the
    slow robot's following rate drops, the table shows both side by side, the files are written."""
    out = tmp_path / "st"
    code = main(["study", "scenarios/radio.xml", "scenarios/follow_crossing.xml", "--seeds", "0", "--workers", "1",
                 "--condition", "as-written", "--condition", "slow=robot.max-speed=0.08", "--out", str(out)])
    assert code == 0
    doc = json.loads((out / "study.json").read_text())
    assert len(doc["runs"]) == 4 and {r["condition"] for r in doc["runs"]} == {"as-written", "slow"}
    follow = doc["capabilities"]["following"]["by_condition"]
    assert follow["as-written"]["rate"] == 1.0 and follow["slow"]["rate"] < 1.0
    for cap in doc["capabilities"].values():
        assert 0 <= cap["ci95"][0] <= cap["rate"] <= cap["ci95"][1] <= 1
    slow_run = next(r for r in doc["runs"] if r["condition"] == "slow" and r["verdict"] == "FAIL")
    assert slow_run["first_failed_kind"] and slow_run["first_failed_capability"]
    assert doc["failures"] and doc["throughput"]["runs_per_cpu_minute"] > 0
    assert (out / "study.png").stat().st_size > 1000 and (out / "study.svg").read_text().startswith("<?xml")
    assert (out / "conditions" / "slow" / "follow_crossing.xml").is_file()
    text = capsys.readouterr().out
    assert "| capability | as-written | slow |" in text and "following" in text


def test_study_needs_files_or_generated(tmp_path, capsys):
    assert main(["study", "--out", str(tmp_path)]) == 2
    assert main(["study", "--generated", "2", "--out", str(tmp_path)]) == 2
    assert "--seed" in capsys.readouterr().err


def test_a_dask_cluster_gives_the_same_study_as_local_processes(tmp_path):
    distributed = pytest.importorskip("distributed")
    from pathlib import Path

    from homesim.tour.study import Condition, study

    files = [str(Path("scenarios/radio.xml").resolve())]
    local = study(files, [0, 1], [Condition("default")], tmp_path / "local", workers=1)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            remote = study(files, [0, 1], [Condition("default")], tmp_path / "dask", scheduler=client)
    assert remote["capabilities"] == local["capabilities"] and remote["failures"] == local["failures"]
    assert [(r["seed"], r["verdict"]) for r in remote["runs"]] == [(r["seed"], r["verdict"]) for r in local["runs"]]
    assert remote["throughput"]["workers"] == "dask"


def test_resume_reuses_the_runs_already_made(tmp_path):
    from pathlib import Path

    from homesim.tour.study import Condition, study

    files = [str(Path("scenarios/radio.xml").resolve())]
    first = study(files, [0], [Condition("default")], tmp_path, workers=1)
    again = study(files, [0, 1], [Condition("default")], tmp_path, workers=1, resume=True)
    assert first["throughput"]["runs"] == 1 and again["throughput"]["runs"] == 1  # only seed 1 was run now
    assert [r["seed"] for r in again["runs"]] == [0, 1]
    assert again["runs"][0]["verdict"] == first["runs"][0]["verdict"]
    assert again["capabilities"]["greeting"]["runs"] == 2


def test_conditions_can_select_the_robot_profile(tmp_path):
    """Two robot profiles side by side (docs/semantics.md §8): the condition reaches the run."""
    from pathlib import Path

    from homesim.tour.study import study

    files = [str(Path("scenarios/radio.xml").resolve())]
    doc = study(files, [0], [parse_condition("full=profile=full"), parse_condition("old=profile=biron-2005")], tmp_path, workers=1)
    assert doc["study"]["conditions"] == {"full": "profile=full", "old": "profile=biron-2005"}
    summaries = sorted(p.name for p in (tmp_path / "summaries").glob("*.json"))
    assert summaries == ["radio-0-full.json", "radio-0-old.json"]
    assert {r["verdict"] for r in doc["runs"]} <= {"PASS", "FAIL"}  # both ran (an unknown profile would be an ERROR row)
    with pytest.raises(Exception):
        from homesim.tour.runner import RunOptions, Run
        Run.from_file(Path(files[0]), RunOptions(seed=0, profile="no-such-robot")).close()


def test_resume_never_reuses_a_run_of_another_scenario_version_or_condition(tmp_path):
    """A summary left by an older version of the scenario file (or the same condition name with
    other run options) is not this study's run: --resume makes the run again."""
    from pathlib import Path

    from homesim.tour.study import study

    scen = tmp_path / "radio.xml"
    scen.write_bytes(Path("scenarios/radio.xml").read_bytes())
    out = tmp_path / "out"
    study([str(scen)], [0], [parse_condition("c=strict=false")], out, workers=1)
    again = study([str(scen)], [0], [parse_condition("c=strict=false")], out, workers=1, resume=True)
    assert again["throughput"]["runs"] == 0  # the same scenario and condition: reused
    other = study([str(scen)], [0], [parse_condition("c=strict=true")], out, workers=1, resume=True)
    assert other["throughput"]["runs"] == 1  # same name, other run options: made again
    scen.write_bytes(scen.read_bytes().replace(b"</scenario>", b"<!-- edited -->\n</scenario>"))
    edited = study([str(scen)], [0], [parse_condition("c=strict=true")], out, workers=1, resume=True)
    assert edited["throughput"]["runs"] == 1  # the scenario file changed: made again


def test_resume_makes_again_the_runs_of_other_code_and_says_so(tmp_path, monkeypatch, capsys):
    """A researcher fixes the robot and resumes: the old robot's runs are not mixed into the new
    rates (the key holds homesim's version and a digest of homesim/robot/humans)."""
    from pathlib import Path

    from homesim import __version__
    from homesim.tour import study as st

    assert st.code_digest() == st.code_digest() and st.code_digest().startswith(__version__ + "+sha256:")
    scen = tmp_path / "radio.xml"
    scen.write_bytes(Path("scenarios/radio.xml").read_bytes())
    out = tmp_path / "out"
    first = st.study([str(scen)], [0], [st.Condition("default")], out, workers=1)
    assert first["study"]["code"] == st.code_digest()
    capsys.readouterr()
    monkeypatch.setattr(st, "code_digest", lambda: __version__ + "+sha256:changedrobot0000")
    again = st.study([str(scen)], [0], [st.Condition("default")], out, workers=1, resume=True)
    assert again["throughput"]["runs"] == 1  # made again, with this code
    err = capsys.readouterr().err
    assert "1 run in" in err and "made by other code" in err


def test_every_expectation_of_the_library_and_the_generator_has_a_capability(tmp_path):
    """No expectation falls silently into "other": each library scenario's and each generated tour's
    expectations map to a named capability (a new kind or event needs a line in capabilities.py)."""
    from pathlib import Path

    from homesim.scenario.loader import load_scenario
    from homesim.tour.capabilities import capability_of
    from homesim.tour.generate import generate

    generate(5, 8, tmp_path)
    files = sorted(Path("scenarios").rglob("*.xml")) + sorted(tmp_path.glob("*.xml"))
    unmapped = []
    for f in files:
        sc = load_scenario(f)
        unmapped += [f"{f}:{e.line} <{e.kind}>" for e in sc.expectations if capability_of(e, sc.expectations) == "other"]
    assert not unmapped, unmapped


def test_a_condition_with_an_unknown_robot_profile_is_refused_before_any_run():
    with pytest.raises(OptionError, match="unknown robot profile 'no-such-robot'"):
        parse_condition("old=profile=no-such-robot")
    assert dict(parse_condition("old=profile=biron-2005").run) == {"profile": "biron-2005"}


def test_two_scenario_files_of_one_name_are_refused(tmp_path):
    """Run summaries are named by the file's stem: a/radio.xml and b/radio.xml would overwrite each other."""
    from pathlib import Path

    from homesim.tour.study import Condition, study

    for d in ("a", "b"):
        (tmp_path / d).mkdir()
        (tmp_path / d / "radio.xml").write_bytes(Path("scenarios/radio.xml").read_bytes())
    with pytest.raises(OptionError, match="the same name"):
        study([str(tmp_path / "a" / "radio.xml"), str(tmp_path / "b" / "radio.xml")], [0], [Condition("default")], tmp_path / "out", workers=1)


def _cell(passed: int, runs: int) -> dict:
    from homesim.tour.capabilities import wilson

    return {"runs": runs, "passed": passed, "rate": passed / runs, "ci95": list(wilson(passed, runs))}


LONG = ["robot.max-speed=0.15,user=impatient", "robot.max-speed=0.3,user=patient-and-chatty",
        "option.follow-distance=1.4,robot.max-speed=0.6", "user-profile=wrong-confirmer-who-misnames",
        "biron-2005-as-in-the-papers-with-slow-speech"]


@pytest.mark.parametrize("k, long", [(2, False), (3, False), (5, False), (4, True), (5, True)])
def test_the_study_plots_legend_covers_no_bar_interval_or_count(k, long):
    """With several conditions the legend sits outside the axes: rates near 100 % reach the
    right edge (where the old "lower right" legend hid them), and the counts stand past it."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from homesim.viz.study import rates_figure

    conds = LONG[:k] if long else [f"condition-{j}" for j in range(k)]
    caps = {name: {"by_condition": {c: _cell(40 - j, 40) for j, c in enumerate(conds)}}
            for name in ("greeting", "following", "good-bye", "no collision")}
    doc = {"study": {"conditions": conds, "runs": 40 * k, "scenarios": 40, "seeds": [0]},
           "overall": {"by_condition": {c: _cell(39, 40) for c in conds}}, "capabilities": caps}
    fig = rates_figure(doc)
    renderer = FigureCanvasAgg(fig).get_renderer()
    fig.draw(renderer)
    (legend,) = fig.legends
    box = legend.get_window_extent(renderer)
    (ax,) = fig.axes
    drawn = [a.get_window_extent(renderer) for a in (*ax.patches, *ax.texts, ax.title)]
    drawn += [c.get_datalim(ax.transData).transformed(ax.transData) for c in ax.collections]  # the intervals
    assert len(ax.texts) == 5 * k and len(ax.collections) == k
    assert not any(box.overlaps(b) for b in drawn)
    assert not box.overlaps(ax.get_window_extent(renderer))
    fig_box = fig.bbox
    assert fig_box.x0 <= box.x0 and box.x1 <= fig_box.x1 and fig_box.y0 <= box.y0 and box.y1 <= fig_box.y1
    assert [t.get_text().replace("\n", "") for t in legend.get_texts()] == conds  # every name, whole
    for t in legend.get_texts():  # no name clipped at the figure's edges
        tb = t.get_window_extent(renderer)
        assert fig_box.x0 <= tb.x0 and tb.x1 <= fig_box.x1, t.get_text()


def test_a_fully_resumed_study_says_it_made_no_run():
    from homesim.tour.study import throughput_line

    line = throughput_line({"runs": 0, "cpu_s": 0.0, "runs_per_cpu_minute": None, "cpu_s_all": 0.4,
                            "runs_per_cpu_minute_all": None, "wall_s": 1.0})
    assert "None" not in line and line.startswith("no run made")
    made = throughput_line({"runs": 3, "cpu_s": 6.0, "runs_per_cpu_minute": 30.0, "wall_s": 7.0})
    assert made.startswith("3 runs made") and "30.0 runs per CPU minute" in made


def test_a_condition_with_another_profile_skips_a_scenario_that_needs_full(tmp_path):
    """A scenario saying <robot profile="full"> under a biron-2005 condition is not run and not
    counted as failing any capability: a 'skipped' group says why."""
    import re
    from pathlib import Path

    from homesim.tour.study import study

    scen = tmp_path / "radio_full.xml"
    scen.write_text(re.sub(r"<robot\b", '<robot profile="full"', Path("scenarios/radio.xml").read_text(encoding="utf-8"), count=1),
                    encoding="utf-8")
    doc = study([str(scen)], [0], [parse_condition("old=profile=biron-2005")], tmp_path / "out", workers=1)
    assert [r["verdict"] for r in doc["runs"]] == ["SKIPPED"]
    assert all(c.get("old", {}).get("runs", 0) == 0 for c in doc["capabilities"].values())
    assert any(g["capability"] == "skipped" and "needs profile full" in g["cause"] for g in doc["failures"])
