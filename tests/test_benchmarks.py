"""Smoke test: ``python -m benchmarks --tiny`` runs every row and writes its JSON (figures not checked)."""

from __future__ import annotations

import json

from benchmarks.__main__ import main


def test_tiny_benchmarks_write_every_row(tmp_path, capsys):
    out = tmp_path / "bench.json"
    assert main(["--tiny", "--json", str(out)]) == 0
    doc = json.loads(out.read_text(encoding="utf-8"))
    assert doc["tiny"] is True
    names = {f"{r['group']}/{r['name']}" for r in doc["rows"]}
    for want in ("speed/two_people_radio.xml", "speed/home_tour.xml", "stage/1 people", "stage/10 people",
                 "memory/2 s", "loop/sleep", "loop/pingpong", "supervisor/bus", "laser/361 beams", "bus/publish",
                 "bus/publish --strict", "speed/home_tour.xml --strict", "modules/camera", "modules/(kernel and rest)"):
        assert want in names
    # Rows that need no optional engine always measure something positive.
    for r in doc["rows"]:
        if r["group"] in ("speed", "stage", "memory", "laser", "bus") or r["name"] == "camera":
            assert r["value"] > 0, r
    printed = capsys.readouterr().out
    assert "speed/home_tour.xml" in printed and str(out) in printed
