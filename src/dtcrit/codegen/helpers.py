"""The helper functions emitted beside the kernels, per language, read from real source files.

The sources are package data under ``dtcrit/codegen/helper_sources`` (each compiled on its own by
``tests/codegen/test_helper_sources.py``: ``gcc -c``, ``gfortran -c``, Python ``compile``):

* ``cubic_positive_root.{c,f90,py.txt}``: the cubic-root helper for the integrators whose boundary
  is a cubic (``paper-eq40``).  The algorithm of :func:`dtcrit.numerics.cubic.cubic_positive_root`:
  Viete's trigonometric form when the three roots are real, the hyperbolic forms of Cardano's
  formula otherwise, the smallest (or largest) positive candidate, three Newton steps on the cubic,
  then two Newton steps whose residual is evaluated by compensated Horner (error-free
  transformations: ``fma`` in C, Dekker's product in NumPy and Fortran), so the root is as accurate
  as the coefficients allow even where ``a1 t`` and ``a0`` nearly cancel (small damping).  The NumPy
  text is ``cubic_positive_root(..., compensated_steps=2)`` written out (checked bit for bit).
* ``primitives.{c,f90,py.txt}``: the floating-point primitives of ``dtcrit.symbolic.careful_forms``
  (frexp parts, scaling by a power of two, error-free product and sum; :mod:`dtcrit.numerics.eft`,
  :mod:`dtcrit.numerics.scaling`), one function each, separated by blank lines.  C and Fortran use
  the same operations (Dekker's product with Veltkamp's splitting, no fma), so they agree bit for bit.

In the C files the identifiers ``PREFIX_...`` carry the prefix of the emitted file's helpers
(``<name>_mantissa``, ``<name>_cubic_positive_root``); the Fortran helpers are private module
procedures and need none.  The constants below are those texts as ``str.format`` templates (field
``name`` for the C cubic helper, ``p`` for the C prefix), the form ``dtcrit.codegen.step`` fills in.
"""
from __future__ import annotations

from importlib import resources

NUMPY_HELPER_NAME = "_cubic_positive_root"
PRIMITIVE_KEYS = ("mantissa", "exponent", "ldexp", "two_product_error", "two_sum_error")
"""The primitives of ``dtcrit.symbolic.careful_forms``, in the order of the ``primitives.*`` files."""
C_PREFIX = "PREFIX"
"""The placeholder of the emitted file's helper prefix in the C sources."""


def helper_source(filename: str) -> str:
    """The text of one helper source file shipped with the package.

    Parameters
    ----------
    filename : str
        A file name under ``dtcrit/codegen/helper_sources`` (e.g. ``"primitives.c"``).

    Returns
    -------
    str
        The file's text, as emitted (placeholders unfilled).
    """
    return (resources.files("dtcrit.codegen") / "helper_sources" / filename).read_text()


def _template(text: str, placeholder: str, field: str) -> str:
    """``text`` as a ``str.format`` template: braces doubled, ``placeholder`` replaced by ``{field}``."""
    return text.replace("{", "{{").replace("}", "}}").replace(placeholder, "{" + field + "}")


def _blocks(text: str, sep: str) -> dict[str, str]:
    """Split a primitives file into its functions, keyed by the primitive each implements."""
    blocks = [b.strip("\n") + "\n" for b in text.split(sep) if b.strip()]
    if len(blocks) != len(PRIMITIVE_KEYS):  # pragma: no cover - a source file changed shape
        raise RuntimeError(f"expected {len(PRIMITIVE_KEYS)} primitive helpers, found {len(blocks)}")
    return dict(zip(PRIMITIVE_KEYS, blocks))


NUMPY_HELPER = helper_source("cubic_positive_root.py.txt").strip("\n")
C_HELPER = _template(helper_source("cubic_positive_root.c"), f"{C_PREFIX}_cubic_positive_root", "name")
FORTRAN_HELPER = _template(helper_source("cubic_positive_root.f90"), "cubic_positive_root", "name")
C_PRIMITIVE_BLOCKS = {k: _template(v, C_PREFIX, "p") for k, v in _blocks(helper_source("primitives.c"), "\n\n").items()}
FORTRAN_PRIMITIVE_BLOCKS = _blocks(helper_source("primitives.f90"), "\n\n")
NUMPY_PRIMITIVE_BLOCKS = _blocks(helper_source("primitives.py.txt"), "\n\n\n")
