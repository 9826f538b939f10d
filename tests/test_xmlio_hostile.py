"""Hostile XML whatever its encoding, and inputs that are not regular files.

The class under test: a document must never make homesim open a file other
than its own input, connect anywhere, or block. UTF-16/UTF-32 (with or without
a byte-order mark) and foreign encoding declarations (UTF-7 can spell ``<`` as
``+ADw-``) used to hide a DOCTYPE from the byte-level check; the parser itself
then loaded parameter entities. Both layers are tested: the refusal (a clear
error naming the encoding) and, under ``strace``, that libxml2 opens nothing.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from homesim.errors import InputError, XMLInputError
from homesim.xmlio import MAX_DOCUMENT_BYTES, parse_bytes, parse_file, read_input

from .conftest import examples

ROOT = Path(__file__).resolve().parents[1]

#: (codec, name written in the declaration) for every non-UTF-8 form we know libxml2 detects.
FOREIGN = [
    ("utf-16", "UTF-16"),  # with BOM
    ("utf-16-le", "UTF-16"),  # no BOM
    ("utf-16-be", "UTF-16"),
    ("utf-32", "UTF-32"),
    ("utf-32-le", "UTF-32"),
    ("utf-32-be", "UTF-32"),
]


def payloads(target: str) -> list[str]:
    """Documents that would read ``target`` if any DTD or entity were honoured."""
    return [
        f'<!DOCTYPE r [<!ENTITY % p SYSTEM "{target}"> %p;]><r>x</r>',
        f'<!DOCTYPE r SYSTEM "{target}"><r>x</r>',
        f'<!DOCTYPE r [<!ENTITY g SYSTEM "{target}">]><r>&g;</r>',
        f'<!DOCTYPE r PUBLIC "-//X//Y" "{target}"><r/>',
        f'<!-- c --><?pi x?>\n<!DOCTYPE r [<!ENTITY % p SYSTEM "{target}"> %p;]><r>x</r>',
        f'<r xmlns:xi="http://www.w3.org/2001/XInclude"><xi:include href="{target}" parse="text"/></r>',
    ]


def encoded(doc: str, codec: str, declared: str | None) -> bytes:
    decl = f'<?xml version="1.0" encoding="{declared}"?>' if declared else ""
    return (decl + doc).encode(codec)


@pytest.mark.parametrize("codec,declared", FOREIGN)
@pytest.mark.parametrize("with_decl", [True, False])
def test_utf16_and_utf32_documents_are_refused_naming_the_encoding(tmp_path, codec, declared, with_decl):
    secret = tmp_path / "secret.txt"
    secret.write_text("TOP-SECRET")
    for doc in payloads(f"file://{secret}") + ["<r>harmless</r>"]:
        data = encoded(doc, codec, declared if with_decl else None)
        with pytest.raises(XMLInputError, match=r"UTF-(16|32)|NUL byte.*UTF-8 only") as info:
            parse_bytes(data, source="enc.xml")
        assert "TOP-SECRET" not in str(info.value)
        assert str(info.value).startswith("enc.xml:1: ")


@pytest.mark.parametrize("declared", ["UTF-7", "ISO-8859-1", "windows-1252", "Shift_JIS", "EBCDIC-US", "UTF-16", "  "])
def test_encoding_declarations_other_than_utf8_are_refused(declared):
    # UTF-7 would turn "+ADw-" into "<": the DOCTYPE check would see no DOCTYPE.
    data = f'<?xml version="1.0" encoding="{declared}"?>\n<r>+ADw-b/+AD4-</r>'.encode()
    with pytest.raises(XMLInputError, match=r"enc\.xml:1: declared encoding .* refused: homesim reads UTF-8"):
        parse_bytes(data, source="enc.xml")


@pytest.mark.parametrize("declared", ["UTF-8", "utf-8", "utf8", "US-ASCII", "ascii"])
def test_utf8_and_ascii_declarations_are_accepted(declared):
    root = parse_bytes(f"<?xml version='1.0' encoding='{declared}'?>\n<r a='1'/>".encode())
    assert root.get("a") == "1"
    assert parse_bytes(b"\xef\xbb\xbf<r/>").tag == "r"  # a UTF-8 byte-order mark is fine


@settings(max_examples=examples(200, 1000))
@given(
    body=st.sampled_from(payloads("file:///etc/hostname") + ["<r>é</r>", "<r/>"]),
    codec=st.sampled_from(["utf-8", "utf-16", "utf-16-le", "utf-16-be", "utf-32", "utf-32-le", "utf-32-be", "utf-7", "latin-1", "cp500"]),
    declared=st.sampled_from([None, "UTF-8", "UTF-16", "UTF-32", "UTF-7", "ISO-8859-1", "EBCDIC"]),
    prefix=st.sampled_from(["", "\n", "<!-- x -->", "<?pi?>", " \t"]),
)
def test_any_encoding_gives_a_doctype_free_tree_or_an_input_error(body, codec, declared, prefix):
    """Property: whatever the encoding, parse_bytes returns a tree without a DTD or raises XMLInputError."""
    try:
        data = encoded(prefix + body, codec, declared) if declared else (prefix + body).encode(codec)
    except UnicodeEncodeError:
        return
    try:
        root = parse_bytes(data, source="p.xml")
    except XMLInputError as exc:
        assert str(exc).startswith("p.xml")
        return
    info = root.getroottree().docinfo
    assert not info.doctype and info.internalDTD is None and info.externalDTD is None
    assert "xi:include" not in str(root.tag)



# ----------------------------------------------------------- system-call trace
def _strace_usable() -> str | None:
    """None when ``strace -f`` can trace a child here, else the reason it cannot."""
    exe = shutil.which("strace")
    if exe is None:
        return "strace is not installed (.ci/run installs it from Debian when it can)"
    try:
        proc = subprocess.run([exe, "-f", "-e", "trace=openat", "-o", os.devnull, "true"], capture_output=True, timeout=60)
    except (OSError, subprocess.TimeoutExpired) as exc:
        return f"strace cannot run: {exc}"
    if proc.returncode != 0:
        return f"strace cannot trace here (ptrace refused?): {proc.stderr.decode(errors='replace').strip()[:200]}"
    return None


PROBE = textwrap.dedent(
    """
    import os, sys
    from lxml import etree
    from homesim.xmlio import parse_bytes, parse_file, hardened_parser, ExternalResourceRefused
    from homesim.errors import InputError
    from homesim.scenario.loader import load_scenario
    from homesim.afsm.loader import check_file
    from tests.test_xmlio_hostile import payloads, FOREIGN, encoded

    inputs = {inputs!r}
    targets = {targets!r}
    os.makedirs(inputs, exist_ok=True)
    docs = []
    for t in targets:
        for body in payloads(t):
            # the UTF-8 XInclude document is well-formed and inert (XInclude is never processed)
            if "DOCTYPE" in body:
                docs.append(body.encode("utf-8"))
            docs.append(('<?xml version="1.0" encoding="UTF-7"?>' + body.replace("<", "+ADw-")).encode())
            for codec, declared in FOREIGN:
                docs.append(encoded(body, codec, declared))
                docs.append(encoded(body, codec, None))
    paths = []
    for i, d in enumerate(docs):
        p = os.path.join(inputs, f"doc{{i}}.xml")
        with open(p, "wb") as fh:
            fh.write(d)
        paths.append(p)
    # warm up every entry point (lazy imports, schema compilation) before the mark
    ok = os.path.join(inputs, "ok.xml")
    with open(ok, "wb") as fh:
        fh.write(b"<r/>")
    for f in (parse_file, load_scenario, check_file):
        try:
            f(ok)
        except InputError:
            pass
    try:
        open("/nonexistent-homesim-mark/BEGIN")
    except OSError:
        pass
    refused = 0
    for d in docs:
        try:
            parse_bytes(d, source="x")
        except InputError:
            refused += 1
        try:  # the bare parser (no pre-checks) must load nothing either
            etree.fromstring(d, hardened_parser())
        except (etree.XMLSyntaxError, ExternalResourceRefused):
            pass
    for p in paths:
        for f in (parse_file, load_scenario, check_file):
            try:
                r = f(p)
                if isinstance(r, list) and r:
                    refused += 1
            except InputError:
                refused += 1
    print("REFUSED", refused, "OF", len(docs) + len(paths) * 3)
    """
)


def test_no_document_in_any_encoding_opens_a_file_or_a_socket(tmp_path):
    """Under strace: after the warm-up, only the input files are opened and nothing connects."""
    reason = _strace_usable()
    if reason:
        pytest.skip(reason)
    secret = tmp_path / "secret.txt"
    secret.write_text("TOP-SECRET")
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    inputs = tmp_path / "inputs"
    targets = [f"file://{secret}", str(secret), f"file://{fifo}", "/dev/zero", "http://127.0.0.1:9/evil.dtd"]
    script = tmp_path / "probe.py"
    script.write_text(PROBE.format(inputs=str(inputs), targets=targets))
    log = tmp_path / "strace.log"
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    proc = subprocess.run(
        ["strace", "-f", "-qq", "-e", "trace=open,openat,openat2,creat,connect", "-o", str(log), sys.executable, str(script)],
        capture_output=True,
        text=True,
        env=env,
        timeout=600,  # a hang safeguard only (a FIFO or /dev/zero read would block for ever)
    )
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert "REFUSED" in proc.stdout
    lines = log.read_text().splitlines()
    mark = next(i for i, line in enumerate(lines) if "homesim-mark" in line)
    after = lines[mark + 1 :]
    assert not [line for line in after if "connect(" in line]
    opened = [line for line in after if "open" in line and "ENOENT" not in line]
    foreign = [line for line in opened if str(inputs) not in line]
    assert foreign == [], "files opened other than the inputs:\n" + "\n".join(foreign[:20])
    for needle in (str(secret), str(fifo), "/dev/zero"):
        assert not [line for line in after if needle in line]
    refused, total = (int(w) for w in proc.stdout.split()[1::2])
    assert refused == total  # every hostile document was refused, by every entry point


# ------------------------------------------------------- non-regular files
def _kinds(tmp_path: Path) -> list[tuple[str, str]]:
    fifo = tmp_path / "fifo.xml"
    os.mkfifo(fifo)
    return [
        ("/dev/zero", "character device"),
        ("/dev/urandom", "character device"),
        (str(fifo), "FIFO"),
        (str(tmp_path), "directory"),
    ]


def test_read_input_refuses_devices_fifos_and_directories_before_reading(tmp_path):
    for path, kind in _kinds(tmp_path):
        with pytest.raises(XMLInputError, match=f"is not a regular file \\(an? {kind}\\)") as info:
            read_input(path)
        assert str(info.value).startswith(path + ": ")


def test_read_input_refuses_files_over_the_limit_and_names_it(tmp_path):
    big = tmp_path / "big.xml"
    big.write_bytes(b"<r>" + b" " * 100 + b"</r>")
    with pytest.raises(XMLInputError, match=r"big\.xml: file is 107 bytes, larger than the limit of 50"):
        read_input(big, limit=50)
    assert read_input(big, limit=107) == big.read_bytes()


def test_read_input_follows_symlinks_to_check_the_real_file(tmp_path):
    link = tmp_path / "link.xml"
    link.symlink_to("/dev/zero")
    with pytest.raises(XMLInputError, match="character device"):
        read_input(link)


def test_every_file_entry_point_refuses_non_regular_files(tmp_path):
    from homesim.afsm.loader import check_file, load
    from homesim.scenario.loader import load_scenario

    for path, kind in _kinds(tmp_path):
        for entry in (parse_file, load_scenario, load):
            with pytest.raises(InputError, match=f"not a regular file \\(an? {kind}\\)"):
                entry(path)
        problems = check_file(path)
        assert len(problems) == 1 and kind in str(problems[0])


@pytest.mark.parametrize("argv", [["scenario", "run"], ["scenario", "plot", "--at", "1"], ["afsm", "check"], ["afsm", "show"]])
def test_cli_refuses_non_regular_files_with_one_line(tmp_path, argv, capsys):
    from homesim.cli import main

    for path, kind in _kinds(tmp_path):
        if argv[0] == "scenario":
            args = argv[:2] + [path] + argv[2:] + (["-o", str(tmp_path / "o.png")] if argv[1] == "plot" else [])
        else:
            args = argv + [path]
        code = main(args)
        out = capsys.readouterr()
        assert code in (1, 2)
        assert kind in out.out + out.err and "Traceback" not in out.out + out.err


def test_documented_size_limit_is_the_one_enforced():
    text = (ROOT / "docs" / "running.md").read_text(encoding="utf-8")
    assert f"`MAX_DOCUMENT_BYTES` = {MAX_DOCUMENT_BYTES} bytes" in text


def test_reading_a_trace_refuses_non_regular_files(tmp_path):
    from homesim.trace import read_trace

    for path, kind in _kinds(tmp_path):
        with pytest.raises(InputError, match=f"not a regular file \\(an? {kind}\\)"):
            next(read_trace(path))
