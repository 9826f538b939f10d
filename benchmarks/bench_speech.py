"""Speech understanding and dialog cost per utterance (thread CPU time).

Run: ``python benchmarks/bench_speech.py [--rounds N]``. Not a test: wall-clock
numbers belong here, never in the test suite.

* understanding: :meth:`robot.speech.grammar.Understander.understand` on every
  utterance of the corpus (``robot/speech/corpus/tuning.tsv``: clean commands,
  fillers, self-corrections, fragments, recogniser errors, nonsense): lexicon,
  disfluency clean-up, LALR parse (with the partial-parse recovery when it
  fails) and the frame XML. Reported as p50/p99/mean per utterance, and the
  same for the clean-parse and recovery cases separately.
* frame message: the above plus the channel element (``frame_message``) and
  its XSD validation, i.e. what the ``understanding`` module does per utterance.
* dialog manager: :meth:`DialogManager.on_frame` / ``on_condition`` for a
  teaching exchange (frame -> event; condition -> sentence), per input.

Also prints the corpus pass rate (frames equal to the expected ones) and the
pass rate on ``benchmarks/data/heldout_utterances.tsv``, utterances written
after the grammar and never used to tune it (the corpus was), with every miss.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
from lxml import etree

from homesim.xmlio import load_schema
from robot.dialog.loader import load
from robot.dialog.manager import DialogManager
from robot.speech.grammar import Understander
from robot.speech.module import FRAMES_XSD, frame_message

CORPUS = Path(__file__).resolve().parent.parent / "robot" / "speech" / "corpus" / "tuning.tsv"
HELD_OUT = Path(__file__).resolve().parent / "data" / "heldout_utterances.tsv"


def corpus(path: Path = CORPUS) -> list[tuple[str, str]]:
    rows = []
    for line in path.read_text(encoding="utf-8").splitlines():
        if line.startswith("#") or not line.strip("\t"):
            continue
        w, f, _ = line.split("\t")
        rows.append((w, f))
    return rows


def stats(name: str, us: np.ndarray) -> None:
    print(f"{name:38s} n={len(us):6d}  p50 {np.percentile(us, 50):7.1f} us  p99 {np.percentile(us, 99):7.1f} us  mean {us.mean():7.1f} us")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--rounds", type=int, default=20)
    args = ap.parse_args()
    rows = corpus()
    u = Understander()
    ok = sum(
        (etree.tostring(r.frame, encoding="unicode") if (r := u.understand(w)).frame is not None else "NOT_UNDERSTOOD") == f
        for w, f in rows
    )
    print(f"corpus: {len(rows)} utterances, {ok} give the expected frame ({100.0 * ok / len(rows):.1f} %)")
    held = corpus(HELD_OUT)
    misses = []
    for w, f in held:
        r = u.understand(w)
        got = etree.tostring(r.frame, encoding="unicode") if r.frame is not None else "NOT_UNDERSTOOD"
        if got != f:
            misses.append(f"  miss: {w!r}: got {got}, expected {f}")
    done = len(held) - len(misses)
    print(f"held-out: {len(held)} utterances, {done} give the expected frame ({100.0 * done / len(held):.1f} %)")
    for m in misses:
        print(m)
    for w, _ in rows:  # warm up
        u.understand(w)
    clean, recovered, alls, full = [], [], [], []
    schema = load_schema(FRAMES_XSD)
    pc = time.thread_time  # CPU time of this thread: what the utterance costs, not the other jobs on the machine
    for _ in range(args.rounds):
        for w, _ in rows:
            t0 = pc()
            r = u.understand(w)
            t1 = pc()
            schema.check(frame_message(r, 0.0, 1.0, 0.9))
            t2 = pc()
            dt = (t1 - t0) * 1e6
            alls.append(dt)
            full.append((t2 - t0) * 1e6)
            (recovered if (r.partial or r.frame is None) else clean).append(dt)
    stats("understand (all corpus)", np.array(alls))
    stats("understand (clean parse)", np.array(clean))
    stats("understand (recovery / not understood)", np.array(recovered))
    stats("understand + message + XSD", np.array(full))

    doc = load()
    f_obj = etree.fromstring('<understood start="0" end="1" confidence="0.9"><SPEECH><OBJECT type="cup"><GESTURE val="probably_pointing"/>'
                             '<TITLE name="cup"/><OWNER name="speaker"/></OBJECT></SPEECH><words>w</words></understood>')
    c_obj = etree.fromstring('<condition name="object_learned" target="dialog" event="e" state="Interacting">'
                             '<param name="object"><OBJECT type="cup"/></param></condition>')
    times = []
    for _ in range(args.rounds * 50):
        dm = DialogManager(doc)
        dm.es_state = "Interacting"
        t0 = pc()
        dm.on_frame(f_obj)
        dm.on_condition(c_obj)
        times.append((pc() - t0) * 1e6 / 2)
    stats("dialog manager per input", np.array(times))


if __name__ == "__main__":
    main()
