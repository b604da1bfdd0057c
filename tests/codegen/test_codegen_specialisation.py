"""What the emitted code leaves out, and that leaving it out changes nothing where both forms apply.

* specialised kernels have strictly fewer operations than the general form (SymPy's count after
  CSE, and an independent count of operators and calls in the emitted C);
* they give the same values as the general form fed with the specialised case's parameters;
* the arm-based A of the kernel bounds the largest eigenvalue of the contact coefficient matrix
  (dtcrit.bodies.contact.coefficient_matrix) for random arms and orientations, so the emitted step is safe
  for every contact with those arm lengths; at the scene's largest arms it is never larger than
  the step ``dtcrit step`` reports, and equal for spheres;
* the output is deterministic and its header carries what produced it.
"""
import math
import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dtcrit.codegen import (KernelStructure, build_kernel, count_c_operations, emit_for_scene, general_structure,
                            render, structure_of_scene)
from dtcrit.bodies.contact import coefficient_matrix
from dtcrit.scenes.scene import load_scene
from dtcrit.bodies import Box, Ellipsoid, Sphere
from dtcrit.scenes.timestep import critical_step

from support.codegen import GFORTRAN, c_function, fortran_function, kernel_for, numpy_function
from support.precision import ulps
from support.paths import REPO_ROOT as ROOT

EXAMPLE = {p.stem: p for p in (ROOT / "examples").glob("*.toml")}


def _general_args(kernel, p1, p2, kn, ks, cn, cs, omega_max):
    """Arguments of the general kernel for two particles given as (m, Ixx, Iyy, Izz, r)."""
    v = dict(kn=kn, ks=ks, cn=cn, cs=cs, omega_max=omega_max)
    for n, p in (("1", p1), ("2", p2)):
        v.update({f"m{n}": p[0], f"I_xx{n}": p[1], f"I_yy{n}": p[2], f"I_zz{n}": p[3], f"r{n}": p[4]})
    return [v[a.name] for a in kernel.arguments]


@pytest.mark.parametrize("scene", ["paper_ellipsoids", "glass_spheres_hertz", "mixed_pair", "damped_ellipsoids",
                                   "superquadric", "polyhedron_cube"])
def test_specialised_code_is_smaller_than_the_general_form(scene):
    s = load_scene(EXAMPLE[scene])
    special = build_kernel(structure_of_scene(s))
    general = build_kernel(general_structure(s.integrator))
    assert special.op_count() < general.op_count(), (scene, special.op_count(), general.op_count())
    c_special, c_general = render(special, "c"), render(general, "c")
    assert count_c_operations(c_special) < count_c_operations(c_general)
    assert len(special.arguments) < len(general.arguments)


def test_op_counts_of_two_example_scenes():
    """The figures quoted in the report (SymPy count_ops after CSE / operators+calls in the C)."""
    counts = {}
    for scene in ("paper_ellipsoids", "glass_spheres_hertz"):
        s = load_scene(EXAMPLE[scene])
        sp_, ge = build_kernel(structure_of_scene(s)), build_kernel(general_structure(s.integrator))
        counts[scene] = (sp_.op_count(), ge.op_count(), count_c_operations(render(sp_, "c")), count_c_operations(render(ge, "c")))
    assert counts["paper_ellipsoids"][0] < counts["paper_ellipsoids"][1]
    assert counts["glass_spheres_hertz"][0] < counts["glass_spheres_hertz"][1]


def test_what_is_left_out():
    s = load_scene(EXAMPLE["paper_ellipsoids"])  # identical, undamped, omega_max given
    names = [a.name for a in build_kernel(structure_of_scene(s)).arguments]
    assert names == ["m", "I_xx", "I_yy", "I_zz", "r", "kn", "ks", "omega_max"]
    s = load_scene(EXAMPLE["glass_spheres_hertz"])  # identical spheres, damped, no omega_max
    k = build_kernel(structure_of_scene(s))
    assert [a.name for a in k.arguments] == ["m", "kn", "ks", "cn", "cs"]
    m = k.arguments[0].symbol
    assert k.steps[0][1] == 2 / m and k.steps[1][1] == 7 / m  # exact sphere modes: A_n = 2/m, A_s = 7/m
    s = load_scene(EXAMPLE["damped_ellipsoids"])
    assert "omega_max" not in [a.name for a in build_kernel(structure_of_scene(s)).arguments]
    s = load_scene(EXAMPLE["mixed_pair"])  # two types, all pairings: both sides general
    assert [a.name for a in build_kernel(structure_of_scene(s)).arguments][:5] == ["m1", "I_xx1", "I_yy1", "I_zz1", "r1"]
    # leapfrog-centred: tau = 2 whatever the damping, so damping arguments are dropped
    k = build_kernel(KernelStructure("leapfrog-centred", True, ("general",), True, True, False))
    assert [a.name for a in k.arguments] == ["m", "I_xx", "r", "kn", "ks"]


def test_undamped_scheme_without_a_stable_step_is_refused():
    from dtcrit.errors import InputError

    with pytest.raises(InputError) as exc:
        build_kernel(KernelStructure("forward-euler", True, ("sphere",), False, False, False))
    assert exc.value.key == "integrator"
    with pytest.raises(InputError) as exc:  # paper-eq40 with an undamped shear direction: dt = 0 always
        build_kernel(KernelStructure("paper-eq40", True, ("general",), True, False, False))
    assert "undamped in the shear direction" in exc.value.reason
    with pytest.raises(InputError) as exc:  # B = 0 for spheres: no rotation bound to emit
        KernelStructure("velocity-verlet", False, ("sphere", "sphere"), True, True, True)
    assert exc.value.key == "rotation"


@settings(max_examples=40)
@given(
    integrator=st.sampled_from(["velocity-verlet", "paper-eq40", "forward-euler", "velocity-verlet-predicted"]),
    log_m=st.floats(-8, 5), log_size=st.floats(-4, 1), ratios=st.tuples(st.floats(1, 3), st.floats(1, 3)),
    log_k=st.floats(0, 11), zeta=st.floats(0.01, 20.0), log_w=st.floats(-3, 5),
)
def test_specialised_forms_equal_the_general_form(integrator, log_m, log_size, ratios, log_k, zeta, log_w):
    m, size, k = 10.0**log_m, 10.0**log_size, 10.0**log_k
    general = kernel_for(general_structure(integrator))
    g = c_function(general)
    # identical ellipsoid-like particles, damped, with rotation
    ixx = 0.2 * m * size**2
    p = (m, ixx, ixx * ratios[0], ixx * ratios[0] * ratios[1], size)
    c = 2 * zeta * math.sqrt(k * m / 4)
    ident = kernel_for(KernelStructure(integrator, True, ("general",), True, True, True))
    a_id = [dict(m=p[0], I_xx=p[1], I_yy=p[2], I_zz=p[3], r=p[4], kn=k, ks=k / 2, cn=c, cs=c / 3, omega_max=10**log_w)[a.name]
            for a in ident.arguments]
    assert ulps(c_function(ident)(*a_id), g(*_general_args(general, p, p, k, k / 2, c, c / 3, 10**log_w))) <= 4
    # identical spheres (exact modes A_n = 2/m, A_s = 7/m) against the general form taken one direction at a
    # time: arm 0 gives A = 2/m, arm R with I = 2/5 m R^2 gives A = 7/m; the other direction is switched off with a
    # vanishing spring and a tiny dashpot (its step is 1e10 times longer for every integrator)
    sph = kernel_for(KernelStructure(integrator, True, ("sphere",), True, True, False))
    got = c_function(sph)(m, k, k / 2, c, c / 3)
    point = (m, 0.4 * m * size**2, 0.4 * m * size**2, 0.4 * m * size**2, 0.0)
    sphere = (m, 0.4 * m * size**2, 0.4 * m * size**2, 0.4 * m * size**2, size)
    off_k, off_c = k * 1e-30, c * 1e-10 + 1e-300
    normal = g(*_general_args(general, point, point, k, off_k, c, off_c, 1.0))
    shear = g(*_general_args(general, sphere, sphere, off_k, k / 2, off_c, c / 3, 1.0))
    assert ulps(got, min(normal, shear)) <= 4
    # undamped velocity-verlet family: one sqrt of max(kn A_n, ks A_s) equals the min over directions
    if integrator != "forward-euler" and integrator != "paper-eq40":
        und = kernel_for(KernelStructure(integrator, True, ("sphere",), False, False, False))
        normal = g(*_general_args(general, point, point, k, off_k, 0.0, 0.0, 1.0))
        shear = g(*_general_args(general, sphere, sphere, off_k, k / 2, 0.0, 0.0, 1.0))
        assert ulps(c_function(und)(m, k, k / 2), min(normal, shear)) <= 4


def _random_rotation(rng):
    q = rng.normal(size=4)
    return q / np.linalg.norm(q)


@pytest.mark.parametrize("shapes", [
    (Ellipsoid(3.0, 2.0, 1.0, density=1000.0), Ellipsoid(3.0, 2.0, 1.0, density=1000.0)),
    (Box(1.0, 0.6, 0.3, density=2.0), Ellipsoid(2.0, 0.5, 0.4, density=3.0)),
    (Sphere(0.5, density=7.0), Box(0.8, 0.8, 0.2, density=1.0)),
])
def test_arm_based_A_bounds_the_coefficient_matrix(shapes):
    """lambda_max of the contact coefficient matrix <= 1/m1 + 1/m2 + r1^2/I_min1 + r2^2/I_min2 for any
    arms of lengths r1, r2 and any orientations (||[r]x I^-1 [r]x^T|| <= |r|^2 / I_min)."""
    p1, p2 = shapes
    rng = np.random.default_rng(7)
    worst = 0.0
    for _ in range(2000):
        r1 = rng.normal(size=3)
        r2 = rng.normal(size=3)
        r1 *= p1.max_arm * rng.uniform(0.2, 1.0) / np.linalg.norm(r1)
        r2 *= p2.max_arm * rng.uniform(0.2, 1.0) / np.linalg.norm(r2)
        W = coefficient_matrix(p1, p2, r1, r2, body_to_world=(_random_rotation(rng), _random_rotation(rng)))
        bound = 1 / p1.mass + 1 / p2.mass + r1 @ r1 / min(p1.inertia) + r2 @ r2 / min(p2.inertia)
        worst = max(worst, np.linalg.eigvalsh(W)[-1] / bound)
    assert worst <= 1 + 1e-12
    assert worst > 0.5  # the bound is not vacuous


@pytest.mark.parametrize("scene", sorted(EXAMPLE))
def test_emitted_step_at_the_scene_values_against_dtcrit_step(scene):
    """The emitted function at the scene's masses, moments, largest arms, stiffnesses and damping
    never exceeds the verified step of ``dtcrit step`` (A at the largest arm >= a_bound) and equals
    it for spheres, where both are 7/(2m) per particle.  The scene's C and Fortran (when gfortran
    is present) give the NumPy's value within 1 ulp."""
    s = load_scene(EXAMPLE[scene])
    kernel = build_kernel(structure_of_scene(s))
    f = numpy_function(kernel)
    compiled = [c_function(kernel)] + ([fortran_function(kernel)] if GFORTRAN else [])
    result = critical_step(s)
    for pair in result.pairs:
        c = pair.contact
        if c.wall is not None:  # the kernel is for particle-particle contacts
            continue
        values = dict(kn=c.kn, ks=c.ks, cn=c.cn, cs=c.cs, omega_max=s.omega_max)
        sides = [s.particle(c.i), s.particle(c.j)]
        for tag, part, radius in zip(("1", "2") if not s.identical else ("",), sides, (c.radius_i, c.radius_j)):
            sh = part.shape_at(radius)
            values.update({f"m{tag}": sh.mass, f"I_xx{tag}": sh.inertia[0], f"I_yy{tag}": sh.inertia[1],
                           f"I_zz{tag}": sh.inertia[2], f"r{tag}": sh.max_arm})
        args = [values[a.name] for a in kernel.arguments]
        got = f(*args)
        for g in compiled:
            assert ulps(g(*args), got) <= 1, (scene, pair.label, g(*args), got)
        expected = min(pair.dt_translation, pair.dt_rotation or math.inf)
        assert got <= expected * (1 + 1e-13), (scene, pair.label, got, expected)
        if all(side == "sphere" for side in kernel.structure.sides):  # the exact sphere modes on both routes
            assert got == pytest.approx(expected, rel=1e-13)


def test_output_is_deterministic_and_documented():
    s = load_scene(EXAMPLE["damped_ellipsoids"])
    for lang in ("c", "numpy", "fortran"):
        a = emit_for_scene(s, lang)
        b = emit_for_scene(load_scene(EXAMPLE["damped_ellipsoids"]), lang)
        assert a == b
        assert "GENERATED by dtcrit codegen" in a and "Derivation hash: " in a and "velocity-verlet" in a
        assert "Eq. (26)" in a and "Eqs. (29)-(30)" in a
        assert not re.search(r"20\d\d-\d\d-\d\d|\d\d:\d\d:\d\d|version", a, flags=re.I)
        assert str(ROOT) not in a
    text = emit_for_scene(s, "c")
    for arg in ("m", "I_xx", "r", "kn", "ks", "cn", "cs"):
        assert re.search(rf"\* +{arg} +\[", text), arg
