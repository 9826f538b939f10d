"""BIRON's contract as code (robot/contract.py) agrees with the docs, the schemas and a real run."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest
from lxml import etree

from robot import contract

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "robot-contract.md"
XS = "{http://www.w3.org/2001/XMLSchema}"


def _doc() -> str:
    return DOC.read_text(encoding="utf-8")


def test_the_docs_channel_table_is_the_contracts():
    text = _doc()
    m = re.search(r"<!-- contract table: begin -->\n(.*?)<!-- contract table: end -->", text, re.S)
    assert m, "docs/robot-contract.md lost its generated channel table"
    assert m.group(1) == contract.markdown_table()


def test_every_channel_the_docs_describe_is_in_the_contract_with_its_sender():
    """The hand-written table ("Channels added by the robot"): channel and sender as the contract says."""
    rows = re.findall(r"^\| `(/robot/[^`]+)` \| ([a-z_]+) \|", _doc(), re.M)
    described = [(ch, who) for ch, who in rows if who != "published"]
    assert len(described) >= 10
    for ch, who in described:
        assert who in contract.channel(ch).publishers, f"{ch}: docs say {who}, contract {contract.channel(ch).publishers}"


def test_each_schema_exists_and_declares_the_payload_root():
    for c in contract.CHANNELS:
        tops = {e.get("name") for e in etree.parse(str(c.schema_path)).getroot().findall(f"{XS}element")}
        assert set(c.root.split("|")) <= tops, f"{c.name}: {c.schema} declares {sorted(tops)}, not {c.root}"


def test_names_are_unique_and_family_members_resolve():
    assert len(contract.BY_NAME) == len(contract.CHANNELS)
    assert contract.channel("/robot/es/orders/player").name == contract.ES_ORDERS
    with pytest.raises(KeyError, match="not a channel"):
        contract.channel("/robot/laser/scan/extra")
    with pytest.raises(KeyError):
        contract.channel("/robot/nowhere")


def _robot_channel_literals() -> list[tuple[str, int, str]]:
    out = []
    for pkg in ("robot", "homesim/tour", "humans"):
        for path in sorted((ROOT / pkg).rglob("*.py")):
            for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
                if isinstance(node, ast.Constant) and isinstance(node.value, str) and re.fullmatch(r"/robot/[a-z_/]+", node.value):
                    out.append((str(path.relative_to(ROOT)), node.lineno, node.value))
    return out


def test_every_robot_channel_written_in_code_is_in_the_contract():
    unknown = []
    for where, line, name in _robot_channel_literals():
        if name.endswith("/"):  # a prefix to subscribe or match by
            continue
        try:
            contract.channel(name)
        except KeyError:
            unknown.append(f"{where}:{line}: {name}")
    assert unknown == []


def test_a_run_declares_exactly_the_contracts_schemas():
    from homesim.tour.runner import Run, RunOptions

    with Run.from_file(ROOT / "scenarios" / "two_people_radio.xml", RunOptions(seed=0, until=0.1)) as run:
        declared = {ch: s.name for ch, s in run.sim.bus._channel_schemas.items() if ch.startswith("/robot/")}
    for ch, schema in declared.items():
        assert Path(contract.channel(ch).schema or "").name == schema, ch
    assert {contract.channel(ch).name for ch in declared} == set(contract.BY_NAME)


def _robot_channels_built_in_fstrings(root: Path, packages: tuple[str, ...]) -> list[str]:
    """f-strings that spell a robot channel out (``f"/robot/{NAME}/refused"``) instead of building on a
    contract name (``f"{ES_ORDERS}/{NAME}"``, a family member): a name the contract cannot see."""
    out = []
    for pkg in packages:
        for path in sorted((root / pkg).rglob("*.py")):
            for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
                if isinstance(node, ast.JoinedStr) and node.values and isinstance(node.values[0], ast.Constant) \
                        and str(node.values[0].value).startswith("/robot/"):
                    out.append(f"{path.relative_to(root)}:{node.lineno}")
    return out


def test_no_robot_channel_is_spelled_out_in_an_fstring(tmp_path):
    assert _robot_channels_built_in_fstrings(ROOT, ("robot", "homesim/tour", "humans")) == []
    (tmp_path / "m.py").write_text('N = "x"\nA = f"/robot/{N}/refused"\nB = f"{A}/{N}"\n', encoding="utf-8")
    assert _robot_channels_built_in_fstrings(tmp_path, (".",)) == ["m.py:2"]
