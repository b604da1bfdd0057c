"""The committed generated code is exactly what the symbolic layer produces now."""
from pathlib import Path

import pytest

from dtcrit.symbolic.regenerate import GENERATED_DIR, PRODUCERS, all_generated_files


def test_producers_are_listed():
    assert PRODUCERS, "no code producers registered"


@pytest.mark.parametrize("rel,text", sorted(all_generated_files().items()))
def test_generated_file_has_not_drifted(rel, text):
    path = GENERATED_DIR / rel
    assert path.exists(), f"src/dtcrit/_generated/{rel} missing: run `python3 dev.py generate`"
    assert path.read_text() == text, f"src/dtcrit/_generated/{rel} drifted: run `python3 dev.py generate`"


def test_no_orphan_generated_files():
    produced = set(all_generated_files())
    on_disk = {
        str(p.relative_to(GENERATED_DIR)) for p in Path(GENERATED_DIR).rglob("*.py") if p.name != "__init__.py"
    }
    assert on_disk <= produced, f"generated files nobody produces: {sorted(on_disk - produced)}"
