"""Recording benchmark: what ``--trace`` and ``--record`` cost a run, in CPU and bytes, and what a recording saves when read.

Run: ``python -m benchmarks.bench_recording [--scenario scenarios/home_tour.xml] [--seed 0] [--repeat 2]``
(needs the ``export`` extra: the mcap library). Prints, for the whole scenario run by
:class:`homesim.tour.runner.Run` (every subsystem, metrics, expectations):

- CPU seconds of the run with nothing recorded, with the JSON Lines trace to a file, with the MCAP
  recording (:mod:`homesim.tour.recording`), and with both (best of ``--repeat``, the variants
  alternating so that load drifts hit them alike), and each one's extra over the bare run;
- the size of the trace and of the recording, and the recording's bytes per channel group before
  compression (what the zstd-compressed file holds: the laser's ranges, the world's truth, the
  embedded trace, the Foxglove views, the bus channels);
- reading: drawing the moment at the middle of the run from the recording alone vs re-creating
  the run from the trace (``homesim plot --at``), and ``homesim trace info`` on each file.

Not a test: CPU and byte figures belong here (process CPU time; expect +-10 % under load).
"""

from __future__ import annotations

import argparse
import tempfile
import time
from collections import defaultdict
from pathlib import Path

from homesim.tour.runner import Run, RunOptions

ROOT = Path(__file__).resolve().parents[1]


def one_run(path: Path, seed: int, *, trace: Path | None, record: Path | None) -> float:
    """CPU seconds of one whole run with the asked outputs (the files closed before the clock stops)."""
    from homesim.tour.recording import record as start_recording

    t0 = time.process_time()
    with Run.from_file(path, RunOptions(seed=seed, trace=trace)) as run:
        rec = start_recording(run, record) if record is not None else None
        run.run()
        run.finish()
        if rec is not None:
            rec.close()
    return time.process_time() - t0


def group(topic: str) -> str:
    if topic == "/laser":
        return "/laser (ranges)"
    if topic.startswith("/homesim/"):
        return topic
    if topic.startswith("/scene/") or topic == "/tf":
        return "Foxglove views (/tf, /scene/*)"
    return "bus channels (homesim.BusMessage)"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scenario", type=Path, default=ROOT / "scenarios" / "home_tour.xml")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--repeat", type=int, default=2)
    a = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="bench-recording-") as d:
        tr, mc = Path(d) / "run.jsonl", Path(d) / "run.mcap"
        variants = {"no output": (None, None), "--trace": (tr, None), "--record": (None, mc), "--trace --record": (tr, mc)}
        best: dict[str, float] = {}
        for _ in range(max(1, a.repeat)):
            for name, (t, r) in variants.items():
                cpu = one_run(a.scenario, a.seed, trace=t, record=r)
                best[name] = min(best.get(name, cpu), cpu)
        with Run.from_file(a.scenario, RunOptions(seed=a.seed)) as run:
            sim = run.end
        print(f"{a.scenario.name}, seed {a.seed}, {sim:g} simulated s (CPU s, best of {a.repeat})")
        base = best["no output"]
        for name, cpu in best.items():
            extra = "" if name == "no output" else f"  +{cpu - base:.2f} s (+{100 * (cpu - base) / base:.0f} %)"
            print(f"  {name:<18} {cpu:6.2f} s{extra}")

        from homesim.tour.recorded import Recording

        size_t, size_m = tr.stat().st_size, mc.stat().st_size
        print(f"\nsizes: trace {size_t / 2**20:.1f} MiB ({size_t / sim / 1024:.0f} KiB per simulated s), "
              f"recording {size_m / 2**20:.1f} MiB ({size_m / sim / 1024:.0f} KiB per simulated s), zstd chunks")
        raw: dict[str, int] = defaultdict(int)
        count: dict[str, int] = defaultdict(int)
        with Recording(mc) as rec:
            for topic, _, _, data in rec.messages():
                raw[group(topic)] += len(data)
                count[group(topic)] += 1
        total = sum(raw.values())
        print(f"recording before compression: {total / 2**20:.1f} MiB (compression {total / size_m:.1f}x)")
        for g, n in sorted(raw.items(), key=lambda kv: -kv[1]):
            print(f"  {g:<36} {n / 2**20:7.1f} MiB  {100 * n / total:4.0f} %  {count[g]:>8} messages")

        from homesim.tour.plot_cli import plot_moment_of_recording, plot_moment_of_trace
        from homesim.tour.trace_cli import file_info

        at = round(sim / 2, 1)
        for label, fn, f in (("plot --at from the recording", plot_moment_of_recording, mc), ("plot --at from the trace (re-run)", plot_moment_of_trace, tr)):
            t0 = time.process_time()
            fn(f, at)
            print(f"{label:<36} t = {at:g} s: {time.process_time() - t0:6.2f} CPU s")
        for label, f in (("trace info on the trace", tr), ("trace info on the recording", mc)):
            t0 = time.process_time()
            file_info(f)
            print(f"{label:<36} {time.process_time() - t0:6.2f} CPU s")


if __name__ == "__main__":
    main()
