"""``dtcrit bench``: error against run time for every route to the critical step, the
extreme-case suite and the stability check by simulation.

Modules: ``suite`` (the named extreme cases and the random batch), ``reference`` (>= 50-digit
references), ``routes`` (every route as a callable over arrays of (k, c, A)), ``fused`` (fused,
in-place closed forms), ``c_kernel`` (the closed forms emitted as C), ``paper_forms`` (the paper's
printed forms in float64), ``bisection`` and ``amplification`` (the direct routes),
``simulation_check`` (section 3), ``config`` (the quick and full sizes), ``runner`` (``run_bench``)
and ``report`` (Markdown, CSV, PNG); ``dense_table_writer`` writes the dense-packing bound's start-up
table (``dtcrit.scenes.dense_tables``); ``cluster_model`` prints the per-rank memory and time model
of the distributed SLEPc routes.
Nothing is imported here: the reference step needs SymPy, the command line must not.
"""
