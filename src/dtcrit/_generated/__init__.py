"""Code emitted by ``dtcrit.symbolic`` (committed; regenerate with ``python3 dev.py generate``).

Nothing here imports SymPy.  ``tests/symbolic/test_generated_drift.py`` regenerates every file and fails on
any drift from the committed text.
"""
