"""The committed derivation records are what the derivation scripts produce now.

Identical text, except that numbers printed with ten or more significant digits may differ within a
relative 1e-9 (``_records_compare``: they carry the last bits of floating point, which depend on the
processor's SIMD loops); ``test_records_dispatch.py`` rebuilds the records under another NumPy
dispatch.
"""
import importlib.util
import sys

import pytest
from support.records_compare import differences
from support.paths import DERIVATIONS



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
    diff = differences(record.read_text(), module.build(), record.name)
    assert not diff, f"{record.name} drifted: run `python3 dev.py generate`\n{diff}"
