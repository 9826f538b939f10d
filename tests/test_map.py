"""docs/architecture.md is a true map: it names no file that is missing, and lists every module.

A newcomer trusts the map to find where a thing lives; a module added without its line, or a line
left behind by a move, makes the map lie. Each module under ``homesim/``, ``robot/`` and ``humans/``
must be named in its own layer's section (``homesim/world/`` and ``homesim/viz/`` in the world's,
``homesim/tour/`` in the run package's, the rest of ``homesim/`` in the kernel's): by its path, by
its file name after its directory's path in the same entry (```afsm/`: `model.py```), or by its
name after its directory's path (```metrics/`: tracking, following```).
"""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
MAP = ROOT / "docs" / "architecture.md"

#: Where a section's paths start, by the section's heading.
SECTIONS = {
    "homesim/ (kernel)": ("homesim/",),
    "homesim/world/ and homesim/viz/ (world)": ("homesim/",),
    "robot/ (BIRON)": ("robot/",),
    "humans/": ("humans/",),
    "homesim/tour/ (run package)": ("homesim/tour/",),
}
#: Where any path in the map may start (walks, "where to add", cross references).
ANYWHERE = ("", "homesim/", "robot/", "humans/", "homesim/tour/")
PATHLIKE = re.compile(r"^[\w./-]+(\.(py|c|xml|xsd|scxml|md|tsv|toml|json)|/)$")


def entries(text: str) -> list[tuple[str, str]]:
    """``(section heading, entry text)``: an entry is a list item with its continuation lines."""
    out: list[tuple[str, str]] = []
    section = ""
    for line in text.splitlines():
        if line.startswith("## "):
            section = line[3:].strip()
        elif re.match(r"^(- |\d+\. )", line):
            out.append((section, line))
        elif line.startswith("  ") and out and out[-1][0] == section:
            out[-1] = (section, out[-1][1] + " " + line.strip())
        elif line.strip():
            out.append((section, line))
    return out


def resolve(section: str, text: str) -> tuple[list[str], list[str], list[tuple[str, str]]]:
    """The files and directories an entry names (relative to the repository), the paths that name
    nothing, and ``(directory, entry text)`` for each directory named."""
    found: list[str] = []
    missing: list[str] = []
    dirs: list[tuple[str, str]] = []
    context: list[str] = []  # the directories of the paths named so far in this entry
    for token in re.findall(r"`([^`]+)`", text):
        if not PATHLIKE.match(token) or token.startswith("/"):
            continue
        bases = context + list(SECTIONS.get(section, ())) + list(ANYWHERE)
        hit = next((b + token for b in bases if (ROOT / (b + token)).exists()), None)
        if hit is None:
            missing.append(token)
            continue
        hit = hit.rstrip("/")
        found.append(hit)
        if (ROOT / hit).is_dir():
            dirs.append((hit, text))
            context.insert(0, hit + "/")
        else:
            context.insert(0, str(Path(hit).parent) + "/")
    return found, missing, dirs


def home_section(rel: str) -> str:
    if rel.startswith("homesim/tour/"):
        return "homesim/tour/ (run package)"
    if rel.startswith(("homesim/world/", "homesim/viz/")):
        return "homesim/world/ and homesim/viz/ (world)"
    if rel.startswith("robot/"):
        return "robot/ (BIRON)"
    if rel.startswith("humans/"):
        return "humans/"
    return "homesim/ (kernel)"


def modules() -> list[str]:
    return sorted(str(p.relative_to(ROOT)) for pkg in ("homesim", "robot", "humans")
                  for p in (ROOT / pkg).rglob("*.py") if p.name != "__init__.py")


def unlisted(text: str) -> list[str]:
    named: dict[str, set[str]] = {}
    by_dir: dict[str, list[tuple[str, str]]] = {}
    for section, entry in entries(text):
        found, _, dirs = resolve(section, entry)
        named.setdefault(section, set()).update(found)
        for d, t in dirs:
            by_dir.setdefault(section, []).append((d, t))
    out = []
    for rel in modules():
        section = home_section(rel)
        parent, stem = str(Path(rel).parent), Path(rel).stem
        if rel in named.get(section, set()):
            continue
        if any(d == parent and re.search(rf"\b{re.escape(stem)}\b", t) for d, t in by_dir.get(section, [])):
            continue
        out.append(rel)
    return out


def test_the_map_names_no_missing_file():
    missing = [f"{section}: `{m}`" for section, entry in entries(MAP.read_text(encoding="utf-8"))
               for m in resolve(section, entry)[1]]
    assert missing == []


def test_the_map_lists_every_module_in_its_layer():
    assert unlisted(MAP.read_text(encoding="utf-8")) == []


def test_the_map_check_can_fail():
    """A module left out, a file that is gone, and a module listed in another layer's section are found."""
    text = MAP.read_text(encoding="utf-8")
    assert "homesim/vloop.py" in unlisted(text.replace("- `vloop.py`:", "- the loop:"))
    gone = "## homesim/ (kernel)\n\n- `nowhere.py`: a module that was moved away.\n"
    assert [m for s, e in entries(gone) for m in resolve(s, e)[1]] == ["nowhere.py"]
    moved = text.replace("- `viz/moment.py`:", "- moment:") + "\n## homesim/ (kernel)\n\n- `viz/moment.py`: here.\n"
    assert "homesim/viz/moment.py" in unlisted(moved)


#: A citation of a document that lives outside the repository (the product brief, the papers' folder).
OUTSIDE = re.compile(r"DESIGN\.md|\bDESIGN \d|shared/reference|\.\./shared|/work/shared")
TEXT = (".py", ".md", ".xml", ".xsd", ".scxml", ".toml", ".txt", ".tsv", ".c", ".cfg", ".ini", ".yml", ".yaml")


def outside_citations(root: Path) -> list[str]:
    out = []
    for path in sorted(root.rglob("*")):
        rel = path.relative_to(root)
        if rel.parts[0].startswith(".") or "build" in rel.parts or not path.is_file() or path.suffix not in TEXT \
                or path == Path(__file__).resolve() or any(p.endswith(".egg-info") for p in rel.parts):
            continue
        for i, line in enumerate(path.read_text(encoding="utf-8", errors="replace").splitlines(), 1):
            if OUTSIDE.search(line):
                out.append(f"{rel}:{i}: {line.strip()[:100]}")
    return out


def test_nothing_cites_a_document_outside_the_repository():
    """A reader of a clean clone can follow every reference: rules are cited from docs/semantics.md."""
    assert outside_citations(ROOT) == []


def test_an_outside_citation_is_found(tmp_path):
    (tmp_path / "s.xml").write_text("<!-- DESIGN 2.6: following -->\n", encoding="utf-8")
    (tmp_path / "m.py").write_text('"""See docs/semantics.md §6."""\n', encoding="utf-8")
    assert outside_citations(tmp_path) == ["s.xml:1: <!-- DESIGN 2.6: following -->"]
