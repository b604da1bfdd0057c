"""Solvers for the critical step of a packing.

Modules: ``largest_mode`` (``K phi = omega^2 M phi``), ``filter_updates`` (its Chebyshev start's fused vector
updates), ``mode_kind`` (rotational or translational), ``integrator_step`` (the integrator-specific step of the
highest mode), ``damped_step`` (the exact step with per-contact dashpots), ``spectral_step`` (its spectral-radius route), ``certificate`` (a bracket that holds
whether or not the solver converged), ``memory`` (refuse up front what would not fit).
"""
