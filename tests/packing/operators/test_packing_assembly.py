"""Global mass and stiffness matrices: pair results, rigid-body modes, an energy-based Hessian."""
import math

import mpmath as mp
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from dtcrit.packing.operators.assembly import mass_diagonal, mass_matrix, scale_symmetric, stiffness_matrix
from dtcrit.packing.detection.overlaps import convex_penetration, find_convex_contacts, find_sphere_contacts
from dtcrit.packing.solvers.mode_kind import rotational_fraction
from dtcrit.packing.bounds.estimates import peng_a_max
from dtcrit.packing.model import Box, HertzMindlinLaw, LinearLaw, Packing, apply_law
from dtcrit.packing.report import analyse
from support.strategies import log_uniform as decades



def _omega2_all(packing, contacts):
    a = scale_symmetric(stiffness_matrix(packing, contacts), mass_diagonal(packing)).toarray()
    return np.linalg.eigvalsh(a)


def _two_spheres(r1, r2, rho1, rho2, direction=(1.0, 0.0, 0.0)):
    n = np.asarray(direction, float) / np.linalg.norm(direction)
    x = np.array([np.zeros(3), (r1 + r2) * n])
    m = np.array([4 / 3 * math.pi * r1**3 * rho1, 4 / 3 * math.pi * r2**3 * rho2])
    return Packing.spheres(x, [r1, r2], masses=m)


# ---------------------------------------------------------------- the two-sphere "packing"

@given(r1=decades(-6, 3), r2=decades(-6, 3), rho1=decades(0, 4), rho2=decades(0, 4), kn=decades(-2, 10),
       ks_ratio=decades(-3, 1), d=st.tuples(*[st.floats(-1, 1)] * 3).filter(lambda v: np.linalg.norm(v) > 0.1))
def test_two_unequal_spheres_pair_frequencies(r1, r2, rho1, rho2, kn, ks_ratio, d):
    """Normal mode omega^2 = kn (1/m1 + 1/m2); sliding mode omega^2 = ks (1/m1 + 1/m2 + R1^2/I1 +
    R2^2/I2) (rolling without sliding is free); everything else is a rigid motion."""
    ks = kn * ks_ratio
    p = _two_spheres(r1, r2, rho1, rho2, d)
    c = apply_law(find_sphere_contacts(p), LinearLaw(kn, ks))
    m1, m2 = p.masses
    i1, i2 = 0.4 * m1 * r1**2, 0.4 * m2 * r2**2
    normal = kn * (1 / m1 + 1 / m2)
    sliding = ks * (1 / m1 + 1 / m2 + r1**2 / i1 + r2**2 / i2)
    w = _omega2_all(p, c)
    top = max(normal, sliding)
    # the dense reference solve loses accuracy with the mass ratio (cond(M) up to 1e21 here):
    # allow rounding of order eps * sqrt(m_max/m_min) on top of the 1e-9 target
    rel = 1e-9 + 1e-15 * math.sqrt(max(m1 / m2, m2 / m1))
    assert w.max() == pytest.approx(top, rel=rel)
    nonzero = np.sort(w[w > 1e-9 * top])
    assert nonzero == pytest.approx(np.sort([normal, sliding, sliding]), rel=1e-8)


@given(m=decades(-9, 3), k=decades(-2, 10))
def test_equal_spheres_reproduce_peng_eq49(m, k):
    """Two equal spheres, kn = ks = k: dt = 2/sqrt(7) sqrt(m/k) (Peng et al. 2020, Eq. (49)),
    checked against mpmath at 50 digits; A_max of Eq. (26) is 7/m."""
    p = Packing.spheres([[0, 0, 0], [2.0, 0, 0]], 1.0, masses=m)
    c = apply_law(find_sphere_contacts(p), LinearLaw(k, k))
    rep = analyse(p, contacts=c)
    mp.mp.dps = 50
    expected = 2 / mp.sqrt(7) * mp.sqrt(mp.mpf(m) / mp.mpf(k))
    assert rep.dt_crit == pytest.approx(float(expected), rel=1e-12)
    assert peng_a_max(p, c)[0] == pytest.approx(7.0 / m, rel=1e-14)
    assert rep.estimates["two_particle_amax"].dt == pytest.approx(float(expected), rel=1e-12)


@pytest.mark.parametrize("integrator", ["paper-eq40", "symplectic-euler", "leapfrog", "leapfrog-centred",
                                        "velocity-verlet", "velocity-verlet-predicted", "forward-euler"])
@pytest.mark.parametrize("c_over_critical", [0.0, 0.05, 0.3, 1.0, 3.0])
def test_two_sphere_packing_matches_stability_engine(integrator, c_over_critical):
    """Dashpots proportional to the springs (c_n = c_s = c, k_n = k_s = k) give C = (c/k) K, so the
    top mode of the pair packing is the paper's contact ODE x'' = -k A x - c A x' with A = 7/m;
    the packing's damped bound is the stability engine's pair result."""
    stability = pytest.importorskip("dtcrit.integrators.stability")
    m, k = 2.5, 3.0e4
    a_max = 7.0 / m
    c = c_over_critical * 2.0 * math.sqrt(k / a_max)
    zeta = c * a_max / (2.0 * math.sqrt(k * a_max))
    p = Packing.spheres([[0, 0, 0], [0, 0, 2.0]], 1.0, masses=m)
    rep = analyse(p, LinearLaw(k, k), integrator=integrator, damping_ratio=zeta)
    pair = stability.critical_dt(integrator, k, c, a_max)
    assert rep.dt_integrator == pytest.approx(pair.dt, rel=1e-10, abs=1e-300)
    if integrator in ("velocity-verlet", "leapfrog") and c == 0:
        assert rep.dt_integrator == pytest.approx(rep.dt_crit, rel=1e-12)


def test_shapes_module_sphere_agrees():
    shapes = pytest.importorskip("dtcrit.bodies")
    s = shapes.Sphere(0.3, density=2650.0)
    p = Packing.spheres([[0, 0, 0], [0.6, 0, 0]], 0.3, density=2650.0)
    assert p.masses[0] == pytest.approx(s.mass, rel=1e-14)
    assert p.inertia[0] == pytest.approx(np.array(s.inertia), rel=1e-14)
    contact = pytest.importorskip("dtcrit.bodies.contact")
    c = find_sphere_contacts(p)
    assert peng_a_max(p, c)[0] == pytest.approx(contact.a_max(s, s), rel=1e-12)


# ---------------------------------------------------------------- an independent Hessian

def _rot(rng):
    q, _ = np.linalg.qr(rng.standard_normal((3, 3)))
    return q * np.sign(np.linalg.det(q))


def _relative_displacement(packing, contacts, c, q):
    """Relative displacement of the two material points at contact c, with explicit cross products."""
    q = q.reshape(-1, 6)
    rot = packing.orientations if packing.orientations is not None else np.repeat(np.eye(3)[None], packing.n, 0)
    i, j = contacts.i[c], contacts.j[c]
    ti, tj = rot[i] @ q[i, 3:], rot[j] @ q[j, 3:]
    return (q[j, :3] + np.cross(tj, contacts.arm_j[c])) - (q[i, :3] + np.cross(ti, contacts.arm_i[c]))


def _energy(packing, contacts, q):
    e = 0.0
    for c in range(contacts.count):
        delta = _relative_displacement(packing, contacts, c, q)
        n = contacts.normal[c]
        dn = n @ delta
        dt = delta - dn * n
        e += 0.5 * (contacts.kn[c] * dn * dn + contacts.ks[c] * dt @ dt)
    return e


def _hessian(packing, contacts):
    """Exact Hessian of the quadratic spring energy by polarisation:
    K_ab = E(e_a + e_b) - E(e_a) - E(e_b), restricted to the DOFs of each contact's two bodies."""
    n = packing.dofs
    eye = np.eye(n)
    k = np.zeros((n, n))
    for c in range(contacts.count):
        one = type(contacts)(*(None if f is None else f[c:c + 1] for f in (
            contacts.i, contacts.j, contacts.normal, contacts.arm_i, contacts.arm_j, contacts.overlap,
            contacts.image, contacts.radius_eff, contacts.kn, contacts.ks)))
        dofs = sorted({*range(6 * contacts.i[c], 6 * contacts.i[c] + 6), *range(6 * contacts.j[c], 6 * contacts.j[c] + 6)})
        single = {a: _energy(packing, one, eye[a]) for a in dofs}
        for a in dofs:
            k[a, a] += 2 * single[a]
            for b in dofs:
                if b > a:
                    v = _energy(packing, one, eye[a] + eye[b]) - single[a] - single[b]
                    k[a, b] += v
                    k[b, a] += v
    return k


def _touching(shape_i, rot_i, shape_j, rot_j, direction, overlap=1e-6):
    """Centre separation along ``direction`` at which the bodies overlap by about ``overlap``."""
    direction = np.asarray(direction, float) / np.linalg.norm(direction)
    lo, hi = 0.0, 2.0 * (shape_i.max_arm + shape_j.max_arm)
    for _ in range(45):
        mid = 0.5 * (lo + hi)
        depth = convex_penetration(shape_i, rot_i, shape_j, rot_j, mid * direction)[0]
        lo, hi = (mid, hi) if depth > overlap else (lo, mid)
    return lo * direction


def test_stiffness_is_the_hessian_of_the_spring_energy_rotated_ellipsoids():
    shapes = pytest.importorskip("dtcrit.bodies")
    rng = np.random.default_rng(3)
    e1 = shapes.Ellipsoid(3.0, 2.0, 1.0, density=1000.0)
    e2 = shapes.Ellipsoid(2.0, 1.5, 0.7, density=500.0)
    r1, r2, r3 = _rot(rng), _rot(rng), _rot(rng)
    x2 = _touching(e1, r1, e2, r2, [1.0, 0.1, 0.05], overlap=1e-3)
    x3 = _touching(e1, r1, e2, r3, [0.1, 1.0, -0.05], overlap=1e-3)
    pk = Packing.from_shapes([e1, e2, e2], [np.zeros(3), x2, x3], [r1, r2, r3])
    c = apply_law(find_convex_contacts(pk), LinearLaw(2.0e3, 7.0e2))
    assert c.count >= 2
    k = stiffness_matrix(pk, c).toarray()
    ref = _hessian(pk, c)
    assert np.allclose(k, ref, rtol=1e-10, atol=1e-9 * np.abs(ref).max())


@settings(max_examples=25)
@given(seed=st.integers(0, 10_000))
def test_stiffness_is_the_hessian_of_the_spring_energy_spheres(seed):
    rng = np.random.default_rng(seed)
    n = 5
    r = rng.uniform(0.5, 1.5, n)
    x = np.cumsum(np.vstack([np.zeros(3), rng.standard_normal((n - 1, 3))]), axis=0)
    for k in range(1, n):  # chain: each sphere touches the previous one with a small overlap
        d = x[k] - x[k - 1]
        x[k] = x[k - 1] + d / np.linalg.norm(d) * (r[k] + r[k - 1]) * 0.999
    p = Packing.spheres(x, r, density=1.0)
    c = apply_law(find_sphere_contacts(p), LinearLaw(rng.uniform(0.1, 10), rng.uniform(0.1, 10)))
    assert np.allclose(stiffness_matrix(p, c).toarray(), _hessian(p, c), rtol=1e-10, atol=1e-12)


def test_rigid_body_modes():
    """An isolated connected cluster has exactly six zero modes (3 translations, 3 rotations about
    any point: the single contact point per contact keeps rigid rotation strain-free even with
    overlap).  A periodic FCC lattice keeps only the 3 translations; BCC is bipartite (every contact
    joins the two sublattices), so the two sublattices counter-rotating roll on each other without
    sliding: 3 more zero modes."""
    rng = np.random.default_rng(1)
    x = np.array([[0, 0, 0], [1.9, 0, 0], [0.9, 1.7, 0], [0.9, 0.6, 1.6]], float) + rng.normal(0, 0.01, (4, 3))
    p = Packing.spheres(x, 1.0, density=1.0)
    c = apply_law(find_sphere_contacts(p), LinearLaw(1.0, 0.5))
    assert c.count == 6
    assert np.all(c.overlap > 0)
    w = _omega2_all(p, c)
    assert np.sum(w < 1e-10 * w.max()) == 6
    from dtcrit.packing.generators.lattices import lattice
    for name, zeros in (("fcc", 3), ("bcc", 6)):
        p = lattice(name, 2, mass=1.0)
        w = _omega2_all(p, apply_law(find_sphere_contacts(p), LinearLaw(1.0, 0.5)))
        assert np.sum(w < 1e-10 * w.max()) == zeros


def test_mass_matrix():
    p = Packing.spheres([[0, 0, 0], [3, 0, 0]], [1.0, 2.0], density=3.0)
    m = mass_matrix(p).toarray()
    m1, m2 = 4 / 3 * math.pi * 3.0, 4 / 3 * math.pi * 8 * 3.0
    assert np.diag(m) == pytest.approx([m1] * 3 + [0.4 * m1] * 3 + [m2] * 3 + [0.4 * m2 * 4] * 3, rel=1e-14)
    assert np.count_nonzero(m - np.diag(np.diag(m))) == 0


def test_symmetric_and_positive_semidefinite():
    from dtcrit.packing.generators.random_packing import random_packing
    p = random_packing(40, cn=7, sizes="lognormal", spread=0.4, seed=5)
    c = apply_law(find_sphere_contacts(p), LinearLaw(1.0, 0.7))
    k = stiffness_matrix(p, c).toarray()
    assert np.abs(k - k.T).max() <= 1e-14 * np.abs(k).max()
    assert np.linalg.eigvalsh(k).min() >= -1e-12 * np.abs(k).max()


# ---------------------------------------------------------------- non-spherical bodies

def test_ellipsoid_pair_matches_rigid_body_compliance():
    """Two rotated bodies: the global eigenproblem's top value equals the contact's own frequency
    from rigid-body dynamics (relative acceleration of the contact points per unit force,
    a_rel = (1/m1 + 1/m2) F + sum J^-1 (r x F) x r), built here with cross products."""
    shapes = pytest.importorskip("dtcrit.bodies")
    rng = np.random.default_rng(11)
    e1, e2 = shapes.Ellipsoid(3.0, 2.0, 1.0, density=1000.0), shapes.Superquadric(2.0, 1.5, 1.0, 0.6, 0.8, density=800.0)
    r1, r2 = _rot(rng), _rot(rng)
    p = Packing.from_shapes([e1, e2], [np.zeros(3), _touching(e1, r1, e2, r2, [1.0, 0.4, -0.3])], [r1, r2])
    c = apply_law(find_convex_contacts(p), LinearLaw(1.0e10, 0.6e10))
    assert c.count == 1
    jinv = [r @ np.diag(1 / np.array(s.inertia)) @ r.T for s, r in ((e1, r1), (e2, r2))]
    arms = [c.arm_i[0], c.arm_j[0]]
    comp = np.zeros((3, 3))
    for k in range(3):
        f = np.eye(3)[k]
        acc = (1 / e1.mass + 1 / e2.mass) * f
        for ji, r in zip(jinv, arms):
            acc = acc + np.cross(ji @ np.cross(r, f), r)
        comp[:, k] = acc
    n = c.normal[0]
    kc = 1.0e10 * np.outer(n, n) + 0.6e10 * (np.eye(3) - np.outer(n, n))
    expected = np.linalg.eigvals(comp @ kc).real.max()
    assert _omega2_all(p, c).max() == pytest.approx(expected, rel=1e-9)
    # Peng's A_max (largest half-length, smallest moment) bounds this pair from above
    assert max(1.0e10, 0.6e10) * peng_a_max(p, c)[0] >= expected


def test_convex_penetration_against_brute_force_directions():
    """Depth and normal from the optimiser against the minimum of the overlap over 200 000
    sampled directions (the sampled minimum can only be larger)."""
    shapes = pytest.importorskip("dtcrit.bodies")
    rng = np.random.default_rng(5)
    e1, e2 = shapes.Ellipsoid(3.0, 2.0, 1.0, density=1.0), shapes.Superquadric(2.0, 1.5, 1.0, 0.7, 0.9, density=1.0)
    r1, r2 = _rot(rng), _rot(rng)
    sep = 0.7 * np.array([3.2, 1.1, -0.4])
    depth, n, _, _ = convex_penetration(e1, r1, e2, r2, sep)
    d = rng.standard_normal((200_000, 3))
    d /= np.linalg.norm(d, axis=1)[:, None]
    si = np.einsum("ij,ij->i", d, e1.support(d @ r1) @ r1.T)
    sj = np.einsum("ij,ij->i", -d, e2.support(-d @ r2) @ r2.T)
    h = si + sj - d @ sep
    assert depth > 0
    assert depth <= h.min() + 1e-12
    assert depth == pytest.approx(h.min(), rel=2e-3)
    assert n == pytest.approx(d[np.argmin(h)], abs=0.05)


def test_convex_contact_of_spheres_matches_sphere_path():
    shapes = pytest.importorskip("dtcrit.bodies")
    s1, s2 = shapes.Sphere(1.0, density=1.0), shapes.Sphere(0.5, density=1.0)
    x = [[0, 0, 0], [1.2, 0.5, -0.6]]
    x[1] = list(np.array(x[1]) / np.linalg.norm(x[1]) * 1.49)
    a = find_convex_contacts(Packing.from_shapes([s1, s2], x))
    b = find_sphere_contacts(Packing.spheres(x, [1.0, 0.5], density=1.0))
    assert a.count == b.count == 1
    assert a.normal[0] == pytest.approx(b.normal[0], abs=1e-7)
    assert a.arm_i[0] == pytest.approx(b.arm_i[0], abs=1e-7)
    assert a.overlap[0] == pytest.approx(b.overlap[0], abs=1e-9)


def test_ellipsoid_tip_to_tip_contact_point():
    shapes = pytest.importorskip("dtcrit.bodies")
    e = shapes.Ellipsoid(3.0, 2.0, 1.0, density=1000.0)
    c = find_convex_contacts(Packing.from_shapes([e, e], [[0, 0, 0], [5.99, 0, 0]]))
    assert c.count == 1
    assert c.normal[0] == pytest.approx([1, 0, 0], abs=1e-7)
    assert c.arm_i[0] == pytest.approx([2.995, 0, 0], abs=1e-6)
    assert c.overlap[0] == pytest.approx(0.01, rel=1e-6)


# ---------------------------------------------------------------- Hertz-Mindlin tangent stiffness

@given(youngs=decades(6, 11), nu=st.floats(0.0, 0.49), r1=decades(-4, 0), r2=decades(-4, 0), frac=decades(-6, -2))
def test_hertz_tangent_stiffness_is_the_derivative_of_the_force(youngs, nu, r1, r2, frac):
    x = [[0, 0, 0], [(r1 + r2) * (1 - frac), 0, 0]]
    p = Packing.spheres(x, [r1, r2], density=1000.0)
    c = apply_law(find_sphere_contacts(p), HertzMindlinLaw(youngs, nu))
    mp.mp.dps = 50
    e_star = mp.mpf(youngs) / (2 * (1 - mp.mpf(nu) ** 2))
    r_star = mp.mpf(r1) * r2 / (mp.mpf(r1) + r2)
    force = lambda d: mp.mpf(4) / 3 * e_star * mp.sqrt(r_star) * d**1.5  # noqa: E731
    assert c.kn[0] == pytest.approx(float(mp.diff(force, mp.mpf(c.overlap[0]))), rel=1e-9)
    g = mp.mpf(youngs) / (2 * (1 + mp.mpf(nu)))
    g_star = g / (2 * (2 - mp.mpf(nu)))
    assert c.ks[0] == pytest.approx(float(8 * g_star * mp.sqrt(r_star * mp.mpf(c.overlap[0]))), rel=1e-9)


def test_mode_character():
    v = np.zeros(12)
    v[3] = 1.0
    assert rotational_fraction(v) == 1.0
    p = Packing.spheres([[0, 0, 0], [2.0, 0, 0]], 1.0, masses=1.0)
    rep = analyse(p, LinearLaw(1.0, 1.0))
    # sliding mode of two equal spheres: translation 2/m vs rotation 2 R^2/I = 5/m of A = 7/m
    assert rep.rotational_fraction == pytest.approx(5.0 / 7.0, rel=1e-9)
    assert rep.mode == "rotational"
    assert analyse(p, LinearLaw(1.0, 0.1)).mode == "translational"


def test_box_and_periodic_self_contact():
    """One sphere in a periodic cube of side 2R touches its own images on three axes."""
    p = Packing.spheres([[0.5, 0.5, 0.5]], 1.0, masses=1.0, box=Box.cube(2.0))
    c = find_sphere_contacts(p)
    assert c.count == 3
    assert np.all(c.i == c.j)
    assert c.coordination(1)[0] == 6
    w = _omega2_all(p, apply_law(c, LinearLaw(1.0, 1.0)))
    assert w.max() == pytest.approx(20.0, rel=1e-12)  # co-rotation, (10/3) CN k/m


def test_degenerate_top_eigenspace_is_named_as_such():
    """FCC with k_s/k_n = 1/4: omega_max^2 = 10 k/m six times over, spanned by translational and
    rotational modes alike, so the label must not depend on which member the solver returns."""
    from dtcrit.packing import lattice
    from dtcrit.packing.solvers.mode_kind import mode_character

    p = lattice("fcc", 2, mass=1.0)
    rep = analyse(p, LinearLaw(1.0, 0.25))
    assert rep.omega_max**2 == pytest.approx(10.0, rel=1e-12)
    assert rep.mode == "degenerate: translational and rotational"
    # independent route: NumPy's full eigen-solve of the same matrix, any rotation of the basis
    from dtcrit.packing import apply_law, scale_symmetric, stiffness_matrix
    from dtcrit.packing.report import find_contacts, mass_diagonal

    c = apply_law(find_contacts(p), LinearLaw(1.0, 0.25))
    a = scale_symmetric(stiffness_matrix(p, c), mass_diagonal(p)).toarray()
    w, V = np.linalg.eigh(a)
    space = V[:, w > w[-1] * (1 - 1e-9)]
    fractions = [rotational_fraction(space[:, j]) for j in range(space.shape[1])]
    assert space.shape[1] == 6 and min(fractions) < 0.5 < max(fractions)
    Q, _ = np.linalg.qr(np.random.default_rng(3).normal(size=(6, 6)))
    assert mode_character(space[:, 0], space @ Q) == "degenerate: translational and rotational"
    # a non-degenerate top mode keeps its single-vector label
    assert analyse(p, LinearLaw(1.0, 1.0)).mode == "rotational"
