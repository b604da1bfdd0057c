"""Sorted distinct values and rows (dtcrit.numerics.distinct) against ``numpy.unique``, over many
decades, duplicates and signed zeros; and that they do not load ``numpy.ma``.
"""
import subprocess
import sys

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from dtcrit.numerics.distinct import distinct, distinct_rows
from support.paths import SRC

FINITE = st.floats(min_value=-1e300, max_value=1e300, allow_nan=False, allow_infinity=False)
# few distinct values, so that rows and values repeat
SMALL_POOL = st.sampled_from([-1e30, -2.5, -0.0, 0.0, 1e-300, 3.0, 7e12])


@settings(max_examples=300, derandomize=True, deadline=None)
@given(hnp.arrays(np.float64, st.integers(0, 60), elements=st.one_of(FINITE, SMALL_POOL)))
def test_distinct_values_are_numpy_unique(a):
    got, want = distinct(a), np.unique(a)
    assert got.dtype == want.dtype and np.array_equal(got, want)


@settings(max_examples=300, derandomize=True, deadline=None)
@given(st.one_of(hnp.arrays(np.bool_, st.tuples(st.integers(0, 30), st.integers(1, 8))),
                 hnp.arrays(np.int64, st.tuples(st.integers(0, 30), st.integers(1, 4)),
                            elements=st.integers(-300, 300)),
                 hnp.arrays(np.float64, st.tuples(st.integers(0, 30), st.integers(1, 3)), elements=SMALL_POOL)))
def test_distinct_rows_are_numpy_unique_along_rows(a):
    got, want = distinct_rows(a), np.unique(a, axis=0)
    assert got.shape == want.shape and np.array_equal(got, want)


def test_neither_imports_numpy_ma():
    code = ("import sys, numpy as np\n"
            "from dtcrit.numerics.distinct import distinct, distinct_rows\n"
            "distinct(np.array([2.0, 1.0, 2.0])); distinct_rows(np.array([[True, False], [True, False]]))\n"
            "print('numpy.ma' in sys.modules)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         env={"PYTHONPATH": str(SRC)}).stdout.strip()
    assert out == "False"
