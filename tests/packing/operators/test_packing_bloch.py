"""Lattice results of the global analysis against an independent Bloch (dispersion) analysis.

The test builds its own dynamical matrix: for a wave vector k every sphere of basis site s moves as
``Q_s exp(i k . x)``; each ordered contact (s -> t through cell offset L) contributes half of
``P^H K_c P`` where ``P`` maps the two spheres' amplitudes to the relative displacement of the
contact point, evaluated with ``np.cross`` on unit vectors.  The largest eigenvalue over k of
``M^-1/2 Phi(k) M^-1/2`` is omega_max^2 of the infinite lattice.
"""
import itertools

import numpy as np
import pytest

from dtcrit.packing.operators.assembly import mass_diagonal, scale_symmetric, stiffness_matrix
from dtcrit.packing.detection.overlaps import find_sphere_contacts
from dtcrit.packing.solvers.largest_mode import largest_mode
from dtcrit.packing.generators.lattices import lattice
from dtcrit.packing.model import LinearLaw, apply_law

R = 1.0
MASS = 1.0
INERTIA = 0.4 * MASS * R**2

# basis (fractions of the cell) and cell edges / R, written out again here on purpose
CELLS = {
    "sc": ([[0, 0, 0]], [2, 2, 2]),
    "bcc": ([[0, 0, 0], [0.5, 0.5, 0.5]], [4 / np.sqrt(3)] * 3),
    "fcc": ([[0, 0, 0], [0.5, 0.5, 0], [0.5, 0, 0.5], [0, 0.5, 0.5]], [2 * np.sqrt(2)] * 3),
    "hcp": ([[0, 0, 0], [0.5, 0.5, 0], [0.5, 1 / 6, 0.5], [0, 2 / 3, 0.5]], [2, 2 * np.sqrt(3), 2 * np.sqrt(8 / 3)]),
}


def _bonds(name):
    frac, edge = CELLS[name]
    edge = np.array(edge) * R
    basis = np.array(frac) * edge
    bonds = []
    for s, t in itertools.product(range(len(basis)), repeat=2):
        for L in itertools.product((-1, 0, 1), repeat=3):
            shift = np.array(L) * edge
            d = basis[t] + shift - basis[s]
            if abs(np.linalg.norm(d) - 2 * R) < 1e-9:
                bonds.append((s, t, shift, d / np.linalg.norm(d)))
    return basis, edge, bonds


def _relative_map(n):
    """3x6 maps of (u, theta) of the 'from' and 'to' spheres onto the relative contact displacement."""
    p_from, p_to = np.zeros((3, 6)), np.zeros((3, 6))
    for k in range(3):
        e = np.eye(3)[k]
        p_from[:, k] = -e
        p_to[:, k] = e
        p_from[:, 3 + k] = -np.cross(e, R * n)  # contact point sits at +R n from the 'from' centre
        p_to[:, 3 + k] = np.cross(e, -R * n)  # and at -R n from the 'to' centre
    return p_from, p_to


def bloch_max(name, kn, ks, wavevectors):
    basis, edge, bonds = _bonds(name)
    nb = len(basis)
    minv = 1 / np.sqrt(np.tile([MASS] * 3 + [INERTIA] * 3, nb))
    best = 0.0
    maps = [(s, t, shift, _relative_map(n), kn * np.outer(n, n) + ks * (np.eye(3) - np.outer(n, n)))
            for s, t, shift, n in bonds]
    for k in wavevectors:
        phi = np.zeros((6 * nb, 6 * nb), complex)
        for s, t, shift, (pf, pt), kc in maps:
            p = np.zeros((3, 6 * nb), complex)
            p[:, 6 * s:6 * s + 6] += pf * np.exp(1j * k @ basis[s])
            p[:, 6 * t:6 * t + 6] += pt * np.exp(1j * k @ (basis[t] + shift))
            phi += 0.5 * p.conj().T @ kc @ p
        dyn = minv[:, None] * phi * minv[None, :]
        best = max(best, np.linalg.eigvalsh(dyn).max())
    return best, edge


def supercell_wavevectors(edge, cells):
    ranges = [2 * np.pi * np.arange(cells) / (cells * e) for e in edge]
    return [np.array(k) for k in itertools.product(*ranges)]


def global_omega2(name, cells, kn, ks):
    p = lattice(name, cells, radius=R, mass=MASS)
    c = apply_law(find_sphere_contacts(p), LinearLaw(kn, ks))
    a = scale_symmetric(stiffness_matrix(p, c), mass_diagonal(p))
    return largest_mode(a, "dense").value


@pytest.mark.parametrize("name", ["sc", "bcc", "fcc", "hcp"])
@pytest.mark.parametrize("kn,ks", [(1.0, 0.0), (1.0, 1.0), (1.0, 0.3), (0.2, 1.0)])
def test_supercell_equals_bloch_on_its_wavevectors(name, kn, ks):
    cells = 2
    _, edge, _ = _bonds(name)
    expected, _ = bloch_max(name, kn, ks, supercell_wavevectors(edge, cells))
    assert global_omega2(name, cells, kn, ks) == pytest.approx(expected, rel=1e-10)


@pytest.mark.parametrize("name", ["sc", "bcc", "fcc", "hcp"])
@pytest.mark.parametrize("kn,ks", [(1.0, 0.0), (1.0, 1.0), (1.0, 0.3)])
def test_two_cells_contain_the_maximising_wavevector(name, kn, ks):
    """A fine Brillouin-zone grid (plus random wave vectors) never exceeds the 2-cell result."""
    _, edge, _ = _bonds(name)
    grid = supercell_wavevectors(edge, 6)  # includes the 2-cell points and many more
    rng = np.random.default_rng(7)
    grid += [rng.uniform(0, 2 * np.pi, 3) / edge for _ in range(40)]
    dense_max, _ = bloch_max(name, kn, ks, grid)
    assert dense_max <= global_omega2(name, 2, kn, ks) * (1 + 1e-10)


@pytest.mark.parametrize("name,expected", [("sc", 4.0), ("bcc", 16.0 / 3.0), ("fcc", 8.0), ("hcp", 8.0)])
def test_normal_springs_only_closed_forms(name, expected):
    """Central nearest-neighbour springs: SC omega^2 = 4k/m (k = pi/a, 1-D chain), BCC 16k/3m
    (H point), FCC and HCP 8k/m; the rotations are inert."""
    assert global_omega2(name, 2, 1.0, 0.0) == pytest.approx(expected, rel=1e-12)
    _, edge, _ = _bonds(name)
    assert bloch_max(name, 1.0, 0.0, supercell_wavevectors(edge, 2))[0] == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("name,cn", [("sc", 6), ("bcc", 8), ("fcc", 12), ("hcp", 12)])
def test_equal_springs_top_mode_is_co_rotation(name, cn):
    """kn = ks = k: all spheres co-rotating slide every contact by 2R |theta x n|; summed over the
    contacts of these lattices, sum (1 - n n^T) = (2/3) CN 1, so omega^2 = (4/3) CN k R^2 / I =
    (10/3) CN k / m.  It is the top of the spectrum at k = 0."""
    assert global_omega2(name, 1, 1.0, 1.0) == pytest.approx(10.0 / 3.0 * cn, rel=1e-12)
    assert global_omega2(name, 2, 1.0, 1.0) == pytest.approx(10.0 / 3.0 * cn, rel=1e-12)


def test_sparse_solver_on_a_larger_lattice():
    p = lattice("fcc", 5, radius=R, mass=MASS)
    c = apply_law(find_sphere_contacts(p), LinearLaw(1.0, 0.4))
    a = scale_symmetric(stiffness_matrix(p, c), mass_diagonal(p))
    _, edge, _ = _bonds("fcc")
    expected, _ = bloch_max("fcc", 1.0, 0.4, supercell_wavevectors(edge, 5))
    assert largest_mode(a, "eigsh").value == pytest.approx(expected, rel=1e-8)
