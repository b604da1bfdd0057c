"""The headline of ``dtcrit step`` is safe for the simulation the scene describes.

* Without packing keys it is the step proven for *any* packing of the scene's particles: it never exceeds
  the exact step of a real packing of them (the global eigen-solve of :mod:`dtcrit.packing`, an
  independent route: sparse assembly of the packing's 6-DOF ``M^-1 K``; and the spectral radius of the
  whole damped packing's update-rule matrix).
* A distribution of 10^5 radii is answered in seconds: for linear and YADE laws the extreme radii carry
  every extreme (checked here against the brute-force minimum over every pair of sizes, each pair
  evaluated on its own), other laws are refused in one line naming ``radii``.
"""
from __future__ import annotations

import math
import subprocess
import sys
import time

import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st

from support.packing_scene import sphere_sizes_toml
from support.multidof import spectral_radius
from dtcrit.packing import LinearLaw, analyse, apply_law, find_sphere_contacts, lattice, mass_matrix, stiffness_matrix, random_packing
from dtcrit.scenes.dense import block_terms, dense_step
from dtcrit.scenes.laws import resolve_pair
from dtcrit.scenes.pair_modes import pair_step
from dtcrit.scenes.scene import parse_scene
from dtcrit.scenes.timestep import critical_step
from support.paths import REPO_ROOT as ROOT



def _overlap(packing) -> float:
    c = find_sphere_contacts(packing)
    return float(np.max(c.overlap / (packing.radii[c.i] + packing.radii[c.j]))) if c.count else 0.0


def _scene_text(packing, kn, ks, damping="", integrator="velocity-verlet"):
    """The scene of the packing's particles with no packing key (overlap_max only where the packing overlaps
    more than the default 5 %: the assumption the bound states)."""
    sizes, density = sphere_sizes_toml(packing)
    eps = _overlap(packing)
    top = f'integrator = "{integrator}"\n' + (f"overlap_max = {eps * (1 + 1e-9) + 1e-15!r}\n" if eps > 0.05 else "")
    return (f'{top}[[particle]]\nshape = "sphere"\n{sizes}density = {density!r}\n'
            f'[contact]\nmodel = "linear"\nkn = {kn!r}\nks = {ks!r}\n{damping}')


@pytest.mark.parametrize("ks_ratio", (0.0, 2 / 7, 1.0, 2.0))
@pytest.mark.parametrize("name,build", [
    ("fcc", lambda: lattice("fcc", 2, radius=1.0, density=1.0)),
    ("bcc", lambda: lattice("bcc", 2, radius=1.0, density=1.0)),
    ("random-uniform", lambda: random_packing(64, cn=5.0, sizes="uniform", spread=0.3, seed=4)),
])
def test_default_headline_never_exceeds_the_exact_step_of_a_packing_of_the_same_particles(name, build, ks_ratio):
    packing = build()
    kn = 1.0e4
    exact = analyse(packing, LinearLaw(kn, ks_ratio * kn), integrator="velocity-verlet", with_estimates=False).dt_crit
    res = critical_step(parse_scene(_scene_text(packing, kn, ks_ratio * kn)))
    assert res.basis == "any packing" and res.dense is not None
    assert res.dt_crit <= exact * (1 + 1e-12), (name, ks_ratio, res.dt_crit, exact)
    # ...while the isolated-contact step, printed beside it, does exceed the packing's step (the point)
    assert res.dt_isolated > exact


def test_default_headline_holds_for_a_damped_fcc_packing():
    """FCC of equal spheres with dashpots not proportional to the springs: the update-rule matrix of the
    whole packing has spectral radius <= 1 at the headline (0.999 x) for every scheme with a packing bound."""
    packing = lattice("fcc", 1, radius=1.0, density=1.0)
    kn, ks, cn, cs = 1.0e4, 3.0e3, 40.0, 2.0
    contacts = find_sphere_contacts(packing)
    K = stiffness_matrix(packing, apply_law(contacts, LinearLaw(kn, ks))).toarray()
    C = stiffness_matrix(packing, apply_law(contacts, LinearLaw(cn, cs))).toarray()
    M = mass_matrix(packing).toarray()
    for scheme in ("velocity-verlet", "leapfrog", "symplectic-euler"):
        res = critical_step(parse_scene(_scene_text(packing, kn, ks, f"cn = {cn!r}\ncs = {cs!r}\n", scheme)))
        assert res.basis == "any packing"
        assert spectral_radius(scheme, 0.999 * res.dt_crit, M, K, C) <= 1 + 1e-7, scheme


def test_a_wall_adds_one_contact_to_the_coordination():
    base = ('integrator = "velocity-verlet"\n[[particle]]\nshape = "sphere"\nradius = 0.001\ndensity = 2500.0\n'
            '[contact]\nmodel = "linear"\nkn = 1e5\nks = 2e4\n')
    free = critical_step(parse_scene(base))
    walled = critical_step(parse_scene(base + "[[wall]]\nkn = 1e5\nks = 2e4\n"))
    assert walled.coordination.z == free.coordination.z + 1 and "wall" in walled.coordination.how
    assert walled.dt_crit <= walled.dt_isolated


def test_forward_euler_has_no_packing_bound_and_says_so():
    text = ('integrator = "forward-euler"\n[[particle]]\nshape = "sphere"\nradius = 0.001\ndensity = 2500.0\n'
            '[contact]\nmodel = "linear"\nkn = 1e5\nks = 2e4\ndamping_ratio = 0.5\n')
    res = critical_step(parse_scene(text))
    assert res.basis == "isolated" and "no packing bound" in res.basis_note and res.dt_crit == res.dt_isolated
    assert res.to_json()["headline_note"] == res.basis_note


@pytest.mark.parametrize("value,reason", [('"yes"', "true or false"), ("true\ncoordination_max = 6", "give one of them")])
def test_isolated_key_errors_are_one_line(tmp_path, value, reason):
    f = tmp_path / "s.toml"
    f.write_text(f'integrator = "velocity-verlet"\nisolated = {value}\n[[particle]]\nshape = "sphere"\nradius = 0.001\n'
                 'density = 2500.0\n[contact]\nmodel = "linear"\nkn = 1e5\nks = 2e4\n')
    p = subprocess.run([sys.executable, "-m", "dtcrit", "step", str(f)], capture_output=True, text=True, cwd=ROOT)
    assert p.returncode == 2 and p.stdout == ""
    assert p.stderr.count("\n") == 1 and p.stderr.startswith(f"{f}:isolated: ") and reason in p.stderr


# --------------------------------------------------------------------------- many radii

def _many_radii(tmp_path, n, contact):
    rs = np.geomspace(1e-3, 2e-3, n)
    f = tmp_path / "many.toml"
    f.write_text('integrator = "velocity-verlet"\n[[particle]]\nshape = "sphere"\n'
                 f"radii = [{', '.join(repr(float(r)) for r in rs)}]\nfractions = [{', '.join(['1e-5'] * n)}]\n"
                 f"density = 2500.0\n[contact]\n{contact}")
    return f


def test_one_hundred_thousand_radii_are_answered_in_seconds(tmp_path):
    f = _many_radii(tmp_path, 100_000, 'model = "linear"\nkn = 1e5\nks = 2e4\n')
    t0 = time.perf_counter()
    p = subprocess.run([sys.executable, "-m", "dtcrit", "step", str(f), "--json"], capture_output=True, text=True, cwd=ROOT)
    assert time.perf_counter() - t0 < 10.0 and p.returncode == 0, p.stderr
    import json

    doc = json.loads(p.stdout)
    # the isolated step is the smallest spheres' (exact normal mode 2/sqrt(kn A_n), A_n = 2/m)
    m = 2500.0 * 4 / 3 * math.pi * 1e-3**3
    assert doc["dt_isolated"] == pytest.approx(2 / math.sqrt(1e5 * 2 / m), rel=1e-12)
    assert doc["headline_basis"] == "any packing" and doc["dt_crit"] < doc["dt_isolated"]


def test_many_radii_with_hertz_are_refused_up_front_naming_radii(tmp_path):
    f = _many_radii(tmp_path, 100_000, 'model = "hertz"\nyoungs_modulus = 7e10\npoisson_ratio = 0.25\nvelocity = 1.0\n')
    t0 = time.perf_counter()
    p = subprocess.run([sys.executable, "-m", "dtcrit", "step", str(f)], capture_output=True, text=True, cwd=ROOT)
    assert time.perf_counter() - t0 < 10.0
    assert p.returncode == 2 and p.stdout == "" and p.stderr.count("\n") == 1
    assert p.stderr.startswith(f"{f}:particle[1].radii: ") and "hertz" in p.stderr


def _brute_force(scene):
    """Every pair of sizes evaluated on its own (no reduction): ``(dt_isolated, steps)``."""
    steps = []
    for i, j in scene.pair_numbers():
        p, q = scene.particle(i), scene.particle(j)
        for r1 in p.radii:
            for r2 in q.radii:
                pc = resolve_pair(scene, i, j, r1, r2)
                steps.append(pair_step(scene.integrator, pc, p.shape_at(r1), q.shape_at(r2), p.kind, q.kind))
    return min(s.dt_translation for s in steps), steps


_radii = st.lists(st.floats(-5.0, 1.0), min_size=3, max_size=7, unique=True).map(lambda xs: sorted(10.0**x for x in xs))


@settings(max_examples=25, deadline=None)
@given(_radii, _radii, st.floats(0.1, 10.0), st.floats(0.0, 2.0), st.sampled_from(["linear", "linear-cn", "yade"]),
       st.floats(0.0, 0.9), st.floats(-1.0, 1.0))
def test_extreme_radii_carry_every_extreme(r1, r2, density_ratio, ks_ratio, law, zeta, log_e_ratio):
    """Two sphere types with their own densities (and Young's moduli for YADE), radii spanning six decades:
    the isolated step and the dense block bound of the reduced evaluation equal the brute-force ones."""
    assume(max(r1 + r2) / min(r1 + r2) < 1e6)
    if law == "linear":
        contact = f'model = "linear"\nkn = 1e5\nks = {1e5 * ks_ratio!r}\ndamping_ratio = {zeta!r}\n'
    elif law == "linear-cn":
        contact = f'model = "linear"\nkn = 1e5\nks = {1e5 * ks_ratio!r}\ncn = {zeta!r}\ncs = {zeta / 3!r}\n'
    else:
        assume(ks_ratio > 0)
        contact = (f'model = "yade"\nyoungs_modulus = [7e10, {7e10 * 10**log_e_ratio!r}]\nks_ratio = {ks_ratio!r}\n'
                   f"damping_ratio = {zeta!r}\n")

    def table(rs, rho):
        fr = [1.0 / len(rs)] * len(rs)
        fr[-1] = 1.0 - sum(fr[:-1])
        return f'[[particle]]\nshape = "sphere"\nradii = {rs!r}\nfractions = {fr!r}\ndensity = {rho!r}\n'

    scene = parse_scene('integrator = "velocity-verlet"\ncoordination_max = 12\n' + table(r1, 2500.0)
                        + table(r2, 2500.0 * density_ratio) + "[contact]\n" + contact)
    res = critical_step(scene)
    dt_brute, steps = _brute_force(scene)
    assert res.dt_isolated == pytest.approx(dt_brute, rel=1e-12)
    block = dense_step(scene.integrator, block_terms(scene, steps), 12)
    assert res.dense.lambda_k <= block.lambda_k * (1 + 1e-12)  # the sphere bound may be sharper, never looser
    if len(r1) + len(r2) > 6:  # block bound only: the same terms
        assert res.dense.lambda_k == pytest.approx(block.lambda_k, rel=1e-12)
        assert res.dense.lambda_c == pytest.approx(block.lambda_c, rel=1e-12, abs=0.0)


def test_default_headline_of_ellipsoids_never_exceeds_their_packing_step(capsys):
    """The example chain of four ellipsoids (examples/packings/ellipsoids.json: contacts found between the
    rotated bodies, the 24-DOF M^-1 K solved and certified by ``dtcrit packing``, an independent route) and the
    scene of the same ellipsoids without packing keys: the headline (volume-count coordination) is below."""
    import json

    from dtcrit.cli import main

    assert main(["packing", str(ROOT / "examples" / "packings" / "ellipsoids.json"), "--kn", "1e5", "--ks", "1e5",
                 "--json"]) == 0
    exact = json.loads(capsys.readouterr().out)["dt_crit"]
    res = critical_step(parse_scene('integrator = "velocity-verlet"\n[[particle]]\nshape = "ellipsoid"\n'
                                    'semi_axes = [0.0015, 0.001, 0.00075]\ndensity = 2650.0\n'
                                    '[contact]\nmodel = "linear"\nkn = 1e5\nks = 1e5\n'))
    assert res.basis == "any packing" and res.coordination.z >= 12
    assert res.dt_crit <= exact < res.dt_isolated  # the chain (2 contacts each) is already below the pair step



def _ring_code_size(theta: float) -> int:
    """A constructed set of points of S^2 pairwise at least ``theta`` apart (independent of the bound):
    rings at polar angles ``j theta``, each holding as many points as fit at azimuth spacing ``d`` with
    ``sin(phi) sin(d/2) >= sin(theta/2)`` (so every chord on a ring is at least the one of ``theta``)."""
    count = 0
    for j in range(int(math.pi / theta) + 1):
        s = math.sin(j * theta)
        if s <= math.sin(0.5 * theta):
            count += 1  # a pole (or a ring too small for two points)
            continue
        count += int(math.pi / math.asin(math.sin(0.5 * theta) / s))
    return count


@pytest.mark.parametrize("small", [0.2, 0.05, 2e-3, 2e-4])
def test_sphere_coordination_is_at_least_a_constructed_arrangement(small):
    """Small spheres touching a unit sphere, not overlapping each other (overlap_max = 0): the coordination
    bound must admit the arrangement built by ``_ring_code_size`` (at a size ratio of 5000 the contact-angle
    count once stopped at a loop limit of 1e7 and was taken as a bound)."""
    from dtcrit.scenes.coordination import sphere_coordination

    theta = 2.0 * math.asin(small / (1.0 + small))
    z, _ = sphere_coordination([small, 1.0], 0.0)
    assert z >= _ring_code_size(theta)


def test_a_user_written_integrator_gets_every_size_pair():
    """The reduction to the extreme radii rests on the built-in steps being non-increasing in A, which
    is not proven for a user's scheme: its scene is evaluated size pair by size pair."""
    from dtcrit.scenes.timestep import _not_reducible

    text = ('[[particle]]\nshape = "sphere"\nradii = [1e-3, 2e-3, 3e-3]\nfractions = [0.25, 0.5, 0.25]\n'
            'density = 2500\n[contact]\nmodel = "linear"\nkn = 1e5\nks = 1e5\ncn = 0.1\n'
            '[integrator]\nname = "mine"\nstate = ["x", "v"]\nupdate = ["v = v + h*f(x, v)", "x = x + h*v"]\n')
    assert "user-written" in _not_reducible(parse_scene(text))
