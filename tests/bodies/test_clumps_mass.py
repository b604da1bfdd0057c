"""Clumps: mass properties of the union of spheres against independent routes (adaptive SciPy quadrature
of the union's cross-sections, mpmath for the lens, Monte Carlo with its standard error), the bound used in
``dtcrit step`` against the coefficient matrix at sampled member-surface contacts, and bad input."""
from __future__ import annotations

import math
import subprocess
import sys

import mpmath
import numpy as np
import pytest
from scipy import integrate

from dtcrit.bodies import Clump
from dtcrit.bodies.clump_mass import closed_form, quadrature
from dtcrit.bodies.contact import a_bound, coefficient_matrix
from dtcrit.scenes.scene import parse_scene
from dtcrit.scenes.timestep import critical_step


def axial(c1, r1, c2, r2):
    """(V, x_c, int (x - x_c)^2, int (y^2 + z^2)) of two balls on the x axis, SciPy adaptive quadrature."""
    rho2 = lambda x: max(r1 * r1 - (x - c1) ** 2, r2 * r2 - (x - c2) ** 2, 0.0)  # noqa: E731
    lo, hi = min(c1 - r1, c2 - r2), max(c1 + r1, c2 + r2)
    xm = ((r1 * r1 - r2 * r2) - (c1 * c1 - c2 * c2)) / (2.0 * (c2 - c1))
    cuts = sorted({lo, min(max(xm, lo), hi), hi})
    q = lambda f: sum(integrate.quad(f, a, b, epsabs=0, epsrel=1e-10, limit=200)[0]  # noqa: E731
                      for a, b in zip(cuts[:-1], cuts[1:]))
    v = q(lambda x: math.pi * rho2(x))
    xc = q(lambda x: math.pi * x * rho2(x)) / v
    return v, xc, q(lambda x: math.pi * (x - xc) ** 2 * rho2(x)), q(lambda x: 0.5 * math.pi * rho2(x) ** 2)


PAIRS = [(1.0, 0.7, 1.2), (1.0, 1.0, 0.3), (1.0, 0.2, 0.95), (1.0, 1.0, 1.999), (2e-3, 1.5e-3, 1e-3), (5.0, 4.0, 8.9)]


@pytest.mark.parametrize("r1,r2,d", PAIRS)
def test_two_overlapping_spheres_closed_form_against_quadrature(r1, r2, d):
    cf = closed_form([[0, 0, 0], [d, 0, 0]], [r1, r2])
    v, xc, sxx, srr = axial(0.0, r1, d, r2)
    assert cf.volume == pytest.approx(v, rel=1e-9)
    assert cf.centre[0] == pytest.approx(xc, rel=1e-9, abs=1e-12 * r1)
    assert cf.second_moment[0, 0] == pytest.approx(sxx, rel=1e-9)
    assert cf.second_moment[1, 1] + cf.second_moment[2, 2] == pytest.approx(srr, rel=1e-9)
    # and the mass and principal inertia of the Clump body to 1e-6
    c = Clump([[0, 0, 0, r1], [d, 0, 0, r2]], density=1000.0)
    assert c.mass == pytest.approx(1000.0 * v, rel=1e-6)
    axial_moment, transverse = 1000.0 * srr, 1000.0 * (sxx + srr / 2)
    assert sorted(c.inertia) == pytest.approx(sorted([axial_moment, transverse, transverse]), rel=1e-6)


def test_lens_volume_against_mpmath():
    r1, r2, d = mpmath.mpf(1), mpmath.mpf("0.7"), mpmath.mpf("1.2")
    mpmath.mp.dps = 40
    a = (d * d + r1 * r1 - r2 * r2) / (2 * d)
    cap = lambda r, h: mpmath.pi * h * h * (3 * r - h) / 3  # noqa: E731
    lens = cap(r1, r1 - a) + cap(r2, r2 - (d - a))
    union = 4 * mpmath.pi * (r1**3 + r2**3) / 3 - lens
    assert closed_form([[0, 0, 0], [1.2, 0, 0]], [1.0, 0.7]).volume == pytest.approx(float(union), rel=4e-16)


def _monte_carlo(centres, radii, n=400_000, seed=5):
    rng = np.random.default_rng(seed)
    c, r = np.asarray(centres, float), np.asarray(radii, float)
    lo, hi = (c - r[:, None]).min(0), (c + r[:, None]).max(0)
    p = rng.uniform(lo, hi, (n, 3))
    inside = (np.linalg.norm(p[:, None, :] - c[None], axis=-1) <= r[None]).any(1)
    box = float(np.prod(hi - lo))
    f = inside.mean()
    return box * f, box * math.sqrt(f * (1 - f) / n), p[inside].mean(0)


def test_three_overlapping_members_quadrature_against_monte_carlo():
    centres, radii = [[0, 0, 0], [1.0, 0, 0], [0.5, 0.7, 0.2]], [0.8, 0.6, 0.5]
    q = quadrature(centres, radii)
    v, se, centre = _monte_carlo(centres, radii)
    assert abs(q.volume - v) < 4 * se
    assert q.quadrature_error < 1e-3
    assert np.allclose(q.centre, centre, atol=0.01)
    assert Clump([c + [r] for c, r in zip(centres, radii)], density=1.0).mass_method.startswith("quadrature")


def test_ray_quadrature_agrees_with_the_closed_form_for_two():
    cf = closed_form([[0, 0, 0], [1.2, 0, 0]], [1.0, 0.7])
    q = quadrature([[0, 0, 0], [1.2, 0, 0]], [1.0, 0.7])
    assert abs(q.volume / cf.volume - 1) < 5 * q.quadrature_error


def test_a_bound_holds_at_member_surface_contacts():
    c = Clump([[0, 0, 0, 0.01], [0.012, 0.003, 0, 0.007], [-0.009, 0, 0.004, 0.006]], density=2500.0)
    bound = a_bound(c, c)
    rng = np.random.default_rng(3)
    pts, _ = c.surface_points(4000)
    worst = 0.0
    for _ in range(3000):
        p1, p2 = pts[rng.integers(len(pts))], pts[rng.integers(len(pts))]
        q1, q2 = (np.linalg.qr(rng.standard_normal((3, 3)))[0] for _ in range(2))
        q1, q2 = q1 * np.sign(np.linalg.det(q1)), q2 * np.sign(np.linalg.det(q2))
        A = coefficient_matrix(c, c, q1 @ p1, q2 @ p2, body_to_world=(q1, q2))
        worst = max(worst, float(np.linalg.eigvalsh(A)[-1]))
    assert worst <= bound * (1 + 1e-12)


def test_clump_scene_step_uses_the_bound():
    text = ('integrator = "velocity-verlet"\n[[particle]]\nshape = "clump"\nspheres = [[0, 0, 0, 0.01], [0.012, 0, 0, 0.007]]\n'
            'density = 2500.0\n[contact]\nmodel = "linear"\nkn = 1e5\nks = 1e5\n')
    res = critical_step(parse_scene(text))
    c = res.scene.particles[0].shape
    assert res.dt_isolated == pytest.approx(2.0 / math.sqrt(1e5 * a_bound(c, c)), rel=1e-13)
    assert res.translation.method == "bound (A_bound)"


@pytest.mark.parametrize("spheres,key", [
    ("[]", "particle[1].spheres"),
    ("[[0, 0, 0, -0.01]]", "particle[1].spheres[1][4]"),
    ("[[0, 0, 0, 0.01], [1, 0, 0, 0.01]]", "particle[1].spheres"),
    ("[[0, 0, 0]]", "particle[1].spheres[1]"),
])
def test_bad_clump_is_one_line(tmp_path, spheres, key):
    path = tmp_path / "c.toml"
    path.write_text(f'integrator = "leapfrog"\n[[particle]]\nshape = "clump"\nspheres = {spheres}\ndensity = 1000.0\n'
                    '[contact]\nmodel = "linear"\nkn = 1e5\nks = 1e4\n')
    p = subprocess.run([sys.executable, "-m", "dtcrit", "step", str(path)], capture_output=True, text=True)
    assert p.returncode == 2 and p.stdout == ""
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"{path}:{key}:"), p.stderr
