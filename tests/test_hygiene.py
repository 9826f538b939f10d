"""Determinism hygiene: nothing outside the real-time pacer reads the wall clock."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FORBIDDEN = re.compile(
    r"time\.time\(|time\.monotonic\(|time\.perf_counter\(|datetime\.now\(|datetime\.utcnow\(|"
    r"uuid4\(|^\s*import random\b|^\s*from random import|\brandom\.(random|randint|choice|uniform|seed|shuffle)\(|"
    r"np\.random\.(seed|rand|randn|randint|random|choice|normal|uniform)\(",
    re.M,
)
ALLOWED = {Path("homesim/realtime.py")}


def test_no_wall_clock_or_global_randomness_in_the_product():
    offenders = []
    for pkg in ("homesim", "robot", "humans"):
        for path in sorted((ROOT / pkg).rglob("*.py")):
            rel = path.relative_to(ROOT)
            if rel in ALLOWED:
                continue
            for m in FORBIDDEN.finditer(path.read_text(encoding="utf-8")):
                line = path.read_text(encoding="utf-8").count("\n", 0, m.start()) + 1
                offenders.append(f"{rel}:{line}: {m.group(0).strip()}")
    assert offenders == []


def test_matplotlib_is_imported_only_by_the_viz_module():
    offenders = []
    for pkg in ("homesim", "robot", "humans"):
        for path in sorted((ROOT / pkg).rglob("*.py")):
            rel = path.relative_to(ROOT)
            if rel.name == "viz.py" or "viz" in rel.parts:
                continue
            if re.search(r"^\s*(import|from)\s+matplotlib", path.read_text(encoding="utf-8"), re.M):
                offenders.append(str(rel))
    assert offenders == []


def test_kernel_never_imports_the_robot_or_humans():
    """Only the run package (homesim/tour/) imports them; tests/test_layers.py checks every arrow."""
    offenders = []
    for path in sorted((ROOT / "homesim").rglob("*.py")):
        if path.relative_to(ROOT).parts[:2] == ("homesim", "tour"):
            continue
        if re.search(r"^\s*(import|from)\s+(robot|humans)\b", path.read_text(encoding="utf-8"), re.M):
            offenders.append(str(path.relative_to(ROOT)))
    assert offenders == []


#: What only the hardware models and the scoring may see: the simulated world and its people,
#: the scenario, the run package that holds them (stage, runner, ground-truth metrics) and the plots.
GROUND_TRUTH = re.compile(r"^(homesim\.(world|scenario|tour|viz)|humans)(\.|$)")


def _imports(path: Path) -> list[tuple[int, str]]:
    import ast

    out = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            out += [(node.lineno, a.name) for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            out.append((node.lineno, node.module))
            out += [(node.lineno, f"{node.module}.{a.name}") for a in node.names]
    return out


def test_robot_outside_the_hardware_never_imports_the_world_the_people_or_ground_truth():
    """Honest robot (HELPERS, issue 10): above robot/hardware/ BIRON sees only the bus. Also no
    attribute access to a world or ground truth handed in by a composition root (``run.world``)."""
    offenders = []
    for path in sorted((ROOT / "robot").rglob("*.py")):
        rel = path.relative_to(ROOT)
        if rel.parts[:2] == ("robot", "hardware"):
            continue
        for line, name in _imports(path):
            if GROUND_TRUTH.match(name):
                offenders.append(f"{rel}:{line}: imports {name}")
        for m in re.finditer(r"\b(run|sim|self)\.(world|truth|humans|stage)\b", path.read_text(encoding="utf-8")):
            offenders.append(f"{rel}: uses {m.group(0)}")
    assert offenders == []
