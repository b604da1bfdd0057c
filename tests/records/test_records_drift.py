"""The committed derivation records are what the derivation scripts produce now.

Identical text, except that numbers printed with ten or more significant digits may differ within a
relative 1e-9 (``_records_compare``: they carry the last bits of floating point, which depend on the
processor's SIMD loops); ``test_records_dispatch.py`` rebuilds the records under another NumPy
dispatch.
"""
import sys

import pytest
from support.records_compare import differences
from support.paths import DERIVATIONS

sys.path.insert(0, str(DERIVATIONS))
import run_all  # noqa: E402  (derivations/ is not a package: its runner and scripts load from the folder)

_load = run_all.load
SCRIPTS = run_all.scripts()


def test_there_are_records():
    assert SCRIPTS, "no derivation scripts found"


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: p.stem)
def test_record_has_not_drifted(script):
    module = _load(script)
    assert module.RECORD == script.stem + ".md", f"{script.name} writes {module.RECORD}: name them alike"
    record = DERIVATIONS / "records" / module.RECORD
    assert record.exists(), f"{record.name} missing: run `python3 dev.py generate`"
    diff = differences(record.read_text(), module.build(), record.name)
    assert not diff, f"{record.name} drifted: run `python3 dev.py generate`\n{diff}"
