"""Explicit DEM integrators (their update rules) and their exact critical steps; runtime, no SymPy."""
