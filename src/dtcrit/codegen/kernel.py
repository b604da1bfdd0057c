"""The per-contact critical-step kernel as a chain of SymPy assignments, specialised to a structure.

For a contact between particles 1 and 2 (Peng, Burns & Hanley 2020):

* inverse inertia coefficient (Eq. (26) with the contact arms r1, r2 in place of the semi-axes)::

      A = 1/m1 + 1/m2 + r1^2/I_xx1 + r2^2/I_xx2

  ``I_xx`` is the smallest principal moment.  A bounds the largest eigenvalue of the 3x3
  coefficient matrix (1/m1 + 1/m2) 1 + sum_i [r_i]x I_i^-1 [r_i]x^T of *any* contact with those
  arms, because ||[r]x I^-1 [r]x^T|| <= |r|^2 / I_min (checked against the matrix in the tests).
  A sphere side gives r^2/I = 5/(2 m), hence A = 7/m for two identical spheres (Section 4.3);
* per direction j = n, s (Eqs. (29)-(30)): omega_j = sqrt(k_j A), zeta_j = c_j A / (2 omega_j) and
  dt_j = tau(zeta_j) / omega_j, tau the exact dimensionless critical step of the integrator from
  ``dtcrit.symbolic`` (its piecewise closed form or the root of its cubic); undamped, tau is a
  constant and min(dt_n, dt_s) = tau / sqrt(max(k_n, k_s) A);
* rotation (Eqs. (54), (56)): B_i = max(|I_xx - I_yy|/I_zz, |I_xx - I_zz|/I_yy, |I_yy - I_zz|/I_xx),
  dt_rot = 2 / (omega_max (B1 + B2)) (1 / (omega_max B) for identical particles);
* the result is the smallest of these.

Arguments the chain does not use are dropped, so the emitted code takes exactly the scene's free
parameters.  :func:`dtcrit.codegen.kernel_mp.evaluate_mp` evaluates the same chain in mpmath (the reference of the tests).
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import sympy as sp

from dtcrit.codegen.functions import critical_step, critical_step_undamped, cubic_positive_root
from dtcrit.codegen.direction import GAMMA, direction_kernel, undamped_tau
from dtcrit.codegen.chain import cse_chain, dependency_order
from dtcrit.codegen.structure import KernelStructure
from dtcrit.errors import InputError
from dtcrit.symbolic.closed_forms import formula_text
from dtcrit.symbolic.careful_forms import nan_max, nan_min
from dtcrit.symbolic.emit import derivation_hash


def _pos(name: str) -> sp.Symbol:
    return sp.Symbol(name, positive=True)


@dataclass(frozen=True)
class Argument:
    """One argument of an emitted kernel: symbol, meaning and unit.

    Parameters
    ----------
    symbol : sympy.Symbol
        The argument's symbol (its name is the emitted name).
    meaning : str
        What the argument is, for the header.
    unit : str
        Its unit.
    """

    symbol: sp.Symbol
    meaning: str
    unit: str

    @property
    def name(self) -> str:
        """The argument's name in the emitted code."""
        return self.symbol.name


@dataclass(frozen=True)
class ContactKernel:
    """An emitted kernel: arguments in order, assignment chain, and the result symbol.

    Parameters
    ----------
    structure : KernelStructure
        The scene's structure the kernel is specialised to.
    arguments : tuple of Argument
        The arguments in order.
    steps : tuple of (sympy.Symbol, sympy.Expr)
        The assignments, each of the arguments and earlier names.
    result : sympy.Symbol
        The name of the critical step [s].
    equations : tuple of str
        Human-readable lines for the header.
    """

    structure: KernelStructure
    arguments: tuple[Argument, ...]
    steps: tuple[tuple[sp.Symbol, sp.Expr], ...]  # (name, expression of args and earlier names)
    result: sp.Symbol
    equations: tuple[str, ...]  # human-readable lines for the header

    @property
    def symbols(self) -> tuple[sp.Symbol, ...]:
        """The argument symbols, in order."""
        return tuple(a.symbol for a in self.arguments)

    @property
    def uses_step(self) -> bool:
        """Whether the chain calls a careful step helper (``dtcrit.codegen.step``)."""
        return bool(self.step_variants)

    @property
    def step_variants(self) -> tuple[bool, ...]:
        """Which careful steps the chain calls: True the damped dt(k, c, A), False the undamped dt(k, A)."""
        return tuple(d for d, f in ((True, critical_step), (False, critical_step_undamped))
                     if any(e.has(f) for _, e in self.steps))

    def hash(self) -> str:
        """Short stable hash of the derivation (integrator, arguments, every step and the careful step's chain).

        Returns
        -------
        str
            16 hexadecimal digits (``dtcrit.symbolic.emit.derivation_hash``).
        """
        from dtcrit.codegen.step import chain

        items = [sp.Symbol(self.structure.integrator)] + list(self.symbols)
        for s, e in self.steps:
            items += [s, e]
        for d in self.step_variants:
            for s, e in chain(self.structure.integrator, d).steps:
                items += [s, e]
        return derivation_hash(items)

    def cse(self) -> tuple[list[tuple[sp.Symbol, sp.Expr]], list[tuple[sp.Symbol, sp.Expr]]]:
        """Common-subexpression elimination over the whole chain.

        Returns
        -------
        tuple of (list, list)
            ``(temporaries, steps)``: temporaries ``x0, x1, ...`` first, then the named steps
            rewritten in terms of them; the last step defines ``result``.
        """
        return cse_chain(self.symbols, self.steps)

    def statements(self) -> list[tuple[sp.Symbol, sp.Expr]]:
        """All assignments after CSE, each after everything it uses; the last defines ``result``.

        Returns
        -------
        list of (sympy.Symbol, sympy.Expr)
            The assignments to emit, in order.
        """
        return list(self._statements)

    @cached_property
    def _statements(self) -> tuple[tuple[sp.Symbol, sp.Expr], ...]:
        """See :meth:`statements`.

        Assignments nothing uses (a name CSE made redundant) are dropped; a bare copy ``y = x`` is
        folded into its uses.
        """
        temps, steps = self.cse()
        items = temps + steps
        changed = True
        while changed:
            changed = False
            for n, (sym, expr) in enumerate(items):
                if sym != self.result and expr.is_Symbol:  # y = x: use x directly
                    items = [(s, e.xreplace({sym: expr})) for s, e in items[:n] + items[n + 1:]]
                    changed = True
                    break
            used = set().union(*(e.free_symbols for _, e in items))
            kept = [(s, e) for s, e in items if s == self.result or s in used]
            if len(kept) != len(items):
                items, changed = kept, True
        return tuple(dependency_order(self.symbols, items, self.result))

    def op_count(self) -> int:
        """Arithmetic and function operations after CSE (``sympy.count_ops``, each emitted statement,
        including those of the careful steps it calls).

        Returns
        -------
        int
            The operation count printed in the header.
        """
        from dtcrit.codegen.step import chain

        own = sum(sp.count_ops(e) for _, e in self.statements())
        return int(own + sum(sp.count_ops(e) for d in self.step_variants for _, e in chain(self.structure.integrator, d).steps))

    def full_expression(self) -> sp.Expr:
        """The result as one expression of the arguments (steps substituted back).

        Returns
        -------
        sympy.Expr
            The critical step [s] in the arguments.
        """
        expr = self.result
        for s, e in reversed(self.steps):
            expr = expr.xreplace({s: e})
        return expr


# ----------------------------------------------------------------------------------------------
# Building blocks
# ----------------------------------------------------------------------------------------------
def _side_symbols(suffix: str, kind: str, rotation: bool) -> dict[str, sp.Symbol]:
    syms = {"m": _pos(f"m{suffix}")}
    if kind == "general":
        syms["I_xx"] = _pos(f"I_xx{suffix}")
        syms["r"] = _pos(f"r{suffix}")
        if rotation:
            syms["I_yy"] = _pos(f"I_yy{suffix}")
            syms["I_zz"] = _pos(f"I_zz{suffix}")
    return syms


def _side_arguments(suffix: str, kind: str, rotation: bool, syms: dict[str, sp.Symbol]) -> list[Argument]:
    who = f"particle {suffix}" if suffix else "each particle"
    out = [Argument(syms["m"], f"mass of {who}", "kg")]
    if kind == "general":
        out.append(Argument(syms["I_xx"], f"smallest principal moment of inertia of {who} (I_xx <= I_yy <= I_zz)", "kg m^2"))
        if rotation:
            out.append(Argument(syms["I_yy"], f"middle principal moment of inertia of {who}", "kg m^2"))
            out.append(Argument(syms["I_zz"], f"largest principal moment of inertia of {who}", "kg m^2"))
        out.append(Argument(syms["r"], f"contact arm of {who}: distance from its centre of mass to the contact point "
                            "(the largest centre-to-surface distance bounds every contact)", "m"))
    return out


def _side_A_term(kind: str, syms: dict[str, sp.Symbol]) -> sp.Expr:
    if kind == "sphere":
        return sp.Rational(7, 2) / syms["m"]  # 1/m + R^2 / (2/5 m R^2)
    return 1 / syms["m"] + syms["r"] ** 2 / syms["I_xx"]


def _b_max(syms: dict[str, sp.Symbol]) -> sp.Expr:
    """Peng et al. 2020, Eq. (54)."""
    ixx, iyy, izz = syms["I_xx"], syms["I_yy"], syms["I_zz"]
    return nan_max(sp.Abs(ixx - iyy) / izz, sp.Abs(ixx - izz) / iyy, sp.Abs(iyy - izz) / ixx)


# ----------------------------------------------------------------------------------------------
# The chain
# ----------------------------------------------------------------------------------------------
def build_kernel(structure: KernelStructure) -> ContactKernel:
    """The specialised assignment chain for ``structure`` (see the module docstring).

    Parameters
    ----------
    structure : KernelStructure
        The scene's structure (integrator, particle kinds, what is specialised).

    Returns
    -------
    ContactKernel
        The chain, its arguments and its header equations.
    """
    integrator = structure.integrator
    kernel = direction_kernel(integrator)
    depends_on_damping = kernel.has(GAMMA)
    tau0 = undamped_tau(integrator)
    undamped = [] if depends_on_damping and structure.damped_normal else ["normal"]
    undamped += [] if depends_on_damping and structure.damped_shear else ["shear"]
    if undamped and not (tau0.is_number and tau0 > 0) and depends_on_damping:
        where = "an undamped contact" if len(undamped) == 2 else f"a contact undamped in the {undamped[0]} direction"
        raise InputError(
            "integrator",
            f"'{integrator}' has no stable step for {where} (tau_crit(0) = {tau0}); nothing to generate",
        )

    steps: list[tuple[sp.Symbol, sp.Expr]] = []
    args: list[Argument] = []
    equations: list[str] = []

    # particles and A
    if structure.identical:
        kind = structure.sides[0]
        syms = _side_symbols("", kind, structure.rotation)
        args += _side_arguments("", kind, structure.rotation, syms)
        side_syms = [syms]
        if kind == "sphere":
            A_expr = 7 / syms["m"]
            A_normal_expr = 2 / syms["m"]
            equations.append("A_n = 2/m, A_s = 7/m  (two identical spheres, arm R: the normal and the sliding-rolling "
                             "modes separate exactly; Peng et al. 2020, Section 4.3)")
        else:
            half = _pos("A_half")
            steps.append((half, _side_A_term(kind, syms)))
            A_expr = 2 * half
            equations.append("A = 2 (1/m + r^2/I_xx)  (Peng et al. 2020, Eq. (26), identical particles, arm r)")
    else:
        side_syms = []
        terms = []
        for n, kind in enumerate(structure.sides, start=1):
            syms = _side_symbols(str(n), kind, structure.rotation)
            args += _side_arguments(str(n), kind, structure.rotation, syms)
            side_syms.append(syms)
            terms.append(_side_A_term(kind, syms))
        A_expr = terms[0] + terms[1]
        if structure.sides == ("sphere", "sphere"):
            A_normal_expr = 1 / side_syms[0]["m"] + 1 / side_syms[1]["m"]
            equations.append("A_n = 1/m1 + 1/m2, A_s = (7/2)(1/m1 + 1/m2)  (two spheres, arm R: the normal and the "
                             "sliding-rolling modes separate exactly)")
        else:
            parts = ["(7/2)/m%d" % n if k == "sphere" else "1/m%d + r%d^2/I_xx%d" % (n, n, n) for n, k in enumerate(structure.sides, 1)]
            equations.append("A = " + " + ".join(parts) + "  (Peng et al. 2020, Eq. (26) with the contact arms)")
    spheres = all(k == "sphere" for k in structure.sides)
    A = _pos("A_s" if spheres else "A")
    A_n = _pos("A_n") if spheres else A
    if spheres:
        steps.append((A_n, A_normal_expr))
    steps.append((A, A_expr))
    A_dir = {"n": A_n, "s": A}

    # translation: per direction
    kn, ks, cn, cs = _pos("kn"), _pos("ks"), _pos("cn"), _pos("cs")
    damping = {"n": cn if structure.damped_normal else None, "s": cs if structure.damped_shear else None}
    stiff = {"n": kn, "s": ks}
    args.append(Argument(kn, "normal contact stiffness (Hertz: tangent stiffness 2 E* sqrt(R* delta) at the overlap delta)", "N/m"))
    args.append(Argument(ks, "shear contact stiffness (Hertz-Mindlin: 8 G* sqrt(R* delta))", "N/m"))
    for j in ("n", "s"):
        if damping[j] is not None and depends_on_damping:
            args.append(Argument(damping[j], f"viscous damping coefficient, {'normal' if j == 'n' else 'shear'} direction", "N s/m"))

    dt_names = []
    tau_text = formula_text(integrator)
    for j in ("n", "s"):
        dt_j = _pos(f"dt_{j}")
        if damping[j] is not None and depends_on_damping:
            steps.append((dt_j, critical_step(stiff[j], damping[j], A_dir[j])))
        else:
            steps.append((dt_j, critical_step_undamped(stiff[j], A_dir[j])))
        dt_names.append(dt_j)
    a_j = "A_j" if spheres else "A"
    equations.append(f"dt_j = tau(zeta_j)/omega_j, omega_j = sqrt(k_j {a_j}), gamma_j = c_j {a_j}/2, zeta_j = gamma_j/omega_j, "
                     "j = n, s  (Peng et al. 2020, Eqs. (29)-(30))" + ("" if structure.damped and depends_on_damping
                                                                       else f"; undamped: tau = {sp.sstr(tau0)}"))
    equations.append(f"tau: {tau_text}")
    equations.append("each dt_j by critical_step(k_j, c_j, A_j): the careful evaluation of dtcrit.integrators.precise "
                     "(exact power-of-two scaling, forward Euler's error-free residual, the cubic's identity; "
                     "NaN for NaN or negative inputs)")
    if direction_kernel(integrator).has(cubic_positive_root):
        equations.append("cubic roots: zeta <= 1: smallest positive root tau of the cubic above; zeta > 1: tau = 1/(zeta y), "
                         "y the largest positive root of the cubic in y with coefficients in eps = 1/zeta^2 = (omega/gamma)^2")

    # rotation
    if structure.rotation:
        om = _pos("omega_max")
        args.append(Argument(om, "largest particle angular speed", "rad/s"))
        bs = [(_b_max(s) if k == "general" else sp.S.Zero) for s, k in zip(side_syms, structure.sides)]
        dt_r = _pos("dt_rotation")
        if structure.identical:
            B = _pos("B")
            steps.append((B, bs[0]))
            steps.append((dt_r, 1 / (om * B)))
            equations.append("dt_rotation = 1/(omega_max B), B = max(|I_xx-I_yy|/I_zz, |I_xx-I_zz|/I_yy, |I_yy-I_zz|/I_xx)  "
                             "(Peng et al. 2020, Eqs. (54), (56) with B1 = B2)")
        else:
            total = 0
            for n, b in enumerate(bs, start=1):
                if b != 0:
                    Bn = _pos(f"B{n}")
                    steps.append((Bn, b))
                    total += Bn
            steps.append((dt_r, 2 / (om * total)))
            equations.append("dt_rotation = 2/(omega_max (B1 + B2)), B_i = max(|I_xx-I_yy|/I_zz, |I_xx-I_zz|/I_yy, "
                             "|I_yy-I_zz|/I_xx)  (Peng et al. 2020, Eqs. (54), (56); B = 0 for a sphere)")
        dt_names.append(dt_r)

    result = _pos("dt")
    if len(dt_names) > 1:
        steps.append((result, nan_min(*dt_names)))
        equations.append("dt = min(" + ", ".join(s.name for s in dt_names) + ")")
    else:  # a single bound: it is the result
        last, expr = steps.pop()
        steps.append((result, expr))
        equations.append(f"dt = {last.name}")

    used = set().union(*(e.free_symbols for _, e in steps))
    arguments = tuple(a for a in args if a.symbol in used)
    return ContactKernel(structure, arguments, tuple(steps), result, tuple(equations))
