"""Two processes writing to one memory store at once lose no confirmed write.

Each writer opens the store (both read the same id counter), waits until the
other has opened it too, then inserts and updates documents as fast as it
can. Every insert a writer reports as done must be in the store afterwards,
with the content that writer gave it.
"""

from __future__ import annotations

import json
import subprocess
import sys
import time
from pathlib import Path

from homesim.memory import ActiveMemory, SqliteStore

WRITER = r"""
import json, sys, time
from pathlib import Path
from homesim.memory import ActiveMemory, SqliteStore

store_path, who, n, gate = sys.argv[1], sys.argv[2], int(sys.argv[3]), Path(sys.argv[4])
store = SqliteStore(store_path)
mem = ActiveMemory("objects", store=store)
(gate / f"ready-{who}").touch()
while not (gate / "go").exists():  # both have read the counter before either writes
    time.sleep(0.001)
done = {}
for i in range(n):
    doc_id = mem.insert(f'<OBJECT who="{who}" n="{i}"/>')
    done[doc_id] = i
    if i % 5 == 0:
        mem.update(doc_id, f'<OBJECT who="{who}" n="{i}" updated="1"/>')
store.close()
print(json.dumps(done))
"""


def _writers(store: Path, gate: Path, n: int) -> list[dict[int, int]]:
    procs = [subprocess.Popen([sys.executable, "-c", WRITER, str(store), who, str(n), str(gate)],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) for who in ("a", "b")]
    while not all((gate / f"ready-{who}").exists() for who in ("a", "b")):
        assert all(p.poll() is None for p in procs), [p.communicate() for p in procs]
        time.sleep(0.005)
    (gate / "go").touch()
    out = []
    for p in procs:
        stdout, stderr = p.communicate()
        assert p.returncode == 0, stderr
        out.append({int(k): v for k, v in json.loads(stdout).items()})
    return out


def test_two_writers_in_two_processes_keep_every_confirmed_write(tmp_path):
    store = tmp_path / "store" / "scene_model.sqlite"
    with SqliteStore(store) as s:  # one document from an earlier run: both writers start from counter 2
        ActiveMemory("objects", store=s).insert('<OBJECT who="earlier" n="0"/>')
    n = 40
    a, b = _writers(store, tmp_path, n)
    assert len(a) == len(b) == n
    assert not set(a) & set(b), "both writers were given the same ids"
    with SqliteStore(store) as s:
        mem = ActiveMemory("objects", store=s)
        assert len(mem) == 2 * n + 1
        for who, done in (("a", a), ("b", b)):
            for doc_id, i in done.items():
                x = mem.get(doc_id).xml
                assert (x.get("who"), x.get("n")) == (who, str(i))
                assert (x.get("updated") == "1") == (i % 5 == 0)
        # The counter on disk is past every id: the next insert replaces nothing.
        new = mem.insert('<OBJECT who="after"/>')
        assert new > max(a | b) and len(mem) == 2 * n + 2
