"""Imports point one way: kernel <- world <- robot / humans <- run package <- command line.

Every arrow is read from the source, three ways: ``import`` statements (also
inside functions and ``TYPE_CHECKING`` blocks, relative ones resolved),
modules loaded by name (``importlib.import_module("x")``, ``__import__("x")``)
and module names or robot channels written in strings (``"robot.install"``,
``"/robot/es/log"``): a kernel that loads the robot by a name in a string
names it all the same. The layers (docs/architecture.md):

====================  ==========================================================
layer                 modules
====================  ==========================================================
0 kernel              ``homesim.*`` but the ones below: loop, bus, memory,
                      geometry, scenario model and loader, trace, registries
1 world               ``homesim.world.*``, ``homesim.viz.*`` (draws the world)
2 robot / humans      ``robot.*``, ``humans.*`` (siblings: neither imports the other)
3 run package         ``homesim.tour.*`` (the composition root)
4 command line        ``homesim.cli``, ``homesim.__main__``
====================  ==========================================================

A module may import its own layer and those below it, nothing above. The
same sources must have no package cycle (package A imports package B and B
imports A, through any chain).
"""

from __future__ import annotations

import ast
import re
from collections.abc import Iterator
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("homesim", "robot", "humans")
LAYERS = ("kernel", "world", "robot/humans", "run package", "command line")

#: A robot or people module (``robot.install``), file (``robot/afsm/...``) or channel (``/robot/es/log``) in a string.
NAMES_ROBOT = re.compile(r"(?<![\w.])(robot|humans)(?:[./][A-Za-z_]\w*)+")
#: The run package or the command line by module name.
NAMES_UPPER = re.compile(r"(?<![\w.])homesim\.(tour|cli)\b")


def layer(module: str) -> int:
    """The layer index of a module name of this project (see the module docstring)."""
    parts = module.split(".")
    if parts[0] in ("robot", "humans"):
        return 2
    if parts[:2] == ["homesim", "tour"]:
        return 3
    if parts[:2] in (["homesim", "cli"], ["homesim", "__main__"]):
        return 4
    if parts[:2] in (["homesim", "world"], ["homesim", "viz"]):
        return 1
    return 0


def module_name(path: Path) -> str:
    rel = path.relative_to(ROOT).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def sources() -> Iterator[tuple[Path, str]]:
    for pkg in PACKAGES:
        for path in sorted((ROOT / pkg).rglob("*.py")):
            yield path, module_name(path)


def _resolve(module: str, is_package: bool, level: int, name: str | None) -> str:
    base = module.split(".") if is_package else module.split(".")[:-1]
    if level > 1:
        base = base[: len(base) - (level - 1)]
    return ".".join(base + ([name] if name else []))


def _docstrings(tree: ast.AST) -> set[int]:
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)) and node.body:
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant) and isinstance(first.value.value, str):
                out.add(id(first.value))
    return out


def arrows(path: Path, module: str) -> Iterator[tuple[int, str, str]]:
    """``(line, target, how)`` for every module this file imports, loads by name or names in a string."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    is_package = path.name == "__init__.py"
    docs = _docstrings(tree)
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                yield node.lineno, a.name, "import"
        elif isinstance(node, ast.ImportFrom):
            target = node.module or "" if node.level == 0 else _resolve(module, is_package, node.level, node.module)
            yield node.lineno, target, "import"
            for a in node.names:
                yield node.lineno, f"{target}.{a.name}", "import"
        elif isinstance(node, ast.Call):
            fn = node.func
            called = fn.attr if isinstance(fn, ast.Attribute) else fn.id if isinstance(fn, ast.Name) else ""
            if called in ("import_module", "__import__") and node.args and isinstance(node.args[0], ast.Constant) \
                    and isinstance(node.args[0].value, str):
                yield node.lineno, node.args[0].value, "loaded by name"
        elif isinstance(node, ast.Constant) and isinstance(node.value, str):
            for m in NAMES_ROBOT.finditer(node.value):
                yield node.lineno, m.group(0).replace("/", "."), f"named in a string ({node.value[max(m.start() - 20, 0):m.end() + 20]!r})"
            if id(node) not in docs:
                for m in NAMES_UPPER.finditer(node.value):
                    yield node.lineno, m.group(0), f"named in a string ({node.value[:60]!r})"


def _project(target: str) -> bool:
    return target.split(".")[0] in PACKAGES


def back_arrows() -> list[str]:
    bad = []
    for path, module in sources():
        mine = layer(module)
        for line, target, how in arrows(path, module):
            if not _project(target):
                continue
            theirs = layer(target)
            sibling = mine == theirs == 2 and target.split(".")[0] != module.split(".")[0]
            if theirs > mine or sibling:
                rel = path.relative_to(ROOT)
                bad.append(f"{rel}:{line}: {LAYERS[mine]} -> {LAYERS[theirs]}: {target} ({how})")
    return bad


def test_no_arrow_runs_against_the_layers():
    assert back_arrows() == []


def test_the_kernel_never_names_the_robot_not_even_in_a_string():
    """Stricter than the layers for one case the ISSUE names: ``/robot/...`` channels and robot module
    names appear in ``homesim/`` only inside the run package (docstrings included)."""
    bad = []
    for path, module in sources():
        if layer(module) in (0, 1):
            for i, text in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
                if NAMES_ROBOT.search(text.split("#", 1)[0]):
                    bad.append(f"{path.relative_to(ROOT)}:{i}: {text.strip()}")
    assert bad == []


#: What every robot module may import of another robot package: the contract, the floor plan, and the
#: robot's configuration (its deployment: which host a module runs on and how fast that host is, for
#: processing costs; its profile: which robot is simulated). None of them imports another robot package.
ROBOT_SHARED = ("robot.contract", "robot.floorplan", "robot.deployment", "robot.profiles")


def test_robot_modules_talk_only_over_the_bus():
    """A robot module imports nothing of another robot package (``robot/install.py``, which installs
    them, and the shared contract and floor plan aside): modules meet on the bus, not in code."""
    bad = []
    for path, module in sources():
        parts = module.split(".")
        if parts[0] != "robot" or module in ("robot", "robot.install"):
            continue
        own = ".".join(parts[:2])
        for line, target, how in arrows(path, module):
            if how == "import" and target.startswith("robot.") and not target.startswith(own + ".") and target != own \
                    and not any(target == s or target.startswith(s + ".") for s in ROBOT_SHARED):
                bad.append(f"{path.relative_to(ROOT)}:{line}: {module} imports {target}")
    assert bad == []


def package_of(module: str) -> str | None:
    """The package a module belongs to for the cycle check: a directory below the top (``homesim.world``)."""
    parts = module.split(".")
    for n in range(len(parts), 1, -1):
        if (ROOT.joinpath(*parts[:n]) / "__init__.py").is_file():
            return ".".join(parts[:n]) if n >= 2 else None
    return None


def package_graph() -> dict[str, set[str]]:
    graph: dict[str, set[str]] = {}
    for path, module in sources():
        src = package_of(module)
        if src is None:
            continue
        for _, target, how in arrows(path, module):
            if how != "import" or not _project(target):
                continue
            dst = package_of(target)
            if dst is not None and dst != src and not dst.startswith(src + ".") and not src.startswith(dst + "."):
                graph.setdefault(src, set()).add(dst)
    return graph


def find_cycle(graph: dict[str, set[str]]) -> list[str] | None:
    """One cycle of the graph (its nodes in order), or None."""
    state: dict[str, int] = {}
    stack: list[str] = []

    def visit(n: str) -> list[str] | None:
        state[n] = 1
        stack.append(n)
        for m in sorted(graph.get(n, ())):
            if state.get(m) == 1:
                return stack[stack.index(m):] + [m]
            if m not in state:
                found = visit(m)
                if found:
                    return found
        stack.pop()
        state[n] = 2
        return None

    for n in sorted(graph):
        if n not in state:
            found = visit(n)
            if found:
                return found
    return None


def test_no_package_cycle():
    assert find_cycle(package_graph()) is None


# ----------------------------------------------------------- the test can fail
@pytest.mark.parametrize("source, module, expected", [
    ("import robot.install\n", "homesim.sim", "robot.install"),
    ("from ..tour.runner import Run\n", "homesim.world.stage", "homesim.tour.runner"),
    ("import importlib\nimportlib.import_module('humans.install')\n", "homesim.scenario.loader", "humans.install"),
    ("ACTORS = ('robot.hardware.install',)\n", "homesim.world.x", "robot.hardware.install"),
    ("LOG = '/robot/es/log'\n", "homesim.observe", "robot.es"),
    ("MODS = ['homesim.tour.run_cli']\n", "homesim.check", "homesim.tour"),
    ("from homesim.tour import runner\n", "robot.x", "homesim.tour"),
    ("from humans.person import Person\n", "robot.hardware.x", "humans.person"),
    ("from homesim.cli import main\n", "homesim.tour.x", "homesim.cli"),
    ("from homesim.world.world import World\n", "homesim.scenario.x", "homesim.world.world"),
])
def test_a_back_arrow_is_found(tmp_path, source, module, expected):
    path = tmp_path / "m.py"
    path.write_text(source, encoding="utf-8")
    found = [(t, how) for _, t, how in arrows(path, module) if _project(t) and layer(t) > layer(module)
             or (layer(t) == layer(module) == 2 and t.split(".")[0] != module.split(".")[0])]
    assert any(t.startswith(expected) for t, _ in found), found


def test_docstrings_may_point_up_but_code_strings_may_not(tmp_path):
    path = tmp_path / "m.py"
    path.write_text('"""See :mod:`homesim.tour.runner`."""\nX = "homesim.tour.runner"\n', encoding="utf-8")
    assert [line for line, t, _ in arrows(path, "homesim.x") if t.startswith("homesim.tour")] == [2]


def test_a_package_cycle_is_found():
    assert find_cycle({"a.x": {"a.y"}, "a.y": {"a.z"}, "a.z": {"a.x"}}) == ["a.x", "a.y", "a.z", "a.x"]
    assert find_cycle({"a.x": {"a.y"}, "a.y": set()}) is None
