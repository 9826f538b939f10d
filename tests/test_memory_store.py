"""The SQLite store: crash safety under SIGKILL in the middle of a burst of writes (a real subprocess),
corrupt and newer stores refused and kept, the migration path from version 1, attachments round trip."""

from __future__ import annotations

import os
import signal
import sqlite3
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from homesim.errors import MemoryStoreError
from homesim.memory import SCHEMA_VERSION, ActiveMemory, SqliteStore
from homesim.memory.sqlite import create_v1

ROOT = Path(__file__).resolve().parents[1]

# The writer: each insert (a 6 KB document + an 8 KB attachment) is one commit; every third step also
# updates the previous document and its attachment together. It prints an id only after its commit.
WRITER = r"""
import sys
import numpy as np
from homesim.memory import ActiveMemory, SqliteStore
m = ActiveMemory("burst", store=SqliteStore(sys.argv[1]))
for k in range(1_000_000):
    body = ("%d;" % k) * (6000 // (len(str(k)) + 1))
    i = m.insert('<doc k="%d" n="%d">%s</doc>' % (k, len(body), body), {"a": np.full(1000, k, dtype=np.int64)})
    print("insert", i, flush=True)
    if k % 3 == 2:
        prev = ("%d;" % (k - 1)) * (6000 // (len(str(k - 1)) + 1))
        m.update(i - 1, '<doc k="%d" n="%d" updated="1">%s</doc>' % (k - 1, len(prev), prev),
                 {"a": np.full(1000, -(k - 1), dtype=np.int64)})
        print("update", i - 1, flush=True)
"""


def check_consistent(m: ActiveMemory) -> None:
    """Every stored document is whole, and its attachment belongs to the same version."""
    for rec in m.query():
        k, body = int(rec.xml.get("k")), rec.xml.text
        assert len(body) == int(rec.xml.get("n")) and set(body.split(";")[:-1]) == {str(k)}
        want = -k if rec.xml.get("updated") == "1" else k
        a = rec.attachments["a"]
        assert a.shape == (1000,) and (a == want).all()


def kill_mid_burst(path: Path, kill_after: int) -> tuple[list[tuple[str, int]], bool]:
    """Run the writer, kill it with SIGKILL inside a transaction after ``kill_after`` reported commits.

    Returns the commits it reported and whether the kill left a hot journal (an interrupted transaction).
    """
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    proc = subprocess.Popen([sys.executable, "-c", WRITER, str(path)], stdout=subprocess.PIPE, text=True, env=env)
    journal = path.with_name(path.name + "-journal")
    committed: list[tuple[str, int]] = []
    try:
        while len(committed) < kill_after:
            line = proc.stdout.readline()
            assert line, f"the writer stopped early (exit {proc.poll()})"
            op, i = line.split()
            committed.append((op, int(i)))
        while not journal.exists() and proc.poll() is None:
            pass  # the journal exists only while a transaction is open: kill inside one
        proc.send_signal(signal.SIGKILL)
        rest = proc.stdout.read()  # lines printed (so committed) before the kill landed
        committed += [(op, int(i)) for op, i in (ln.split() for ln in rest.splitlines())]
    finally:
        proc.kill()
        proc.wait()
        proc.stdout.close()
    assert proc.returncode == -signal.SIGKILL
    return committed, journal.exists() and journal.stat().st_size > 0


@pytest.mark.parametrize("kill_after", [25, 60])
def test_sigkill_during_a_burst_of_writes_loses_nothing_committed_and_leaves_nothing_half_written(tmp_path, kill_after):
    interrupted = False
    for attempt in range(3):  # until one kill lands inside a transaction (nearly always the first)
        path = tmp_path / f"burst{attempt}.sqlite"
        committed, interrupted = kill_mid_burst(path, kill_after)
        store = SqliteStore(path)  # rolls back whatever transaction the kill interrupted
        m = ActiveMemory("burst", store=store)
        check_consistent(m)
        ids = set(m.ids())
        inserted = [i for op, i in committed if op == "insert"]
        assert set(inserted) <= ids
        assert len(ids) <= len(inserted) + 1  # at most the one commit the writer had no time to report
        for op, i in committed:
            if op == "update":
                assert m.get(i).xml.get("updated") == "1"
        assert m.insert("<doc/>") > max(ids)  # the store goes on; ids are never reused
        store.close()
        if interrupted:
            break
    assert interrupted, "no kill landed inside a transaction: the rollback path was not exercised"


def test_a_corrupt_store_is_refused_and_moved_aside_never_overwriting(tmp_path):
    path = tmp_path / "m.sqlite"
    with SqliteStore(path) as s:
        ActiveMemory("objects", store=s).insert('<OBJECT type="cup"/>')
    good = path.read_bytes()
    (tmp_path / "m.sqlite.corrupt-1").write_bytes(b"an earlier casualty")
    broken = good[:100] + b"\xff" * 4096 + good[4196:]  # header intact, first page's contents destroyed
    path.write_bytes(broken)
    with pytest.raises(MemoryStoreError, match="corrupt") as err:
        SqliteStore(path)
    assert err.value.kept_at == str(tmp_path / "m.sqlite.corrupt-2")
    assert (tmp_path / "m.sqlite.corrupt-2").read_bytes() == broken
    assert (tmp_path / "m.sqlite.corrupt-1").read_bytes() == b"an earlier casualty"
    assert not path.exists()
    with SqliteStore(path) as fresh:  # the next run starts a new store
        assert ActiveMemory("objects", store=fresh).ids() == []


@pytest.mark.parametrize("content", [b"plain text, not a database\n" * 50, b""])
def test_garbage_or_a_foreign_database_is_refused(tmp_path, content):
    path = tmp_path / "m.sqlite"
    if content:
        path.write_bytes(content)
    else:
        db = sqlite3.connect(path)
        db.execute("CREATE TABLE t (x)")
        db.commit()
        db.close()
    before = path.read_bytes()
    with pytest.raises(MemoryStoreError) as err:
        SqliteStore(path)
    assert Path(err.value.kept_at).read_bytes() == before


def test_a_document_that_does_not_parse_makes_the_whole_store_refused(tmp_path):
    path = tmp_path / "m.sqlite"
    with SqliteStore(path) as s:
        m = ActiveMemory("objects", store=s)
        m.insert("<a/>")
        m.insert("<b/>")
    db = sqlite3.connect(path)
    db.execute("UPDATE documents SET xml = ? WHERE id = 2", (b"<b><unclosed></b>",))
    db.commit()
    db.close()
    with pytest.raises(MemoryStoreError, match="document 2 does not parse"):
        SqliteStore(path)


def test_a_store_from_a_newer_homesim_is_refused_and_left_untouched(tmp_path):
    path = tmp_path / "m.sqlite"
    with SqliteStore(path) as s:
        ActiveMemory("objects", store=s).insert("<a/>")
    db = sqlite3.connect(path)
    db.execute(f"PRAGMA user_version = {SCHEMA_VERSION + 1}")
    db.commit()
    db.close()
    before = path.read_bytes()
    with pytest.raises(MemoryStoreError, match="newer homesim") as err:
        SqliteStore(path)
    assert err.value.kept_at == str(path)
    assert path.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.sqlite"]


def test_a_version_1_store_is_migrated_and_keeps_its_documents(tmp_path):
    path = tmp_path / "old.sqlite"
    create_v1(path, {"objects": {1: b'<OBJECT type="cup"/>', 4: b'<OBJECT type="plant"/>'}, "places": {2: b"<PLACE/>"}})
    with SqliteStore(path) as s:
        assert s.migrated_from == 1
        m = ActiveMemory("objects", store=s)
        assert m.ids() == [1, 4]
        assert m.insert("<OBJECT/>", {"h": np.arange(4.0)}) == 5  # ids continue after the largest
        assert ActiveMemory("places", store=s).ids() == [2]
    db = sqlite3.connect(path)
    assert db.execute("PRAGMA user_version").fetchone()[0] == SCHEMA_VERSION
    db.close()
    with SqliteStore(path) as s:
        assert s.migrated_from is None
        np.testing.assert_array_equal(ActiveMemory("objects", store=s).get(5).attachments["h"], np.arange(4.0))


def test_without_a_store_nothing_is_written(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    m = ActiveMemory("objects")
    m.insert("<a/>", {"b": b"x"})
    m.remove(1)
    assert list(tmp_path.iterdir()) == []


def test_memory_show_prints_a_store_read_only_and_moves_nothing(tmp_path, capsys):
    from homesim.cli import main

    path = tmp_path / "scene_model.sqlite"
    with SqliteStore(path) as s:
        m = ActiveMemory("objects", store=s)
        m.insert('<OBJECT type="cup" name="cup"/>', {"hist": np.arange(3.0)})
        m.insert('<OBJECT type="plant" name="flower"/>')
        ActiveMemory("places", store=s).insert('<PLACE name="kitchen"/>')
    before = path.read_bytes()
    assert main(["memory", "show", str(path), "--memory", "objects", "--xpath", "/OBJECT[@type='cup']"]) == 0
    out = capsys.readouterr().out
    assert "[objects] 1 of 2 document(s)" in out and '#1 <OBJECT type="cup" name="cup"/>' in out
    assert "attachment hist: dtype <f8 shape 3" in out and "kitchen" not in out
    assert path.read_bytes() == before

    path.write_bytes(b"garbage" * 100)
    assert main(["memory", "show", str(path)]) == 2
    assert "cannot read the memory store" in capsys.readouterr().err
    assert path.read_bytes() == b"garbage" * 100 and sorted(p.name for p in tmp_path.iterdir()) == ["scene_model.sqlite"]

    old = tmp_path / "old.sqlite"
    create_v1(old, {"objects": {1: b"<a/>"}})
    with pytest.raises(MemoryStoreError, match="schema version 1"):
        SqliteStore(old, readonly=True)
    with SqliteStore(old) as s:  # a run migrates it
        assert s.migrated_from == 1


def test_one_memory_name_is_opened_once_per_store(tmp_path):
    with SqliteStore(tmp_path / "m.sqlite") as s:
        ActiveMemory("objects", store=s)
        with pytest.raises(MemoryStoreError, match="already open"):
            ActiveMemory("objects", store=s)


from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402
from hypothesis.extra import numpy as hnp  # noqa: E402

from homesim.memory.sqlite import decode_attachment, encode_attachment  # noqa: E402

from .conftest import examples  # noqa: E402

arrays = hnp.arrays(
    dtype=st.one_of(hnp.integer_dtypes(), hnp.unsigned_integer_dtypes(), hnp.floating_dtypes(), hnp.complex_number_dtypes(), hnp.boolean_dtypes()),
    shape=hnp.array_shapes(min_dims=0, max_dims=3, min_side=0, max_side=4),
)


@settings(max_examples=examples(100, 500))
@given(st.one_of(arrays, st.binary(max_size=64)))
def test_attachments_round_trip_exactly(value):
    back = decode_attachment(*encode_attachment(value))
    if isinstance(value, bytes):
        assert back == value
    else:
        assert back.dtype == value.dtype and back.shape == value.shape
        assert back.tobytes() == value.tobytes()  # bit for bit, NaNs included
        assert not back.flags.writeable
