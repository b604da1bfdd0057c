"""``dtcrit step`` results against direct routes.

* Direct eigen-solve of the time-stepped three-dimensional contact: the amplification matrix of the
  integrator applied to ``xdd = -W K x`` (W the 3x3 coefficient matrix of an admissible contact from
  dtcrit.bodies.contact_search, K the contact stiffness) has spectral radius <= 1 at the reported step for
  every sampled contact, and > 1 just above it at the worst contact (the step is tight).
* The paper's sphere result, Eq. (49): dt = (2/sqrt(7)) sqrt(m/k) for undamped identical spheres.
* Rotation bound, Eq. (56); the minimum over pairs; the safety factor; the unsafe flags.
"""
import dataclasses
import math

import numpy as np
import pytest

from dtcrit.bodies.arm_supremum import arm_term_supremum
from dtcrit.bodies.contact_search import mirror_contact, random_contacts
from dtcrit.scenes.laws import resolve_pair
from dtcrit.scenes.scene import load_scene, parse_scene
from dtcrit.physics.estimate import SAFE_RTOL as UNSAFE_RTOL
from dtcrit.scenes.timestep import critical_step
from support.paths import REPO_ROOT as ROOT

EXAMPLES = ROOT / "examples"


def _amplification(integrator, M, h):
    """6x6 amplification matrix of one step for xdd = -M x (undamped), state (x, v), written out here."""
    n = M.shape[0]
    I, Z = np.eye(n), np.zeros((n, n))
    if integrator in ("velocity-verlet", "velocity-verlet-predicted", "leapfrog-centred"):
        # x1 = x + h v - h^2/2 M x ; v1 = v - h/2 (M x + M x1)
        X = np.block([[I - 0.5 * h * h * M, h * I]])
        x1 = X
        a0 = np.block([[-M, Z]])
        a1 = -M @ x1
        V = np.block([[Z, I]]) + 0.5 * h * (a0 + a1)
        return np.vstack([X, V])
    if integrator in ("symplectic-euler", "leapfrog"):
        # v1 = v - h M x ; x1 = x + h v1
        V = np.block([[-h * M, I]])
        X = np.block([[I, Z]]) + h * V
        return np.vstack([X, V])
    raise AssertionError(integrator)


def _rho(G):
    return float(np.max(np.abs(np.linalg.eigvals(G))))


def _stiffness(kn, ks, normal):
    n = normal / np.linalg.norm(normal)
    return ks * np.eye(3) + (kn - ks) * np.outer(n, n)


def _worst_contact(shape):
    sup = arm_term_supremum(shape)
    p = np.asarray(sup.point, float)
    if shape.vertices is not None:
        normal = p / np.linalg.norm(p)  # inside a vertex's normal cone of a centrally symmetric body
    else:
        normal = p / np.asarray(shape.half_lengths) ** 2  # ellipsoid gradient direction
    return mirror_contact(shape, p, normal)


@pytest.mark.parametrize("scene", ["paper_ellipsoids.toml", "polyhedron_cube.toml"])
def test_step_is_safe_for_sampled_contacts_and_tight_at_the_worst(scene):
    s = dataclasses.replace(load_scene(EXAMPLES / scene), isolated=True)  # the two-particle step
    r = critical_step(s)
    assert r.governing == "translation"
    shape = s.particle(1).shape
    pc = resolve_pair(s, 1, 1)
    dt = r.dt_crit
    contacts = random_contacts(shape, shape, 300, seed=3)
    Ws = contacts.coefficient_matrices(shape, shape)
    for W, nrm in zip(Ws, contacts.normal):
        M = W @ _stiffness(pc.kn, pc.ks, nrm)
        assert _rho(_amplification(s.integrator, M, dt * (1 - 1e-6))) <= 1 + 1e-9
    worst = _worst_contact(shape)
    W = worst.coefficient_matrices(shape, shape)[0]
    assert np.linalg.eigvalsh(W)[-1] == pytest.approx(r.translation.A_bound, rel=1e-6)
    M = W @ _stiffness(pc.kn, pc.ks, worst.normal[0])
    assert _rho(_amplification(s.integrator, M, dt * (1 - 1e-6))) <= 1 + 1e-9
    if pc.kn == pc.ks:  # isotropic stiffness: the worst contact sits exactly on the boundary
        assert _rho(_amplification(s.integrator, M, dt * (1 + 1e-4))) > 1 + 1e-6


@pytest.mark.parametrize("log_m,log_k", [(-9.0, 2.0), (0.0, 7.0), (4.0, 11.0)])
def test_undamped_identical_spheres_recover_eq49(log_m, log_k):
    """Peng et al. 2020, Eq. (49): dt = (2/sqrt(7)) sqrt(m/k) for velocity Verlet (A = 7/m)."""
    m, k = 10.0**log_m, 10.0**log_k
    text = f"""
integrator = "velocity-verlet"
[[particle]]
shape = "sphere"
radius = 1.0e-2
mass = {m!r}
[contact]
model = "linear"
kn = {k!r}
ks = {k!r}
"""
    r = critical_step(parse_scene("isolated = true\n" + text))
    assert r.translation.A_bound == pytest.approx(7 / m, rel=1e-12)
    assert r.dt_crit == pytest.approx(2 / math.sqrt(7) * math.sqrt(m / k), rel=1e-12)
    assert r.to_json()["estimators"]["paper_eq46"]["unsafe"] is False  # Eq. (46) undamped = Eq. (49): a tie


def test_rotation_bound_is_eq56_and_can_govern():
    base = "isolated = true\n" + (EXAMPLES / "paper_ellipsoids.toml").read_text()
    r = critical_step(parse_scene(base))
    inertia = r.scene.particle(1).shape.inertia
    ixx, iyy, izz = inertia
    B = max(abs(ixx - iyy) / izz, abs(ixx - izz) / iyy, abs(iyy - izz) / ixx)  # Eq. (54), written out
    assert r.rotation.dt_rotation == pytest.approx(2 / (1.0 * 2 * B), rel=1e-14)
    assert r.governing == "translation"
    fast = parse_scene(base.replace("omega_max = 1.0", "omega_max = 1.0e4"))
    rf = critical_step(fast)
    assert rf.governing == "rotation" and rf.dt_crit == pytest.approx(1 / (1e4 * B), rel=1e-14)
    assert rf.to_json()["rotation"]["dt"] == rf.dt_crit


def test_mixed_scene_takes_the_smallest_pair_and_ks_above_kn_uses_shear():
    r = critical_step(load_scene(EXAMPLES / "mixed_pair.toml"))
    assert r.dt_isolated == min(min(p.dt_translation, p.dt_rotation or math.inf) for p in r.pairs)
    assert [p.label for p in r.pairs] == ["1-1", "1-2", "2-2"]
    text = (EXAMPLES / "paper_ellipsoids.toml").read_text().replace("ks = 1.0e10", "ks = 3.0e10")
    r = critical_step(parse_scene(text))
    assert r.translation.governing_direction.direction == "shear"
    assert r.scene.warnings and r.scene.warnings[0][0] == "contact.ks"


def test_safety_factor_and_unsafe_flags():
    r = critical_step(load_scene(EXAMPLES / "glass_spheres_hertz.toml"))
    j = r.to_json()
    assert j["safety"] == 0.5 and j["dt_recommended"] == pytest.approx(0.5 * j["dt_crit"], rel=1e-15)
    for key, e in j["estimators"].items():
        if e["dt"] is None:
            assert e["unsafe"] is None
        else:
            assert e["unsafe"] == (e["dt"] > j["dt_crit"] * (1 + UNSAFE_RTOL)), key
    # the damped paper scene: Eq. (46) grows with damping and exceeds the verified step
    d = critical_step(load_scene(EXAMPLES / "damped_ellipsoids.toml")).to_json()
    assert d["estimators"]["paper_eq46"]["unsafe"] is True
    # the cube: Eq. (26) with the half-length is not a bound for boxes, so Eq. (46) is unsafe
    c = critical_step(load_scene(EXAMPLES / "polyhedron_cube.toml")).to_json()
    assert c["translation"]["A_bound"] > c["translation"]["A_max"]
    assert c["estimators"]["paper_eq46"]["unsafe"] is True
