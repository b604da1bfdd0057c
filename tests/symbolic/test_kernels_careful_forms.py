"""The careful forms of dtcrit.symbolic.careful_forms are the derived closed forms (symbolic checks), so the
emitted step computes the exact boundary of dtcrit.symbolic and nothing typed by hand."""
import mpmath as mp
import sympy as sp

from dtcrit.symbolic.careful_forms import careful_chain, cubic_identity, cubic_small_zeta
from dtcrit.symbolic.closed_forms import closed_pieces, gamma, omega
from dtcrit.symbolic.integrators import tau, zeta
from dtcrit.integrators.schemes import NAMES

k, c, A, z = sp.symbols("k c A z", positive=True)


def test_forward_euler_residual_forms_are_the_derived_pieces():
    under, over = closed_pieces("forward-euler")
    w, g = sp.sqrt(k * A), c * A / 2
    assert sp.simplify(under.dt_expr.subs({omega: w, gamma: g}) - c / k) == 0  # zeta <= 1: dt = c/k
    R = c**2 * A - 4 * k
    assert sp.simplify((over.dt_expr.subs({omega: w, gamma: g}) - 4 / (c * A + sp.sqrt(A * R))).subs(c, 2 * sp.sqrt(k / A) * (1 + z))) == 0


def test_cubic_identity_of_the_eq40_scheme():
    (cp,) = closed_pieces("paper-eq40")
    P0, h, q0 = cubic_identity(cp)
    P = tau**3 + sum(co * tau ** (2 - i) for i, co in enumerate(cp.cubic))
    assert sp.expand(tau * ((tau - h) ** 2 + q0) + P0 - P) == 0
    assert sp.simplify(-P0 / (2 * zeta)) == 1  # -P0/omega = 2 zeta/omega = c/k


def test_small_zeta_leading_order_of_adams_bashforth_2():
    """Its undamped cubic is tau^3, so omega dt = (8 zeta)^(1/3) to leading order; below zeta = 2^E the
    exact smallest positive root (mpmath polyroots at 80 digits) is that to 2^-60, and not far above it;
    the eq40 cubic (undamped roots 0, +-i sqrt 2) has no such branch."""
    (cp, _) = closed_pieces("adams-bashforth-2")
    p1, e_max = cubic_small_zeta(cp)
    assert p1 == 8 and cubic_small_zeta(closed_pieces("paper-eq40")[0]) is None
    w, g = sp.sqrt(k * A), c * A / 2
    assert sp.simplify(sp.cbrt(p1 * g / w) / w - sp.cbrt(p1 * c / (2 * k**2 * A))) == 0

    def rel_error(e):
        with mp.workdps(80):
            zz = mp.mpf(2) ** e
            roots = mp.polyroots([1, -2 * zz, -8 * zz**2, -8 * zz], maxsteps=400, extraprec=400)
            root = min(mp.re(r) for r in roots if abs(mp.im(r)) < mp.mpf(10) ** -70 and mp.re(r) > 0)
            return abs(mp.cbrt(8 * zz) / root - 1)

    assert rel_error(e_max) <= mp.mpf(2) ** -60
    assert rel_error(e_max + 30) > mp.mpf(2) ** -53  # the threshold is not loose by decades


def test_every_chain_ends_with_the_nan_guard_and_uses_no_rate_product():
    for name in NAMES:
        ch = careful_chain(name)
        assert ch.result == ch.steps[-1][0] and ch.steps[-1][1].has(sp.nan)
        products = {k * A, c * A}
        assert not any(e.has(p) for _, e in ch.steps for p in products)  # k A, c A never formed
