"""The "done when" scenario end to end: it runs under ``homesim``, passes, repeats, plots."""

from __future__ import annotations

import math

import numpy as np
import pytest

from homesim.cli import main
from homesim.scenario.loader import load_scenario
from homesim.sim import Simulation
from homesim.world.geometry import distance_points_segments, polygon_edges
from homesim.world.legs import detect_leg_pairs
from homesim.world.stage import Stage
from tests.world_helpers import EXAMPLE


@pytest.fixture(scope="module")
def stage() -> Stage:
    sc = load_scenario(EXAMPLE)
    sim = Simulation(seed=sc.seed, scenario=sc.name)
    st = Stage(sim, sc)
    st.run()
    yield st
    sim.close()


def test_every_expectation_of_the_example_holds(stage):
    verdicts = stage.verdicts()
    assert len(verdicts) == 5
    assert all(v.passed for v in verdicts), [v.line() for v in verdicts]


def test_sensor_streams_run_at_their_rates(stage):
    counts = {}
    for m in stage.messages:
        counts[m.channel] = counts.get(m.channel, 0) + 1
    for ch in ("/robot/laser/scan", "/robot/camera/faces", "/robot/audio/sources", "/robot/odometry"):
        assert counts[ch] == 400, ch  # 10 Hz for 40 s
    assert counts["/robot/audio/speech"] == len(stage.world.sound.all())


def test_laser_legs_follow_the_true_people_through_the_run(stage):
    """Every scan with a person in the open, 0.8-5 m ahead, shows their legs near their bearing
    (a pair, or a single leg when one hides the other along the line of sight)."""
    scans = [m for m in stage.messages if m.channel == "/robot/laser/scan"]
    bearings = math.radians(-90) + math.radians(0.5) * np.arange(361)
    checked = 0
    for m in scans[::10]:
        frame = stage.truth.at(m.created)
        rx, ry, rth = frame.robot
        ox, oy = rx + 0.13 * math.cos(rth), ry + 0.13 * math.sin(rth)
        pairs = detect_leg_pairs(np.asarray(m.attachments["ranges"]), bearings)
        for p in frame.people:
            if not p.present or p.room != "living room":
                continue
            d = math.hypot(p.x - ox, p.y - oy)
            b = math.remainder(math.atan2(p.y - oy, p.x - ox) - rth, 2 * math.pi)
            if not (0.8 < d < 5.0 and abs(b) < math.radians(80)) or _near_furniture(stage.world, p.x, p.y):
                continue
            checked += 1
            assert any(abs(q.bearing - b) < math.radians(4) and abs(q.distance - d) < 0.25 for q in pairs), (m.created, p.name)
    assert checked >= 3


def _near_furniture(world, x, y, margin=0.6):
    """Table legs next to a person make a legitimately ambiguous scan: skip those moments."""
    for ob in world.obstacles:
        if ob.kind != "wall":
            a, b = polygon_edges(ob.polygon)
            if distance_points_segments(np.array([[x, y]]), a, b).min() < margin:
                return True
    return False


def test_the_radio_speaks_with_nobody_there_and_is_heard_from_the_kitchen(stage):
    radio = stage.world.sound.by("radio")
    assert len(radio) == 4 and all("Hello BIRON" in u.text for u in radio)
    speech = [m for m in stage.messages if m.channel == "/robot/audio/speech" and m.created == pytest.approx(radio[0].end)]
    assert len(speech) == 1


def test_cli_run_is_byte_identical_and_passes(capsys):
    assert main(["scenario", "run", str(EXAMPLE), "--quiet"]) == 0
    first = capsys.readouterr().out
    assert main(["scenario", "run", str(EXAMPLE), "--quiet"]) == 0
    assert capsys.readouterr().out == first
    assert "verdict: PASS (5/5" in first


def test_cli_plot_writes_a_png(tmp_path, capsys):
    out = tmp_path / "moment.png"
    assert main(["scenario", "plot", str(EXAMPLE), "--at", "9", "-o", str(out)]) == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "wrote" in capsys.readouterr().out


def test_cli_reports_a_broken_scenario_with_file_and_line(tmp_path, capsys):
    bad = tmp_path / "broken.xml"
    bad.write_text(EXAMPLE.read_text(encoding="utf-8").replace('<walk-to room="kitchen"/>', '<walk-to room="garage"/>'), encoding="utf-8")
    assert main(["scenario", "run", str(bad)]) == 2
    err = capsys.readouterr().err
    assert f"{bad}:" in err and "no room named 'garage'" in err
