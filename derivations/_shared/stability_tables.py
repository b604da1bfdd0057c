"""Sections of the Section 4 record with the numbers: two spheres (Eqs. (48)-(49)), the table of
verified bounds against the printed ones, spectral radii, the CFL note, the labelled claims and the
numerics of the Cardano roots.
"""
from __future__ import annotations

import mpmath as mp
import sympy as sp
from .stability_tools import (
    BETAS,
    DPS,
    ZETAS,
    ZETAS_UNDER,
    A,
    _n,
    _verdict,
    _zero,
    beta,
    c,
    k,
    lambda_minus_one_bound,
    m,
    rho,
    tau_cfl,
    tau_eq34,
    tau_eq46,
    tau_star,
)

from dtcrit.bodies import Sphere, contact
from dtcrit.integrators.schemes import NAMES
from dtcrit.symbolic import paper_section4 as p4
from dtcrit.symbolic.boundary import tau_crit_mp
from dtcrit.symbolic.integrators import zeta


def section_spheres() -> list[str]:
    # contact coefficient matrix of two identical spheres touching along n = e_x (tangential e_y)
    r_, m_ = sp.symbols("r m", positive=True)
    I_ = sp.Rational(2, 5) * m_ * r_**2

    def cross(v):
        return sp.Matrix([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])

    r1 = sp.Matrix([r_, 0, 0])
    r2 = sp.Matrix([-r_, 0, 0])
    Amat = (2 / m_) * sp.eye(3) - cross(r1) * cross(r1) / I_ - cross(r2) * cross(r2) / I_
    Amat = Amat.applyfunc(sp.simplify)
    eig = sorted(set(Amat.eigenvals()), key=lambda e: sp.N(e.subs(m_, 1)))
    A_sphere = eig[-1]
    sph = Sphere(0.5, density=1000.0)
    A_num = 2.0 / sph.mass + 2.0 * sph.max_arm**2 / sph.inertia[0]
    A_contact = (contact.a_max(sph) * sph.mass, contact.a_bound(sph) * sph.mass)
    eq49 = sp.simplify((2 / sp.sqrt(k * A)).subs(A, A_sphere.subs(m_, m)))
    eq49_ok = _zero(eq49 - 2 / sp.sqrt(7) * sp.sqrt(m / k))
    with mp.workdps(DPS):
        alpha_vv = tau_star("velocity-verlet", "0") / mp.sqrt(7)
    return [
        "## 4. Undamped bound and identical spheres (Eqs. (48)-(49))",
        "",
        "Printed (48): $\\Delta t_{cri}=2/\\sqrt{k_nA_{max}}$; (49): $\\Delta t_{cri,sphere}=\\frac{2}{\\sqrt7}\\sqrt{m/k_n}$ "
        "with $A_{max}=7/m$.  No extraction damage.",
        "",
        "* (48) is (47) with $k_n\\ge k_s$; $2/\\sqrt{kA}$ decreases in $k$, so taking $k_n$ is conservative: "
        "**reproduced** (for the integrators whose undamped bound is $\\tau^*=2$, Section 5).",
        f"* Two identical spheres touching at arm $r$: the contact coefficient matrix "
        f"$A=(1/m_1+1/m_2)I-[r_1]_\\times I_1^{{-1}}[r_1]_\\times-[r_2]_\\times I_2^{{-1}}[r_2]_\\times$ with $I=\\frac25mr^2$ "
        f"has eigenvalues ${', '.join(sp.latex(e) for e in eig)}$ (normal, tangential); the largest is "
        f"${sp.latex(A_sphere)}$ (`dtcrit.bodies.Sphere`, $r=0.5$, $\\rho=1000$: $2/m+2r^2/I={_n(A_num * sph.mass, 6)}/m$; "
        f"`dtcrit.bodies.contact.a_max` (Eq. (26)) and `a_bound` for that sphere: {_n(A_contact[0], 6)}/m and {_n(A_contact[1], 6)}/m).  "
        f"With it (48) gives (49): {_verdict(eq49_ok)}; the exact undamped bound of `velocity-verlet` gives "
        f"$\\alpha=\\tau^*(0)/\\sqrt7={_n(alpha_vv, 12)}=2/\\sqrt7$.",
        "* The normal direction alone has $A=2/m$ and $\\alpha=\\sqrt2$ (Burns et al.'s value quoted after (49)); "
        "the rotation in the shear direction lowers it to $2/\\sqrt7$.",
        "",
    ]


def section_table() -> list[str]:
    from dtcrit._generated.critical_steps import FORMULAS

    eq46_tau = 2 * zeta + 2 * sp.sqrt(zeta**2 + 1)
    lines = [
        "## 5. Integrators: undamped bound, damped bound, '$\\lambda=-1$ only' bound, Eq. (46)",
        "",
        "'$\\lambda=-1$ only': the smallest positive root of $(-1)^np(-1)=0$, i.e. where a real eigenvalue reaches $-1$ "
        "(what Eqs. (44)-(46) compute), derived from each integrator's characteristic polynomial.  'Exact' is the "
        "full Jury boundary (all eigenvalues, complex pairs included).",
        "",
        "| integrator | undamped $\\tau^*(0)$ | damped closed form $\\omega\\Delta t_{crit}$ | '$\\lambda=-1$ only' bound | "
        "is it the exact bound? | agrees with Eq. (46)? |",
        "| --- | --- | --- | --- | --- | --- |",
    ]
    for name in NAMES:
        with mp.workdps(DPS):
            t0 = tau_star(name, "0")
        lm1 = lambda_minus_one_bound(name)
        formula = FORMULAS[name].split("; with omega")[0].replace("omega*dt = ", "").replace("**", "^")
        if lm1 is None:
            lm1_text, exact_text, agrees = "none", "-", "no"
        else:
            lm1_text = f"${sp.latex(lm1)}$"
            if _zero(sp.simplify(lm1 - eq46_tau)):
                agrees = "**yes** (identical)"
            elif sp.simplify(lm1.subs(zeta, 0)) == 2:
                agrees = "no (equal only at $\\zeta=0$)"
            else:
                agrees = "no"
            # compare with the exact bound at the sample damping ratios
            same = []
            with mp.workdps(DPS):
                for z in ZETAS:
                    val = sp.N(lm1.subs(zeta, sp.Rational(z)), 40)
                    ts = tau_star(name, z)
                    same.append(val.is_real and abs(mp.mpf(str(val)) - ts) < mp.mpf(10) ** -30)
            if all(same):
                exact_text = "yes"
            elif any(same):
                exact_text = "only for $\\zeta\\ge1$" if name == "forward-euler" else "partly"
            else:
                exact_text = "**no**"
        undamped = _n(t0) if t0 > 0 else "0 (unstable for all $\\Delta t$)"
        lines.append(f"| {name} | {undamped} | `{formula}` | {lm1_text} | {exact_text} | {agrees} |")
    lines += [
        "",
        "Eq. (46) is $\\tau=2\\zeta+2\\sqrt{\\zeta^2+1}$.  Only the Eq. (40) scheme has it as its $\\lambda=-1$ boundary, and "
        "for that scheme it is not the exact bound.  For the central-difference family the $\\lambda=-1$ boundary *is* "
        "the exact bound, and it is $2(\\sqrt{\\zeta^2+1}-\\zeta)$: Eq. (46) with the sign of $\\zeta$ reversed.  "
        "'exact' was compared at $\\zeta\\in\\{" + ", ".join(ZETAS) + "\\}$ to 30 digits.",
        "",
        "Values of the exact bound $\\tau^*$ (Jury boundary, 50 digits) and of Eq. (46):",
        "",
        "| integrator | " + " | ".join(f"$\\zeta={z}$" for z in ZETAS) + " |",
        "| --- |" + " --- |" * len(ZETAS),
    ]
    with mp.workdps(DPS):
        for name in NAMES:
            lines.append(f"| {name} | " + " | ".join(_n(tau_star(name, z)) for z in ZETAS) + " |")
        lines.append("| Eq. (46) | " + " | ".join(_n(tau_eq46(z)) for z in ZETAS) + " |")
    lines.append("")
    return lines


def section_radius() -> list[str]:
    lines = [
        "## 6. Spectral radius at the printed steps",
        "",
        "$\\rho$ of each integrator's amplification matrix (update rule applied to unit vectors, `mpmath.eig`, 50 "
        "digits) at $\\tau$ of Eq. (46) and, for $\\zeta<1$, of Eq. (34).  $\\rho>1$: the step is unstable.",
        "",
        "At Eq. (46), $\\tau=2\\zeta+2\\sqrt{\\zeta^2+1}$:",
        "",
        "| integrator | " + " | ".join(f"$\\zeta={z}$" for z in ZETAS) + " |",
        "| --- |" + " --- |" * len(ZETAS),
    ]
    with mp.workdps(DPS):
        lines.append("| $\\tau$ | " + " | ".join(_n(tau_eq46(z)) for z in ZETAS) + " |")
        for name in NAMES:
            lines.append(f"| {name} | " + " | ".join(_n(rho(name, tau_eq46(z), z), 8) for z in ZETAS) + " |")
        lines += [
            "",
            "At $\\zeta=0$, $\\rho=1$ is marginal (a double eigenvalue $-1$: the undamped bound itself).  For every "
            "$\\zeta>0$ sampled, $\\rho>1$ for every integrator: **Eq. (46) is not a stability bound of any of them.**",
            "",
            "At Eq. (34), $\\tau=2/\\sqrt{1-\\zeta^2}$ (defined for $\\zeta<1$ only):",
            "",
            "| integrator | " + " | ".join(f"$\\zeta={z}$" for z in ZETAS_UNDER) + " |",
            "| --- |" + " --- |" * len(ZETAS_UNDER),
            "| $\\tau$ | " + " | ".join(_n(tau_eq34(z)) for z in ZETAS_UNDER) + " |",
        ]
        for name in NAMES:
            lines.append(f"| {name} | " + " | ".join(_n(rho(name, tau_eq34(z), z), 8) for z in ZETAS_UNDER) + " |")
    lines += ["", "Eq. (34) is not a stability bound of any integrator for $\\zeta>0$ either.", ""]
    return lines


def section_cfl() -> list[str]:
    note = 2 * (sp.sqrt(zeta**2 + 1) - zeta)
    lines = [
        "## 7. Which integrators the CFL note's bound belongs to",
        "",
        "Seed 004: $\\Delta t\\le\\frac2\\omega(\\sqrt{\\zeta^2+1}-\\zeta)$, 'for a typical central difference scheme'.",
        "",
        "Spectral radius just below and just above the note's step, over $\\zeta\\in\\{" + ", ".join(ZETAS[1:]) + "\\}$:",
        "",
        "| integrator | $\\lambda=-1$ bound equals the note's (SymPy) | max $\\rho$ at $0.999\\tau_{note}$ | "
        "min $\\rho$ at $1.001\\tau_{note}$ | verdict |",
        "| --- | --- | --- | --- | --- |",
    ]
    conservative, unstable = [], []
    with mp.workdps(DPS):
        for name in NAMES:
            lm1 = lambda_minus_one_bound(name)
            same = lm1 is not None and _zero(sp.simplify(lm1 - note))
            below = [rho(name, tau_cfl(z) * mp.mpf("0.999"), z) for z in ZETAS[1:]]
            above = [rho(name, tau_cfl(z) * mp.mpf("1.001"), z) for z in ZETAS[1:]]
            exact = max(below) <= 1 and min(above) > 1
            if same and exact:
                verdict = "**the note's bound is exact**"
            elif max(below) <= 1 and max(above) <= 1:
                verdict = "conservative (stable on both sides)"
                conservative.append(f"`{name}`")
            else:
                verdict = "unstable at some sampled $\\zeta$"
                unstable.append(f"`{name}`")
            lines.append(
                f"| {name} | {'yes' if same else 'no'} | {_n(max(below), 8)} | {_n(min(above), 8)} | {verdict} |"
            )
    lines += [
        "",
        "The note's bound belongs to `symplectic-euler`, `leapfrog` (central difference, damping from the lagged "
        "half-step velocity, as in PFC/YADE) and `velocity-verlet` (damping from $v_{n+1/2}$, as in LAMMPS/LIGGGHTS): "
        "$\\rho\\le1$ just below and $\\rho>1$ just above it at every sampled $\\zeta$, and its $\\lambda=-1$ boundary "
        "equals it identically.  For " + (", ".join(conservative) or "none") + " it is conservative; for "
        + (", ".join(unstable) or "none") + " the note's step is unstable for some $\\zeta$ (it exceeds their own "
        "bound, Section 5).  See also `records/cfl_impact.md`.",
        "",
    ]
    return lines


def section_labelled() -> list[str]:
    b = sp.Symbol("beta", nonnegative=True)
    printed58 = 4 / sp.sqrt(28 - 49 * beta**2)
    printed59 = sp.pi / sp.sqrt(2 - beta**2 / 4)
    printed60 = beta + sp.sqrt(beta**2 + sp.Rational(4, 7))
    ok58 = _zero(sp.simplify(p4.beta_form(p4.eq34()) - printed58))
    ok59 = _zero(sp.simplify(p4.eq36().subs(c, beta * sp.sqrt(m * k)) * sp.sqrt(k / m) - printed59))
    ok60 = _zero(sp.simplify(p4.beta_form(p4.eq46()) - printed60))
    asym58 = [r for r in sp.solve(28 - 49 * b**2, b)]
    asym59 = [r for r in sp.solve(2 - b**2 / 4, b)]
    zeta_of_beta = sp.simplify((c * A / (2 * sp.sqrt(k * A))).subs({A: 7 / m, c: beta * sp.sqrt(m * k)}))
    lines = [
        "## 8. The beta forms for identical spheres (Eqs. (58)-(60)) and which formula bounds which integrator",
        "",
        "Printed: (58) $\\Delta t\\sqrt{k/m}=4/\\sqrt{28-49\\beta^2}$, (59) $\\pi/\\sqrt{2-\\beta^2/4}$, (60) "
        "$\\beta+\\sqrt{\\beta^2+4/7}$, with $A=7/m$, $\\beta=c/\\sqrt{mk}$.  No extraction damage.",
        "",
        f"* (34), (36), (46) with $A=7/m$, $c=\\beta\\sqrt{{mk}}$: (58) {_verdict(ok58)}, (59) {_verdict(ok59)}, "
        f"(60) {_verdict(ok60)}.  Asymptotes: (58) at $\\beta={sp.latex(asym58[-1])}$ ($\\zeta=1$ for $A=7/m$), (59) at "
        f"$\\beta={sp.latex(asym59[-1])}$ (as printed; see Section 1 for what it corresponds to).",
        f"* For $A=7/m$: $\\zeta={sp.latex(zeta_of_beta)}$ and $\\Delta t\\sqrt{{k/m}}=\\tau/\\sqrt7$.  Exact bounds "
        "(Jury boundary) in the same units:",
        "",
        "| $\\beta$ | $\\zeta$ | (58) | (59) | (60) | " + " | ".join(NAMES) + " |",
        "| --- | --- | --- | --- | --- |" + " --- |" * len(NAMES),
    ]
    over = {f: set() for f in ("58", "59", "60")}
    with mp.workdps(DPS):
        s7 = mp.sqrt(7)
        for bt in BETAS:
            bv = mp.mpf(bt)
            z = sp.Rational(bt) * sp.sqrt(7) / 2
            zf = bv * s7 / 2
            vals = {}
            vals["58"] = 4 / mp.sqrt(28 - 49 * bv**2) if 28 - 49 * bv**2 > 0 else None
            vals["59"] = mp.pi / mp.sqrt(2 - bv**2 / 4) if 2 - bv**2 / 4 > 0 else None
            vals["60"] = bv + mp.sqrt(bv**2 + mp.mpf(4) / 7)
            truths = []
            for name in NAMES:
                ts = tau_crit_mp(name, z, dps=40)[0] / s7
                truths.append(ts)
                for f, v in vals.items():
                    if v is not None and v > ts * (1 + mp.mpf(10) ** -30):
                        over[f].add(name)
            cells = [_n(vals[f]) if vals[f] is not None else "complex" for f in ("58", "59", "60")]
            lines.append(f"| {bt} | {_n(zf)} | " + " | ".join(cells) + " | " + " | ".join(_n(t) for t in truths) + " |")
    lines += [""]
    for f, label in (("58", "(58) = (34), Belytschko"), ("59", "(59) = (36), Silbert"), ("60", "(60) = (46)")):
        exceeded = [n for n in NAMES if n in over[f]]
        lines.append(
            f"* {label}: exceeds the exact bound of {', '.join(f'`{n}`' for n in exceeded) or 'no integrator'} at some "
            "sampled $\\beta$ -- **not a stability bound** for "
            + ("any integrator" if len(exceeded) == len(NAMES) else "those") + "."
        )
    lines += [
        "* At $\\beta=0$, (58) and (60) equal $2/\\sqrt7$, the exact undamped bound of the central-difference family and "
        "of `leapfrog-centred` and `velocity-verlet-predicted`; for $\\beta>0$ both exceed every exact bound (they grow "
        "with $\\beta$, the exact bounds do not).  (59) exceeds every exact bound at every $\\beta$ (by "
        "$\\pi\\sqrt7/(2\\sqrt2)\\approx2.94$ at $\\beta=0$).  'Similar for low damping' (text after Fig. 3) holds for "
        "(58) vs (60), but neither is a bound for any damped case.",
        "* Eq. (37) is no time step; in these units the critical damping is $\\beta=2/\\sqrt7$ ($\\zeta=1$).",
        "",
    ]
    return lines


def section_cardano_numerics() -> list[str]:
    rows = []
    one = mp.mpf(1)
    pts = (
        ("0.5", "(1+10^{-2})/3", lambda: (one + mp.mpf("1e-2")) / 3, "next to $\\tau\\zeta=1/6$"),
        ("0.5", "(1+10^{-4})/3", lambda: (one + mp.mpf("1e-4")) / 3, "next to $\\tau\\zeta=1/6$"),
        ("0.5", "(1+10^{-6})/3", lambda: (one + mp.mpf("1e-6")) / 3, "next to $\\tau\\zeta=1/6$"),
        ("0.3", "1.2", lambda: mp.mpf("1.2"), "$N<0$, $4\\lvert M\\rvert^3\\ll N^2$"),
        ("0.01", "3", lambda: mp.mpf("3"), "$N<0$, $4\\lvert M\\rvert^3\\ll N^2$"),
        ("0.1", "10^{-8}", lambda: mp.mpf("1e-8"), "small step"),
        ("1", "10^{-4}", lambda: mp.mpf("1e-4"), "small step, near a double root"),
    )
    with mp.workdps(DPS):
        for z, texpr, tfun, what in pts:
            zv = mp.mpf(z)
            tv = tfun()
            Nn = 18 * zv * tv - 27 * tv * tv - 2
            Mn = 1 - 6 * zv * tv
            S = mp.sqrt(mp.mpc(Nn * Nn - 4 * Mn**3))
            kappa_D = (abs(Nn) + abs(S)) / abs(Nn + S)
            kappa_S = (Nn * Nn + 4 * abs(Mn) ** 3) / abs(Nn * Nn - 4 * Mn**3)
            rows.append(f"| {z} | ${texpr}$ | {what} | {_n(kappa_S, 2)} | {_n(kappa_D, 2)} |")
    return [
        "## 9. Cardano's form (42)-(43) in floating point",
        "",
        "Exact in exact arithmetic (Section 2), but two subtractions cancel in floating point, with condition numbers "
        "(relative rounding error amplification, computed here at 50 digits) "
        "$\\kappa_S=(N^2+4|M|^3)/|N^2-4M^3|$ for the discriminant (large near a double eigenvalue, and for small "
        "$\\tau$ where $N\\to-2$, $M\\to1$) and $\\kappa_D=(|N|+|S|)/|N+S|$ for $D^3=N+S$ (large when $N<0$ and "
        "$4|M|^3\\ll N^2$: next to $\\tau\\zeta=1/6$, where $D\\to0$ and (42) divides by it, and for larger steps):",
        "",
        "| $\\zeta$ | $\\tau$ | where | $\\kappa_S$ | $\\kappa_D$ |",
        "| --- | --- | --- | --- | --- |",
        *rows,
        "",
        "An error in $S$ partly cancels between $u$ and $v=\\sqrt[3]2M/(3D)$, so $\\kappa_S$ overstates its effect; an "
        "error from $\\kappa_D$ does not cancel.  Measured in float64 (`tests/test_roots.py`, against 50-digit "
        "eigen-solves; normwise error $|\\Delta\\lambda|/\\max(1,|\\lambda|)$): a median of about $10^{-14}$, up to "
        "about $10^{-10}$ at $\\tau=10^{-8}$ and $4\\cdot10^{-9}$ anywhere with $|1-6\\tau\\zeta|\\ge0.1$; $10^{-5}$ to "
        "$10^{-2}$ at $|1-6\\tau\\zeta|=10^{-4}$; NaN within about $10^{-6}$ to $10^{-5}$ of $\\tau\\zeta=1/6$ "
        "($N+S$ rounds to 0).  `dtcrit._generated.eigenvalues` therefore uses the trigonometric / hyperbolic forms "
        "with the symbolically factored discriminant (near-zero factors in double-double), which the same tests hold "
        "to $2\\cdot10^{-15}$ everywhere on $\\tau\\in[10^{-8},4]$, $\\zeta\\in\\{0\\}\\cup[10^{-6},10^3]$, double and "
        "triple eigenvalues included; `eigenvalues_cardano_paper_eq40` keeps the literal route for comparison only.",
        "",
    ]
