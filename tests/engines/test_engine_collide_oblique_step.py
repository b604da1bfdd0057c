"""LAMMPS collides two spheres obliquely at dtcrit's oblique resolution step: within tol there, not just above.

dtcrit's step is ``collisions.oblique_resolution.oblique_resolve`` (what ``dtcrit collide --angle`` reports
per t_c); the engine is LAMMPS (``support.engines.collisions_lammps``: ``pair_style granular hertz/material
... tangential mindlin NULL 0 mu``, ``fix nve/sphere``), elastic Hertz, E = 1e7, nu = 0.3, elastic peak
overlap 1e-3 R, over ``PHASES`` entry phases; the continuum is the harness's own
(``support.collision_reference``: SI, both spheres, sliding or sticking throughout).  The error is
max(|e_t/e_t,ref - 1|, |spin - spin_ref|) over the phases: at 0.999x dtcrit's step it is within tol at
every phase; at 1.005x or 1.2x it exceeds tol at some phase (the error is not monotone in the step at
a few steps per collision, see ``tests/collisions/test_oblique_resolution_step.py``).

* sliding: mu = 0.1, v_t = 2 v_n (N_res ~ 4);
* sticking: mu = 1e4, v_t = v_n (N_res in the hundreds: LAMMPS's history convention is first order).
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from support.collision_reference import oblique_sliding, oblique_sticking
from support.engines import collisions_lammps, require_engine
from support.engines.collisions import design

DT = 1.0e-6
PHASES = (np.arange(40) + 0.5) / 40
TOL = 0.01
FACTORS = (0.999, 1.005, 1.2)
CASES = {"slide": (0.1, 2.0, oblique_sliding), "stick": (1.0e4, 1.0, oblique_sticking)}


def _impact(mode, n, phase):
    mu, ratio, _ = CASES[mode]
    base = design("hertz", "none", 0.0, dt=DT, steps_per_collision=n, phase=phase)
    return replace(base, tangential_speed=ratio * base.speed, friction=mu)


@pytest.mark.parametrize("mode", list(CASES))
def test_lammps_oblique_impact_at_dtcrits_oblique_resolution_step(mode):
    """Within tol at 0.999x dtcrit's step over every phase; outside it at 1.005x or 1.2x."""
    from dtcrit.collisions.oblique import oblique_case
    from dtcrit.collisions.oblique_resolution import oblique_resolve

    require_engine("lammps")
    mu, ratio, continuum = CASES[mode]
    case = oblique_case(normal="hertz", damping="none", restitution=1.0, friction=mu, tangential_ratio=ratio,
                        poisson=0.3, overlap_ratio=1.0e-3)
    res = oblique_resolve(case, TOL)
    assert res.mode == mode
    ref = continuum(_impact(mode, 100.0, 0.5))  # the continuum is free of N and phase
    impacts = [_impact(mode, res.steps_per_collision / f, p) for f in FACTORS for p in PHASES]
    outs = collisions_lammps.collide(impacts, DT)
    worst = {}
    for k, f in enumerate(FACTORS):
        errs = [max(abs(o.tangential_restitution / ref.tangential_restitution - 1.0), abs(o.spin - ref.spin))
                for o in outs[k * len(PHASES):(k + 1) * len(PHASES)]]
        worst[f] = max(errs) / TOL
    assert worst[0.999] <= 1.0, worst
    assert max(worst[1.005], worst[1.2]) > 1.0, worst
