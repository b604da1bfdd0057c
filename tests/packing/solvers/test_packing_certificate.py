"""The certified bracket (dtcrit.packing.solvers.certificate): the inertia count of sigma I - A matches the
number of eigenvalues above sigma from a dense eigen-solve (scipy.linalg.eigvalsh, the independent
reference), on a degenerate top eigenspace too; an unconverged Ritz value, whose step is unsafe, is
not certified and the bracket falls back to dt_safe, which stays below the true step."""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
import scipy.linalg as sla

from dtcrit.packing.operators.assembly import mass_diagonal, scale_symmetric, stiffness_matrix
from dtcrit.packing.solvers.certificate import bracket, certify
from dtcrit.packing.detection.overlaps import find_sphere_contacts
from dtcrit.packing.solvers.largest_mode import largest_mode
from dtcrit.packing.bounds.estimates import block_diagonal, gershgorin
from dtcrit.packing.generators.lattices import lattice
from dtcrit.packing.model import LinearLaw, apply_law
from dtcrit.packing.operators.matrix_free import ContactOperator
from dtcrit.packing.generators.random_packing import random_packing
from dtcrit.packing.report import analyse


def _scaled(p, law=LinearLaw(1e5, 4e4)):
    c = apply_law(find_sphere_contacts(p), law)
    return scale_symmetric(stiffness_matrix(p, c), mass_diagonal(p)), c


@pytest.mark.parametrize("route", ["dense", "sparse"])
@pytest.mark.parametrize("packing", ["fcc", "random"])
def test_inertia_matches_a_dense_eigen_solve(packing, route):
    p = lattice("fcc", 2) if packing == "fcc" else random_packing(60, cn=6.0, sizes="uniform", spread=0.3, seed=2)
    a, _ = _scaled(p)
    w = sla.eigvalsh(a.toarray())
    top = w[-1]
    dense_dofs = 10**6 if route == "dense" else 0
    above = certify(a, top, dense_dofs=dense_dofs)
    assert above.certified and above.sigma == pytest.approx(top * (1 + 1e-6))
    assert above.dt_lower == pytest.approx(2 / math.sqrt(top * (1 + 1e-6)))
    # sigma inside the spectrum: not certified; the dense route counts exactly the modes above it
    for frac in (0.999, 0.95, 0.61):  # not 0.6: ks/kn = 0.4 puts FCC eigenvalues at exactly 0.6 top (a tie)
        cut = certify(a, top * frac / (1 + 1e-6), dense_dofs=dense_dofs)
        assert not cut.certified and cut.dt_lower is None
        if route == "dense":
            assert cut.above == int(np.count_nonzero(w > top * frac))


def test_degenerate_top_eigenspace():
    """A perfect FCC lattice: the top eigenvalue is multiple; the certificate holds just above it and
    counts the whole eigenspace just below it."""
    p = lattice("fcc", 2)
    a, _ = _scaled(p, LinearLaw(1e5, 1e5))
    w = sla.eigvalsh(a.toarray())
    multiplicity = int(np.count_nonzero(w >= w[-1] * (1 - 1e-9)))
    assert multiplicity > 1
    top = largest_mode(a, "eigsh")
    assert certify(a, top.value).certified
    below = certify(a, w[-1] * (1 - 1e-7) / (1 + 1e-6))
    assert below.above == multiplicity


def test_an_unconverged_ritz_value_is_not_certified():
    """A Ritz value from a three-dimensional Krylov space (what an iterative solver stopped after
    two products holds) is well below lambda_max, so 2/sqrt(theta) is an unsafe step.  The
    certificate refuses it and the bracket's lower end is dt_safe, a true lower bound; its upper end
    2/sqrt(theta) is above the true step, as it must be."""
    p = random_packing(300, cn=6.0, sizes="lognormal", spread=0.3, seed=5)
    a, _ = _scaled(p)
    true = sla.eigvalsh(a.toarray())[-1]
    v = np.random.default_rng(3).standard_normal(a.shape[0])
    basis = np.linalg.qr(np.column_stack([v, a @ v, a @ (a @ v)]))[0]
    rough = SimpleNamespace(value=float(sla.eigvalsh(basis.T @ (a @ basis))[-1]))
    assert rough.value < true * (1 - 1e-3)  # the case is built so that the Ritz value is off
    dt_true = 2 / math.sqrt(true)
    assert 2 / math.sqrt(rough.value) > dt_true * 1.0005  # unsafe if trusted
    cert = certify(a, rough.value, sparse_dofs=10**6)
    assert not cert.certified
    md = np.ones(a.shape[0])
    dt_safe = max(block_diagonal(a).dt, gershgorin(a, md).dt)
    b = bracket(rough.value, dt_safe, cert)
    assert b.lower_from == "dt_safe" and b.lower <= dt_true <= b.upper
    good = largest_mode(a)
    b = bracket(good.value, dt_safe, certify(a, good.value, sparse_dofs=10**6))
    # (the converged Ritz value and eigvalsh agree to rounding: a few ulps of slack on the upper end)
    assert b.lower_from == "certificate" and b.lower <= dt_true <= b.upper * (1 + 1e-12)
    assert (b.upper - b.lower) / b.upper < 1e-6


def test_operator_and_limits():
    p = random_packing(40, cn=5.0, seed=1)
    a, c = _scaled(p)
    op = ContactOperator(p, c)
    top = sla.eigvalsh(a.toarray())[-1]
    assert certify(op, top).certified
    too_big = certify(a, top, dense_dofs=0, sparse_dofs=10)
    assert not too_big.certified and too_big.method.startswith("none: too costly")
    assert not certify(a, 0.0).certified


def test_analyse_reports_the_bracket():
    p = random_packing(200, cn=6.0, seed=3)
    r = analyse(p, LinearLaw(1e6, 3e5))
    a, _ = _scaled(p, LinearLaw(1e6, 3e5))
    dt_true = 2 / math.sqrt(sla.eigvalsh(a.toarray())[-1])
    assert r.certificate.certified and r.bracket.lower_from == "certificate"
    assert r.bracket.lower <= dt_true <= r.bracket.upper * (1 + 1e-12)
    assert r.dt_safe <= r.bracket.lower
    off = analyse(p, LinearLaw(1e6, 3e5), certify_step=False)
    assert off.certificate is None and off.bracket.lower == off.dt_safe
