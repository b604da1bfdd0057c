"""The careful critical step of one mode, dt(k, c, A), printed as a function in C, Fortran and NumPy.

The assignment chain is ``dtcrit.symbolic.careful_forms.careful_chain`` (the forms of
``dtcrit.integrators.precise``: exact power-of-two scaling from the larger rate, forward Euler's
error-free residual, the cubic's identity, NaN for NaN or negative inputs).  The per-contact
kernels call it once per direction (``dtcrit.codegen.kernel``); ``render_step`` emits it alone,
with a header, as the bare kernel of a mode (the bench's compiled route and
``tests/codegen/test_kernels_extreme_suite.py`` use it).
"""
from __future__ import annotations

from functools import lru_cache

import sympy as sp

from dtcrit.codegen.helpers import (C_HELPER, C_PRIMITIVE_BLOCKS, FORTRAN_HELPER, FORTRAN_PRIMITIVE_BLOCKS,
                                    NUMPY_HELPER, NUMPY_HELPER_NAME, NUMPY_PRIMITIVE_BLOCKS)
from dtcrit.codegen.functions import cubic_positive_root
from dtcrit.codegen.printers import CPrinter, FortranPrinter, NumPyPrinter
from dtcrit.symbolic.careful_forms import ARGUMENTS as ARGUMENTS  # the step's arguments, read by codegen.render
from dtcrit.symbolic.careful_forms import Chain, careful_chain
from dtcrit.symbolic.emit import derivation_hash
from dtcrit.symbolic.stability_codegen import CUBIC_ROOT

FORTRAN_CUBIC = "cubic_positive_root"
FORTRAN_STEP = "critical_step"
NUMPY_STEP = "_critical_step"
SUFFIX = {True: "critical_step", False: "critical_step_undamped"}
FORTRAN_IEEE = ("  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_is_nan, ieee_value, "
                "ieee_quiet_nan")


@lru_cache(maxsize=None)
def chain(integrator: str, damped: bool = True) -> Chain:
    """The careful chain with the cubic root as the codegen's helper function (``damped=False``:
    the chain of an undamped mode, arguments k and A).
    """
    ch = careful_chain(integrator, damped)
    steps = [(s, e.replace(CUBIC_ROOT, cubic_positive_root)) for s, e in ch.steps]
    needed, kept = {ch.result}, []
    for s, e in reversed(steps):  # drop what nothing uses (e.g. gamma for the centred leapfrog)
        if s in needed:
            kept.append((s, e))
            needed |= e.free_symbols
    return Chain(ch.integrator, ch.args, tuple(reversed(kept)), ch.result, ch.equations)


def check_emittable(integrator: str) -> None:
    """Refuse (InputError on ``integrator``, one line) a user-written scheme whose boundary has no emitted
    closed form: more than three state variables (Jury conditions of degree <= 3), a characteristic
    polynomial with terms in h^5 or higher (boundary factors beyond the cubic), or a derivation the symbolic
    layer does not support.  The
    degree checks come first, so the refusal is quick; ``dtcrit step`` still gives such a scheme's step.

    Parameters
    ----------
    integrator : str
        Name of a built-in or user-written scheme (built-in ones always pass).

    Raises
    ------
    InputError
        When the user-written scheme's boundary cannot be emitted, with the reason.
    """
    from dtcrit.errors import InputError
    from dtcrit.integrators.schemes import USER_INTEGRATORS
    from dtcrit.integrators.user_rules import h_degree_of

    integ = USER_INTEGRATORS.get(integrator)
    if integ is None:
        return
    why = None
    degree = h_degree_of(integ)
    if len(integ.state) > 3:
        why = f"it has {len(integ.state)} state variables (the emitted boundaries cover at most 3)"
    elif degree is not None and degree > 4:
        why = (f"its characteristic polynomial has terms in h^{degree} (the emitted boundaries cover h^4 at most, "
               "e.g. a two-stage Runge-Kutta)")
    else:
        try:
            chain(integrator, True)
        except (RuntimeError, NotImplementedError, ValueError, ZeroDivisionError) as exc:
            why = f"its stability boundary has no closed form dtcrit can emit ({str(exc).split(': ', 1)[-1]})"
    if why:
        raise InputError("integrator", f"no code for the user-written scheme '{integrator}': {why}; "
                         "dtcrit step gives its step")


def chain_hash(integrator: str, damped: bool = True) -> str:
    """The derivation hash of a careful chain (``dtcrit.symbolic.emit.derivation_hash``).

    Parameters
    ----------
    integrator : str
        Name of the scheme.
    damped : bool
        The chain of a damped mode (k, c, A) rather than an undamped one (k, A).

    Returns
    -------
    str
        The hash over the scheme's name, the arguments and every assignment of the chain.
    """
    ch = chain(integrator, damped)
    return derivation_hash([sp.Symbol(integrator), *ch.args, *(x for s, e in ch.steps for x in (s, e))])


def uses_cubic(integrator: str, variants=(True,)) -> bool:
    """Whether any of the chains calls the cubic-root helper.

    Parameters
    ----------
    integrator : str
        Name of the scheme.
    variants : tuple of bool
        The chains to look at: ``True`` for the damped one, ``False`` for the undamped one.

    Returns
    -------
    bool
        True when a step of a chain contains ``cubic_positive_root``.
    """
    return any(e.has(cubic_positive_root) for d in variants for _, e in chain(integrator, d).steps)


def primitives_used(integrator: str, variants=(True,)) -> list[str]:
    """The primitives of ``careful_forms`` the chains call, in a fixed order.

    Parameters
    ----------
    integrator : str
        Name of the scheme.
    variants : tuple of bool
        The chains to look at: ``True`` for the damped one, ``False`` for the undamped one.

    Returns
    -------
    list of str
        Names among ``mantissa``, ``exponent``, ``ldexp``, ``two_product_error``, ``two_sum_error``.
    """
    from dtcrit.symbolic import careful_forms as cf

    used = set()
    for _, e in (x for d in variants for x in chain(integrator, d).steps):
        for key in ("mantissa", "exponent", "ldexp", "two_product_error", "two_sum_error"):
            if e.has(getattr(cf, key)):
                used.add(key)
    return [k for k in ("mantissa", "exponent", "ldexp", "two_product_error", "two_sum_error") if k in used]


def local_names(integrator: str, variants=(True,)) -> set[str]:
    """The names the chains assign (the emitted code's local variables).

    Parameters
    ----------
    integrator : str
        Name of the scheme.
    variants : tuple of bool
        The chains to look at: ``True`` for the damped one, ``False`` for the undamped one.

    Returns
    -------
    set of str
        The assigned symbols' names.
    """
    return {str(s) for d in variants for s, _ in chain(integrator, d).steps}


# --- C ---------------------------------------------------------------------------------------

def c_support(integrator: str, prefix: str, variants=(True,)) -> str:
    """The C helpers the steps need (primitives, the cubic root), ``static``, names prefixed.

    Parameters
    ----------
    integrator : str
        Name of the scheme.
    prefix : str
        Prefix of the helpers' names (the emitted function's name), so two kernels can share a file.
    variants : tuple of bool
        The chains to serve: ``True`` for the damped one, ``False`` for the undamped one.

    Returns
    -------
    str
        C source of the helper functions.
    """
    out = "\n".join(C_PRIMITIVE_BLOCKS[key] for key in primitives_used(integrator, variants)).format(p=prefix)
    if uses_cubic(integrator, variants):
        out += "\n" + C_HELPER.format(name=f"{prefix}_cubic_positive_root")
    return out


def _what(integrator, damped):
    return (f"careful critical step of one {'' if damped else 'undamped '}mode, '{integrator}' "
            f"(k [N/m], {'c [N s/m], ' if damped else ''}A [1/kg]) -> dt [s]")


def c_function(integrator: str, fname: str, prefix: str, static: bool, damped: bool = True) -> str:
    """The careful step of one mode as a C function ``double fname(k, [c,] A)``.

    Parameters
    ----------
    integrator : str
        Name of the scheme.
    fname : str
        Name of the function.
    prefix : str
        Prefix of the helpers it calls (see ``c_support``).
    static : bool
        Declare the function ``static`` (a helper of a kernel rather than the file's entry point).
    damped : bool
        The damped mode's step (k, c, A) rather than the undamped one (k, A).

    Returns
    -------
    str
        C source of the function, newline-terminated.
    """
    ch = chain(integrator, damped)
    printer = CPrinter(f"{prefix}_cubic_positive_root", prefix)
    params = ", ".join(f"double {a}" for a in ch.args)
    lines = [f"/* {_what(integrator, damped)} */", f"{'static ' if static else ''}double {fname}({params})", "{"]
    for sym, expr in ch.steps:
        lines.append(f"    const double {sym} = {printer.doprint(expr)};")
    lines += [f"    return {ch.result};", "}"]
    return "\n".join(lines) + "\n"


# --- Fortran ---------------------------------------------------------------------------------

def fortran_support(integrator: str, variants=(True,)) -> str:
    """The Fortran helpers the steps need (primitives, the cubic root), as module procedures.

    Parameters
    ----------
    integrator : str
        Name of the scheme.
    variants : tuple of bool
        The chains to serve: ``True`` for the damped one, ``False`` for the undamped one.

    Returns
    -------
    str
        Fortran source of the helper procedures.
    """
    out = "\n".join(FORTRAN_PRIMITIVE_BLOCKS[key] for key in primitives_used(integrator, variants))
    if uses_cubic(integrator, variants):
        out += "\n" + FORTRAN_HELPER.format(name=FORTRAN_CUBIC)
    return out


def fortran_function(integrator: str, fname: str, bind: bool, damped: bool = True) -> list[str]:
    """The careful step of one mode as a Fortran function of ``real(c_double)`` arguments.

    Parameters
    ----------
    integrator : str
        Name of the scheme.
    fname : str
        Name of the function.
    bind : bool
        Give it ``bind(C)`` and ``value`` arguments (callable from C); otherwise a ``pure`` module function.
    damped : bool
        The damped mode's step (k, c, A) rather than the undamped one (k, A).

    Returns
    -------
    list of str
        The function's source lines, indented for a module's ``contains`` part.
    """
    ch = chain(integrator, damped)
    printer = FortranPrinter(FORTRAN_CUBIC)
    res = str(ch.result)
    params = ", ".join(str(a) for a in ch.args)
    head = f"  {'' if bind else 'pure '}function {fname}({params}) result({res})" + (f" bind(C, name=\"{fname}\")" if bind else "")
    out = [f"  ! {_what(integrator, damped)}", head,
           f"    real(c_double), {'value, ' if bind else ''}intent(in) :: {params}", f"    real(c_double) :: {res}"]
    local = [str(s) for s, _ in ch.steps if s != ch.result]
    out += _fortran_wrap("    real(c_double) :: " + ", ".join(local))
    for sym, expr in ch.steps:
        out += ["    " + ln for ln in printer.doprint(expr, assign_to=sym).splitlines()]
    out.append(f"  end function {fname}")
    return out


# --- NumPy -----------------------------------------------------------------------------------

def numpy_support(integrator: str, variants=(True,)) -> str:
    """The NumPy helpers the steps need (primitives, the cubic root), as module-level functions.

    Parameters
    ----------
    integrator : str
        Name of the scheme.
    variants : tuple of bool
        The chains to serve: ``True`` for the damped one, ``False`` for the undamped one.

    Returns
    -------
    str
        Python source of the helper functions.
    """
    out = "\n\n".join(NUMPY_PRIMITIVE_BLOCKS[key] for key in primitives_used(integrator, variants))
    if uses_cubic(integrator, variants):
        out += "\n\n" + NUMPY_HELPER.strip("\n") + "\n"
    return out


def numpy_function(integrator: str, fname: str, damped: bool = True) -> str:
    """The careful step of one mode as an elementwise NumPy function ``fname(k, [c,] A)``.

    Parameters
    ----------
    integrator : str
        Name of the scheme.
    fname : str
        Name of the function.
    damped : bool
        The damped mode's step (k, c, A) rather than the undamped one (k, A).

    Returns
    -------
    str
        Python source of the function, newline-terminated.
    """
    ch = chain(integrator, damped)
    printer = NumPyPrinter(NUMPY_HELPER_NAME)
    params = ", ".join(str(a) for a in ch.args)
    lines = [f"def {fname}({params}):",
             f'    """{_what(integrator, damped)[0].upper() + _what(integrator, damped)[1:]}; elementwise."""',
             f"    {params}, = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in ({params},)))",
             '    with np.errstate(all="ignore"):']
    for sym, expr in ch.steps:
        lines.append(f"        {sym} = {printer.doprint(expr)}")
    lines.append(f"    return {ch.result}")
    return "\n".join(lines) + "\n"


def _fortran_wrap(line: str, width: int = 100) -> list[str]:
    """A long Fortran line split with continuation ampersands."""
    import textwrap

    if len(line) <= width:
        return [line]
    indent = len(line) - len(line.lstrip()) + 4
    parts = textwrap.wrap(line, width - 2, subsequent_indent=" " * indent, break_long_words=False, break_on_hyphens=False)
    return [p + " &" for p in parts[:-1]] + [parts[-1]]
