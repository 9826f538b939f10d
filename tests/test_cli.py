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
