"""A LIGGGHTS input read into the same step as its LAMMPS equivalent (no LIGGGHTS binary needed).

LIGGGHTS Hertz (``normal_model_hertz.h``) is LAMMPS ``pair_style granular hertz/material E eta nu`` with
``damping tsuji``: both give the force ``4/3 Y* a delta`` and a normal dashpot ``c sqrt(m* k)`` with
``k = 4/3 Y* a`` the secant stiffness -- LIGGGHTS ``2 sqrt(5/6) |beta| sqrt(2 Y* a m*) = sqrt(5) |beta| sqrt(k m*)``,
LAMMPS ``alpha(e_L) sqrt(k m*)`` with Tsuji's polynomial: the LAMMPS restitution ``e_L`` solving
``alpha(e_L) = sqrt(5) |beta(e)|`` (found here by mpmath) reproduces the dashpot.  The tangential dashpot
``mindlin NULL x`` with ``x = sqrt(S_t/S_n) = sqrt(2 (1 - nu)/(2 - nu))`` matches too, but LAMMPS
``granular`` uses the full radius for the slip velocity where LIGGGHTS (``surface_model_default.h``) uses
``R - delta/2``: with friction the arms differ, so the frictional case is checked against contacts
built here with LIGGGHTS's arms and terms computed in mpmath.
"""
from __future__ import annotations

import mpmath as mp
import numpy as np
import pytest

from dtcrit import audit_snapshot, read_snapshot
from dtcrit.packing.audit.run import Snapshot
from dtcrit.packing.conventions.engines import ENGINES, engine_sphere_contacts, with_arms
from support.paths import REPO_ROOT

DUMP = REPO_ROOT / "examples" / "packings" / "random_lognormal_60.dump"
YOUNG, NU = 5e7, 0.3
TSUJI = (1.2728, -4.2783, 11.087, -22.348, 27.467, -18.022, 4.8218)


def tsuji_restitution(e: float) -> str:
    """LAMMPS's ``e_L`` with ``alpha(e_L) = sqrt(5) |ln e|/sqrt(ln^2 e + pi^2)``, 17 digits."""
    with mp.workdps(40):
        log_e = mp.log(mp.mpf(e))
        target = mp.sqrt(5) * abs(log_e) / mp.sqrt(log_e**2 + mp.pi**2)
        root = mp.findroot(lambda x: sum(mp.mpf(c) * x**k for k, c in enumerate(TSUJI)) - target, 0.5)
        return mp.nstr(root, 17)


def _liggghts(tmp_path, e, mu):
    path = tmp_path / "in.liggghts"
    path.write_text(f"""fix m1 all property/global youngsModulus peratomtype {YOUNG!r}
fix m2 all property/global poissonsRatio peratomtype {NU!r}
fix m3 all property/global coefficientRestitution peratomtypepair 1 {e!r}
fix m4 all property/global coefficientFriction peratomtypepair 1 {mu!r}
pair_style gran model hertz tangential history
""")
    return path


@pytest.mark.parametrize("e", [1.0, 0.5, 0.9])
def test_frictionless_liggghts_equals_lammps_granular_tsuji(tmp_path, e):
    """Frictionless: the LIGGGHTS input and LAMMPS granular tsuji give one step (1e-12)."""
    lig = audit_snapshot(DUMP, engine="liggghts", liggghts_input=_liggghts(tmp_path, e, 0.0))
    eta = "0" if e == 1.0 else tsuji_restitution(e)
    damping = "velocity" if e == 1.0 else "tsuji"
    lmp = audit_snapshot(DUMP, pair_style=f"granular hertz/material {YOUNG!r} {eta} {NU!r} "
                                          f"tangential linear_nohistory 0 0 damping {damping}")
    assert lig.damped == (e < 1) and lmp.damped == (e < 1)
    assert abs(lig.dt_crit / lmp.dt_crit - 1) < 1e-12
    assert abs(lig.dt_undamped / lmp.dt_undamped - 1) < 1e-12


def _mp_terms(packing, contacts, e):
    """Per contact (one material): S_n, S_t, gamma_n, gamma_t, the force, from LIGGGHTS's formulas in mpmath."""
    with mp.workdps(30):
        return _mp_rows(packing, contacts, e)


def _mp_rows(packing, contacts, e):
    y, nu = mp.mpf(YOUNG), mp.mpf(NU)
    yeff = 1 / (2 * (1 - nu**2) / y)
    geff = 1 / (2 * 2 * (2 - nu) * (1 + nu) / y)
    log_e = mp.log(mp.mpf(e))
    beta = log_e / mp.sqrt(log_e**2 + mp.pi**2)
    rows = []
    for k in range(contacts.count):
        i, j = contacts.i[k], contacts.j[k]
        ri, rj, mi, mj = (mp.mpf(float(v)) for v in (packing.radii[i], packing.radii[j],
                                                      packing.masses[i], packing.masses[j]))
        delta = mp.mpf(float(contacts.overlap[k]))
        sqrtval = mp.sqrt(ri * rj / (ri + rj) * delta)
        meff = mi * mj / (mi + mj)
        sn, st = 2 * yeff * sqrtval, 8 * geff * sqrtval
        g = -2 * mp.sqrt(mp.mpf(5) / 6) * beta
        rows.append([sn, st, g * mp.sqrt(sn * meff), g * mp.sqrt(st * meff), mp.mpf(4) / 3 * yeff * sqrtval * delta])
    return np.array([[float(v) for v in r] for r in rows]).T


def test_frictional_damped_liggghts_equals_its_terms_with_liggghts_arms(tmp_path):
    """Frictional, damped: the same step as contacts built here with LIGGGHTS's arms and terms."""
    e = 0.5
    read = read_snapshot(DUMP, engine="liggghts", liggghts_input=_liggghts(tmp_path, e, 0.5))
    packing = read.packing
    contacts = engine_sphere_contacts(packing, ENGINES["liggghts"])
    contacts = with_arms(packing, contacts, "mid-overlap")
    kn, ks, cn, cs, fn = _mp_terms(packing, contacts, e)
    contacts = contacts.with_stiffness(kn, ks).with_damping(cn, cs).with_normal_force(fn)
    by_hand = Snapshot(str(DUMP), packing, contacts, ENGINES["liggghts"], "by hand")
    lig, ref = audit_snapshot(read), audit_snapshot(by_hand)
    assert lig.damped and abs(lig.dt_crit / ref.dt_crit - 1) < 1e-12
    assert abs(lig.dt_undamped / ref.dt_undamped - 1) < 1e-12


def test_with_friction_the_lammps_arms_differ(tmp_path):
    """The one difference from LAMMPS ``granular``: its full-radius slip velocity.  Recorded, not hidden."""
    lig = audit_snapshot(DUMP, engine="liggghts", liggghts_input=_liggghts(tmp_path, 1.0, 0.5))
    lmp = audit_snapshot(DUMP, pair_style=f"granular hertz/material {YOUNG!r} 0 {NU!r} tangential mindlin NULL 0 0.5 "
                                          "damping velocity")
    assert 1e-3 < lig.dt_crit / lmp.dt_crit - 1 < 0.05


def test_the_engine_tests_lammps_restitution_is_this_root():
    """``tests/engines/test_engine_liggghts_input.py`` writes e_L for e = 0.5 as a literal: it is this root."""
    assert tsuji_restitution(0.5) == "0.36665136156871792"
