"""Real engines collide two spheres obliquely: LAMMPS and YADE against dtcrit's ``collisions.oblique``.

Harness: ``support.engines.collisions`` (``design``, ``measure``: tangential restitution = exit/entry
contact-point slip along the entry tangent, spin = rebound spin of sphere 1 times R over v_t),
``collisions_lammps`` (``granular hertz/material ... tangential mindlin NULL 0 mu``) and
``collisions_yade`` (``Law2_ScGeom_MindlinPhys_Mindlin``).  Elastic Hertz normal law, E = 1e7,
nu = 0.3, elastic peak overlap 1e-3 R (dtcrit's ``overlap_ratio``).

* sliding: mu = 0.1, v_t = 2 v_n (slides throughout); LAMMPS and YADE;
* sticking: mu = 1e4, v_t = v_n (LAMMPS only: YADE's shear law is incremental).  LAMMPS's first
  contact step adds the whole step's slip ``v_tr dt`` to the history (the part before touch too),
  and with this huge ``mu`` its ``frameupdate`` test (``|xi.n| k_t > 1e-10 mu |F_n|``) never
  projects the history onto the turning tangent plane, so the history keeps a normal part;
  dtcrit models both, and with them matches LAMMPS to ~1e-10.

At N = 5, 12, 40 and three entry phases, dtcrit's stepped outcome equals the engines' to 1e-9
relative (1e-12 absolute on the spin, which nearly vanishes at some phases); also with LAMMPS's
2021 ``tsuji`` dashpot (e = 0.5), tangential damping, ``limit_damping`` and a stick-slip case.
"""
from __future__ import annotations

from dataclasses import replace

import pytest

from support.engines import collisions_lammps, collisions_yade, require_engine
from support.engines.collisions import design

DT = 1.0e-6
COARSE_N = (5, 12, 40)
PHASES = (0.1, 0.5, 0.93)
CASES = {"slide": (0.1, 2.0), "stick": (1.0e4, 1.0)}


def _impacts(mode):
    mu, ratio = CASES[mode]
    out = []
    for n in COARSE_N:
        for p in PHASES:
            base = design("hertz", "none", 0.0, dt=DT, steps_per_collision=n, phase=p)
            out.append((n, p, replace(base, tangential_speed=ratio * base.speed, friction=mu)))
    return out


def _assert_same(mode, cases, outs):
    from dtcrit.collisions.oblique import oblique_case, step_oblique

    mu, ratio = CASES[mode]
    c = oblique_case(normal="hertz", damping="none", restitution=1.0, friction=mu, tangential_ratio=ratio,
                     poisson=0.3, overlap_ratio=1.0e-3)
    bad = []
    for (n, p, _), got in zip(cases, outs):
        want = step_oblique(c, n, p)
        for name in ("restitution", "tangential_restitution", "spin"):
            a, b = getattr(got, name), getattr(want, name)
            if abs(a - b) > 1e-9 * abs(b) + 1e-12:
                bad.append(f"{mode} N={n} phase={p}: {name} engine {a!r} dtcrit {b!r}")
    assert not bad, "\n".join(bad)


def test_lammps_oblique_sliding_and_sticking_equal_dtcrits_stepped_impact():
    """LAMMPS ``mindlin`` sliding (mu = 0.1) and sticking (mu = 1e4) at coarse N: dtcrit to 1e-9."""
    require_engine("lammps")
    slide, stick = _impacts("slide"), _impacts("stick")
    outs = collisions_lammps.collide([c[2] for c in slide + stick], DT)
    _assert_same("slide", slide, outs[: len(slide)])
    _assert_same("stick", stick, outs[len(slide):])


def test_yade_oblique_sliding_equals_dtcrits_stepped_impact():
    """YADE Hertz-Mindlin sliding (mu = 0.1) at coarse N: dtcrit's stepped impact to 1e-9."""
    require_engine("yade")
    slide = _impacts("slide")
    outs = collisions_yade.collide([c[2] for c in slide], DT)
    _assert_same("slide", slide, outs)


@pytest.mark.parametrize("mode", ["slide", "stick"])
def test_engine_cases_are_the_regimes_the_continuum_reference_checks(mode):
    """The cases stay in one regime in the continuum (the reference refuses mixed stick-slip)."""
    from dtcrit.collisions.oblique import oblique_case, reference_oblique

    mu, ratio = CASES[mode]
    ref = reference_oblique(oblique_case(normal="hertz", damping="none", restitution=1.0, friction=mu,
                                         tangential_ratio=ratio), mode)
    assert ref.restitution == pytest.approx(1.0, abs=1e-3)


DAMPED = [(1.0e4, 1.0, 0.5, False), (0.1, 2.0, 0.0, True), (0.3, 0.5, 0.3, False)]  # mu, v_t/v_n, gammat, clip


def test_lammps_damped_and_stick_slip_oblique_impacts_equal_dtcrits_stepped_impact():
    """LAMMPS 2021 ``tsuji`` (e = 0.5) with tangential damping, ``limit_damping``, and stick-slip (mu = 0.3).

    dtcrit's key for Debian's 2021 ``tsuji`` is ``lammps-tsuji-2021``; 1e-9 relative (measured 2.6e-11).
    """
    from dtcrit.collisions.oblique import oblique_case, step_oblique

    require_engine("lammps")
    cases = []
    for mu, ratio, gammat, clip in DAMPED:
        for n in COARSE_N:
            for p in PHASES:
                base = design("hertz", "lammps-tsuji", 0.5, dt=DT, steps_per_collision=n, phase=p, clip=clip)
                imp = replace(base, tangential_speed=ratio * base.speed, friction=mu, gammat_ratio=gammat)
                cases.append(((mu, ratio, gammat, clip), n, p, imp))
    outs = collisions_lammps.collide([c[3] for c in cases], DT)
    bad = []
    for ((mu, ratio, gammat, clip), n, p, _), got in zip(cases, outs):
        c = oblique_case(normal="hertz", damping="lammps-tsuji-2021", restitution=0.5, friction=mu,
                         tangential_ratio=ratio, gammat_ratio=gammat, clip=clip)
        want = step_oblique(c, n, p)
        for name in ("restitution", "tangential_restitution", "spin"):
            a, b = getattr(got, name), getattr(want, name)
            if abs(a - b) > 1e-9 * abs(b) + 1e-12:
                bad.append(f"mu={mu} gammat={gammat} clip={clip} N={n} phase={p}: {name} engine {a!r} dtcrit {b!r}")
    assert not bad, "\n".join(bad)
