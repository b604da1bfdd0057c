"""Sections of the Section 4 record on the schemes themselves: Belytschko's Eq. (34), the paper's
Eq. (40) scheme as printed, and where a real eigenvalue reaches -1 (Eq. (46)).
"""
from __future__ import annotations

import mpmath as mp
import sympy as sp
from .stability_tools import DPS, ZETAS, A, _n, _verdict, _zero, beta, c, eigenvalues, k, m, mpz, rho, tau_eq46, tau_star

from dtcrit.symbolic import paper_section4 as p4
from dtcrit.symbolic import paper_cardano as PC
from dtcrit.symbolic.boundary import boundary_factors
from dtcrit.symbolic.integrators import C, K, amplification_matrix, h, lam, tau, zeta


def section_belytschko() -> list[str]:
    s = p4.s
    # (30)/(31): x = exp(s t) in the ODE
    t_ = sp.Symbol("t")
    x = sp.exp(s * t_)
    ode = sp.diff(x, t_, 2) + c * A * sp.diff(x, t_) + k * A * x
    eq31_ok = _zero(sp.simplify(ode / x) - (s**2 + c * A * s + k * A))
    printed32 = {(-c * A + sp.sqrt(c**2 * A**2 - 4 * k * A)) / 2, (-c * A - sp.sqrt(c**2 * A**2 - 4 * k * A)) / 2}
    lib32 = p4.characteristic_roots()
    eq32_ok = all(any(_zero(sp.simplify(a - b)) for b in lib32) for a in printed32)
    printed33 = sp.sqrt(4 * k * A - c**2 * A**2) / 2
    eq33_ok = _zero(sp.simplify(printed33 - p4.omega_damped()))
    printed34 = 4 / sp.sqrt(4 * k * A - c**2 * A**2)
    eq34_ok = _zero(sp.simplify(printed34 - p4.eq34())) and _zero(sp.simplify(printed34 - 2 / printed33))
    printed35 = 2 / sp.sqrt(k * A)
    eq35_ok = _zero(sp.simplify(p4.eq34().subs(c, 0) - printed35))
    printed36 = sp.pi / sp.sqrt(2 * k / m - c**2 / (4 * m**2))
    eq36_ok = _zero(sp.simplify(printed36 - p4.eq36()))
    printed37 = 2 * sp.sqrt(k / A)
    eq37_ok = _zero(sp.simplify(printed37 - p4.eq37()))
    zeta_at_37 = sp.simplify((c * A / (2 * sp.sqrt(k * A))).subs(c, printed37))
    tau34 = sp.simplify(p4.eq34() * sp.sqrt(k * A)).subs(c, 2 * zeta * sp.sqrt(k / A))
    tau34 = sp.simplify(tau34)
    # Silbert with the reduced mass m* = m/2 throughout: omega_d^2 = k/m* - (c/(2 m*))^2
    mstar = m / 2
    silbert_consistent = sp.pi / sp.sqrt(k / mstar - (c / (2 * mstar)) ** 2)
    zn = sp.Symbol("zeta_n", nonnegative=True)  # zeta of the normal, translation-only contact: A = 2/m
    cn = zn * 2 * sp.sqrt(k * mstar)
    tau36_printed = sp.simplify(printed36.subs(c, cn) * sp.sqrt(k / mstar))
    tau36_consistent = sp.simplify(silbert_consistent.subs(c, cn) * sp.sqrt(k / mstar))
    beta_cri_normal = sp.simplify((2 * sp.sqrt(k * mstar)) / sp.sqrt(m * k))
    beta_cri_shear = sp.simplify((2 * sp.sqrt(k / (7 / m))) / sp.sqrt(m * k))
    beta_asym_59 = sp.solve(sp.Eq(2 - beta**2 / 4, 0), beta)
    lines = [
        "## 1. Belytschko's criterion, the contact ODE, Silbert's collision time (Eqs. (28)-(37))",
        "",
        "| Eq. | printed (transcribed) | extraction repairs | library | verdict |",
        "| --- | --- | --- | --- | --- |",
        "| (28) | $\\Delta t_{cri}=2/\\varphi_{max}$ | none | undamped: $\\tau^*(0)=2$ for `symplectic-euler`, `leapfrog`, "
        "`leapfrog-centred`, `velocity-verlet`, `velocity-verlet-predicted` (Section 5); 0 for `forward-euler`, "
        "`paper-eq40` | **reproduced** as the *undamped* bound of the central-difference family (the paper quotes "
        "it for a linear system with Rayleigh damping; with viscous contact damping it is not the bound, below) |",
        "| (29) | $F_j=-k_jx_{cj}-c_j\\dot x_{cj}$ | none | `dtcrit.integrators.schemes.LinearForce` | definition |",
        "| (30) | $\\ddot x_{cj}+c_jA\\dot x_{cj}+k_jA x_{cj}=0$ | subscript $i$ printed for $j$ (the equation is labelled $j=1,2,3$) | "
        "$\\ddot x=-Kx-C\\dot x$, $K=kA$, $C=cA$ | definition |",
        f"| (31) | $s^2+c_jAs+k_jA=0$ | none | $x=e^{{st}}$ in (30) (SymPy) | {_verdict(eq31_ok)} |",
        f"| (32) | $s=\\frac12(-c_jA\\pm\\sqrt{{c_j^2A^2-4k_jA}})$ | none | roots of (31) | {_verdict(eq32_ok)} |",
        f"| (33) | $\\omega_{{max}}=\\frac12\\sqrt{{4k_jA-c_j^2A^2}}$ | none | imaginary part of the roots (32) | "
        f"{_verdict(eq33_ok)}; it is the *damped* frequency $\\omega\\sqrt{{1-\\zeta^2}}<\\omega$ |",
        f"| (34) | $\\Delta t=2/\\omega_{{max}}=4/\\sqrt{{4k_jA-c_j^2A^2}}$ | none | `paper_section4.eq34` | "
        f"{_verdict(eq34_ok)} as algebra; **not a stability bound** (below) |",
        f"| (35) | $\\Delta t=2/\\sqrt{{k_jA}}$ | subscript $i$ for $j$ | (34) at $c=0$ | {_verdict(eq35_ok)} |",
        f"| (36) | $\\Delta t=\\pi/\\sqrt{{2k_n/m-c_n^2/(4m^2)}}$ | none | transcription equals `paper_section4.eq36` | "
        f"{_verdict(eq36_ok, 'transcribed')}; a collision time, **not a stability bound** (below) |",
        f"| (37) | $c_{{j,cri}}=2\\sqrt{{k_j/A}}$ | none | discriminant of (31) vanishes | {_verdict(eq37_ok)}; "
        f"$\\zeta$ there $={sp.latex(zeta_at_37)}$ |",
        "",
        f"* Eq. (34) in the dimensionless step: $\\tau={sp.latex(tau34)}$, which *grows* with $\\zeta$ and exceeds 2 for "
        "every $\\zeta>0$, while every integrator's exact bound is $\\le2$ (Section 5).  $2/\\omega$ is the exact bound "
        "of the **undamped** central difference; putting the damped frequency (33) into (28) does not give the damped "
        "bound.  The damped central-difference bound is $\\tau^*=2(\\sqrt{\\zeta^2+1}-\\zeta)$ (the CFL note, "
        "Section 7), smaller than 2.  Spectral radii at the step of Eq. (34) are in Section 6.",
        "* Eq. (36), Silbert et al.'s collision time $\\pi/\\omega_d$: for two identical spheres of mass $m$ the "
        "reduced mass is $m^*=m/2$, so $k/m^*=2k/m$ as printed, but the damping term of the same convention is "
        "$(c/(2m^*))^2=c^2/m^2$, four times the printed $c^2/(4m^2)$: the printed form uses $m$ in the damping "
        "term and $m/2$ in the stiffness term.  With the normal contact's own ratio "
        f"$\\zeta_n=c/(2\\sqrt{{km^*}})$ (translation only, $A=2/m$): printed $\\omega\\Delta t={sp.latex(tau36_printed)}$, "
        f"consistent reduced mass ${sp.latex(tau36_consistent)}$ (the CFL note's contact duration $t_d$).  Both are "
        "$\\ge\\pi>2$: a contact duration, of which codes take a fraction (e.g. $t_c/50$), never a stability bound.  "
        f"The printed asymptote $\\beta={sp.latex(beta_asym_59[-1])}$ of Eq. (59) is therefore not the critical damping of "
        f"the normal contact ($\\beta={sp.latex(beta_cri_normal)}$, $\\zeta_n=1$) nor of the shear contact with "
        f"$A=7/m$ ($\\beta={sp.latex(beta_cri_shear)}$), contrary to the text after Fig. 3.",
        "* Eq. (37) is the critical damping of the contact ODE (30) ($\\zeta=1$); it is not a time step.  It bounds the "
        "validity of (33)-(34) and is where `forward-euler`'s governing stability condition switches "
        "(complex pair for $\\zeta<1$, real eigenvalue at $-1$ for $\\zeta>1$).",
        "",
    ]
    return lines


def section_scheme() -> list[str]:
    G_lib = amplification_matrix("paper-eq40", dimensionless=False)
    G_printed = PC.paper_eq40_matrix().subs({PC.Kj: -K, PC.Cj: -C, PC.dt: h})
    eq40_ok = (G_lib - G_printed).applyfunc(sp.simplify) == sp.zeros(3, 3)
    fe = amplification_matrix("forward-euler", dimensionless=False)
    check = PC.check_paper_cardano()
    printed41 = PC.paper_eq41_determinant()
    # numeric check of the transcribed Eqs. (42)-(43) at 50 digits
    f42 = sp.lambdify((tau, zeta, PC.dt), [PC.to_dimensionless(e) for e in PC.paper_eq42_roots()], modules="mpmath")
    pts = (("0.05", "0"), ("0.5", "0.3"), ("1.7", "2"), ("3.9", "0.01"), ("0.000001", "10"))
    rows = []
    worst = mp.mpf(0)
    with mp.workdps(DPS + 10):
        for t, z in pts:
            got = [mp.mpc(v) for v in f42(mp.mpf(t), mp.mpf(z), mp.mpf(1))]
            ref = eigenvalues("paper-eq40", t, z)
            err = max(min(abs(g - r) for r in ref) for g in got)
            worst = max(worst, err)
            kinds = "3 real" if all(abs(mp.im(r)) < mp.mpf(10) ** -40 for r in ref) else "1 real + pair"
            rows.append(f"| {t} | {z} | {kinds} | {_n(err, 2)} |")
    lines = [
        "## 2. The printed scheme and its eigenvalues (Eqs. (38)-(43))",
        "",
        "Printed (38)-(39): $(x_{n+1}-x_n)/\\Delta t=\\dot x_n$, $(\\dot x_{n+1}-\\dot x_n)/\\Delta t=\\ddot x_n$; "
        "(40): $[x,\\dot x,\\ddot x]_{n+1}^T=\\begin{bmatrix}1&\\Delta t&0\\\\0&1&\\Delta t\\\\K_j&C_j&0\\end{bmatrix}"
        "[x,\\dot x,\\ddot x]_n^T$.  No extraction damage.",
        "",
        f"* The library's `paper-eq40` update rule gives exactly this matrix with $K_j=-kA$, $C_j=-cA$: {_verdict(eq40_ok)}.",
        "* Its third row sets $\\ddot x_{n+1}=K_jx_n+C_j\\dot x_n$: the acceleration used to advance $\\dot x$ from $n$ "
        "to $n+1$ is the force at the *previous* state $(x_{n-1},\\dot x_{n-1})$, a one-step lag.  Equations "
        "(38)-(39) with the contact law evaluated at the current state are forward Euler, whose matrix is "
        f"${sp.latex(fe)}$ (2x2; library symbols $h=\\Delta t$, $K=kA$, $C=cA$).  The two schemes differ; both are unstable for every $\\Delta t$ when undamped (Section 5).",
        "* The text says velocity Verlet 'would result in a 5x5 amplification matrix'.  With state "
        "$(x,\\dot x,\\ddot x)$ it is 3x3; one eigenvalue is identically 0 and the other two are those of symplectic "
        "Euler / leapfrog (`dtcrit.symbolic.integrators.characteristic_polynomial`): the same polynomial "
        "$\\lambda^2+\\lambda(\\tau^2+2\\tau\\zeta-2)+1-2\\tau\\zeta$ for all three.",
        "",
        "Printed (41): $\\begin{bmatrix}1-\\lambda&\\Delta t&0\\\\0&1-\\lambda&\\Delta t\\\\K_j&C_j&-\\lambda\\end{bmatrix}=0$.  "
        "Repair: the bracket is a determinant, $\\det(\\cdot)=0$.",
        "",
        f"* $\\det={sp.latex(sp.collect(printed41, lam))}$, equal to $-\\det(\\lambda I-G)$ of the library with "
        f"$K_j=-K$, $C_j=-C$: {_verdict(check.eq41_equals_library)}.",
        "",
        "Printed (42): $\\lambda_1=\\frac{D}{3\\sqrt[3]2}+\\frac{\\sqrt[3]2(3C_j\\Delta t+1)}{3D}+\\frac23$, "
        "$\\lambda_{2,3}=\\frac{(\\pm\\sqrt3i-1)D}{6\\sqrt[3]2}-\\frac{(1\\pm\\sqrt3i)(3C_j\\Delta t+1)}{3\\cdot2^{2/3}D}+\\frac23$; "
        "(43): $D=\\sqrt[3]{\\sqrt{(-9C_j\\Delta t+27K_j\\Delta t^2-2)^2-4(3C_j\\Delta t+1)^3}-9C_j\\Delta t+27K_j\\Delta t^2-2}$.  "
        "Repair in (43): in the extracted text the inner square root runs to the end; it ends after "
        "$(3C_j\\Delta t+1)^3$ (only this reading gives roots of (41)).",
        "",
        "* Cardano: with $\\lambda=t+2/3$ the monic form of (41) is $t^3+pt+q$ with "
        "$p=-(1+3C_j\\Delta t)/3$, $q=(2+9C_j\\Delta t-27K_j\\Delta t^2)/27$.  For $u=D/(3\\sqrt[3]2)$ and "
        f"$v=\\sqrt[3]2(3C_j\\Delta t+1)/(3D)$: $uv=-p/3$ {_verdict(check.uv_product)}, $u^3+v^3=-q$ "
        f"{_verdict(check.u3_plus_v3)} (SymPy, using $D^3=N+S$, $S^2=N^2-4(3C_j\\Delta t+1)^3$), shift $2/3$ "
        f"{_verdict(check.shift_is_two_thirds)}; the second and third roots are $\\omega u+\\bar\\omega v$ and "
        "$\\bar\\omega u+\\omega v$ with $\\omega=e^{2\\pi i/3}$, as printed.  The pairing holds for any cube root $D$.",
        f"* Numerically (transcribed (42)-(43) at 60 digits, principal roots, vs `mpmath.eig` of the numeric matrix): "
        f"largest deviation {_n(worst, 2)}.",
        "",
        "| $\\tau$ | $\\zeta$ | eigenvalues | max deviation |",
        "| --- | --- | --- | --- |",
        *rows,
        "",
        "* In the dimensionless variables $N=18\\zeta\\tau-27\\tau^2-2$ and $M=3C_j\\Delta t+1=1-6\\zeta\\tau$.  (42) divides "
        "by $D$, and $D=0$ exactly when $M=0$ and $N\\le0$: on the curve $\\tau\\zeta=1/6$ for $\\zeta\\le\\sqrt3/2$ "
        "(Section 9: how this costs digits in floating point).",
        "",
    ]
    return lines


def section_minus_one() -> list[str]:
    x, y, s_ = sp.symbols("x y s")  # x = C_j dt, y = K_j dt^2, s = the square root in the D-solutions
    M = 3 * x + 1
    u = sp.Symbol("u")
    # Eq. (44): D/(3 cbrt 2) + cbrt2 M/(3D) + 2/3 = +-1  <=>  u + M/(9u) = +-1 - 2/3 with u = D/(3 cbrt 2)
    sols = {}
    for target in (-1, 1):
        us = sp.solve(sp.Eq(u + M / (9 * u), target - sp.Rational(2, 3)), u)
        sols[target] = [sp.simplify(3 * sp.cbrt(2) * v) for v in us]
    printed_minus = [sp.cbrt(2) / 2 * (-5 + sp.sqrt(21 - 12 * x)), sp.cbrt(2) / 2 * (-5 - sp.sqrt(21 - 12 * x))]
    printed_plus = [sp.cbrt(2) / 2 * (-1 + sp.sqrt(-3 - 12 * x)), sp.cbrt(2) / 2 * (-1 - sp.sqrt(-3 - 12 * x))]
    minus_ok = all(any(_zero(sp.radsimp(a - b)) for b in sols[-1]) for a in printed_minus)
    plus_ok = all(any(_zero(sp.radsimp(a - b)) for b in sols[1]) for a in printed_plus)

    def lam1_of(Dval):
        uu = Dval / (3 * sp.cbrt(2))
        return sp.simplify(sp.radsimp(uu + M / (9 * uu) + sp.Rational(2, 3)))

    lam_printed_plus = lam1_of(printed_plus[0])
    # Eq. (45): roots of p(-1) = 0 in dt
    det = PC.paper_eq41_determinant()
    p_minus1 = sp.factor(det.subs(lam, -1))
    p_plus1 = sp.factor(det.subs(lam, 1))
    roots45 = sp.solve(p_minus1, PC.dt)
    printed45 = [(PC.Cj + sp.sqrt(PC.Cj**2 - 4 * PC.Kj)) / PC.Kj, (PC.Cj - sp.sqrt(PC.Cj**2 - 4 * PC.Kj)) / PC.Kj]
    eq45_ok = all(any(_zero(sp.radsimp(a - b)) for b in roots45) for a in printed45)
    neg_root_sign = sp.simplify(printed45[0].subs({PC.Cj: -c * A, PC.Kj: -k * A}))
    # squaring step: (w^3 - N)^2 = N^2 - 4 M^3 with w one of the lambda = -1 D-solutions
    N = -9 * x + 27 * y - 2
    w = sp.cbrt(2) * (-5 + s_) / 2
    squared = sp.rem(sp.expand(w**6 - 2 * N * w**3 + 4 * M**3), s_**2 - (21 - 12 * x), s_)
    squared = sp.factor(squared)
    other = [f for f, _ in sp.factor_list(squared)[1] if f.has(s_)][0]
    a_s, b_s = sp.Poly(other, s_).all_coeffs()  # other = a_s s + b_s
    spurious = sp.factor(sp.expand(a_s**2 * (21 - 12 * x) - b_s**2))
    # Eq. (46)
    printed46_a = (PC.Cj - sp.sqrt(PC.Cj**2 - 4 * PC.Kj)) / PC.Kj
    printed46_b = (sp.sqrt(4 * k * A + c**2 * A**2) + c * A) / (k * A)
    eq46_forms_ok = _zero(sp.simplify(printed46_a.subs({PC.Cj: -c * A, PC.Kj: -k * A}) - printed46_b))
    eq46_lib_ok = _zero(sp.simplify(printed46_b - p4.eq46()))
    printed47 = sp.sqrt(-4 / PC.Kj)
    eq47_ok = _zero(sp.simplify(printed47.subs(PC.Kj, -k * A) - 2 / sp.sqrt(k * A))) and _zero(
        sp.simplify(p4.eq46().subs(c, 0) - 2 / sp.sqrt(k * A))
    )
    lam_factor = next(f for f in boundary_factors("paper-eq40") if f.condition.startswith("(-1)^n"))
    cubic = next(f for f in boundary_factors("paper-eq40") if f.poly.degree() == 3)
    # the spurious step dt = -1/(3 C_j): tau = 1/(6 zeta)
    rows_sp = []
    with mp.workdps(DPS):
        for z in ("0.05", "0.5", "0.8", "1", "2"):
            t = 1 / (6 * mpz(z))
            ev = eigenvalues("paper-eq40", t, z)
            Nn = 18 * mpz(z) * t - 27 * t * t - 2
            rows_sp.append(
                f"| {z} | {_n(t)} | {_n(min(abs(v + 1) for v in ev), 3)} | {_n(max(abs(v) for v in ev))} | "
                f"{'0' if Nn <= 0 else _n(mp.cbrt(2 * Nn))} |"
            )
        z_coincide = 1 / mp.sqrt(168)
    lines = [
        "## 3. The 'real eigenvalue at -1' boundary (Eqs. (44)-(47))",
        "",
        "Printed (44): $\\frac{D}{3\\sqrt[3]2}+\\frac{\\sqrt[3]2(3C_j\\Delta t+1)}{3D}+\\frac23=\\pm1$, with the solutions "
        "$D=\\frac{\\sqrt[3]2}{2}(-5\\pm\\sqrt{21-12C_j\\Delta t})$ and $D=\\frac{\\sqrt[3]2}{2}(-1\\pm\\sqrt{-3-12C_j\\Delta t})$.  "
        "No extraction damage.",
        "",
        f"* $\\lambda_1=-1$: the printed $D$ values {_verdict(minus_ok)}.",
        f"* $\\lambda_1=+1$: the library gives $D={sp.latex(sols[1][0])}$, ${sp.latex(sols[1][1])}$; the printed pair "
        f"{_verdict(plus_ok)} -- it has the opposite sign of the 1: substituted into $\\lambda_1$ it gives "
        f"$\\lambda_1={sp.latex(lam_printed_plus)}$, not 1.  (Harmless: $\\det$ at $\\lambda=1$ is "
        f"${sp.latex(p_plus1)}$, zero only at $\\Delta t=0$, so no eigenvalue reaches $+1$.)",
        "* Eq. (44) only looks at the real root $\\lambda_1$ and only at $\\pm1$; a complex pair reaching $|\\lambda|=1$ "
        "is not considered.  That is the gap that makes Eq. (46) not a stability bound (below).",
        "",
        "Printed (45): $\\Delta t=\\frac{C_j\\pm\\sqrt{C_j^2-4K_j}}{K_j}$.  Repair: the denominator's subscript $i$ "
        "is $j$.  Printed (46): $\\Delta t_{cri}=\\frac{C_j-\\sqrt{C_j^2-4K_j}}{K_j}=\\frac{\\sqrt{4k_jA+c_j^2A^2}+c_jA}{k_jA}$.  "
        "Repair: in the extracted text the root runs over $+c_jA$; it ends before it (the first form fixes it).  "
        "Printed (47): $\\Delta t_{cri}=\\sqrt{-4/K_j}=2/\\sqrt{k_jA}$ (subscript $i$ for $j$ repaired).",
        "",
        f"* $\\det$ of (41) at $\\lambda=-1$ is ${sp.latex(p_minus1)}$; its roots in $\\Delta t$ are the two of (45): "
        f"{_verdict(eq45_ok)}.  The '+' root is ${sp.latex(neg_root_sign)}<0$ (as the paper says); the other is (46).",
        f"* The two forms of (46) agree {_verdict(eq46_forms_ok)}, and equal `paper_section4.eq46` (derived from the "
        f"Jury condition $(-1)^n p(-1)>0$, factor ${sp.latex(lam_factor.poly.as_expr())}$ in $\\tau$) {_verdict(eq46_lib_ok)}.  "
        f"(47) follows at $c=0$ {_verdict(eq47_ok)}.",
        f"* The 'third solution' $\\Delta t=-1/(3C_j)=1/(3cA)$ ($\\tau=1/(6\\zeta)$): equating a $\\lambda=-1$ value of $D$ "
        f"with (43) and squaring out the roots gives ${sp.latex(squared)}=0$ ($x=C_j\\Delta t$, $y=K_j\\Delta t^2$, "
        f"$s=\\sqrt{{21-12x}}$); the first factor is $\\det(-1)=0$, i.e. (45); removing $s$ from the second gives "
        f"${sp.latex(spurious)}=0$, the triple root $x=-1/3$.  There $3C_j\\Delta t+1=0$, $s=5$ and the $D$ values "
        "are $0$ and $-5\\sqrt[3]2$; $D=0$ makes (42) undefined, as the paper says (**reproduced**).  It is not a "
        "$\\lambda=-1$ step: (43) gives $D=\\sqrt[3]{N+|N|}$ there, i.e. $0$ only for $\\zeta\\le\\sqrt3/2$ and never "
        "$-5\\sqrt[3]2$; the eigenvalues at $\\tau=1/(6\\zeta)$ miss $-1$ except where it happens to coincide with (46), "
        f"at $\\zeta=1/\\sqrt{{168}}={_n(z_coincide)}$:",
        "",
        "| $\\zeta$ | $\\tau=1/(6\\zeta)$ | $\\min\\lvert\\lambda+1\\rvert$ | $\\rho$ | $D$ of (43) |",
        "| --- | --- | --- | --- | --- |",
        *rows_sp,
        "",
        "**What Eq. (46) is.**  It is the step where the real eigenvalue of the Eq. (40) scheme reaches $-1$.  The "
        "scheme's spectral radius first reaches 1 where its complex pair crosses the unit circle, the smallest "
        f"positive root of ${sp.latex(cubic.poly.as_expr())}=0$ (Jury condition '{cubic.condition}'), and for "
        "$\\zeta=0$ it exceeds 1 for every $\\tau>0$ ($\\lambda\\approx1\\pm i\\tau$ for small $\\tau$).  Eq. (46) is "
        "therefore **not the stability bound of the scheme it is derived for**:",
        "",
        "| $\\zeta$ | $\\tau$ of (46) | $\\rho$ at (46) | exact $\\tau^*$ of Eq. (40) | $\\rho$ at $0.999\\tau^*$ | $\\rho$ at $1.001\\tau^*$ | $\\rho$ at $\\tau=0.01$ |",
        "| --- | --- | --- | --- | --- | --- | --- |",
    ]
    with mp.workdps(DPS):
        for z in ZETAS:
            ts = tau_star("paper-eq40", z)
            t46 = tau_eq46(z)
            below = rho("paper-eq40", ts * mp.mpf("0.999"), z) if ts > 0 else None
            above = rho("paper-eq40", ts * mp.mpf("1.001"), z) if ts > 0 else None
            lines.append(
                f"| {z} | {_n(t46)} | {_n(rho('paper-eq40', t46, z))} | {_n(ts) if ts > 0 else '0 (none stable)'} | "
                f"{_n(below)} | {_n(above)} | {_n(rho('paper-eq40', mp.mpf('0.01'), z))} |"
            )
    lines.append("")
    return lines
