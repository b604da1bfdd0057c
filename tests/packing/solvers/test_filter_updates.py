"""The Chebyshev filter's fused updates give the bits of the NumPy expressions they replace
(computed here, operation by operation), and the filtered start is the same with and without them."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from dtcrit.packing.solvers import filter_updates, largest_mode as eigen

pytestmark = pytest.mark.skipif(not filter_updates.available(), reason="the fused loops need Numba")


@settings(max_examples=60, deadline=None, derandomize=True)
@given(st.integers(1, 5000), st.integers(-150, 150), st.integers(0, 2**32 - 1))
def test_the_fused_updates_are_the_numpy_bits(n, decade, seed):
    rng = np.random.default_rng(seed)
    y2, y1, y0 = (rng.standard_normal(n) * 10.0 ** rng.uniform(decade - 3, decade + 3, n) for _ in range(3))
    c = float(10.0 ** rng.uniform(-5, 5))
    want = y2 * c
    want -= y1
    want -= y1
    want -= y0
    got = y2.copy()
    filter_updates.three_term(got, y1, y0, c)
    assert np.array_equal(got, want, equal_nan=True)
    norm = float(np.linalg.norm(want))
    if norm > 0 and np.isfinite(norm):
        a, b = got.copy(), y1.copy()
        filter_updates.divide_both(a, b, norm)
        assert np.array_equal(a, want / norm) and np.array_equal(b, y1 / norm)


def test_the_filtered_start_is_the_same_with_the_numpy_expressions(monkeypatch):
    rng = np.random.default_rng(2)
    m = rng.standard_normal((300, 300))
    a = m @ m.T
    v = rng.standard_normal(300)
    fused = eigen.chebyshev_filter(a, v)
    monkeypatch.setattr(filter_updates, "available", lambda: False)
    plain = eigen.chebyshev_filter(a, v)
    assert np.array_equal(fused[0], plain[0]) and fused[1] == plain[1]
    assert fused[1] <= np.linalg.eigvalsh(a)[-1] * (1 + 1e-12)
