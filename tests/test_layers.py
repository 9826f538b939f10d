"""Imports point one way: kernel <- world <- robot / humans <- run package <- command line.

Every arrow is read from the source, three ways: ``import`` statements (also
inside functions and ``TYPE_CHECKING`` blocks, relative ones resolved),
modules loaded by name (``importlib.import_module("x")``, ``__import__("x")``,
``find_spec``, ``pkgutil.resolve_name``, ``sys.modules["x"]``, a loader under
an alias or through ``getattr``, relative names resolved) and module names or
robot channels written in strings (``"robot.install"``, ``"/robot/es/log"``,
the prefix ``"/robot/"``; also built by f-string, ``+`` or ``Path / "part"``):
a kernel that loads the robot by a name in a string names it all the same.
The entry points in pyproject.toml, the one sanctioned way up, are checked too. The layers (docs/architecture.md):

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

#: A robot or people module (``robot.install``), file (``robot/afsm/...``), channel (``/robot/es/log``) or the
#: channels' prefix alone (``"/robot/"``) in a string.
NAMES_ROBOT = re.compile(r"(?<![\w.])(robot|humans)(?:[./][A-Za-z_]\w*)+"
                         r"|(?<![\w./])/(robot|humans)(?=/?(?:$|[^\w./]))")
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


#: Calls that load a module by the name in their first argument (``pkgutil.resolve_name`` takes ``"mod:attr"``).
LOADERS = ("import_module", "__import__", "find_spec", "resolve_name", "find_loader", "load_module")


def _loader_aliases(tree: ast.AST) -> set[str]:
    """The loaders under this file's own names (``from importlib import import_module as load``)."""
    return {a.asname or a.name for node in ast.walk(tree) if isinstance(node, ast.ImportFrom)
            for a in node.names if a.name in LOADERS}


def _called(fn: ast.expr) -> str:
    """The name a call reaches: ``f()``, ``m.f()``, and ``getattr(m, "f")()``."""
    if isinstance(fn, ast.Attribute):
        return fn.attr
    if isinstance(fn, ast.Name):
        return fn.id
    if isinstance(fn, ast.Call) and isinstance(fn.func, ast.Name) and fn.func.id == "getattr" and len(fn.args) >= 2 \
            and isinstance(fn.args[1], ast.Constant) and isinstance(fn.args[1].value, str):
        return fn.args[1].value
    return ""


def _folded(node: ast.expr) -> str | None:
    """A string built of pieces (f-string, ``+``, ``Path / "part"``) with ``x`` for each unknown piece, or None
    when no piece is a literal string: ``f"/robot/{sub}/log"`` -> ``"/robot/x/log"``."""
    if isinstance(node, ast.Constant):
        return node.value if isinstance(node.value, str) else None
    if isinstance(node, ast.JoinedStr):
        return "".join(v.value if isinstance(v, ast.Constant) else "x" for v in node.values)
    if isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Add, ast.Div)):
        left, right = _folded(node.left), _folded(node.right)
        if left is None and right is None:
            return None
        return (left or "x") + ("/" if isinstance(node.op, ast.Div) else "") + (right or "x")
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in ("Path", "PurePath") \
            and len(node.args) == 1:
        return _folded(node.args[0])
    return None


def _names_in(text: str) -> Iterator[tuple[str, str]]:
    for m in NAMES_ROBOT.finditer(text):
        yield m.group(0).strip("/").replace("/", "."), f"named in a string ({text[max(m.start() - 20, 0):m.end() + 20]!r})"


def arrows(path: Path, module: str) -> Iterator[tuple[int, str, str]]:
    """``(line, target, how)`` for every module this file imports, loads by name or names in a string."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    is_package = path.name == "__init__.py"
    package = module if is_package else module.rpartition(".")[0]
    docs = _docstrings(tree)
    loaders = set(LOADERS) | _loader_aliases(tree)
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                yield node.lineno, a.name, "import"
        elif isinstance(node, ast.ImportFrom):
            target = node.module or "" if node.level == 0 else _resolve(module, is_package, node.level, node.module)
            yield node.lineno, target, "import"
            for a in node.names:
                yield node.lineno, f"{target}.{a.name}", "import"
        elif isinstance(node, ast.Call) and _called(node.func) in loaders and node.args \
                and isinstance(node.args[0], ast.Constant) and isinstance(node.args[0].value, str):
            name = node.args[0].value.split(":")[0]
            if name.startswith("."):
                # a relative name: against the package given (a literal) or this module's own (``__package__``)
                anchor = node.args[1] if len(node.args) > 1 else None
                base = anchor.value if isinstance(anchor, ast.Constant) and isinstance(anchor.value, str) else package
                level = len(name) - len(name.lstrip("."))
                parts = base.split(".")
                name = ".".join(parts[: len(parts) - (level - 1)] + ([name.lstrip(".")] if name.lstrip(".") else []))
            yield node.lineno, name, "loaded by name"
        elif isinstance(node, ast.Subscript) and isinstance(node.value, ast.Attribute) and node.value.attr == "modules" \
                and isinstance(node.slice, ast.Constant) and isinstance(node.slice.value, str):
            yield node.lineno, node.slice.value, "taken from sys.modules"
        if isinstance(node, (ast.Constant, ast.JoinedStr, ast.BinOp)):
            text = _folded(node)
            if text is None:
                continue
            for target, how in _names_in(text):
                yield node.lineno, target, how
            if id(node) not in docs:
                for m in NAMES_UPPER.finditer(text):
                    yield node.lineno, m.group(0), f"named in a string ({text[:60]!r})"


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


#: A whole string that is a robot or people module's dotted name, what a loader takes (``"humans.install"``,
#: ``"robot.hardware.install:install"``, ``f"robot.{name}"``); channels (``/robot/...``) and files are not names.
MODULE_NAME = re.compile(r"\s*(robot|humans)(?:\.[A-Za-z_]\w*)+(?::[A-Za-z_]\w*)?\s*")


def module_names_in_strings(path: Path) -> Iterator[tuple[int, str]]:
    """``(line, text)`` for every string of code (docstrings aside) that is a robot or people module's name."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    docs = _docstrings(tree)
    for node in ast.walk(tree):
        if isinstance(node, (ast.Constant, ast.JoinedStr, ast.BinOp)) and id(node) not in docs:
            text = _folded(node)
            if text is not None and MODULE_NAME.fullmatch(text):
                yield node.lineno, text


def test_homesim_never_names_a_robot_or_people_module_in_a_string():
    """Not even the run package: it imports what it composes (``runner.ACTORS`` holds the install functions
    it hands the stage), so every arrow up is an import the checks above see. A module name in a string
    is a module loaded where the import graph cannot see it, and a stage that names the robot's hardware
    is a kernel that knows BIRON."""
    bad = [f"{path.relative_to(ROOT)}:{line}: {text!r}" for path, module in sources() if module.startswith("homesim")
           for line, text in module_names_in_strings(path)]
    assert bad == []


@pytest.mark.parametrize("source, found", [
    ("ACTORS = ('humans.install', 'robot.hardware.install')\n", ["humans.install", "robot.hardware.install"]),
    ("def load(n):\n    return importlib.import_module(f'robot.{n}')\n", ["robot.x"]),
    ("X = 'robot.hardware.install:install'\n", ["robot.hardware.install:install"]),
    ("X = 'humans.' + 'install'\n", ["humans.install"]),
    # not module names: a docstring, a channel, a file, a word, a sentence naming one
    ('"""Installs ``humans.install``."""\n', []),
    ("C = '/robot/es/log'\nF = 'robot/afsm/biron.scxml'\nW = 'robot'\n", []),
    ("M = 'unknown subsystem (see robot.install.SUBSYSTEMS)'\n", []),
])
def test_a_module_named_in_a_string_is_found(tmp_path, source, found):
    path = tmp_path / "m.py"
    path.write_text(source, encoding="utf-8")
    assert sorted(text for _, text in module_names_in_strings(path)) == found


#: What every robot module may import of another robot package: the contract, the floor plan, and the
#: robot's configuration (its deployment: which host a module runs on and how fast that host is, for
#: processing costs; its profile: which robot is simulated), and the rules modules must agree on (how long a
#: followed partner may stay unseen: the follower's search and person attention's leaving rule; the footprint and
#: the people sweep rule every module that sends a base command keeps). None of them imports another robot package.
ROBOT_SHARED = ("robot.contract", "robot.percepts", "robot.sonar_packet", "robot.floorplan", "robot.deployment", "robot.profiles",
                "robot.partner_search", "robot.footprint", "robot.blindside", "robot.bumpers")


def test_robot_modules_talk_only_over_the_bus():
    """A robot module imports nothing of another robot package (``robot/install.py``, which installs
    them, and the shared contract, its typed percept and sonar records and the floor plan aside): modules meet on the bus,
    not in code."""
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
    # the loader reached another way than ``importlib.import_module("x")``
    ("import importlib\ngetattr(importlib, 'import_module')('robot')\n", "homesim.sim", "robot"),
    ("from importlib import import_module as load\nload('humans')\n", "homesim.sim", "humans"),
    ("import importlib.util\nimportlib.util.find_spec('robot')\n", "homesim.sim", "robot"),
    ("import sys\nBIRON = sys.modules['robot']\n", "homesim.sim", "robot"),
    ("import importlib\nimportlib.import_module('.tour.runner', 'homesim')\n", "homesim.sim", "homesim.tour"),
    ("import importlib\nimportlib.import_module('..tour', __package__)\n", "homesim.world.stage", "homesim.tour"),
    # a name built from pieces: f-strings, concatenation, paths
    ("def load(n):\n    return f'robot.{n}'\n", "homesim.sim", "robot"),
    ("def chan(sub):\n    return f'/robot/{sub}/log'\n", "homesim.observe", "robot"),
    ("def load(n):\n    return 'humans.' + n\n", "homesim.sim", "humans"),
    ("from pathlib import Path\nP = Path(__file__).parent / 'robot' / 'install.py'\n", "homesim.sim", "robot.install"),
    # the robot's channel prefix alone
    ("def mine(ch):\n    return ch.startswith('/robot/')\n", "homesim.observe", "robot"),
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


# ------------------------------------------------- entry points (pyproject.toml)
def entry_point_arrows(pyproject: dict) -> list[str]:
    """What is wrong with the entry points a pyproject declares.

    Entry points are the one sanctioned way code above the kernel hands it something (a document
    kind for ``homesim check``, a scenario check): the kernel reads a group and never names the
    robot. So each must be in a group the kernel reads (else nothing loads it), and its target must
    exist and lie in the robot, the people or the run package: the command line through an entry
    point is the kernel importing the top layer by the back door."""
    from homesim.documents import ENTRY_POINT_GROUP
    from homesim.scenario.checks import CHECKS_GROUP

    bad = []
    for group, points in pyproject.get("project", {}).get("entry-points", {}).items():
        for name, value in points.items():
            target = value.split(":")[0].strip()
            where = f"[project.entry-points.{group!r}] {name} = {value!r}"
            if group not in (ENTRY_POINT_GROUP, CHECKS_GROUP):
                bad.append(f"{where}: no kernel registry reads the group")
            if layer(target) not in (2, 3):
                bad.append(f"{where}: {LAYERS[layer(target)]} is not a layer that extends the kernel")
            elif not (ROOT.joinpath(*target.split(".")).with_suffix(".py").is_file()
                      or (ROOT.joinpath(*target.split(".")) / "__init__.py").is_file()):
                bad.append(f"{where}: no module {target}")
    return bad


def test_entry_points_only_extend_the_kernels_registries():
    import tomllib
    from importlib.metadata import entry_points

    declared = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    assert entry_point_arrows(declared) == []
    # the install is the pyproject's (a stale one silently drops a document kind or a check)
    for group, points in declared["project"]["entry-points"].items():
        assert {e.name: e.value for e in entry_points(group=group)} == points, group


def test_an_entry_point_against_the_layers_is_found():
    from homesim.documents import ENTRY_POINT_GROUP

    toml = {"project": {"entry-points": {
        ENTRY_POINT_GROUP: {"ok": "robot.dialog.document:DOCUMENT_TYPE", "cli": "homesim.cli:main",
                            "gone": "robot.nowhere:X"},
        "homesim.unread": {"x": "humans.checks:check_scenario"},
    }}}
    found = entry_point_arrows(toml)
    assert len(found) == 3 and all(n in " ".join(found) for n in ("cli =", "gone =", "unread"))
