"""The language scenarios (tests/scenarios/lang_*.xml) pass as whole runs: names, everyday
language and confirmations in flats the robot never saw. Seed 0 here; the rates over seeds
0-9 are in robot/speech/corpus/README.md."""

from __future__ import annotations

from pathlib import Path

import pytest

from homesim.cli import main

SCENARIOS = Path(__file__).resolve().parent / "scenarios"


@pytest.mark.parametrize("name", ["lang_names", "lang_everyday", "lang_confirm", "lang_correct", "lang_confirm_always",
                                  "lang_preamble", "lang_room_word", "lang_greet_request", "lang_make_way",
                                  "lang_make_way_behind", "lang_visitor_in_passing", "lang_phone_call", "lang_tv_alone",
                                  "lang_silence", "lang_silence_repair"])
def test_language_scenario_passes(name, capsys):
    assert main(["run", str(SCENARIOS / f"{name}.xml"), "--quiet"]) == 0, capsys.readouterr().out
