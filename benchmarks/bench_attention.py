"""Person attention benchmark: CPU per laser scan, leg detector precision/recall, tracking scores.

Run: ``python benchmarks/bench_attention.py``. Prints

- CPU per scan (process time, microseconds) of person_attention's work on
  recorded scans of ``scenarios/attention/three_crossing.xml`` (three
  people): the leg detector alone (its compiled pass if built, and the
  Python path); detection + anchoring (the batched
  Kalman tracks, gating, GNN); detection + anchoring + cues + selection +
  FSM (everything the module does per scan except building and sending
  its messages); and the whole per-scan step with its bus messages;
- the leg detector's precision and recall per scan against ground truth
  (people the laser could see: in front, within 6.5 m, no wall between),
  on every scenario in ``scenarios/attention/`` and the example flat;
- each scenario's CLEAR-MOT/IDF1 figures from the ``tracking`` metric of a
  full run (the runner, the supervisor and person_attention; no dialog, so
  no interaction), and the metric's own CPU per scored frame (ground truth
  read, visibility, CLEAR-MOT update: scoring, but part of a run's cost);
- the share of interaction time the attention was on the right person, from
  whole-robot runs of the library scenarios with a greeting (distractor,
  two_candidates, two_people_radio; also in every run's summary:
  ``homesim run X --summary s.json``, ``metrics.tracking``);
- the time from a greeting ("Hello BIRON", its start and end in the sound
  field's ground truth) to the first ``potential_partner`` event after it.

Not a test: wall-clock and CPU figures belong here, never in the test suite.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

from homesim.tour.metrics.tracking import detection_scores, visible_region, wall_edges
from homesim.tour.runner import ACTORS, Run, RunOptions
from homesim.scenario.loader import load_scenario
from homesim.sim import Simulation
from homesim.tour.stage import Stage
from robot.attention.clutter import FurnitureLegs
from robot.attention.legs import LegDetector, detect
from robot.attention.module import PersonAttention
from robot.hardware.map_server import floor_plan

ROOT = Path(__file__).resolve().parents[1]
SCENARIOS = sorted((ROOT / "scenarios" / "attention").glob("*.xml")) + [ROOT / "scenarios" / "two_people_radio.xml"]
PARTNER_SCENARIOS = [ROOT / "scenarios" / f"{n}.xml" for n in ("distractor", "two_candidates", "two_people_radio")]
BEARINGS = np.radians(-90 + 0.5 * np.arange(361))


def record(path: Path, until: float | None = None):
    """Scans (t, ranges), odometry (t, x, y, th, v, w) and the truth (robot pose, people) at each scan."""
    sc = load_scenario(path)
    sim = Simulation(seed=sc.seed, scenario=sc.name)
    st = Stage(sim, sc, actors=ACTORS, keep_messages=True)
    plan = floor_plan(sc)
    rows, odom = [], []
    world = st.world

    def on_scan(m):
        people = np.array([h.position for h in world.humans.values() if h.present], dtype=float).reshape(-1, 2)
        rows.append((m.created, np.asarray(m.attachments["ranges"]).copy(), world.robot.pose, people))

    st.dispatcher.add("/robot/laser/scan", on_scan)
    st.dispatcher.add("/robot/odometry", lambda m: odom.append((m.created, *(float(m.xml.get(k)) for k in ("x", "y", "theta", "v", "w")))))
    st.run(until)
    walls = wall_edges(world)
    sim.close()
    return rows, odom, plan, walls


def cpu_per_scan(path: Path, repeat: int = 5) -> dict[str, float]:
    rows, odom, plan, _ = record(path)
    sim = Simulation(seed=0, scenario="bench")
    pa = PersonAttention(sim)
    pa.furniture = FurnitureLegs(plan)
    pa._bearings = BEARINGS
    pa.legs = pa.legs.__class__(offset=0.13)
    odo_at = {round(o[0], 3): o for o in odom}
    out: dict[str, float] = {}
    # Detection alone (the module's detector for this scan geometry, no furniture filter): the
    # compiled pass when it is built, and the Python path it replaces.
    for label, compiled in (("legs", True), ("legs, Python path", False)):
        detector = LegDetector(BEARINGS, pa.legs, compiled=compiled)
        if label == "legs" and detector.kernel is None:
            label = "legs (no compiled kernel)"
        best = math.inf
        for _ in range(repeat):
            t0 = time.process_time()
            for _, r, _, _ in rows:
                detector(r)
            best = min(best, (time.process_time() - t0) / len(rows) * 1e6)
        out[label] = best
    # The whole step, with and without building/sending its messages.
    for label, quiet in (("all but messages", True), ("whole step with messages", False)):
        best = math.inf
        for _ in range(repeat):
            p = PersonAttention(sim, name=f"pa{label[:3]}{_}", typed=False)
            p.furniture, p._bearings, p.legs = pa.furniture, BEARINGS, pa.legs
            if quiet:
                p._publish_tracks = lambda *a, **k: None
                p._publish_state = lambda *a, **k: None
                p._publish_partner = lambda *a, **k: None
                p._act = lambda *a, **k: None
            t0 = time.process_time()
            for t, r, _, _ in rows:
                o = odo_at.get(round(t, 3))
                if o is not None:
                    p._odom = o
                p.process(t, r)
            best = min(best, (time.process_time() - t0) / len(rows) * 1e6)
        out[label] = best
    sim.close()
    return out


def detector_scores(path: Path) -> tuple[int, ...]:
    rows, _, plan, walls = record(path)
    furniture = FurnitureLegs(plan)
    tp = fp = fn = tp2 = fp2 = fn2 = 0
    for _, r, pose, people in rows:
        x, y, th = pose
        c, s = math.cos(th), math.sin(th)

        def to_world(xy):
            return np.column_stack((x + c * xy[:, 0] - s * xy[:, 1], y + s * xy[:, 0] + c * xy[:, 1]))

        det = detect(r, BEARINGS, reject=lambda xy: furniture.inside(to_world(xy)))
        strong = det.kind != 2  # pairs and blobs: what may start a track
        vis = visible_region(walls, pose, people)
        a, b, cnt = detection_scores(to_world(det.xy[strong]) if strong.any() else np.zeros((0, 2)), people[vis])
        tp, fp, fn = tp + a, fp + b, fn + cnt
        a, b, cnt = detection_scores(to_world(det.xy) if len(det) else np.zeros((0, 2)), people[vis])
        tp2, fp2, fn2 = tp2 + a, fp2 + b, fn2 + cnt
    return tp, fp, fn, tp2, fp2, fn2, len(rows)


def _time_frames(metric) -> list[float]:
    """[CPU seconds, frames] of the tracking metric's scoring of each tracks message (process time)."""
    acc = [0.0, 0]
    frame = metric._frame

    def timed(m) -> None:
        t0 = time.process_time()
        frame(m)
        acc[0] += time.process_time() - t0
        acc[1] += 1

    metric._frame = timed
    return acc


def main() -> None:
    three = ROOT / "scenarios" / "attention" / "three_crossing.xml"
    import os
    import timeit

    probe = np.zeros(361)
    idx = np.arange(0, 361, 10)
    # The yardstick is CPU time like the figures below (a wall-clock one grows with the load while
    # process time does not, so the two cannot be divided into each other).
    yard = min(timeit.repeat(lambda: np.add.reduceat(probe, idx), number=2000, repeat=5, timer=time.process_time)) / 2000 * 1e6
    print(f"load average {os.getloadavg()[0]:.1f}; yardstick (CPU time): one np.add.reduceat on 361 values {yard:.1f} us (about 2 us unloaded)")
    print("person_attention CPU per scan, three people (three_crossing.xml), microseconds:")
    for k, v in cpu_per_scan(three).items():
        print(f"  {k:28s} {v:8.1f}")
    print("\nleg detector against ground truth (people the laser could see), over all scans:")
    print(f"  {'scenario':24s} {'scans':>6s} {'pairs+blobs P':>14s} {'R':>6s} {'all candidates P':>17s} {'R':>6s}")
    for p in SCENARIOS:
        tp, fp, fn, tp2, fp2, fn2, n = detector_scores(p)
        print(f"  {p.stem:24s} {n:6d} {tp / max(tp + fp, 1):14.3f} {tp / max(tp + fn, 1):6.3f} {tp2 / max(tp2 + fp2, 1):17.3f} {tp2 / max(tp2 + fn2, 1):6.3f}")
    print("\ntracking (runner + supervisor + person_attention), CLEAR-MOT / IDF1 (no dialog: no interaction):")
    print(f"  {'scenario':24s} {'MOTA':>6s} {'MOTP m':>7s} {'IDF1':>6s} {'miss':>5s} {'FP':>4s} {'IDsw':>5s} {'gt':>3s} {'tracks':>6s} {'metric us/frame':>15s}")
    latencies: list[tuple[str, str, float, float]] = []
    for p in SCENARIOS:
        run = Run.from_file(p, RunOptions(subsystems=("robot.attention",), metrics=("tracking",)))
        scoring = _time_frames(run.metrics["tracking"])
        pp: list[float] = []
        run.dispatcher.add("/robot/es/events", lambda m: pp.append(m.created) if m.xml.get("name") == "potential_partner" else None)
        run.run()
        s = run.metric_values()["tracking"]
        for u in run.world.sound.all():
            if u.source in run.world.humans and "hello biron" in u.text.lower():
                after = [t for t in pp if t >= u.start]
                if after:
                    latencies.append((p.stem, u.source, after[0] - u.start, after[0] - u.end))
        run.close()
        print(
            f"  {p.stem:24s} {s['mota']:6.3f} {s['motp_m']:7.3f} {s['idf1']:6.3f} {s['misses']:5d} {s['false_positives']:4d} "
            f"{s['id_switches']:5d} {s['gt_ids']:3d} {s['track_ids']:6d}"
            f" {scoring[0] / max(scoring[1], 1) * 1e6:15.1f}"
        )
    # The share needs interactions, so a dialog: the library's scenarios with a greeting, the whole robot.
    print("\nattention on the right person during interactions (library scenarios, the whole robot, scenario seed):")
    for p in PARTNER_SCENARIOS:
        run = Run.from_file(p, RunOptions(metrics=("tracking",)))
        run.run()
        s = run.metric_values()["tracking"]
        run.close()
        share = s.get("attention_on_partner_share")
        on = "-" if share is None else f"{share:.3f}"
        print(f"  {p.stem:24s} on partner {on:>6s} of {s['attention_scans_in_interaction']:5d} scans in {s['interactions']} interaction(s)")
    print("\ngreeting -> first potential_partner event (virtual seconds; negative from the end: before she finished):")
    for name, who, from_start, from_end in latencies:
        print(f"  {name:24s} {who:6s} from its start {from_start:5.2f}   from its end {from_end:+5.2f}")


if __name__ == "__main__":
    main()
