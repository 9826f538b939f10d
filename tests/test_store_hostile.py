"""The memory store is untrusted input: hostile stores, fed to ``homesim run --memory``.

A store file may be edited, written by another program or left read-only.
Each is refused at the start of the run with one line naming the store (and
the document), exit 2, and the store is left exactly as it was.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import sys
from pathlib import Path

import pytest

from homesim.cli import main
from homesim.memory import ActiveMemory, SqliteStore

ROOT = Path(__file__).resolve().parents[1]
SCENARIO = ROOT / "scenarios" / "two_people_radio.xml"
STORE_FILE = "scene_model.sqlite"

GOOD_OBJECT = '<OBJECT type="cup" name="cup" x="1.0" y="2.0" frame="map" taught="3.0"/>'
GOOD_PLACE = '<PLACE name="kitchen" x="1.0" y="2.0" theta="0.5" frame="map" taught="3.0"/>'
#: memory -> a stored document no knowledge base could have written.
BAD_DOCUMENTS = {
    "object x not a number": ("objects", '<OBJECT type="cup" name="cup" x="abc" y="2.0" frame="map" taught="3.0"/>'),
    # (no position at all is a valid object: taught from speech alone, the biron-2005 profile)
    "object with x but no y": ("objects", '<OBJECT type="cup" name="cup" x="1.0" frame="map" taught="3.0"/>'),
    "object y NaN": ("objects", '<OBJECT type="cup" name="cup" x="1" y="NaN" frame="map" taught="3.0"/>'),
    "object without a type": ("objects", '<OBJECT name="cup" x="1" y="2" frame="map" taught="3.0"/>'),
    "object in another frame": ("objects", '<OBJECT type="cup" name="cup" x="1" y="2" frame="odom" taught="3.0"/>'),
    "place theta not a number": ("places", '<PLACE name="kitchen" x="1.0" y="2.0" theta="abc" frame="map" taught="3.0"/>'),
    "place with a negative time": ("places", '<PLACE name="kitchen" x="1.0" y="2.0" theta="0" frame="map" taught="-1"/>'),
    "a place among the objects": ("objects", GOOD_PLACE),
    "an object among the places": ("places", GOOD_OBJECT),
    "an unknown element": ("objects", "<script>run()</script>"),
    # numerals the pattern takes that read back as infinity, or a home 1e300 m across
    "object x overflows to infinity": ("objects", '<OBJECT type="cup" name="cup" x="1e999" y="2.0" frame="map" taught="3.0"/>'),
    "object size overflows to infinity": ("objects", '<OBJECT type="cup" name="cup" size="1e999" frame="map" taught="3.0"/>'),
    "place theta overflows to infinity": ("places", '<PLACE name="kitchen" x="1.0" y="2.0" theta="-1e400" frame="map" taught="3.0"/>'),
    "place taught overflows to infinity": ("places", '<PLACE name="kitchen" x="1.0" y="2.0" theta="0" frame="map" taught="1e999"/>'),
    "place 1e300 m from the origin": ("places", '<PLACE name="kitchen" x="1e300" y="2.0" theta="0" frame="map" taught="3.0"/>'),
}


def _store_with(directory: Path, memory: str, bad: str) -> Path:
    path = directory / STORE_FILE
    with SqliteStore(path) as store:
        ActiveMemory("objects", store=store).insert(GOOD_OBJECT)
        ActiveMemory("places", store=store).insert(GOOD_PLACE)
    with SqliteStore(path) as store:  # a second session, as a later run or another program would write
        m = ActiveMemory(memory, store=store)
        m.insert(bad)
    return path


def _digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


@pytest.mark.parametrize("case", sorted(BAD_DOCUMENTS))
def test_a_bad_stored_document_is_refused_at_start_naming_store_and_document(tmp_path, capsys, case):
    memory, bad = BAD_DOCUMENTS[case]
    path = _store_with(tmp_path / "mem", memory, bad)
    before = _digest(path)
    code = main(["run", str(SCENARIO), "--until", "1", "--quiet", "--memory", str(tmp_path / "mem")])
    err = capsys.readouterr().err.strip()
    assert code == 2, err
    assert len(err.splitlines()) == 1 and "Traceback" not in err
    assert str(path) in err and f"memory {memory!r} document 2" in err, err
    assert _digest(path) == before
    assert sorted(p.name for p in (tmp_path / "mem").iterdir()) == [STORE_FILE]


def test_good_stored_documents_load(tmp_path, capsys):
    """The check refuses only what is wrong: the same store with good documents runs."""
    path = _store_with(tmp_path / "mem", "objects", GOOD_OBJECT.replace("cup", "mug"))
    assert main(["run", str(SCENARIO), "--until", "1", "--quiet", "--memory", str(path.parent)]) == 0, capsys.readouterr().err


def _as_unprivileged(argv: list[str]) -> list[str]:
    """``homesim ARGV`` in a process file modes apply to: root without the capabilities that override them."""
    cmd = [sys.executable, "-m", "homesim.cli", *argv]
    if os.geteuid() != 0:
        return cmd
    setpriv = shutil.which("setpriv")
    if setpriv is None:
        pytest.skip("running as root without setpriv: file modes do not apply to this process")
    drop = "-dac_override,-dac_read_search,-fowner"
    return [setpriv, f"--inh-caps={drop}", f"--bounding-set={drop}", *cmd]


def test_a_read_only_store_file_is_refused_at_start(tmp_path):
    """A store file this user cannot write (in a writable directory) stops the run before it starts."""
    import stat
    import subprocess

    mem = tmp_path / "mem"
    path = _store_with(mem, "objects", GOOD_OBJECT.replace("cup", "mug"))
    os.chmod(path, stat.S_IRUSR | stat.S_IRGRP | stat.S_IROTH)  # the directory stays writable: only the file is read-only
    before = _digest(path)
    proc = subprocess.run(_as_unprivileged(["run", str(SCENARIO), "--until", "1", "--quiet", "--memory", str(mem)]),
                          capture_output=True, text=True, cwd=ROOT)
    err = proc.stderr.strip()
    assert proc.returncode == 2, (proc.stdout, err)
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    assert str(path) in err and "cannot be written" in err, err
    assert _digest(path) == before and sorted(p.name for p in mem.iterdir()) == [STORE_FILE]
