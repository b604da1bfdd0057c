"""The 6-DOF contact element (dtcrit.packing.operators.contact_element, element_matrices) against
independent routes.

* The Hessian of the springs' energy of two rigid bodies, computed at 40 digits (mpmath) from
  their positions and exact finite rotations (Rodrigues' formula) by central differences: the
  contact springs on the displacement of the two material points at the contact point, the
  rolling/twisting springs on the relative rotation vector, the pre-load as the work ``-F r`` of a
  constant repulsive force on the centre distance ``r``.
* A hand-derived case: two spheres along x, the slip written out by hand.
* Structure: symmetric, positive semi-definite, rigid-body translations and rotations in the null
  space; the component-form action, the compiled blocks and the vectorised blocks agree.
"""
from __future__ import annotations

import mpmath as mp
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from dtcrit.packing.operators import contact_element as ce
from dtcrit.packing.operators import element_matrices as em
from dtcrit.packing.operators import matrix_free_kernels as kernels


def _full(blocks: tuple[np.ndarray, np.ndarray, np.ndarray], c: int = 0) -> np.ndarray:
    """The 12 x 12 element of contact ``c`` from its blocks (ii, jj, ij)."""
    ii, jj, ij = (b[c] for b in blocks)
    return np.block([[ii, ij], [ij.T, jj]])


def _geometry(seed: int):
    """Two bodies, a contact point between them, a unit normal, body frames: one random contact."""
    rng = np.random.default_rng(seed)
    x_i, x_j = rng.normal(size=3), rng.normal(size=3) + np.array([2.0, 0.0, 0.0])
    x_c = 0.5 * (x_i + x_j) + 0.3 * rng.normal(size=3)
    normal = rng.normal(size=3)
    normal /= np.linalg.norm(normal)
    rot = Rotation.random(2, random_state=seed).as_matrix()
    return x_i, x_j, x_c, normal, rot


def _rodrigues(theta, a):
    """``exp([theta]_x) a`` at the working precision of mpmath."""
    phi = mp.sqrt(sum(t * t for t in theta))
    if phi == 0:
        return list(a)
    k = [t / phi for t in theta]
    ka = sum(ki * ai for ki, ai in zip(k, a))
    kxa = [k[1] * a[2] - k[2] * a[1], k[2] * a[0] - k[0] * a[2], k[0] * a[1] - k[1] * a[0]]
    return [a[m] * mp.cos(phi) + kxa[m] * mp.sin(phi) + k[m] * ka * (1 - mp.cos(phi)) for m in range(3)]


def _rotvec_of_relative(theta_i, theta_j):
    """Rotation vector of ``exp([theta_j]_x) exp([theta_i]_x)^T`` (the relative rotation)."""
    cols = [_rodrigues(theta_j, _rodrigues([-t for t in theta_i], e)) for e in ([1, 0, 0], [0, 1, 0], [0, 0, 1])]
    r = mp.matrix(3, 3)
    for b in range(3):
        for a in range(3):
            r[a, b] = cols[b][a]
    cos = max(min((r[0, 0] + r[1, 1] + r[2, 2] - 1) / 2, mp.mpf(1)), mp.mpf(-1))
    phi = mp.acos(cos)
    scale = mp.mpf(1) / 2 if phi == 0 else phi / (2 * mp.sin(phi))
    return [scale * (r[2, 1] - r[1, 2]), scale * (r[0, 2] - r[2, 0]), scale * (r[1, 0] - r[0, 1])]


def _energy(q, x_i, x_j, x_c, normal, rot, k):
    """Springs' energy of the two bodies displaced by ``q`` (12 body DOFs), at mpmath precision."""
    n = [mp.mpf(v) for v in normal]
    frame = lambda along, across, v: (along * sum(a * b for a, b in zip(n, v)) ** 2  # noqa: E731
                                      + across * (sum(a * a for a in v) - sum(a * b for a, b in zip(n, v)) ** 2))
    theta = []
    points = []
    for p, x in ((0, x_i), (1, x_j)):
        r = mp.matrix(rot[p].tolist())
        t = mp.matrix(q[6 * p + 3:6 * p + 6])
        theta.append([(r * t)[m] for m in range(3)])
        arm = [mp.mpf(c) - mp.mpf(v) for c, v in zip(x_c, x)]
        turned = _rodrigues(theta[p], arm)
        points.append([mp.mpf(x[m]) + q[6 * p + m] + turned[m] for m in range(3)])
    slip = [points[1][m] - points[0][m] for m in range(3)]
    energy = frame(k["kn"], k["ks"], slip) / 2
    if "kr" in k:
        energy += frame(k["ktw"], k["kr"], _rotvec_of_relative(theta[0], theta[1])) / 2
    if "force" in k:
        centre = [mp.mpf(x_j[m]) + q[6 + m] - mp.mpf(x_i[m]) - q[m] for m in range(3)]
        energy -= k["force"] * mp.sqrt(sum(c * c for c in centre))
    return energy


def _hessian(energy, h=mp.mpf("1e-12")) -> np.ndarray:
    """Central second differences of ``energy`` (a function of 12 mpmath numbers) at zero."""
    out = np.empty((12, 12))
    zero = [mp.mpf(0)] * 12

    def at(steps):
        q = list(zero)
        for a, s in steps:
            q[a] += s * h
        return energy(q)

    for a in range(12):
        for b in range(a, 12):
            val = (at([(a, 1), (b, 1)]) - at([(a, 1), (b, -1)]) - at([(a, -1), (b, 1)]) + at([(a, -1), (b, -1)]))
            out[a, b] = out[b, a] = float(val / (4 * h * h))
    return out


@pytest.mark.parametrize("seed", [1, 2])
@pytest.mark.parametrize("terms", ["springs", "rolling", "preload"])
def test_element_is_the_hessian_of_the_two_bodies_energy(seed, terms):
    """Each term against the 40-digit Hessian of its energy (module docstring)."""
    x_i, x_j, x_c, normal, rot = _geometry(seed)
    k = {"kn": 3.0e5, "ks": 1.2e5}
    kw = {}
    if terms == "rolling":
        k.update(ktw=40.0, kr=70.0)
        kw = {"twist": np.array([40.0]), "roll": np.array([70.0])}
    if terms == "preload":  # the pre-load term is written for the centre line as normal (spheres)
        normal = (x_j - x_i) / np.linalg.norm(x_j - x_i)
        k["force"] = 25.0
        kw = {"preload": np.array([25.0 / np.linalg.norm(x_j - x_i)])}
    with mp.workdps(40):
        want = _hessian(lambda q: _energy(q, x_i, x_j, x_c, normal, rot, k))
    got = _full(em.element_blocks(normal[None], (x_c - x_i)[None], (x_c - x_j)[None], np.array([k["kn"]]),
                                  np.array([k["ks"]]), rot_i=rot[:1], rot_j=rot[1:], **kw))
    assert np.max(np.abs(got - want)) <= 1e-12 * np.max(np.abs(want))


def test_two_spheres_along_x_by_hand():
    """Spheres of radius r at the origin and at (2r, 0, 0), n = x: the slip is
    ``(u_jx - u_ix, u_jy - u_iy - r (t_iz + t_jz), u_jz - u_iz + r (t_iy + t_jy))``.
    """
    r, kn, ks = 0.7, 5.0, 2.0
    g = np.zeros((3, 12))  # rows: d delta_x, delta_y, delta_z / d q (q = u_i, t_i, u_j, t_j)
    g[0, [0, 6]] = -1.0, 1.0
    g[1, [1, 7, 5, 11]] = -1.0, 1.0, -r, -r
    g[2, [2, 8, 4, 10]] = -1.0, 1.0, r, r
    want = kn * np.outer(g[0], g[0]) + ks * (np.outer(g[1], g[1]) + np.outer(g[2], g[2]))
    got = _full(em.element_blocks(np.array([[1.0, 0, 0]]), np.array([[r, 0, 0]]), np.array([[-r, 0, 0]]),
                                  np.array([kn]), np.array([ks])))
    assert np.array_equal(got, want)


def _random_contacts(nc: int, seed: int):
    rng = np.random.default_rng(seed)
    x_i, x_j = rng.normal(size=(nc, 3)), rng.normal(size=(nc, 3)) + 2.0
    x_c = 0.5 * (x_i + x_j) + 0.2 * rng.normal(size=(nc, 3))
    normal = rng.normal(size=(nc, 3))
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    rot = Rotation.random(2 * nc, random_state=seed).as_matrix()
    coeff = {name: 10.0 ** rng.uniform(-1, 4, nc) for name in ("kn", "ks", "ktw", "kr")}
    return x_i, x_j, x_c, normal, rot[:nc], rot[nc:], coeff


def test_symmetric_positive_semidefinite_with_rigid_body_modes_in_its_null_space():
    """Springs and rolling/twisting springs on rotated bodies: rank 6, rigid motions unresisted."""
    nc = 50
    x_i, x_j, x_c, normal, rot_i, rot_j, k = _random_contacts(nc, 3)
    blocks = em.element_blocks(normal, x_c - x_i, x_c - x_j, k["kn"], k["ks"], rot_i=rot_i, rot_j=rot_j,
                               twist=k["ktw"], roll=k["kr"])
    rng = np.random.default_rng(4)
    for c in range(nc):
        e = _full(blocks, c)
        scale = np.max(np.abs(e))
        assert np.max(np.abs(e - e.T)) <= 1e-14 * scale
        assert np.linalg.eigvalsh(e)[0] >= -1e-12 * scale
        # rigid motion: translation v and rotation w about a point o (body DOFs t_p = R_p^T w)
        v, w, o = rng.normal(size=3), rng.normal(size=3), rng.normal(size=3)
        q = np.concatenate([v + np.cross(w, x_i[c] - o), rot_i[c].T @ w, v + np.cross(w, x_j[c] - o), rot_j[c].T @ w])
        assert np.max(np.abs(e @ q)) <= 1e-12 * scale * np.max(np.abs(q))
        assert np.sum(np.linalg.eigvalsh(e) > 1e-10 * scale) == 6  # 12 DOFs - 6 rigid modes


def test_action_equals_the_blocks_on_arrays_and_compiled():
    """``body_forces`` on arrays over contacts (the NumPy product) and the compiled
    ``element_blocks_into`` / ``slip_jacobians_into`` give the vectorised blocks.
    """
    nc = 40
    x_i, x_j, x_c, normal, rot_i, rot_j, k = _random_contacts(nc, 5)
    g = np.random.default_rng(6).uniform(-3.0, 3.0, nc)
    arm_i, arm_j = x_c - x_i, x_c - x_j
    blocks = em.element_blocks(normal, arm_i, arm_j, k["kn"], k["ks"], rot_i=rot_i, rot_j=rot_j,
                               twist=k["ktw"], roll=k["kr"], preload=g)
    q = np.random.default_rng(7).normal(size=(nc, 12))
    rows = lambda r: tuple(tuple(r[:, a, b] for b in range(3)) for a in range(3))  # noqa: E731
    f, m_i, m_j = ce.body_forces(em.components(normal), em.components(arm_i), em.components(arm_j),
                                 rows(rot_i), rows(rot_j), True, em.components(q[:, :3]), em.components(q[:, 3:6]),
                                 em.components(q[:, 6:9]), em.components(q[:, 9:]), k["kn"], k["ks"], k["ktw"],
                                 k["kr"], g, True, True, True)
    got = np.column_stack([-f[0], -f[1], -f[2], *m_i, *f, *m_j])
    want = np.stack([_full(blocks, c) @ q[c] for c in range(nc)])
    assert np.max(np.abs(got - want)) <= 1e-13 * np.max(np.abs(want))
    if not kernels.available():
        pytest.skip("the compiled element needs Numba")
    import numba

    compiled = numba.njit(_compiled_element)
    b_i, b_j = em.slip_jacobians(arm_i, arm_j, rot_i, rot_j)
    for c in range(nc):
        ii, jj, ij, bi, bj = compiled(normal[c], arm_i[c], arm_j[c], rot_i[c][None], rot_j[c][None],
                                      np.array([k["kn"][c], k["ks"][c], k["ktw"][c], k["kr"][c], g[c]]))
        ref = _full(blocks, c)
        assert np.max(np.abs(np.block([[ii, ij], [ij.T, jj]]) - ref)) <= 1e-13 * np.max(np.abs(ref))
        for got_b, want_b in ((bi, b_i[c]), (bj, b_j[c])):
            assert np.max(np.abs(got_b - want_b)) <= 4e-16 * np.max(np.abs(want_b))


def _compiled_element(n, a_i, a_j, rot_i, rot_j, k):
    """One contact's blocks and slip Jacobians by the jitted element functions (compiled by the test)."""
    ii, jj, ij = np.zeros((6, 6)), np.zeros((6, 6)), np.zeros((6, 6))
    normal = (n[0], n[1], n[2])
    ai, aj = (a_i[0], a_i[1], a_i[2]), (a_j[0], a_j[1], a_j[2])
    ri, rj = ce.rotation_rows(rot_i, 0), ce.rotation_rows(rot_j, 0)
    em.element_blocks_into(normal, ai, aj, ri, rj, True, k[0], k[1], k[2], k[3], k[4], True, True, True, ii, jj, ij)
    b_i, b_j = np.zeros((3, 6)), np.zeros((3, 6))
    em.slip_jacobians_into(ai, aj, ri, rj, True, b_i, b_j)
    return ii, jj, ij, b_i, b_j
