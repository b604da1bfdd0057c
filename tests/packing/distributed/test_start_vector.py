"""The shell route's random start (``slepc_start.global_uniform``): each rank's piece is its rows of one
vector, whatever the number of ranks, checked against one stream drawn whole."""
from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from dtcrit.packing.distributed.slab_contacts import split_rows
from dtcrit.packing.distributed.slepc_start import global_uniform


@settings(max_examples=60, derandomize=True, deadline=None)
@given(st.integers(0, 2**63 - 1), st.integers(1, 5000), st.integers(1, 9))
def test_the_ranks_pieces_are_one_vector(seed, n, ranks):
    whole = 2.0 * np.random.Generator(np.random.PCG64(seed)).random(n) - 1.0  # one stream, drawn whole
    pieces = [global_uniform(seed, *split_rows(n, ranks, r)) for r in range(ranks)]
    assert np.array_equal(np.concatenate(pieces), whole)
    assert np.all((whole >= -1.0) & (whole < 1.0))


def test_far_rows_are_the_draws_of_the_whole_stream():
    """A rank far into a vector (rows of a 5e5-sphere packing) jumps there (``PCG64.advance``) and gets
    what drawing the whole stream up to it gives."""
    lo, hi = 3_000_000 - 7, 3_000_000
    whole = 2.0 * np.random.Generator(np.random.PCG64(3)).random(hi) - 1.0
    assert np.array_equal(global_uniform(3, lo, hi), whole[lo:])
