"""``dtcrit step``'s ``yade_gsts`` row: YADE's GlobalStiffnessTimeStepper for one contact per body, its
normal along the worst axis, the touching sphere's own radius as the arm (a clump's member, not the
clump's reach), rolling and twisting springs added (``GlobalStiffnessTimeStepper.cpp``); no row for
shapes the stepper does not take.
"""
from __future__ import annotations

import math

import pytest

from dtcrit.scenes.scene import parse_scene
from dtcrit.scenes.timestep import critical_step


def _rows(text: str) -> dict:
    return {e.estimate.name: e.estimate for e in critical_step(parse_scene(text)).estimates}


def test_clump_scene_turns_about_the_member_radius():
    """Unequal members: the larger member's radius (the worst), ks only, against the smallest moment."""
    members = [[-0.0075, 0.0, 0.0, 0.01], [0.0075, 0.0, 0.0, 0.006]]
    kn, ks = 1.0e6, 5.0e5
    row = _rows(f'integrator = "leapfrog"\n[[particle]]\nshape = "clump"\nspheres = {members!r}\n'
                f'density = 2500.0\n[contact]\nmodel = "linear"\nkn = {kn!r}\nks = {ks!r}\n')["yade_gsts"]
    from dtcrit.bodies.clump import Clump

    body = Clump(members, density=2500.0)
    expect = 1.41044 * 0.8 * math.sqrt(min(body.mass / kn, min(body.inertia) / (ks * 0.01**2)))
    assert row.dt == pytest.approx(expect, rel=1e-14)


def test_sphere_scene_with_rolling_springs():
    """K_rot = max(ks R^2 + kr, ktw): the normal across an axis, or along it."""
    r, rho, kn, ks, kr, ktw = 0.001, 2500.0, 1e5, 4e4, 0.05, 0.2
    m = rho * 4 / 3 * math.pi * r**3
    row = _rows(f'integrator = "leapfrog"\n[[particle]]\nshape = "sphere"\nradius = {r!r}\ndensity = {rho!r}\n'
                f'[contact]\nmodel = "linear"\nkn = {kn!r}\nks = {ks!r}\nkr = {kr!r}\nktw = {ktw!r}\n')
    expect = 1.41044 * 0.8 * math.sqrt(min(m / kn, 0.4 * m * r * r / max(ks * r * r + kr, ktw)))
    assert row["yade_gsts"].dt == pytest.approx(expect, rel=1e-14)


def test_no_row_for_shapes_yade_stepper_does_not_take():
    """An ellipsoid scene: the stepper reads sphere contacts, so the row does not apply."""
    row = _rows('integrator = "leapfrog"\n[[particle]]\nshape = "ellipsoid"\nsemi_axes = [0.002, 0.001, 0.001]\n'
                'density = 2500.0\n[contact]\nmodel = "linear"\nkn = 1e5\nks = 4e4\n')["yade_gsts"]
    assert row.dt is None and "sphere contacts" in row.detail
