"""YADE's GlobalStiffnessTimeStepper (``dtcrit.packing.bounds.yade_stepper``) against the formulas read in
its source (``pkg/dem/GlobalStiffnessTimeStepper.cpp``), written out by hand here; the engine itself is
compared in ``tests/engines/test_engine_yade_gsts.py``.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dtcrit.packing.bounds.yade_stepper import StepperInput, single_contact_step, viscous_steps, yade_stepper
from dtcrit.packing.bounds.yade_stepper_export import from_export
from dtcrit.packing.model import Packing

R, RHO = 1.0e-3, 2500.0
M = 4.0 / 3.0 * math.pi * R**3 * RHO


def _pair(n, kn=1e5, ks=3e4, rot=(0.0, 0.0, 0.0), fn=True, dynamic=(True, True)) -> StepperInput:
    return StepperInput(np.full(2, M), np.full((2, 3), 0.4 * M * R * R), np.array(dynamic), np.arange(2),
                        np.array([0]), np.array([1]), np.array([n], float), np.array([kn]), np.array([ks]),
                        np.array([rot], float), np.array([R]), np.array([R]), np.array([fn]), (7, 8))


def _by_hand(n, kn, ks, kr, ktw, mass, inertia, radius, safety=0.8):
    """The source's per-body step for one contact, component by component."""
    n = np.asarray(n, float)
    trans = max((kn - ks) * n[a] ** 2 + ks for a in range(3))
    rots = []
    for a in range(3):
        k = ks * (1.0 - n[a] ** 2) * radius**2 + (ktw - kr) * n[a] ** 2 + kr
        if k != 0:
            with np.errstate(over="ignore"):  # a subnormal spring: an infinite period, as in the source
                rots.append(inertia[a] / k)
    return 1.41044 * safety * math.sqrt(min([mass / trans] + rots))


def test_sphere_pair_oblique_normal():
    """Translation along the global axes: (kn - ks) n_a^2 + ks, the largest of the three."""
    n = np.array([1.0, 0.3, -0.2]) / math.sqrt(1.13)
    step = yade_stepper(_pair(n))
    assert step.dt == pytest.approx(_by_hand(n, 1e5, 3e4, 0, 0, M, [0.4 * M * R * R] * 3, R), rel=1e-14)
    assert step.term == "translation" and step.body == 0


def test_moment_springs_add_ktw_along_the_normal_and_kr_across():
    """The moment springs of getRotStiffness (ktw, kr, kr): (ktw - kr) n_a^2 + kr on each axis, beside ks (1 - n_a^2) R^2."""
    n = np.array([0.0, 0.6, 0.8])
    kr, ktw = 4e4 * R * R, 1e4 * R * R
    step = yade_stepper(_pair(n, rot=(ktw, kr, kr)), 1.0)
    assert step.dt == pytest.approx(_by_hand(n, 1e5, 3e4, kr, ktw, M, [0.4 * M * R * R] * 3, R, 1.0), rel=1e-14)
    assert step.term.startswith("rotation about body axis")


def test_zero_force_contacts_and_fixed_bodies_are_skipped():
    """``if (fn==0) continue``; only dynamic bodies get a step; none at all: YADE keeps its defaultDt."""
    n = [1.0, 0.0, 0.0]
    assert yade_stepper(_pair(n, fn=False)).dt is None
    assert "defaultDt" in yade_stepper(_pair(n, fn=False)).missing
    one = yade_stepper(_pair(n, dynamic=(False, True)))
    assert one.body == 1 and math.isinf(one.per_body[0])


def test_clump_member_radius_is_the_arm_and_inertia_is_body_frame():
    """A clump of two spheres (body 0) touches a free sphere (body 1) with its member 1: the member's
    radius, not its offset from the clump's centre, is the arm; the global-axis sums meet the clump's
    body-frame moments as given (no rotation to its principal frame).
    """
    r_member, kn, ks = 0.5 * R, 1e5, 8e4
    inertia = np.array([1e-12, 5e-12, 5e-12])
    inp = StepperInput(np.array([3 * M, M]), np.array([inertia, [0.4 * M * R * R] * 3]), np.ones(2, bool),
                       np.array([0, 0, 1]), np.array([1]), np.array([2]), np.array([[0.0, 0.0, 1.0]]),
                       np.array([kn]), np.array([ks]), np.zeros((1, 3)), np.array([r_member]), np.array([R]),
                       np.ones(1, bool), (10, 20))
    k_rot_x = ks * r_member**2  # n along z: the x and y axes get ks R^2, z nothing
    expect = 1.41044 * 0.8 * math.sqrt(min(3 * M / kn, inertia[0] / k_rot_x, inertia[1] / k_rot_x))
    step = yade_stepper(inp)
    assert step.body == 0 and step.dt == pytest.approx(expect, rel=1e-14)


@settings(max_examples=40, derandomize=True)
@given(kn=st.floats(1e2, 1e6), ratio=st.floats(0.01, 2.0), kr=st.floats(0, 1e-1), ktw=st.floats(0, 1e-1),
       i1=st.floats(0.2, 1.0), i2=st.floats(0.2, 1.0))
def test_single_contact_step_is_the_worst_normal(kn, ratio, kr, ktw, i1, i2):
    """The smallest step over 2000 random normals is never below it, and comes within 2 % of it."""
    ks = ratio * kn
    inertia = np.array([i1, i2, 1.0]) * 0.4 * M * R * R
    got = single_contact_step(M, inertia, kn, ks, kr * ks * R * R, ktw * ks * R * R, R)
    rng = np.random.default_rng(0)
    normals = rng.normal(size=(2000, 3))
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    trials = [_by_hand(n, kn, ks, kr * ks * R * R, ktw * ks * R * R, M, inertia, R) for n in normals]
    axes = [_by_hand(n, kn, ks, kr * ks * R * R, ktw * ks * R * R, M, inertia, R) for n in np.eye(3)]
    assert min(trials) >= got * (1 - 1e-12)
    assert min(trials) <= got * 1.02
    assert got == pytest.approx(min(axes), rel=1e-14)


def test_viscous_term_has_no_square_root():
    """``dt_visc = 2 safety min(m/C)``: no square root, as the source writes it."""
    got = viscous_steps([2.0], [[1.0, 1.0, 1.0]], [[4.0, 1.0, 1.0]], [[0.0, 0.0, 0.0]], 0.8)
    assert got == pytest.approx([2 * 0.8 * 2.0 / 4.0])


def _export(phys, kr=None, ktw=None, fn=1.0):
    m = M
    sphere = lambda bid, x: {"id": bid, "pos": [x, 0, 0], "radius": R, "mass": m,  # noqa: E731
                             "inertia": [0.4 * m * R * R] * 3, "clump_id": None, "is_clump": False, "fixed": False}
    inter = {"id1": 0, "id2": 1, "kn": 1e5, "ks": 5e4, "kr": kr, "ktw": ktw, "fn": fn, "phys": phys,
             "normal": [1.0, 0.0, 0.0], "radius1": R, "radius2": R}
    return {"bodies": [sphere(0, 0.0), sphere(1, 2 * R - 1e-5)], "interactions": [inter]}


def _packing():
    return Packing.spheres([[0, 0, 0], [2 * R - 1e-5, 0, 0]], R, masses=M, ids=[0, 1])


def test_export_rotational_stiffness_follows_the_physics():
    """FrictPhys has no getRotStiffness (zero, whatever is exported); MindlinPhys and CohFrictPhys
    derive from RotStiffFrictPhys: (ktw, kr, kr); CohFrictPhys without exported kr has no step.
    """
    kr = 5.0 * 5e4 * R * R
    plain = yade_stepper(from_export(_export("FrictPhys", kr, kr), _packing()), 1.0).dt
    with_moments = yade_stepper(from_export(_export("MindlinPhys", kr, kr), _packing()), 1.0).dt
    i = 0.4 * M * R * R
    assert plain == pytest.approx(1.41044 * math.sqrt(min(M / 1e5, i / (5e4 * R * R))), rel=1e-14)
    assert with_moments == pytest.approx(1.41044 * math.sqrt(min(M / 1e5, i / (5e4 * R * R + kr), i / kr)), rel=1e-14)
    missing = from_export(_export("CohFrictPhys"), _packing()).missing
    assert missing is not None and "kr, ktw" in missing
    assert yade_stepper(from_export(_export("FrictPhys", fn=0.0), _packing())).dt is None
