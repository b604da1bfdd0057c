"""One home per numerical primitive (runtime: NumPy only, no SymPy, no mpmath at import).

Modules:

* :mod:`dtcrit.numerics.eft`: error-free transformations (Veltkamp's split, Dekker's product,
  Knuth's two-sum) and double-double polynomials;
* :mod:`dtcrit.numerics.scaling`: exact power-of-two scaling of the rates (``frexp``/``ldexp``);
* :mod:`dtcrit.numerics.cubic`: the positive root of a cubic (the generated kernels' and the
  runtime's solver), with compensated Newton steps;
* :mod:`dtcrit.numerics.polynomial_roots`: all roots of the integrators' characteristic polynomials;
* :mod:`dtcrit.numerics.rotations`: quaternion rotation matrices in the one convention, body to world;
* :mod:`dtcrit.numerics.distinct`: sorted distinct values without ``numpy.unique`` (and its import of
  ``numpy.ma``);
* :mod:`dtcrit.numerics.reference`: the mpmath references (imported only by tests and ``codegen``).

The C, Fortran and NumPy texts of the same primitives that ``dtcrit codegen`` emits are package data
of ``dtcrit.codegen`` (``helper_sources/``).
"""
from __future__ import annotations

from dtcrit.numerics.cubic import compensated_newton, cubic_positive_root
from dtcrit.numerics.eft import dd_polynomial, split, two_product, two_sum
from dtcrit.numerics.rotations import BODY_TO_WORLD, body_to_world_matrix, world_to_body_matrix
from dtcrit.numerics.scaling import frexp_parts, scaled_rates, scaled_root

__all__ = [
    "BODY_TO_WORLD",
    "body_to_world_matrix",
    "compensated_newton",
    "cubic_positive_root",
    "dd_polynomial",
    "frexp_parts",
    "scaled_rates",
    "scaled_root",
    "split",
    "two_product",
    "two_sum",
    "world_to_body_matrix",
]
