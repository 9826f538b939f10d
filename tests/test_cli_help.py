"""The command line behaves like the tools people know: usage and 'did you mean' on a typo, help with
descriptions, defaults and examples, shell completion, one spelling of each option, quiet pipes."""

from __future__ import annotations

import argparse
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from lxml import etree

from homesim.cli import build_parser, main

ROOT = Path(__file__).resolve().parents[1]
SCENARIO = ROOT / "scenarios" / "two_people_radio.xml"


def _run(argv: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, str, str]:
    try:
        code = main(argv)
    except SystemExit as exc:  # --help
        code = int(exc.code or 0)
    out = capsys.readouterr()
    return code, out.out, out.err


def leaves() -> list[tuple[str, argparse.ArgumentParser]]:
    """Every (sub)command with its parser, parents included ('scenario' and 'scenario plot')."""
    out: list[tuple[str, argparse.ArgumentParser]] = []

    def walk(prefix: str, parser: argparse.ArgumentParser) -> None:
        for action in parser._actions:
            if isinstance(action, argparse._SubParsersAction):
                for name, child in action.choices.items():
                    out.append((f"{prefix} {name}".strip(), child))
                    walk(f"{prefix} {name}", child)

    walk("", build_parser())
    return out


def test_a_mistyped_option_gets_usage_and_the_closest_option(capsys):
    code, _out, err = _run(["run", str(SCENARIO), "--untill", "5"], capsys)
    assert code == 2
    assert err.startswith("usage: homesim run ")
    assert "unrecognized arguments: --untill 5 (did you mean '--until'?)" in err


def test_a_mistyped_option_with_its_value_joined_is_suggested_too(capsys):
    code, _out, err = _run(["plot", "t.jsonl", "--timelime"], capsys)
    assert code == 2 and "did you mean '--timeline'?" in err


@pytest.mark.parametrize("argv,meant", [(["rnu"], "run"), (["scenario", "plto", "x.xml"], "plot"),
                                        (["afsm", "show", "x.scxml", "--format", "mermiad"], "mermaid"),
                                        (["completion", "bahs"], "bash")])
def test_a_mistyped_subcommand_or_choice_gets_the_closest_name(argv, meant, capsys):
    code, _out, err = _run(argv, capsys)
    assert code == 2 and err.startswith("usage: homesim")
    assert f"(did you mean {meant!r}?)" in err


def test_nothing_close_is_suggested_for_something_unrelated(capsys):
    code, _out, err = _run(["run", str(SCENARIO), "--zzzzzz"], capsys)
    assert code == 2 and "unrecognized arguments: --zzzzzz" in err and "did you mean" not in err


@pytest.mark.parametrize("name,parser", leaves(), ids=[n for n, _ in leaves()])
def test_every_subcommand_has_a_description_and_examples_that_parse(name, parser):
    assert parser.description, name
    examples = getattr(parser, "examples", [])
    assert examples, f"homesim {name}: register it with add_parser(..., examples=[...])"
    assert "examples:" in parser.format_help()
    for example in examples:
        words = shlex.split(example.split(" > ")[0].split(" | ")[0])
        assert words[0] == "homesim" and " ".join(words[1:]).startswith(name.split()[0]), example
        parsed = build_parser().parse_args(words[1:])  # SystemExit if an example went stale
        assert getattr(parsed, "func", None) is not None, example


@pytest.mark.parametrize("name,parser", leaves(), ids=[n for n, _ in leaves()])
def test_every_positional_argument_is_described_with_an_example(name, parser):
    for action in parser._actions:
        if action.option_strings or isinstance(action, argparse._SubParsersAction):
            continue
        assert action.help and ("e.g." in action.help), (name, action.dest)


def test_help_shows_the_defaults_that_are_values(capsys):
    code, out, _err = _run(["demo", "--help"], capsys)
    out = " ".join(out.split())  # the formatter wraps lines
    assert code == 0
    assert "(default: 1)" in out and "(default: 6.0)" in out and "(default: out/demo-trace.jsonl)" in out
    code, out, _err = _run(["afsm", "show", "--help"], capsys)
    assert "(default: dot)" in out


@pytest.mark.parametrize("shell", ["bash", "zsh"])
def test_completion_scripts_name_every_subcommand_and_option(shell, capsys):
    code, out, _err = _run(["completion", shell], capsys)
    assert code == 0
    for word in ("run", "replay", "plot", "export", "sweep", "study", "memory", "completion", "--until", "--timeline"):
        assert word in out, word
    assert "--output" not in out  # hidden aliases are not offered
    if shell == "bash" and shutil.which("bash"):
        done = subprocess.run(["bash", "-n"], input=out, capture_output=True, text=True)
        assert done.returncode == 0, done.stderr
    if shell == "zsh" and shutil.which("zsh"):
        done = subprocess.run(["zsh", "-n"], input=out, capture_output=True, text=True)
        assert done.returncode == 0, done.stderr


def test_the_bash_completion_completes_subcommands_and_options(tmp_path):
    if not shutil.which("bash"):
        pytest.skip("no bash")
    script = tmp_path / "homesim.bash"
    script.write_text(_completion("bash"), encoding="utf-8")

    def complete(line: str) -> list[str]:
        words = line.split(" ")
        program = (f"source {shlex.quote(str(script))}; COMP_WORDS=({line}); COMP_CWORD={len(words) - 1}; "
                   f"COMP_LINE={shlex.quote(line)}; COMP_POINT=${{#COMP_LINE}}; _shtab_homesim; printf '%s\\n' \"${{COMPREPLY[@]}}\"")
        done = subprocess.run(["bash", "-c", program], capture_output=True, text=True, cwd=tmp_path)
        return done.stdout.split()

    assert "replay" in complete("homesim rep")
    assert "--until" in complete("homesim run --unt")
    assert complete("homesim completion z") == ["zsh"]


def _completion(shell: str) -> str:
    from homesim.completion import script

    return script(shell, build_parser)


def test_out_is_spelled_the_same_everywhere_and_the_old_spelling_still_works(tmp_path, capsys):
    parser = build_parser()
    for name, sub in leaves():
        outs = [a for a in sub._actions if "--out" in a.option_strings]
        if outs:
            assert "-o" in outs[0].option_strings, name
        assert not any("--output" in a.option_strings and a.help is not argparse.SUPPRESS for a in sub._actions), name
    args = parser.parse_args(["scenario", "plot", str(SCENARIO), "--output", str(tmp_path / "x.png")])
    assert args.out == tmp_path / "x.png"


def test_scenario_plot_without_at_draws_the_end(tmp_path, capsys):
    out = tmp_path / "end.png"
    short = tmp_path / "short.xml"
    text = SCENARIO.read_text(encoding="utf-8")
    text = text[:text.index("<expect>")] + text[text.index("</expect>") + len("</expect>"):]  # no windows past 2 s
    short.write_text(text.replace('duration="40"', 'duration="2"', 1), encoding="utf-8")
    code, text, err = _run(["scenario", "plot", str(short), "-o", str(out)], capsys)
    assert code == 0, err
    assert f"wrote {out}" in text and "at t = 2 s" in text and out.is_file()


@pytest.fixture(scope="module")
def short_trace(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A real trace (half a second of walk_away), so a refusal cannot come from a missing file."""
    trace = tmp_path_factory.mktemp("trace") / "t.jsonl"
    assert main(["run", str(ROOT / "scenarios" / "walk_away.xml"), "--until", "0.5", "--quiet", "--trace", str(trace)]) in (0, 1)
    return trace


@pytest.mark.parametrize("argv, prog, option", [
    (["plot", "{trace}", "--timeline", "--at", "3", "-o", "{tmp}/t.png"], "homesim plot", "--at"),
    (["plot", "{trace}", "--from", "3", "-o", "{tmp}/t.png"], "homesim plot", "--from"),
    (["plot", "{trace}", "-o", "{tmp}/p.jpg"], "homesim plot", "--out"),
    (["scenario", "plot", str(ROOT / "scenarios" / "radio.xml"), "--at", "99", "-o", "{tmp}/x.png"], "homesim scenario plot", "--at"),
])
def test_a_refusal_found_after_parsing_shows_the_subcommands_usage_and_name(short_trace, tmp_path, capsys, argv, prog, option):
    argv = [a.format(trace=short_trace, tmp=tmp_path) for a in argv]
    code, out, err = _run(argv, capsys)
    assert code == 2 and out == "", err
    assert err.startswith(f"usage: {prog} ") and f"\n{prog}: error: argument {option}" in err, err
    assert not list(tmp_path.iterdir())  # nothing written


def test_run_names_its_people_in_the_singular_and_prints_what_it_wrote(tmp_path, capsys):
    one = ROOT / "scenarios" / "walk_away.xml"
    trace, summary = tmp_path / "t.jsonl", tmp_path / "s.json"
    code, out, _err = _run(["run", str(one), "--until", "0.5", "--trace", str(trace), "--summary", str(summary)], capsys)
    assert code == 0
    assert ", 1 person," in out and "1 people" not in out
    assert f"wrote {trace} (trace), {summary} (summary)" in out
    code, out, _err = _run(["run", str(SCENARIO), "--until", "0.5", "--quiet", "--trace", str(trace)], capsys)
    assert ", 2 people," not in out and f"wrote {trace} (trace)" in out  # quiet, but the file is named


def test_memory_show_takes_the_directory_given_to_memory(tmp_path, capsys):
    from homesim.memory.core import ActiveMemory
    from homesim.memory.sqlite import SqliteStore

    store = tmp_path / "memory"
    store.mkdir()
    with SqliteStore(store / "scene_model.sqlite") as s:
        ActiveMemory("objects", store=s).insert(etree.fromstring('<object name="cup"/>'))
    code, out, err = _run(["memory", "show", str(store)], capsys)
    assert code == 0, err
    assert '<object name="cup"/>' in out and "scene_model.sqlite" in out
    empty = tmp_path / "empty"
    empty.mkdir()
    code, _out, err = _run(["memory", "show", str(empty)], capsys)
    assert code == 2 and "no store in this directory" in err and "--memory" in err


@pytest.mark.parametrize("argv", [["completion", "bash"], ["run", str(SCENARIO), "--until", "3"]])
def test_output_into_a_closed_pipe_ends_quietly(argv, tmp_path):
    """`homesim ... | head -1`: no 'Broken pipe' error, no traceback (also when the run's transcript meets it)."""
    proc = subprocess.Popen([sys.executable, "-m", "homesim.cli", *argv], cwd=tmp_path,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    proc.stdout.close()  # the reader has gone before the first byte is written
    err = proc.stderr.read().decode()
    proc.stderr.close()
    assert proc.wait(timeout=60) in (0, 141)
    assert "Broken pipe" not in err and "Traceback" not in err and "Exception ignored" not in err, err


def test_the_later_visit_without_a_store_says_it_needs_one(capsys, tmp_path):
    later = ROOT / "scenarios" / "later_visit.xml"
    code, out, err = _run(["run", str(later), "--until", "1"], capsys)
    assert code == 2 and out == ""
    line = next(i for i, text in enumerate(later.read_text(encoding="utf-8").splitlines(), 1) if "<robot " in text)
    assert err.startswith(f"homesim: error: {later}:{line}: <robot>: this scenario starts from what the robot learned")
    assert "--memory DIR" in err and "home_tour.xml" in err
    # A mistyped (missing) or empty store directory is refused the same way, before anything runs.
    (tmp_path / "empty").mkdir()
    for store, why in ((tmp_path / "stroe", "does not exist"), (tmp_path / "empty", "holds no scene model")):
        code, out, err = _run(["run", str(later), "--until", "1", "--memory", str(store)], capsys)
        assert code == 2 and out == "" and f"--memory {store} {why}" in err, err
        assert err.startswith(f"homesim: error: {later}:{line}: <robot>:")
    assert not (tmp_path / "stroe").exists()  # nothing was created


def test_demo_and_run_name_the_realtime_scale_alike_and_sweep_until_has_its_unit():
    parser = build_parser()
    subs = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction)).choices

    def option(cmd: str, flag: str) -> argparse.Action:
        return next(a for a in subs[cmd]._actions if flag in a.option_strings)

    assert option("demo", "--realtime").metavar == option("run", "--realtime").metavar == "X"
    assert option("sweep", "--until").metavar == "SECONDS" and "seconds" in option("sweep", "--until").help


def test_afsm_and_check_examples_name_a_machine_that_exists():
    parser = build_parser()
    subs = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction)).choices
    afsm = next(a for a in subs["afsm"]._actions if isinstance(a, argparse._SubParsersAction)).choices
    examples = subs["check"].examples + subs["afsm"].examples + afsm["show"].examples + afsm["check"].examples
    machines = {w for e in examples for w in shlex.split(e) if w.endswith(".scxml")}
    assert machines and all((ROOT / m).is_file() for m in machines), machines
