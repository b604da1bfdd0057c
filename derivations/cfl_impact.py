"""Record: the CFL note's one-dimensional impact formulas and Feng's claim, re-derived and checked.

Source: seed 004 ("The CFL condition for explicit discrete element methods: 4"), which prints the
linear bound dt <= (2/omega)(sqrt(zeta^2+1) - zeta) in two forms, the impact equations, the contact
duration t_d and exit velocity v_e, and summarises Feng (IJNME 2005, 64:1959).  Every formula is
compared with ``dtcrit.symbolic.impact`` / ``dtcrit.symbolic.closed_forms`` (SymPy), the generated
runtime (``dtcrit.impact``) and an independent high-accuracy integration (scipy DOP853, rtol 1e-12).
"""
from __future__ import annotations

import math

import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp
from _shared.text import num

import dtcrit.impact as imp
from dtcrit.integrators.schemes import NAMES
from dtcrit.integrators.stability import critical_dt
from dtcrit.symbolic import impact as si
from dtcrit.symbolic import impact_contact as sic
from dtcrit.symbolic import impact_stepping as sis
from dtcrit.symbolic.closed_forms import closed_pieces
from dtcrit.symbolic.integrators import zeta as zeta_nn

RECORD = "cfl_impact.md"

GRID_STEP = 0.01
PHASES = 64
ZETAS = (0.0, 0.05, 0.2)


def _ranges(rs) -> str:
    return "none" if not rs else ", ".join(f"[{a:.2f}, {b:.2f}]" for a, b in rs)


# ---------------------------------------------------------------------------------------------

def section_bound() -> list[str]:
    z = sp.Symbol("zeta", nonnegative=True)
    note = 2 * (sp.sqrt(z**2 + 1) - z)  # tau = omega dt
    k, c, m = sp.symbols("k c m", positive=True)
    note_kcm = 2 * sp.sqrt(m / k) * (sp.sqrt(c**2 / (4 * k * m) + 1) - c / (2 * sp.sqrt(k * m)))
    same_forms = sp.simplify(note_kcm - (note / sp.sqrt(k / m)).subs(z, c / (2 * sp.sqrt(k * m)))) == 0
    lines = [
        "## 1. The linear bound",
        "",
        "Printed (seed 004, transcribed; no extraction damage):",
        "",
        r"$$\Delta t \le \frac{2}{\omega}\left(\sqrt{\zeta^2+1}-\zeta\right),\qquad "
        r"\Delta t \le 2\sqrt{\frac{m}{k}}\left(\sqrt{\frac{c^2}{4km}+1}-\frac{c}{2\sqrt{km}}\right)$$",
        "",
        f"* The two printed forms agree with $\\omega=\\sqrt{{k/m}}$, $\\zeta=c/(2\\sqrt{{km}})$ (SymPy: difference "
        f"simplifies to 0): **{'reproduced' if same_forms else 'differs'}**.",
        "* The note attributes the bound to 'a typical central difference scheme'.  Against the exact bound "
        "$\\tau^*(\\zeta)=\\omega\\,\\Delta t_{crit}$ of each integrator (amplification matrix of the update rule, "
        "Jury conditions; `dtcrit.symbolic.closed_forms`), with $2(\\sqrt{\\zeta^2+1}-\\zeta) = "
        "2/(\\zeta+\\sqrt{\\zeta^2+1})$:",
        "",
        "| integrator | exact $\\tau^*(\\zeta)$ | note's bound? | $\\tau^*$ at $\\zeta=0.2$ | at $\\zeta=1$ |",
        "| --- | --- | --- | --- | --- |",
    ]
    note_02 = float(note.subs(z, sp.Rational(1, 5)))
    note_1 = float(note.subs(z, 1))
    for name in NAMES:
        pieces = closed_pieces(name)
        if all(cp.kind == "root" for cp in pieces):
            exprs = [cp.tau_expr.subs(zeta_nn, z) for cp in pieces]
            same = len(exprs) == 1 and sp.simplify(exprs[0] - note) == 0
            text = "; ".join(
                f"${sp.latex(e)}$" + ("" if len(pieces) == 1 else f" ($\\zeta\\in[{cp.piece.zeta_lo}, {sp.latex(cp.piece.zeta_hi)}]$)")
                for e, cp in zip(exprs, pieces)
            )
        else:
            same = False
            text = "smallest positive root of $" + sp.latex(pieces[0].piece.factor.poly.as_expr()) + "$"
        t02 = critical_dt(name, 1.0, 0.4, 1.0).omega_dt
        t1 = critical_dt(name, 1.0, 2.0, 1.0).omega_dt
        verdict = "reproduced (identical)" if same else "differs"
        lines.append(f"| {name} | {text} | {verdict} | {num(t02)} | {num(t1)} |")
    lines += [
        "",
        f"The note's bound gives {num(note_02)} at $\\zeta=0.2$ and {num(note_1)} at $\\zeta=1$.  It is the exact bound of "
        "the central difference with the damping force evaluated from the lagged half-step velocity "
        "(`leapfrog`, `symplectic-euler`) or, in velocity Verlet, from $v_{n+1/2}$ (`velocity-verlet`): "
        "**reproduced for these three**.  It is not the bound of the other variants: with the damping "
        "velocity centred, $(v_{n-1/2}+v_{n+1/2})/2$, the bound is $\\tau^*=2$ for every $\\zeta$; with the "
        "predicted velocity $v_n+\\Delta t\\,a_n$ it is $2/(2\\zeta+\\sqrt{4\\zeta^2+1})$, smaller.",
        "",
    ]
    return lines


def _integrate(zeta: float, kind: str):
    def rhs(s, y):
        return [y[1], -2.0 * zeta * y[1] - y[0]]

    def ev(s, y):
        if s == 0:
            return 1.0
        return y[0] if kind == "geometric" else y[0] + 2.0 * zeta * y[1]

    ev.terminal, ev.direction = True, -1
    sol = solve_ivp(rhs, (0.0, 100.0), [0.0, 1.0], method="DOP853", rtol=1e-12, atol=1e-14, events=ev)
    return sol.t_events[0][0], -sol.y_events[0][0][1]


def section_exact() -> list[str]:
    t_d, v_e = sic.geometric_separation()
    z = sic.zeta
    note_td = sp.pi / sp.sqrt(1 - z**2)
    note_ve = sp.exp(-z * sp.pi / sp.sqrt(1 - z**2))
    td_ok = sp.simplify(t_d - note_td) == 0
    ve_ok = sp.simplify(-v_e - note_ve) == 0
    rel = sic.force_release()
    lines = [
        "## 2. Contact duration and exit velocity",
        "",
        "Printed (seed 004): the impact equation $m\\ddot d=-c\\dot d-kd$ for $d\\ge 0$ (contact), "
        "$m\\ddot d=0$ for $d<0$, with",
        "",
        r"$$t_d=\frac{\pi}{\sqrt{1-\zeta^2}},\qquad v_e=v_0\exp\left[-\frac{\zeta\pi}{\sqrt{1-\zeta^2}}\right].$$",
        "",
        "Transcription notes: the note calls $d$ the gap but counts $d\\ge0$ as contact, so $d$ is the "
        "overlap; $t_d$ is printed without its unit: it is in units of $1/\\omega$, $\\omega=\\sqrt{k/m}$ "
        "($t_d=\\pi/\\omega_d$ with $\\omega_d=\\omega\\sqrt{1-\\zeta^2}$).",
        "",
        "Derivation (`dtcrit.symbolic.impact`, SymPy `dsolve` of $d''+2\\zeta d'+d=0$, $d(0)=0$, $d'(0)=1$, "
        "time $s=\\omega t$):",
        "",
    ]
    for regime in ("undamped", "underdamped", "critical", "overdamped"):
        sub = {"underdamped": "w=\\sqrt{1-\\zeta^2}", "overdamped": "\\mu=\\sqrt{\\zeta^2-1}"}.get(regime, "")
        lines.append(f"* {regime}: $d(s)={sp.latex(sic.contact_motion(regime))}$" + (f" with ${sub}$" if sub else ""))
    lines += [
        "",
        "**Geometric separation** (the note's equation; contact while $d\\ge0$, the dashpot force may turn "
        "tensile): $d$ first returns to 0 at $s=\\pi/w$, where $d'=" + sp.latex(v_e) + "$.",
        "",
        f"* $t_d$: **{'reproduced' if td_ok else 'differs'}** (for $\\zeta<1$, units $1/\\omega$).",
        f"* $v_e$: **{'reproduced' if ve_ok else 'differs'}** (for $\\zeta<1$).",
        "* Not stated in the note: for $\\zeta\\ge1$ the overlap $d=se^{-s}$ resp. "
        "$(e^{-as}-e^{-(a+c)s})/c$ ($a=\\zeta-\\mu$, $c=2\\mu$) stays positive for all $s>0$ "
        "and only tends to 0 (SymPy limits: $d\\to0$, $d'\\to0$): the bodies never separate; $t_d=\\infty$, "
        "$v_e=0$ in the limit.",
        "",
        "**Force-based release** (the contact force $kd+c\\dot d=-m\\ddot d$ acts only while compressive): "
        "the release is the first zero of $\\ddot d$.  SymPy verifies $P(s_f)=0$, $d'(s_f)=-e^{-\\zeta s_f}$ and "
        "$d(s_f)=2\\zeta e^{-\\zeta s_f}$ in every regime with",
        "",
        r"$$s_f=2g(\zeta),\quad g=\frac{\arccos\zeta}{\sqrt{1-\zeta^2}}\ (\zeta<1),\ 1\ (\zeta=1),\ "
        r"\frac{\operatorname{arccosh}\zeta}{\sqrt{\zeta^2-1}}\ (\zeta>1),\qquad \frac{v_e}{v_0}=e^{-2\zeta g(\zeta)}$$",
        "",
        "$g$ is one analytic function (both forms solve $(1-\\zeta^2)g'=\\zeta g-1$, regular at 1); near "
        "$\\zeta=1$ the runtime uses its Taylor polynomial $" + sp.latex(sic.g_series()) + "$ in $u=1-\\zeta$ "
        "(checked against SymPy's direct series).  The bodies always separate; after release they coast "
        "apart and the overlap closes after a further $2\\zeta/\\omega$.",
        "",
        "Released values from the SymPy derivation: "
        + "; ".join(f"{r}: $s_f={sp.latex(v[0])}$" for r, v in rel.items()) + ".",
        "",
        "Check against DOP853 (rtol $10^{-12}$) with event detection (geometric: $d=0$; force-based: "
        "$d+2\\zeta d'=0$), dimensionless:",
        "",
        "| $\\zeta$ | $t_d$ (note) | $v_e/v_0$ (note) | force-based $s_f$ | force-based $v_e/v_0$ | max rel. diff. from integration |",
        "| --- | --- | --- | --- | --- | --- |",
    ]
    for zz in (0.0, 0.05, 0.2, 0.5, 0.9, 1.0, 2.0):
        ex = imp.exact_impact(zz)
        diffs = []
        if zz < 1:
            s_d, r_d = _integrate(zz, "geometric")
            diffs += [abs(s_d / ex.duration - 1), abs(r_d / ex.exit_ratio - 1)]
        s_f, r_f = _integrate(zz, "force")
        diffs += [abs(s_f / ex.force_release_time - 1), abs(r_f / ex.force_exit_ratio - 1)]
        worst = max(diffs)
        lines.append(
            f"| {zz:g} | {num(ex.duration)} | {num(ex.exit_ratio)} | {num(ex.force_release_time)} | "
            f"{num(ex.force_exit_ratio)} | {'< 1e-9' if worst < 1e-9 else num(worst, 2)} |"
        )
    lines += [
        "",
        "The force-based exit speed is larger than the geometric one (no tensile phase): at $\\zeta=0.2$ "
        f"{num(imp.exact_impact(0.2).force_exit_ratio, 4)} vs {num(imp.exact_impact(0.2).exit_ratio, 4)}.  "
        "The time-stepped simulation below uses the **geometric** convention, the note's equation.",
        "",
    ]
    return lines


def section_stepped() -> list[str]:
    grid = imp.sweep_grid(GRID_STEP)
    phases = imp.entry_phases(PHASES)
    lines = [
        "## 3. Stability of the time-stepped impact; Feng's claim",
        "",
        "Printed (seed 004): an algorithm is stable if $v_e\\le v_0$; 'Feng's work (IJNME 2005, 64:1959) used "
        "numerical solutions of the one-dimensional problem to prove that discrete element calculations can "
        "become unconditionally unstable for $\\Delta t<2/\\omega$, except for a few values where the exit "
        "velocity is equal to $v_0$.  However, a small amount of damping can improve the stability behavior.'",
        "",
        "Simulation (`dtcrit.impact.simulate_impacts`): each integrator's own update rule; the force is the "
        "spring-dashpot force where the overlap at the force's evaluation point is $\\ge0$, else 0; the entry "
        "phase $\\phi\\in[0,1)$ places the first in-contact step at $x_0=\\phi\\,\\tau$ ($\\phi=0$: contact begins "
        f"on a step).  Grid $\\tau=\\omega\\Delta t\\in(0,2.2]$ step {GRID_STEP}, {PHASES} phases.",
        "",
        "### 3.1 Undamped closed form (central-difference family)",
        "",
        "SymPy shows that for `symplectic-euler`, `leapfrog`, `leapfrog-centred`, `velocity-verlet` and "
        "`velocity-verlet-predicted` (undamped) the positions obey $x_{n+1}-2x_n+x_{n-1}=-\\tau^2x_n$ in contact "
        "from any state, the first contact step continues the free-flight history, and the exit speed is "
        "$(x_{m-1}-x_m)/\\tau$: the five schemes give identical impacts (residuals 0).  The recurrence "
        "conserves $Q=" + sp.latex(sis.central_difference_invariant()) + "$ ($v$ the half-step velocity).  With "
        "the exit phase $\\psi=-x_m/(x_{m-1}-x_m)\\in(0,1]$:",
        "",
        "$$\\frac{v_e}{v_0}=" + sp.latex(sis.central_difference_ratio_expr()) + ",\\qquad "
        "\\sqrt{1-\\tau^2/4}\\le\\frac{v_e}{v_0}\\le\\frac{1}{\\sqrt{1-\\tau^2/4}}$$",
        "",
        "with $x_n=" + sp.latex(sis.central_difference_position_expr()) + "$.  If $\\pi/\\theta=N$ "
        "($\\cos\\theta=1-\\tau^2/2$), the exit mirrors the entry ($\\psi=\\phi$, SymPy) and $v_e=v_0$ for every "
        "phase: $\\tau_N=2\\sin(\\pi/(2N))$.  A contact beginning on a step ($\\phi=0$) never loses energy.",
        "",
    ]
    run = imp.simulate_impacts("leapfrog", grid[grid < 2], phases, 0.0)
    closed = imp.undamped_exit_ratios("leapfrog", run.omega_dt, phases)
    rel = float(np.max(np.abs(run.ratios / closed - 1)))
    lo, hi = imp.central_difference_bounds(run.omega_dt)
    inside = bool(np.all((run.ratios >= lo[:, None] * (1 - 1e-12)) & (run.ratios <= hi[:, None] * (1 + 1e-12))))
    lines += [
        f"* closed form vs simulation on the grid ($\\tau<2$, {PHASES} phases): max relative difference "
        f"{'< 1e-12' if rel < 1e-12 else num(rel, 2)}; bounds hold: {'yes' if inside else 'no'}.",
        "",
        "| $N$ | $\\tau_N$ | simulated max over phases of $|v_e/v_0-1|$ | max $v_e/v_0$ at the midpoint to $\\tau_{N+1}$ |",
        "| --- | --- | --- | --- |",
    ]
    for N, t in imp.unit_ratio_steps(0.3, 1.99):
        r = imp.simulate_impacts("leapfrog", [t], phases, 0.0).ratios[0]
        t_next = 2 * math.sin(math.pi / (2 * (N + 1)))
        r_mid = imp.simulate_impacts("leapfrog", [(t + t_next) / 2], phases, 0.0).ratios[0]
        dev = float(np.max(np.abs(r - 1)))
        lines.append(f"| {N} | {t:.6f} | {'< 1e-11' if dev < 1e-11 else num(dev, 2)} | {num(float(r_mid.max()), 5)} |")
    lines += [
        "",
        "Mean over phases of $v_e/v_0$ (undamped, leapfrog): "
        + ", ".join(
            f"$\\tau={t:g}$: {num(float(np.mean(imp.simulate_impacts('leapfrog', [t], phases, 0.0).ratios)), 8)}"
            for t in (0.1, 0.5, 1.2, 1.8)
        )
        + ".",
        "",
        "Forward Euler (undamped): one step is $\\sqrt{1+\\tau^2}$ times a rotation by $\\arctan\\tau$; its exit "
        "speed $|v_m|$ exceeds $v_0$ at every step and phase (closed form checked against the simulation in "
        "the tests).  `paper-eq40` has no stable undamped step.",
        "",
        "### 3.2 Sweep per integrator and damping ratio",
        "",
        "'max' is the maximum over entry phases; ranges are runs of grid points where it exceeds the reference by "
        "more than a relative $10^{-9}$.",
        "",
        "| integrator | $\\zeta$ | exact $v_e/v_0$ | linear bound $\\tau^*$ | max > 1 on $\\tau\\in$ | max > exact: smallest $\\tau$, share of grid | largest max below $\\tau^*$ |",
        "| --- | --- | --- | --- | --- | --- | --- |",
    ]
    summary = {}
    worst_below = {}
    for name in NAMES:
        for zz in ZETAS:
            ex = imp.exact_impact(zz)
            _, stats = imp.sweep(name, zz, grid, PHASES)
            mx = np.array([s.max for s in stats])
            above_one = imp.energy_created_ranges(grid, mx, 1.0)
            above_ex = mx > ex.exit_ratio * (1 + imp.RATIO_RTOL)
            tau_star = imp.linear_bound(name, zz)
            below = mx[grid < tau_star]
            summary[(name, zz)] = above_one
            worst_below[(name, zz)] = float(below.max()) if below.size else None
            first = f"{grid[above_ex][0]:.2f}" if above_ex.any() else "-"
            lines.append(
                f"| {name} | {zz:g} | {num(ex.exit_ratio)} | {num(tau_star)} | {_ranges(above_one)} | "
                f"{first}, {above_ex.mean():.2f} | {num(float(below.max()), 4) if below.size else '-'} |"
            )
    cd = summary[("leapfrog", 0.0)]
    lines += [
        "",
        "**Verdict on Feng's claim (as summarised by the note).**",
        "",
        f"* Undamped central difference: the maximum over entry phases exceeds $v_0$ on every grid step in "
        f"$(0,2)$ except at $\\tau_3=1$, which the grid contains (ranges: {_ranges(cd)}); the closed form shows "
        "the exceptions are exactly $\\tau_N=2\\sin(\\pi/(2N))$, $N=2,3,\\dots$ ($\\sqrt2$, 1, 0.765, 0.618, ...), "
        "where $v_e=v_0$ for every phase: **reproduced**, with the isolated values identified.",
        "* 'Unconditionally unstable' needs a qualification: the gain of one impact is bounded, "
        "$v_e/v_0\\le1/\\sqrt{1-\\tau^2/4}$ (energy gain $\\le \\tau^2/(4-\\tau^2)$, e.g. 0.25 % at $\\tau=0.1$), "
        "other phases lose energy ($v_e/v_0\\ge\\sqrt{1-\\tau^2/4}$), and the phase average stays close to 1 at "
        "small steps (means above): energy is created in single impacts at almost every $\\tau<2$, but boundedly.",
        f"* Damping: with $\\zeta=0.05$ the central difference (lagged damping) creates energy only for "
        f"$\\tau\\in$ {_ranges(summary[('leapfrog', 0.05)])}, with $\\zeta=0.2$ only for "
        f"$\\tau\\in$ {_ranges(summary[('leapfrog', 0.2)])}: **reproduced** ('a small amount of damping can "
        "improve the stability behavior').  Note the exit speed still exceeds the *exact* damped exit speed at "
        "almost every step (a discretisation error of the dissipation, not energy creation).",
        "* The linear bound does not guarantee $v_e\\le v_0$ for an impact: with $\\zeta=0.05$ and $0.2$ every "
        "variant creates energy on part of its linearly stable range (column 'largest max below $\\tau^*$' > 1; "
        f"e.g. leapfrog, $\\zeta=0.05$: {num(worst_below[('leapfrog', 0.05)], 4)} below $\\tau^*$="
        f"{num(imp.linear_bound('leapfrog', 0.05), 5)}), and forward Euler at $\\zeta=0.2$ does so even on "
        "[0.36, 0.38], inside its stable range $\\tau<0.4$.",
        "* Forward Euler and `paper-eq40` create energy at every step undamped, and at most steps with light "
        "damping (table).",
        "",
    ]
    return lines


def section_hertz() -> list[str]:
    grid = imp.sweep_grid(GRID_STEP)
    hz = si.hertz()
    lines = [
        "## 4. Hertz contact and the linearised bound",
        "",
        "$m\\ddot d=-k_h d^{3/2}$ ($d\\ge0$), undamped.  SymPy: $d_{max}=" + sp.latex(hz["dmax"]) + "$, duration "
        "$t_c=\\tfrac45 B(\\tfrac25,\\tfrac12)\\,d_{max}/v_0=" + num(float(hz["duration_factor"]), 6) + "\\,d_{max}/v_0$ "
        "(Beta integral, checked by 50-digit quadrature and DOP853 in the tests; with $k_h=\\tfrac43E^*\\sqrt{R^*}$ "
        f"it is ${float(hz['duration_factor']) * (15 / 16) ** 0.4:.4f}\\,(m^2/(R^*E^{{*2}}v_0))^{{1/5}}$, the "
        "2.87 quoted for LIGGGHTS in the reference notes), tangent frequency at "
        "$d_{max}$: $\\omega_t=\\sqrt{1.5\\,k_h d_{max}^{1/2}/m}$.  In units of $d_{max}$ and $1/\\omega_t$: "
        "$u''=-\\tfrac23u^{3/2}$, entry speed $\\sqrt{8/15}$, duration "
        + num(float(hz["scaled_duration"]), 6) + "$/\\omega_t$.",
        "",
        "Linearised bound: the integrator's undamped linear bound applied to the tangent stiffness at maximum "
        "overlap, $\\omega_t\\Delta t\\le\\tau^*$.  Energy error of one impact: max over phases of "
        "$|v_e^2/v_0^2-1|$, threshold 1 %.",
        "",
        "| integrator | $\\tau^*$ | Hertz error at $\\tau^*$ | linear-contact error at $\\tau^*$ | largest $\\omega_t\\Delta t$ within 1 % (share of $\\tau^*$) | linear contact: largest $\\omega\\Delta t$ within 1 % |",
        "| --- | --- | --- | --- | --- | --- |",
    ]
    studies = {}
    for name in ("leapfrog", "velocity-verlet", "leapfrog-centred", "forward-euler"):
        st = studies[name] = imp.hertz_study(name, grid, PHASES, 0.01)
        tau_star = st["linearised_bound"]
        largest = st["largest_omega_dt_within_threshold"]
        share = f" ({largest / tau_star:.2f})" if (largest is not None and tau_star > 0) else ""
        lines.append(
            f"| {name} | {num(tau_star)} | {num(st['energy_error_at_bound'], 3)} | "
            f"{num(st.get('linear_contact_energy_error_at_bound'), 3)} | {num(largest, 3)}{share} | "
            f"{num(st['linear_contact_largest_omega_dt_within_threshold'], 3)} |"
        )
    lf = studies["leapfrog"]
    lines += [
        "",
        f"Verdict: **no**.  At the linearised bound $\\omega_t\\Delta t={num(lf['linearised_bound'])}$ the central "
        f"difference ends the Hertz impact with $v_e^2/v_0^2$ off by {num(lf['energy_error_at_bound'], 3)} (max over "
        f"phases), far above 1 %; the error stays within 1 % only up to $\\omega_t\\Delta t="
        f"{num(lf['largest_omega_dt_within_threshold'], 3)}$ "
        f"({lf['largest_omega_dt_within_threshold'] / lf['linearised_bound']:.2f} of the bound) on this grid.  The "
        "linear contact behaves alike (its one-impact energy gain is bounded by $\\tau^2/(4-\\tau^2)$, which "
        "diverges at $\\tau^*=2$).  Forward Euler has no stable undamped step, so no linearised bound.",
        "",
    ]
    return lines


def build() -> str:
    head = [
        "# CFL note (seed 004): one-dimensional impact, re-derived",
        "",
        "Generated by `derivations/cfl_impact.py`; library: `dtcrit.symbolic.impact`, `dtcrit.impact`.  "
        "Dimensionless throughout: time $s=\\omega t$ ($\\omega=\\sqrt{k/m}$), overlap in $v_0/\\omega$, speed in "
        "$v_0$, $\\zeta=c/(2\\sqrt{km})$, step $\\tau=\\omega\\Delta t$.",
        "",
    ]
    body = section_bound() + section_exact() + section_stepped() + section_hertz()
    return "\n".join(head + body).rstrip() + "\n"
