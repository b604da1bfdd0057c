"""The function name of emitted code (``dtcrit codegen --name``): an identifier of C, Fortran and Python
that is no keyword and no name the emitted file or its compilers already give a meaning.

The name is pasted into code (``double NAME(...)``, ``def NAME(...)``, ``module NAME_module``), so it is
checked against a pattern (a letter, then letters, digits or ``_``; at most 48 characters, so that
``NAME_module`` stays within Fortran's 63) matched over the whole text (no trailing newline), then
against, compared without case as in Fortran:

* the keywords of C99 to C23 and C++ (a C file is also compiled as C++), of Python, and C's
  predefined ``unix``/``linux`` (GNU modes define them as 1);
* the functions and macros of ``<math.h>`` (C99 and glibc's common extensions, each with its ``f``
  and ``l`` variants), which the emitted C includes, and ``main``;
* Python's built-ins (the emitted NumPy calls some: ``abs``, ``float``, ``range``), and ``np``.
"""
from __future__ import annotations

import builtins
import keyword
import re

from dtcrit.errors import InputError

MAX_NAME = 48
_IDENT = re.compile(rf"[A-Za-z][A-Za-z0-9_]{{0,{MAX_NAME - 1}}}")

_C_KEYWORDS = """
    auto break case char const continue default do double else enum extern float for goto if inline int long
    register restrict return short signed sizeof static struct switch typedef union unsigned void volatile while
    alignas alignof bool constexpr false nullptr static_assert thread_local true typeof typeof_unqual
    and and_eq asm bitand bitor catch char8_t char16_t char32_t class compl concept consteval constinit const_cast
    co_await co_return co_yield decltype delete dynamic_cast explicit export friend mutable namespace new noexcept
    not not_eq operator or or_eq private protected public reinterpret_cast requires static_cast template this
    throw try typeid typename using virtual wchar_t xor xor_eq
    unix linux main
""".split()
_MATH_FUNCTIONS = """
    acos asin atan atan2 cos sin tan acosh asinh atanh cosh sinh tanh exp exp2 expm1 exp10 pow10 frexp ilogb ldexp
    log log10 log1p log2 logb modf scalbn scalbln scalb cbrt fabs hypot pow sqrt erf erfc lgamma lgamma_r tgamma
    gamma ceil floor nearbyint rint lrint llrint round lround llround roundeven trunc fmod remainder remquo drem
    copysign nan nextafter nexttoward nextup nextdown fdim fmax fmin fma significand finite isinf isnan j0 j1 jn
    y0 y1 yn sincos lgammaf_r lgammal_r
""".split()
_MATH_MACROS = """
    fpclassify isfinite isgreater isgreaterequal isless islessequal islessgreater isnormal isunordered signbit
    issignaling iszero issubnormal iscanonical math_errhandling float_t double_t
    infinity nan huge_val huge_valf huge_vall math_errno math_errexcept
    fp_ilogb0 fp_ilogbnan fp_infinite fp_nan fp_normal fp_subnormal fp_zero fp_fast_fma fp_fast_fmaf fp_fast_fmal
    m_e m_log2e m_log10e m_ln2 m_ln10 m_pi m_pi_2 m_pi_4 m_1_pi m_2_pi m_2_sqrtpi m_sqrt2 m_sqrt1_2
""".split()
_SITE_BUILTINS = ("copyright", "credits", "exit", "help", "license", "quit")  # also when python -S leaves them out
RESERVED = frozenset(
    [w.lower() for w in _C_KEYWORDS + _MATH_MACROS]
    + [f + s for f in _MATH_FUNCTIONS for s in ("", "f", "l")]
    + [w.lower() for w in keyword.kwlist]
    + [w.lower() for w in {*dir(builtins), *_SITE_BUILTINS} if _IDENT.fullmatch(w)]
    + ["np", "dt", "a", "b", "pi"]
)
"""Names refused whatever the kernel, lower case (the comparison ignores case, as Fortran does)."""


def check_name(name: str) -> str:
    """``name`` if it can name the emitted function in C, Fortran and Python; ``InputError('name', ...)``
    otherwise (the command line reports it as ``--name: ...``).

    Parameters
    ----------
    name : str
        The requested function name (``dtcrit codegen --name``).

    Returns
    -------
    str
        ``name`` unchanged.

    Raises
    ------
    InputError
        When ``name`` is no identifier of all three languages, is longer than ``MAX_NAME``, or is in
        ``RESERVED`` (compared without case).
    """
    if not isinstance(name, str) or not _IDENT.fullmatch(name):
        raise InputError("name", f"must be an identifier valid in C, Fortran and Python (letter first, then letters, "
                         f"digits or _; at most {MAX_NAME} characters) (got {name!r:.80})")
    if name.lower() in RESERVED:
        raise InputError("name", f"{name!r} is a keyword or a name C, Fortran or Python already gives a meaning "
                         "(a <math.h> function or macro, main, a Python built-in; compared without case as in "
                         "Fortran); choose another")
    return name


__all__ = ["MAX_NAME", "RESERVED", "check_name"]
