"""The committed derivation records are exactly what the derivation scripts produce now."""
import importlib.util
import sys
from pathlib import Path

import pytest

DERIVATIONS = Path(__file__).resolve().parents[1] / "derivations"


def _load(path):
    if str(path.parent) not in sys.path:  # the scripts share helper modules (derivations/_*.py)
        sys.path.insert(0, str(path.parent))
    spec = importlib.util.spec_from_file_location(f"derivations_{path.stem}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


SCRIPTS = sorted(DERIVATIONS.glob("sec*.py"))


def test_there_are_records():
    assert SCRIPTS, "no derivation scripts found"


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: p.stem)
def test_record_has_not_drifted(script):
    module = _load(script)
    record = DERIVATIONS / "records" / module.RECORD
    assert record.exists(), f"{record.name} missing: run `python3 dev.py generate`"
    assert record.read_text() == module.build(), f"{record.name} drifted: run `python3 dev.py generate`"
