"""What the command line prints says what it means: the demo's bus counts add up and are explained,
its options are described, a plot names the moment it was asked for."""

from __future__ import annotations

import argparse
import re
from pathlib import Path

from homesim.cli import build_parser, main

EXAMPLE = Path(__file__).resolve().parents[1] / "scenarios" / "two_people_radio.xml"


def test_demo_says_how_many_messages_had_no_subscriber_and_the_counts_add_up(tmp_path, capsys):
    assert main(["demo", "--trace", str(tmp_path / "t.jsonl")]) == 0
    out = capsys.readouterr().out
    m = re.search(r"bus: (\d+) messages sent, (\d+) delivered, (\d+) had no subscriber .*?, (\d+) dropped", out)
    assert m, out
    sent, delivered, unheard, dropped = map(int, m.groups())
    assert unheard > 0 and sent == delivered + unheard + dropped  # one subscriber per heard channel in the demo


def test_every_demo_option_is_described():
    demo = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction)).choices["demo"]
    options = [a for a in demo._actions if a.option_strings and not isinstance(a, argparse._HelpAction)]
    assert {a.dest for a in options} >= {"seed", "trace", "duration", "realtime"}
    assert all(a.help for a in options), [a.dest for a in options if not a.help]


def test_plot_names_the_moment_that_was_asked_for(tmp_path, capsys):
    out = tmp_path / "m.png"
    assert main(["scenario", "plot", str(EXAMPLE), "--at", "9", "-o", str(out)]) == 0
    assert "at t = 9 s)" in capsys.readouterr().out


def test_quiet_prints_no_header_and_no_transcript(capsys):
    """'--quiet: the verdict only': a run stopped early prints exactly its one verdict line."""
    assert main(["run", str(EXAMPLE), "--quiet", "--until", "1"]) == 0
    assert capsys.readouterr().out.splitlines() == ["verdict: not checked (stopped at 1 s of 40 s)"]
