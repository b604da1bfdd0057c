"""Golden outputs: ``dtcrit codegen`` (every example x C, NumPy, Fortran) and ``dtcrit step`` (text and
``--json``) on every example equal the files in ``tests/golden``.

Comparison rule: generated code is pure formatting, compared byte for byte; the step reports carry
numbers computed by NumPy/SciPy, whose last bits change with the CPU's SIMD dispatch (AVX-512 or not),
so there each number is compared at a relative 1e-9 and all other text byte for byte
(``support.golden.same``).  A failure shows the unified diff; ``python3 dev.py golden`` rewrites the
files after an intended change.
"""
from __future__ import annotations

import pytest

from support.golden import GOLDEN, cases, run, same, unified_diff

CASES = cases()


@pytest.mark.parametrize("case", CASES, ids=[c.name for c in CASES])
def test_output_equals_the_golden_file(case):
    """The command's output equals its golden file (byte-exact code, numbers of reports at 1e-9)."""
    path = GOLDEN / case.name
    assert path.exists(), f"tests/golden/{case.name} is missing: python3 dev.py golden writes it"
    expected, got = path.read_text(), run(case)
    assert same(expected, got, case.exact), unified_diff(expected, got, case.name)


def test_every_golden_file_has_a_case():
    """No stale golden file is left behind when an example is removed or renamed."""
    names = {c.name for c in CASES}
    on_disk = {p.relative_to(GOLDEN).as_posix() for p in GOLDEN.rglob("*") if p.is_file()}
    assert on_disk <= names, sorted(on_disk - names)


def test_numbers_are_compared_at_a_relative_tolerance_and_words_exactly():
    """The comparison rule itself, on literals: last-bit changes pass, a changed digit or word does not."""
    assert same("dt = 1.2345678901234e-05 s\n", "dt = 1.2345678901235e-05 s\n", exact=False)
    assert not same("dt = 1.2345678901234e-05 s\n", "dt = 1.2345679e-05 s\n", exact=False)
    assert not same("dt = 1.0 s\n", "dt = 1.0 ms\n", exact=False)
    assert not same("x = 1.0;\n", "x = 1.0000000000000002;\n", exact=True)
