"""The checked XML documents (state machines, dialogs) share one pipeline: read -> hardened parse -> check -> model.

Before, ``homesim/afsm/loader.py`` and ``robot/dialog/loader.py`` each wrote their own read, parse,
error conversion and raise; a fix to one (a size limit, a regular-files-only read) could miss the
other. Now both are a :class:`homesim.xmldoc.DocumentKind`, and neither loader reads or parses
itself. The messages and exception types stay what each kind promised.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from homesim.afsm import loader as afsm
from homesim.errors import AFSMError, AFSMProblems, XMLInputError
from homesim.xmldoc import DocumentKind
from robot.dialog import loader as dialog
from robot.dialog.loader import DialogError, DialogProblems

ROOT = Path(__file__).resolve().parents[1]
LOADERS = (ROOT / "homesim/afsm/loader.py", ROOT / "robot/dialog/loader.py")
#: The pipeline's steps that only :mod:`homesim.xmldoc` may take for these kinds.
READERS = {"parse_bytes", "parse_file", "read_input"}


@pytest.mark.parametrize("path", LOADERS, ids=lambda p: p.parent.name)
def test_neither_loader_reads_or_parses_on_its_own(path):
    tree = ast.parse(path.read_text(encoding="utf-8"))
    used = {a.name for n in ast.walk(tree) if isinstance(n, ast.ImportFrom) for a in n.names} \
        | {n.attr for n in ast.walk(tree) if isinstance(n, ast.Attribute)}
    assert used & READERS == set()


def test_both_kinds_are_the_one_pipeline():
    assert isinstance(afsm.AFSM_DOCUMENT, DocumentKind)
    assert isinstance(dialog.DIALOG_DOCUMENT, DocumentKind)


KINDS = [
    pytest.param(afsm, AFSMError, "afsm", id="afsm"),
    pytest.param(dialog, DialogError, "dialog", id="dialog"),
]


@pytest.mark.parametrize("mod, error, kind", KINDS)
def test_malformed_text_is_one_problem_with_source_and_line(mod, error, kind):
    found = mod.check("<a>\n<b>\n</a>\n", source="x.xml")
    assert len(found) == 1 and isinstance(found[0], error)
    assert found[0].source == "x.xml" and found[0].line == 3


@pytest.mark.parametrize("mod, error, kind", KINDS)
def test_a_directory_is_refused_as_a_problem_naming_it(mod, error, kind, tmp_path):
    found = mod.check_file(tmp_path)
    assert len(found) == 1 and isinstance(found[0], error) and str(tmp_path) in str(found[0])


def test_malformed_text_raises_what_each_kind_promised():
    with pytest.raises(XMLInputError):
        afsm.loads("<scxml", source="m.scxml")
    with pytest.raises(DialogProblems) as exc:
        dialog.loads("<dialogs", source="d.xml")
    assert exc.value.problems[0].source == "d.xml"


def test_problems_raise_the_kinds_exception_listing_every_problem():
    with pytest.raises(AFSMProblems):
        afsm.loads('<scxml xmlns="http://www.w3.org/2005/07/scxml" version="1.0"><nope/></scxml>')
    with pytest.raises(DialogProblems):
        dialog.loads("<dialogs><nope/></dialogs>")


def test_a_kind_sees_the_raw_bytes_and_gets_its_options():
    seen: list[tuple[str, bytes]] = []

    def check_root(root, *, source, flavour="plain"):
        return (f"{root.tag}:{flavour}", []) if root.tag == "ok" else (None, [XMLInputError("bad root", source=source)])

    kind = DocumentKind(check_root=check_root, error=XMLInputError, problems=lambda ps: ValueError(ps),
                        prepare=lambda root, raw: seen.append((root.tag, raw)))
    assert kind.loads("<ok/>", flavour="spicy") == "ok:spicy"
    assert seen == [("ok", b"<ok/>")]
    with pytest.raises(ValueError):
        kind.loads("<no/>")
    assert [str(p) for p in kind.check("<no/>", source="s")] == [str(XMLInputError("bad root", source="s"))]
