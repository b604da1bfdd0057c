"""Producer of ``dtcrit/_generated/critical_steps.py``: the exact critical step of every integrator.

For each integrator of ``dtcrit.integrators.schemes`` the kernel ``dt_<name>(omega, gamma)`` evaluates the
closed form of ``dtcrit.symbolic.closed_forms`` piece by piece, with ``omega = sqrt(k A)`` and
``gamma = c A / 2`` (both in 1/s).  The kernels are homogeneous of degree -1 in (omega, gamma), so
the runtime may rescale both by a power of two (exactly) to stay clear of overflow and underflow.

The same module carries the labelled comparison formulas of Peng et al. 2020 (Eqs. (34), (36),
(37), (46), (58)-(60)), derived in ``dtcrit.symbolic.paper_section4``.
"""
from __future__ import annotations

import sympy as sp

from dtcrit.integrators.schemes import NAMES
from dtcrit.symbolic import paper_section4 as p4
from dtcrit.symbolic.closed_forms import closed_pieces, eps, formula_text, gamma, omega
from dtcrit.symbolic.emit import Kernel, python_module
from dtcrit.symbolic.integrators import zeta

CUBIC_ROOT = sp.Function("_cubic_positive_root")

# the generated kernels call the one cubic solver of dtcrit.numerics (imported, not embedded)
PREAMBLE = "from dtcrit.numerics.cubic import cubic_positive_root as _cubic_positive_root\n"


def py_name(integrator: str) -> str:
    """Name of the emitted critical-step kernel of an integrator.

    Parameters
    ----------
    integrator : str
        Name of the integrator.

    Returns
    -------
    str
        ``dt_<name>`` with dashes as underscores.
    """
    return "dt_" + integrator.replace("-", "_")


def kernel_expr(name: str) -> sp.Expr:
    """dt(omega, gamma) for one integrator, as a SymPy expression (Piecewise over zeta ranges).

    Parameters
    ----------
    name : str
        Name of the integrator.

    Returns
    -------
    sympy.Expr
        ``dt(omega, gamma)``, a Piecewise over the zeta ranges of the closed pieces.
    """
    branches = []
    for cp in closed_pieces(name):
        if cp.kind == "root":
            e = cp.dt_expr
        else:
            if cp.cubic is None or cp.cubic_large is None:  # pragma: no cover - a cubic piece carries both
                raise ValueError(f"'{name}': a cubic piece without its cubics")
            # zeta <= 1: the cubic in tau; zeta > 1: the cubic in y = 1/(zeta tau), eps = (omega/gamma)^2
            a2, a1, a0 = (sp.simplify(c.subs(zeta, gamma / omega)) for c in cp.cubic)
            b2, b1, b0 = (sp.simplify(c.subs(eps, (omega / gamma) ** 2)) for c in cp.cubic_large)
            small = CUBIC_ROOT(a2, a1, a0, False) / omega
            large = 1 / (gamma * CUBIC_ROOT(b2, b1, b0, True))
            e = sp.Piecewise((small, sp.Le(gamma, omega)), (large, True))
        hi = cp.piece.zeta_hi
        branches.append((e, sp.true if hi == sp.oo else sp.Le(gamma, hi * omega)))
    if len(branches) == 1:
        return branches[0][0]
    branches[-1] = (branches[-1][0], sp.true)
    return sp.Piecewise(*branches)


RATE_ARGS = (
    (omega, "sqrt(k*A), undamped contact frequency [rad/s]"),
    (gamma, "c*A/2, half the damping rate [1/s]; zeta = gamma/omega"),
)


def integrator_kernels() -> list[Kernel]:
    """The exact critical-step kernels of every integrator.

    Returns
    -------
    list of Kernel
        ``dt_<name>(omega, gamma)`` for every integrator (Peng et al. 2020, Eqs. (29)-(30)).
    """
    return [
        Kernel(
            py_name(n),
            RATE_ARGS,
            kernel_expr(n),
            f"Exact critical step of the '{n}' integrator for xddot = -kA x - cA xdot.\n\n"
            f"    {formula_text(n)}.\n    Peng et al. 2020, Eqs. (29)-(30); derived from the update rule by\n"
            "    dtcrit.symbolic (amplification matrix, Jury conditions).",
            returns="dt [s] (0.0 where no positive step is stable)",
            as_arrays=True,
        )
        for n in NAMES
    ]


def paper_kernels() -> list[Kernel]:
    """The paper's labelled comparison formulas (``dtcrit.symbolic.paper_section4``).

    Returns
    -------
    list of Kernel
        Eqs. (34), (36), (37), (46), (58)-(60) as kernels.
    """
    k, c, A, m, beta = p4.k, p4.c, p4.A, p4.m, p4.beta
    kcA = ((k, "contact stiffness [N/m]"), (c, "viscous damping coefficient [N s/m]"), (A, "inverse inertia coefficient [1/kg]"))
    return [
        Kernel("paper_eq46", kcA, p4.eq46(), "Peng et al. 2020, Eq. (46) as printed: the 'real eigenvalue at -1' boundary of Eq. (40)."),
        Kernel("belytschko_eq34", kcA, p4.eq34(), "Peng et al. 2020, Eq. (34): Belytschko's 2/omega_max with the damped frequency of Eq. (33); NaN when not underdamped."),
        Kernel("critical_damping_eq37", ((k, "contact stiffness [N/m]"), (A, "inverse inertia coefficient [1/kg]")), p4.eq37(), "Peng et al. 2020, Eq. (37): critical damping coefficient [N s/m]."),
        Kernel("silbert_eq36", ((k, "normal stiffness [N/m]"), (c, "normal damping [N s/m]"), (m, "particle mass [kg] (the paper's convention)")), p4.eq36(), "Peng et al. 2020, Eq. (36): Silbert et al.'s collision time as printed (m the particle mass)."),
        Kernel("beta_eq58", ((beta, "c/sqrt(m k)"),), p4.beta_form(p4.eq34()), "Peng et al. 2020, Eq. (58): Eq. (34) for identical spheres, dt*sqrt(k/m)."),
        Kernel("beta_eq59", ((beta, "c/sqrt(m k)"),), sp.simplify(p4.eq36().subs(c, beta * sp.sqrt(m * k)) * sp.sqrt(k / m)), "Peng et al. 2020, Eq. (59): Eq. (36) for identical spheres, dt*sqrt(k/m)."),
        Kernel("beta_eq60", ((beta, "c/sqrt(m k)"),), p4.beta_form(p4.eq46()), "Peng et al. 2020, Eq. (60): Eq. (46) for identical spheres, dt*sqrt(k/m)."),
    ]


def _float_text(value: sp.Expr) -> str:
    return 'float("inf")' if value == sp.oo else repr(float(value))


def postamble() -> str:
    """The tables appended to ``critical_steps.py``.

    Returns
    -------
    str
        ``DT_KERNELS``, ``FORMULAS``, ``SWITCH_POINTS`` and ``GOVERNING``.
    """
    lines = ["DT_KERNELS = {"]
    lines += [f"    {n!r}: {py_name(n)}," for n in NAMES]
    lines += ["}", "", "FORMULAS = {"]
    lines += [f"    {n!r}: {formula_text(n)!r}," for n in NAMES]
    lines += ["}", "", "# zeta at which the governing boundary factor changes (exact values in the record)", "SWITCH_POINTS = {"]
    for n in NAMES:
        pts = [cp.piece.zeta_hi for cp in closed_pieces(n)][:-1]
        lines.append(f"    {n!r}: ({''.join(repr(float(p)) + ', ' for p in pts)}),")
    lines.append("}")
    lines += ["", "# (upper zeta of the piece, Jury condition that governs it) for each integrator", "GOVERNING = {"]
    for n in NAMES:
        items = "".join(f"({_float_text(cp.piece.zeta_hi)}, {cp.piece.factor.condition!r}), " for cp in closed_pieces(n))
        lines.append(f"    {n!r}: ({items}),")
    lines.append("}")
    return "\n".join(lines)


def generated_files() -> dict[str, str]:
    """The files this producer writes under ``dtcrit/_generated`` (``dtcrit.symbolic.regenerate``).

    Returns
    -------
    dict of str to str
        ``{"critical_steps.py": text}``.
    """
    text = python_module(
        "dtcrit.symbolic.stability_codegen",
        "Exact critical time steps of explicit integrators and the paper's comparison formulas.",
        integrator_kernels() + paper_kernels(),
        preamble=PREAMBLE,
        postamble=postamble(),
    )
    return {"critical_steps.py": text}
