"""Density scaling under laws whose dashpots the engine recomputes from the masses every step.

LAMMPS ``gran/*`` applies ``c_n = m_eff gamma_n`` (``pair_gran_hooke_history.cpp``), ``granular ...
damping tsuji`` ``alpha(e) sqrt(m_eff k)`` (``pair_granular.cpp``): a plan that kept the dashpots of the
unscaled masses promised a step the scaled packing does not have (the written dump's audit gave
8.246e-06 s for a promised 1.000135e-05 s).  Checked here independently of the planner:

* the ``--write-dump`` file read back as ``dtcrit audit`` reads it, its dashpots compared with
  ``gamma_n m_eff`` computed here from the file's masses, and the lagged central difference's
  condition ``4 M - 2h C - h^2 K > 0`` at the target by a dense ``scipy.linalg.eigh``;
* ``dtcrit audit`` of the written dump (the command line) at or above the target;
* for ``tsuji`` (every dashpot ``~ sqrt(m)``, springs fixed) the uniform factor is ``(target / dt_now)^2``
  exactly: ``lambda_max(2h sqrt(f) C + h^2 K, f M) = lambda_max(2 (h/sqrt(f)) C + (h/sqrt(f))^2 K, M)``.
"""
from __future__ import annotations

import json
import math
import os

import jsonschema
import numpy as np
import pytest
import scipy.linalg as sla

from dtcrit.cli import main
from dtcrit.packing.audit.run import audit_snapshot, read_snapshot
from dtcrit.packing.operators.assembly import damping_matrix, mass_diagonal, stiffness_matrix
from dtcrit.plan import plan_density_scaling
from dtcrit.plan.density import CONFIRM_MARGIN
from support.paths import REPO_ROOT as ROOT

EXAMPLE = str(ROOT / "examples" / "packings" / "random_lognormal_60.dump")
SCHEMA = json.loads((ROOT / "src" / "dtcrit" / "schemas" / "dtcrit-plan-1.json").read_text())
HOOKE_DAMPED = "gran/hooke/history 1e5 NULL 2e4 NULL 0.5 1"
HERTZ_DAMPED = "gran/hertz/history 1e9 NULL 2e8 NULL 0.5 1"
TSUJI = "granular hooke 1e5 0.5 tangential linear_history 2e4 1 0.5 damping tsuji"
#: (pair style, gamma_n of c_n = m_eff gamma_n [1/s] for hooke, None otherwise, target [s] or a multiple of dt_now)
CASES = {"hooke-damped": (HOOKE_DAMPED, 2e4, 1e-5), "hertz-damped": (HERTZ_DAMPED, None, 2.0),
         "tsuji": (TSUJI, None, 2.0)}


def _run(capsys, *argv):
    try:
        code = main(list(argv))
    except SystemExit as exc:
        code = exc.code
    out, err = capsys.readouterr()
    return code, out, err


def _target(style: str, spec: float) -> float:
    return spec if spec < 1e-3 else spec * audit_snapshot(EXAMPLE, pair_style=style).dt_crit


def _lagged_stable(snapshot, h: float) -> bool:
    """``4 M - 2h C - h^2 K`` positive definite, dense (the snapshot's own masses and dashpots)."""
    k = stiffness_matrix(snapshot.packing, snapshot.contacts).toarray()
    c = damping_matrix(snapshot.packing, snapshot.contacts).toarray()
    s = 1.0 / np.sqrt(mass_diagonal(snapshot.packing))
    a = 4.0 * np.eye(k.shape[0]) - s[:, None] * (2.0 * h * c + h * h * k) * s[None, :]
    return bool(sla.eigh(a, eigvals_only=True)[0] > 0)


@pytest.mark.parametrize("case", sorted(CASES))
def test_written_dump_meets_the_target_with_its_own_dashpots(case, capsys, tmp_path):
    """The scaled dump, with the dashpots its masses give, is stable at the target (dense) and its audit agrees."""
    style, gamma_n, spec = CASES[case]
    target = _target(style, spec)
    dump = tmp_path / "scaled.dump"
    code, out, err = _run(capsys, "plan", EXAMPLE, "--pair-style", style, "--target-dt", repr(target), "--json",
                          "--write-dump", str(dump))
    assert code == 0, err
    doc = json.loads(out)
    jsonschema.validate(doc, SCHEMA)
    d = doc["density_scaling"]
    assert d["dt_crit_scaled"] >= target * (1.0 + CONFIRM_MARGIN)
    scaled = read_snapshot(dump, pair_style=style)
    if gamma_n is not None:  # the reader's dashpot is m_eff gamma_n of the file's (scaled) masses
        m = scaled.packing.masses
        m_eff = m[scaled.contacts.i] * m[scaled.contacts.j] / (m[scaled.contacts.i] + m[scaled.contacts.j])
        np.testing.assert_allclose(scaled.contacts.cn, gamma_n * m_eff, rtol=1e-13)
    assert _lagged_stable(scaled, target)
    code, out, err = _run(capsys, "audit", str(dump), "--pair-style", style, "--json")
    assert code == 0, err
    audit_dt = json.loads(out)["dt_crit"]
    assert audit_dt >= target
    assert audit_dt == pytest.approx(d["dt_crit_scaled"], rel=1e-9)


def test_fixed_dashpots_would_have_missed_the_target(tmp_path):
    """The repro: the plan's factors with the dashpots of the unscaled masses look stable, with their own they need more.

    With c_n fixed at the unscaled m_eff gamma_n the planned factors would pass; the real dashpots at the
    scaled masses are larger, and the same condition with them is checked on the dump written.
    """
    plan = plan_density_scaling(EXAMPLE, 1e-5, pair_style=HOOKE_DAMPED)
    original = read_snapshot(EXAMPLE, pair_style=HOOKE_DAMPED)
    from dtcrit.plan.dump import write_scaled_dump

    path = tmp_path / "scaled.dump"
    write_scaled_dump(path, original.packing, plan.factors, plan.free)
    scaled = read_snapshot(path, pair_style=HOOKE_DAMPED)
    assert np.all(scaled.contacts.cn >= original.contacts.cn * (1 - 1e-12))
    assert scaled.contacts.cn.sum() > 1.5 * original.contacts.cn.sum()
    assert _lagged_stable(scaled, 1e-5)


def test_tsuji_uniform_factor_is_the_square_of_the_step_ratio():
    """Every dashpot ~ sqrt(m_eff), springs fixed: the uniform factor is (target / dt_now)^2 (module docstring)."""
    dt_now = audit_snapshot(EXAMPLE, pair_style=TSUJI).dt_crit
    target = 2.0 * dt_now
    plan = plan_density_scaling(EXAMPLE, target, pair_style=TSUJI)
    assert plan.uniform_factor == pytest.approx((target / dt_now) ** 2, rel=2e-5)


def test_hooke_with_mindlin_tangential_is_not_hertz(capsys):
    """A granular hooke law with tangential mindlin: the normal law is linear (no Hertz modulus factors)."""
    style = "granular hooke 1e5 0 tangential mindlin 1e3 1 0.5 damping velocity"
    target = 2.0 * audit_snapshot(EXAMPLE, pair_style=style).dt_crit
    code, out, err = _run(capsys, "plan", EXAMPLE, "--pair-style", style, "--target-dt", repr(target), "--json")
    assert code == 0, err
    s = json.loads(out)["stiffness_reduction"]
    assert s["hertz"] is False and s["modulus_factor_impact"] is None


def _restitution_min(snapshot, gamma_n: float) -> float:
    """The smallest linear restitution exp(-pi zeta / sqrt(1 - zeta^2)), zeta = gamma_n m_eff / (2 sqrt(m_eff kn))."""
    m = snapshot.packing.masses
    i, j = snapshot.contacts.i, snapshot.contacts.j
    m_eff = m[i] * m[j] / (m[i] + m[j])
    zeta = gamma_n * m_eff / (2.0 * np.sqrt(m_eff * snapshot.contacts.kn))
    return float(np.min(np.exp(-math.pi * zeta / np.sqrt(1.0 - zeta**2))))


def test_damped_linear_contacts_get_a_collision_resolution(capsys):
    """--velocity with m_eff gamma_n dashpots: N_res of the most damped contact's restitution, not silence."""
    from dtcrit.collisions import resolution_step

    style, gamma_n = "gran/hooke/history 1e5 NULL 500 NULL 0.5 1", 500.0
    target = 2.0 * audit_snapshot(EXAMPLE, pair_style=style).dt_crit
    code, out, err = _run(capsys, "plan", EXAMPLE, "--pair-style", style, "--target-dt", repr(target),
                          "--velocity", "0.3", "--json")
    assert code == 0, err
    doc = json.loads(out)
    jsonschema.validate(doc, SCHEMA)
    c = doc["collisions"]
    e = _restitution_min(read_snapshot(EXAMPLE, pair_style=style), gamma_n)
    n_res = resolution_step(engine="lammps", normal="hooke", damping="lammps-mass-velocity",
                            restitution=e).steps_per_collision
    assert c["resolution_assessed"] is True
    assert c["resolution_steps"] == pytest.approx(n_res, rel=1e-12)
    assert c["resolution_dt_now"] == pytest.approx(c["contact_time_now"] / n_res, rel=1e-12)


def test_damped_hertz_resolution_is_said_not_assessed(capsys):
    """A damped Hertz law has no mapped collision model here: a warning says so."""
    target = 2.0 * audit_snapshot(EXAMPLE, pair_style=HERTZ_DAMPED).dt_crit
    code, out, err = _run(capsys, "plan", EXAMPLE, "--pair-style", HERTZ_DAMPED, "--target-dt", repr(target),
                          "--velocity", "0.3", "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["collisions"]["resolution_assessed"] is False and doc["collisions"]["resolution_steps"] is None
    assert any("not assessed" in w for w in doc["warnings"])


@pytest.mark.parametrize("how", ["same", "dotted", "symlink"])
def test_write_dump_onto_the_snapshot_is_refused(capsys, tmp_path, how):
    """--write-dump naming the snapshot itself (by any path): one line, exit 2, the file untouched."""
    snap = tmp_path / "in.dump"
    snap.write_bytes(open(EXAMPLE, "rb").read())
    target = {"same": snap, "dotted": tmp_path / "." / "in.dump", "symlink": tmp_path / "link.dump"}[how]
    if how == "symlink":
        os.symlink(snap, target)
    before = snap.read_bytes()
    code, out, err = _run(capsys, "plan", str(snap), "--pair-style", HOOKE_DAMPED, "--target-dt", "1e-5",
                          "--write-dump", str(target))
    assert code == 2 and err.count("\n") == 1 and "--write-dump" in err and "snapshot itself" in err
    assert snap.read_bytes() == before


def test_gravity_warning_says_both_ways(capsys):
    """YADE's densityScaling keeps the weight (falls at g/f); the plan applied as masses scales the weight."""
    target = 1e-5
    code, out, err = _run(capsys, "plan", EXAMPLE, "--pair-style", HOOKE_DAMPED, "--target-dt", repr(target),
                          "--gravity", "9.81", "--json")
    assert code == 0, err
    (text,) = [w for w in json.loads(out)["warnings"] if w.startswith("gravity")]
    assert "falls at g/" in text and "still falls at g" in text and "state.mass" in text


def test_wall_dashpots_grow_with_the_particle_mass(capsys, tmp_path):
    """A wall/gran fix with gamma_n (meff = m of the particle): the written dump's audit with the same --wall meets the target."""
    snap = tmp_path / "walled.dump"
    snap.write_text(open(EXAMPLE).read().replace("BOX BOUNDS pp pp pp", "BOX BOUNDS pp pp ff"))
    wall = "fix 2 all wall/gran hooke/history 1e5 NULL 2e4 NULL 0.5 1 zplane -0.0005 NULL"
    dump = tmp_path / "scaled.dump"
    code, out, err = _run(capsys, "plan", str(snap), "--pair-style", HOOKE_DAMPED, "--wall", wall,
                          "--target-dt", "1e-5", "--json", "--write-dump", str(dump))
    assert code == 0, err
    planned = json.loads(out)["density_scaling"]["dt_crit_scaled"]
    code, out, err = _run(capsys, "audit", str(dump), "--pair-style", HOOKE_DAMPED, "--wall", wall, "--json")
    assert code == 0, err
    assert json.loads(out)["dt_crit"] >= 1e-5
    assert json.loads(out)["dt_crit"] == pytest.approx(planned, rel=1e-9)


def test_liggghts_hooke_uniform_factor_follows_its_mass_dependent_stiffness(tmp_path):
    """LIGGGHTS hooke: kn ~ m_eff^(1/5) (characteristicVelocity), c ~ sqrt(m_eff kn) ~ m_eff^(3/5), so a
    uniform f gives lambda_max(2h f^-2/5 C + h^2 f^-4/5 K, M): the step grows as f^(2/5) and the uniform
    factor is (target / dt_now)^(5/2).
    """
    rows = [(1, 1, 0.05, 0.05, 0.05, 1e-3, 1e-5), (2, 1, 0.05 + 1.9e-3, 0.05, 0.05, 1e-3, 1.3e-5),
            (3, 1, 0.05 + 1.9e-3, 0.05 + 1.9e-3, 0.05, 1e-3, 0.8e-5)]
    dump = tmp_path / "p.dump"
    dump.write_text("\n".join(["ITEM: TIMESTEP", "0", "ITEM: NUMBER OF ATOMS", "3", "ITEM: BOX BOUNDS ff ff ff",
                               "0.0 0.1", "0.0 0.1", "0.0 0.1", "ITEM: ATOMS id type x y z radius mass",
                               *(" ".join(str(v) for v in r) for r in rows)]) + "\n")
    script = tmp_path / "in.liggghts"
    script.write_text("\n".join(["atom_style granular",
                                 "fix m1 all property/global youngsModulus peratomtype 6e7",
                                 "fix m2 all property/global poissonsRatio peratomtype 0.3",
                                 "fix m3 all property/global coefficientRestitution peratomtypepair 1 0.6",
                                 "fix m4 all property/global coefficientFriction peratomtypepair 1 0.5",
                                 "fix m5 all property/global characteristicVelocity scalar 2.0",
                                 "pair_style gran model hooke tangential history", "pair_coeff * *"]) + "\n")
    dt_now = audit_snapshot(dump, liggghts_input=script).dt_crit
    plan = plan_density_scaling(dump, 2.0 * dt_now, liggghts_input=script)
    assert plan.uniform_factor == pytest.approx(2.0**2.5, rel=2e-5)
    assert plan.dt_crit_scaled >= 2.0 * dt_now * (1.0 + CONFIRM_MARGIN)
