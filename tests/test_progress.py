"""Progress bars (tqdm) are drawn on a terminal and nowhere else: pipes, files and tests get no carriage returns."""

from __future__ import annotations

import io
from pathlib import Path

from homesim.cli import main
from homesim.progress import VirtualSeconds, bar

SCENARIO = Path(__file__).resolve().parents[1] / "scenarios" / "two_people_radio.xml"


class Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_a_bar_in_virtual_seconds_is_drawn_on_a_terminal_and_removed_at_the_end():
    term = Terminal()
    with VirtualSeconds("replay", file=term) as shown:
        shown(0.0, 30.0)
        shown(30.0, 30.0)
    text = term.getvalue()
    assert "replay:" in text and "/30 s" in text
    assert text.endswith("\r")  # the bar's line is cleared when it closes (leave=False)


def test_nothing_is_drawn_when_the_output_is_not_a_terminal():
    pipe = io.StringIO()
    with VirtualSeconds("run", file=pipe) as shown:
        shown(1.0, 2.0)
    with bar(3, desc="sweep", unit="run", file=pipe) as runs:
        runs.update(3)
    assert pipe.getvalue() == ""


def test_a_run_piped_somewhere_prints_no_bar(capsys):
    assert main(["run", str(SCENARIO), "--until", "2"]) == 0
    captured = capsys.readouterr()
    assert "\r" not in captured.out and "\r" not in captured.err
    assert "%|" not in captured.err
