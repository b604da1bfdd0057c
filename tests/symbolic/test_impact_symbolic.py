"""The SymPy derivation of the one-dimensional impact (``dtcrit.symbolic.impact``), checked by
routes other than the one that produced each result, and the runtime's independence from SymPy."""
import subprocess
import sys

import sympy as sp

from dtcrit.symbolic import impact as si
from dtcrit.symbolic import integrators as sint
from dtcrit.symbolic import impact_contact as sic
from dtcrit.symbolic import impact_stepping as sis


def test_contact_motions_solve_the_ode():
    for regime in ("undamped", "underdamped", "critical", "overdamped"):
        assert sic.residual(regime) == 0, regime
        d = sic.contact_motion(regime)
        assert d.subs(sic.s, 0) == 0
        assert sp.simplify(d.diff(sic.s).subs(sic.s, 0)) == 1


def test_geometric_separation_is_the_cfl_note_formula():
    """t_d = pi/sqrt(1 - zeta^2), v_e = -v0 exp(-zeta pi/sqrt(1 - zeta^2)) (CFL note, as printed)."""
    t_d, v_e = sic.geometric_separation()
    z = sic.zeta
    assert sp.simplify(t_d - sp.pi / sp.sqrt(1 - z**2)) == 0
    assert sp.simplify(v_e + sp.exp(-z * sp.pi / sp.sqrt(1 - z**2))) == 0
    # d stays positive in between: d(t_d/2) > 0 at sample damping ratios
    d = sic.contact_motion("underdamped").subs(sic.w, sp.sqrt(1 - z**2))
    for zz in (sp.Rational(1, 100), sp.Rational(1, 2), sp.Rational(99, 100)):
        assert d.subs({z: zz, sic.s: (t_d / 2).subs(z, zz)}).evalf() > 0


def test_no_geometric_separation_beyond_critical_damping():
    out = sic.no_geometric_separation()
    for regime, (lim_d, lim_v, d) in out.items():
        assert lim_d == 0 and lim_v == 0, regime
    # overdamped d = (exp(-a s) - exp(-(a + c) s))/c > 0 for s > 0: numerically at sample points
    a, c = sp.symbols("a c", positive=True)
    d = out["overdamped"][2]
    for vals in ({a: sp.Rational(1, 10), c: 3}, {a: 2, c: sp.Rational(1, 1000)}):
        for s_val in (sp.Rational(1, 1000), 1, 50):
            assert d.subs(vals).subs(sic.s, s_val).evalf(30) > 0


def test_force_release_zero_of_the_force_and_exit_speed():
    """P(s_f) = 0, d'(s_f) = -exp(-zeta s_f), d(s_f) = 2 zeta exp(-zeta s_f) in every regime."""
    for regime, (s_f, v_f, d_f, p_f) in sic.force_release().items():
        z = {"undamped": 0, "critical": 1}.get(regime, sic.zeta)
        assert p_f == 0, regime
        assert sp.simplify(v_f + sp.exp(-z * s_f)) == 0, regime
        assert sp.simplify(d_f - 2 * z * sp.exp(-z * s_f)) == 0, regime
    # first zero: P > 0 on (0, s_f) at sample damping ratios (numerically, 30 digits)
    P = sic.compressive_force("underdamped").subs(sic.w, sp.sqrt(1 - sic.zeta**2))
    for zz in (sp.Rational(1, 20), sp.Rational(7, 10), sp.Rational(19, 20)):
        s_f = (2 * sp.acos(sic.zeta) / sp.sqrt(1 - sic.zeta**2)).subs(sic.zeta, zz)
        for frac in (sp.Rational(1, 100), sp.Rational(1, 2), sp.Rational(99, 100)):
            assert P.subs({sic.zeta: zz, sic.s: frac * s_f}).evalf(30) > 0


def test_g_series_against_direct_expansion():
    """The ODE-recurrence Taylor polynomial equals SymPy's series of arccos(1-u)/sqrt(u(2-u))."""
    u = sic.u
    direct = sp.series(sp.acos(1 - u) / sp.sqrt(u * (2 - u)), u, 0, sic.SERIES_ORDER).removeO()
    assert sp.expand(direct - sic.g_series()) == 0
    assert sic.g_ode_residuals() == (0, 0)


def test_central_difference_family_shares_the_stoermer_recurrence():
    for name in sic.CENTRAL_DIFFERENCE_FAMILY:
        assert sis.position_recurrence_residual(name) == 0, name
        assert sis.free_flight_entry_residual(name) == (0, 0), name
        assert sis.exit_velocity_residual(name) == 0, name
    for name in ("forward-euler", "paper-eq40"):
        assert sis.position_recurrence_residual(name) != 0, name


def test_invariant_and_ratio_formula():
    x, v, tau = sic.x, sic.v, sint.tau
    Q = sis.central_difference_invariant()
    assert sp.expand(Q - (v**2 + x**2 - tau * x * v)) == 0
    # conserved by the position recurrence written independently: (x0, x1) -> (x1, (2 - tau^2) x1 - x0)
    x0, x1 = sp.symbols("x0 x1")
    q_of = lambda a, b: Q.subs({x: b, v: (b - a) / tau}, simultaneous=True)  # noqa: E731
    assert sp.simplify(q_of(x1, (2 - tau**2) * x1 - x0) - q_of(x0, x1)) == 0
    r = sis.central_difference_ratio_expr()
    phi, psi = sic.phi, sic.psi
    assert sp.simplify(r.subs(psi, phi) - 1) == 0  # mirrored exit: no energy change
    assert sp.simplify(r.subs(psi, 1 - phi) - 1) == 0
    assert sis.unit_step_exit_phase_equals_entry() == 0


def test_position_closed_form_reproduces_the_recurrence():
    xn = sis.central_difference_position_expr()
    n, phi, tau = sic.n, sic.phi, sint.tau
    vals = {phi: sp.Rational(2, 7), tau: sp.Rational(13, 10)}
    seq = [(phi - 1) * tau, phi * tau]
    for _ in range(6):
        seq.append((2 - tau**2) * seq[-1] - seq[-2])
    for k in range(-1, 7):
        assert abs(sp.N((xn.subs(n, k) - seq[k + 1]).subs(vals), 30)) < 1e-25


def test_forward_euler_is_a_scaled_rotation():
    rho, alpha, M = sis.forward_euler_map()
    assert sp.simplify(M.det() - rho**2) == 0
    xn, vn = sis.forward_euler_motion_expr()
    vals = {sic.phi: sp.Rational(1, 3), sint.tau: sp.Rational(7, 10)}
    state = sp.Matrix([sic.phi * sint.tau, 1]).subs(vals)
    for k in range(5):
        assert abs(sp.N((xn.subs(sic.n, k).subs(vals) - state[0]), 30)) < 1e-25
        assert abs(sp.N((vn.subs(sic.n, k).subs(vals) - state[1]), 30)) < 1e-25
        state = M.subs(vals) * state


def test_hertz_scalings():
    hz = si.hertz()
    assert hz["scaled_coefficient"] == sp.Rational(2, 3)
    assert sp.simplify(hz["scaled_speed"] ** 2 - sp.Rational(8, 15)) == 0
    k_h, m, v0 = sic.k_h, sic.m, sic.v0
    # energy balance m v0^2/2 = (2/5) k_h dmax^(5/2)
    assert sp.simplify(m * v0**2 / 2 - sp.Rational(2, 5) * k_h * hz["dmax"] ** sp.Rational(5, 2)) == 0


def test_runtime_never_imports_sympy():
    code = (
        "import sys, dtcrit.impact, dtcrit.cli.impact, dtcrit.cli\n"
        "dtcrit.cli.build_parser()\n"
        "assert 'sympy' not in sys.modules, sorted(m for m in sys.modules if 'sympy' in m)[:5]\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True)
