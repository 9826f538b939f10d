"""Person attention's ES events name the laser scan they were decided on (the trace links scan -> event)."""

from __future__ import annotations

import io
import json
from pathlib import Path

from homesim.tour.runner import Run, RunOptions

ROOT = Path(__file__).resolve().parents[1]


def test_potential_partner_is_caused_by_a_scan_sent_before_it():
    buf = io.StringIO()
    with Run.from_file(ROOT / "scenarios" / "two_people_radio.xml", RunOptions(seed=0, until=4.0, trace=buf)) as run:
        run.run()
    recs = [json.loads(line) for line in buf.getvalue().splitlines()[1:]]
    sends = {r["id"]: r for r in recs if "channel" in r}
    events = [r for r in recs if r.get("channel") == "/robot/es/events" and r.get("sender") == "person_attention"]
    assert any('name="potential_partner"' in r["xml"] for r in events)
    for r in events:
        assert len(r["causes"]) == 1, r
        scan = sends[r["causes"][0]]
        assert scan["channel"] == "/robot/laser/scan" and scan["t"] <= r["t"]
