"""wlan_reorder: with the supervisor on the laptop, the dialog's greeting overtakes the person
attention's older potential_partner on the busy WLAN; the ES counts it and the interaction starts."""

from __future__ import annotations

import io
import json
import re
from pathlib import Path

from homesim.tour.runner import Run, RunOptions

ROOT = Path(__file__).resolve().parents[1]


def test_a_greeting_overtakes_an_older_potential_partner_and_the_interaction_starts():
    trace = io.StringIO()
    with Run.from_file(ROOT / "scenarios" / "wlan_reorder.xml", RunOptions(seed=0, trace=trace)) as run:
        run.run()
        s = run.summary()
    assert s["verdict"] == "PASS", [e for e in s["expectations"] if not e.get("passed")]
    assert s["deployment"]["placement"]["supervisor"] == "laptop"
    assert s["es"]["received_out_of_order"] >= 1
    assert s["metrics"]["network"]["es_out_of_order"] == s["es"]["received_out_of_order"]
    # From the trace: the order in which events reached the supervisor, with their creation times.
    created: dict[str, tuple[float, str]] = {}
    arrived: list[tuple[float, str]] = []
    started = False
    for line in trace.getvalue().splitlines():
        d = json.loads(line)
        if d.get("kind") == "publish" and d.get("channel") == "/robot/es/events":
            created[d["id"]] = (d["created"], re.search(r'<event name="(\w+)"', d["xml"]).group(1))
        elif d.get("kind") == "deliver" and d.get("id") in created and "supervisor" in d.get("receivers", []):
            arrived.append(created[d["id"]])
        elif d.get("channel") == "/robot/es/log" and 'kind="applied"' in d["xml"] and 'name="greeting"' in d["xml"]:
            started = started or 'state="PotentialPartner"' in d["xml"]
    overtaken = [(c, n) for i, (c, n) in enumerate(arrived)
                 if n == "potential_partner" and any(c2 > c and n2 == "greeting" for c2, n2 in arrived[:i])]
    assert overtaken, "no potential_partner reached the ES after a newer greeting"
    # The ES's own count agrees with the arrival order it was handed.
    newest, late = -1.0, 0
    for c, _ in arrived:
        late, newest = (late + 1, newest) if c < newest else (late, c)
    assert late == s["es"]["received_out_of_order"]
    assert started, "no greeting was applied in PotentialPartner (no interaction started)"
