"""Every module of homesim/, robot/ and humans/ imports: a merge that renames a name one module still
uses (``EVENTS`` -> ``ES_EVENTS``) breaks a whole robot profile, found here by the module's name
rather than by whichever run happens to load it."""

from __future__ import annotations

import importlib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
MODULES = sorted(".".join(p.relative_to(ROOT).with_suffix("").parts).removesuffix(".__init__")
                 for pkg in ("homesim", "robot", "humans") for p in (ROOT / pkg).rglob("*.py"))


@pytest.mark.parametrize("name", MODULES)
def test_the_module_imports(name):
    importlib.import_module(name)
