"""The homesim command: the demo runs, bad input gives one clear line."""

from __future__ import annotations

from homesim.cli import main


def test_demo_runs_and_detects_the_crash(tmp_path, capsys):
    trace = tmp_path / "t.jsonl"
    assert main(["demo", "--duration", "4", "--trace", str(trace)]) == 0
    out = capsys.readouterr().out
    assert "module_failed: peer" in out and "PASS" in out
    assert trace.read_text().startswith('{"homesim_trace":1')


def test_no_command_prints_help(capsys):
    assert main([]) == 2
    assert "usage: homesim" in capsys.readouterr().out


def test_each_command_is_parsed_by_a_tree_holding_only_its_own_module():
    """``homesim NAME`` imports one subcommand module (start-up); its parser is the whole tree's, help and all."""
    import argparse

    from homesim.cli import COMMANDS, build_parser

    def commands(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
        return next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction)).choices

    whole = commands(build_parser())
    assert set(whole) == set(COMMANDS)
    for name in COMMANDS:
        own = commands(build_parser(name))
        assert name in own
        assert own[name].format_help() == whole[name].format_help()


def test_the_command_is_found_after_the_watchdog_option_and_nothing_else():
    from homesim.cli import _command

    assert _command(["run", "x.xml"]) == "run"
    assert _command(["--watchdog", "5", "run", "x.xml"]) == "run"
    assert _command(["--watchdog=5", "sweep"]) == "sweep"
    for argv in ([], ["--help"], ["--version"], ["rn", "x.xml"], ["--watch", "5", "run"], ["-h", "run"]):
        assert _command(argv) is None
