"""LAMMPS (real engine) agrees with `dtcrit packing`'s critical step of periodic sphere lattices.

Cases: simple cubic (4 x 4 x 4 cells, 64 spheres), BCC and FCC (2 x 2 x 2 cells, 16 and 32
spheres) of equal spheres at ks/kn = 0, 0.1, 2/7 and 1, run by ``support.engines.lammps_lattice``
(periodic box, neighbours at a uniform overlap of 1e-6 R, gran/hooke/history, fix nve/sphere).
dtcrit predicts each step with its own global eigen-analysis of the same lattice
(``dtcrit.packing.analyse`` of ``dtcrit.packing.lattice``: the step ``dtcrit packing --lattice
NAME --cells N --kn KN --ks KS`` prints, checked once against the command itself).

Checks, LAMMPS being the reference:
  * every case is bounded at 0.99x and grows at 1.01x of dtcrit's step;
  * each case's threshold extrapolated from LAMMPS's growth rates just above it
    (``extrapolated_threshold``) equals dtcrit's step to 2e-6, and two bisected thresholds bracket
    it within the bisection's resolution;
  * the geometric stiffness of the pre-loaded contacts: SC and BCC with ks = 0 are mechanisms,
    and the compressive contact force, turning with the centre line, makes their floppy modes
    buckle at any step.  LAMMPS's BCC lattice grows at the rate dtcrit's stiffness with that term
    (``Contacts.with_normal_force``) predicts, ``sqrt(-lambda_min(M^-1 (K + K_geo)))``, here
    ``2 sqrt(overlap kn / m)`` for both SC and BCC: an e-folding of 500-600 steps at dt_crit and
    1e-6 R, so the 2000-step bounded runs stay short of where it would matter;
  * the overlap's conventions, at 1e-2 R: with LAMMPS's full-radius arm and the pre-load's
    geometric stiffness dtcrit's step is LAMMPS's threshold to 1e-6, while the mid-overlap arm
    without the pre-load term (dtcrit's own contact convention) is 0.5 % above it on FCC at
    ks = kn (a rotational top mode: unsafe) and 0.4 % below it on BCC at ks = 0.1.  At the
    1e-6 R of the other cases both effects are below 1e-6.
"""
from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest

from support.engines import require_engine
from support.engines.lammps import ContactLaw, Sphere
from support.engines.lammps_lattice import (LatticeCase, bisect_threshold, extrapolated_threshold, run_case,
                                           run_many)

R, RHO, KN = 1.0e-3, 2500.0, 1.0e5
SPHERE = Sphere(radius=R, density=RHO)
CELLS = {"sc": 4, "bcc": 2, "fcc": 2}
RATIOS = {"0": 0.0, "0.1": 0.1, "2/7": 2.0 / 7.0, "1": 1.0}
STEPS = 2000  # 0.99x: bounded runs of ~1000 periods; 1.01x halts within ~30 steps
CASES = [(f"{name}-ks/kn={key}", name, ratio) for name in CELLS for key, ratio in RATIOS.items()]


def lattice_case(name: str, ratio: float) -> LatticeCase:
    return LatticeCase(ContactLaw(KN, kt=ratio * KN), name, CELLS[name], SPHERE)


def dtcrit_step(name: str, ratio: float) -> float:
    """dtcrit's critical velocity-Verlet step of the lattice (its global eigen-analysis)."""
    from dtcrit.packing import LinearLaw, analyse, lattice

    report = analyse(lattice(name, CELLS[name], radius=R, density=RHO), LinearLaw(KN, ratio * KN),
                     integrator="velocity-verlet")
    return report.dt_integrator


def _overlapped(name: str, ratio: float, case: LatticeCase):
    """dtcrit's packing and contacts of `case`'s lattice at its overlap (centres 2R - delta0 apart)."""
    from dtcrit.packing import Box, LinearLaw, Packing, apply_law, find_contacts, lattice

    touching = lattice(name, case.cells, radius=R, density=RHO)
    shrink = case.spacing / (2.0 * R)
    packing = Packing.spheres(touching.positions * shrink, R, density=RHO,
                              box=Box(touching.box.lo * shrink, touching.box.hi * shrink, (True,) * 3))
    contacts = apply_law(find_contacts(packing), LinearLaw(KN, ratio * KN))
    assert contacts.overlap == pytest.approx(np.full(contacts.count, case.delta0), rel=1e-6)
    return packing, contacts


@pytest.fixture(scope="module")
def lmp() -> str:
    return require_engine("lammps")


@pytest.fixture(scope="module")
def checks(lmp):
    """Every case at 0.99x and 1.01x of dtcrit's step, two lmp at a time."""
    dts = {cid: dtcrit_step(name, ratio) for cid, name, ratio in CASES}
    jobs = [(lattice_case(name, ratio), f * dts[cid], STEPS) for cid, name, ratio in CASES for f in (0.99, 1.01)]
    runs = run_many(jobs, workers=2, lmp=lmp)
    return {cid: (dts[cid], runs[2 * k], runs[2 * k + 1]) for k, (cid, _, _) in enumerate(CASES)}


@pytest.mark.parametrize("cid", [c[0] for c in CASES])
def test_lammps_bounded_below_and_grows_above_dtcrit(checks, cid):
    dt, below, above = checks[cid]
    assert below.contacts_kept, f"{cid}: contacts per atom went {below.contacts_min}..{below.contacts_max}"
    assert below.bounded, (f"{cid}: LAMMPS grows at 0.99x dtcrit's {dt:.6e}: growth={below.growth:.3g}, "
                           f"window={below.window_growth:.3g}, halted={below.halted}")
    assert not above.bounded and above.halted and above.rate > 1.1, (
        f"{cid}: LAMMPS does not grow at 1.01x dtcrit's {dt:.6e}: growth={above.growth:.3g}, rate={above.rate}")


@pytest.mark.parametrize("cid, name, ratio", [pytest.param(*c, id=c[0]) for c in CASES])
def test_lammps_threshold_from_growth_rates_equals_dtcrit(lmp, cid, name, ratio):
    """Undamped: the critical pair leaves the unit circle as (ln z)^2 = 8 (dt/dt_c - 1)."""
    dt = dtcrit_step(name, ratio)
    trial = [dt * (1 + e) for e in (2e-5, 5e-5, 1e-4, 2e-4)]
    threshold, runs = extrapolated_threshold(lattice_case(name, ratio), trial, lmp=lmp)
    slopes = [math.log(r.rate) ** 2 / (r.dt / dt - 1.0) for r in runs]
    assert slopes == pytest.approx([8.0] * 4, rel=0.05), slopes  # the undamped onset, as assumed
    assert dt / threshold == pytest.approx(1.0, abs=2e-6), f"{cid}: dtcrit / LAMMPS = {dt / threshold:.8f}"


@pytest.mark.parametrize("name, ratio", [("sc", 0.0), ("fcc", 1.0)])
def test_lammps_bisected_threshold_brackets_dtcrit(lmp, name, ratio):
    """A bisection's bracket (4000-step runs, detection limit ~ (ln 10 / 4000)^2 ~ 3e-7) holds dtcrit's step."""
    dt = dtcrit_step(name, ratio)
    lo, hi = bisect_threshold(lattice_case(name, ratio), 0.99 * dt, 1.013 * dt, 1e-5, steps=4000, lmp=lmp)
    assert lo * (1 - 1e-6) <= dt <= hi * (1 + 1e-6), f"dtcrit {dt:.8e} outside LAMMPS's [{lo:.8e}, {hi:.8e}]"


def test_bcc_mechanism_buckles_at_the_geometric_stiffness_rate(lmp):
    """BCC, ks = 0, at half dtcrit's step: LAMMPS's kinetic energy grows as exp(2 lambda t) with
    lambda^2 = -lambda_min(M^-1 (K + K_geo)), K_geo from the contacts' normal force kn*delta0."""
    from dtcrit.packing import stiffness_matrix
    from dtcrit.packing.operators.assembly import mass_diagonal

    case = LatticeCase(ContactLaw(KN, kt=0.0), "bcc", CELLS["bcc"], SPHERE)
    packing, contacts = _overlapped("bcc", 0.0, case)
    contacts = contacts.with_normal_force(KN * contacts.overlap)
    scale = 1.0 / np.sqrt(mass_diagonal(packing))
    a = stiffness_matrix(packing, contacts).toarray() * scale[:, None] * scale[None, :]
    lowest = float(np.linalg.eigvalsh(a)[0])
    assert lowest < 0.0
    predicted = math.sqrt(-lowest)

    dt = 0.5 * dtcrit_step("bcc", 0.0)
    run = run_case(case, dt, 20000, kick=1e-7, lmp=lmp)
    t = run.series["step"] * dt
    log_amp = 0.5 * np.log(run.series["etot"] / run.series["etot"][0])
    late = (log_amp > 5.0) & (log_amp < 10.0)  # after the slower modes die out, before the contacts open
    assert late.sum() > 100
    measured = float(np.polyfit(t[late], log_amp[late], 1)[0])
    assert measured == pytest.approx(predicted, rel=2e-3)
    # without the pre-load term dtcrit's K has no negative eigenvalue: the buckling is K_geo alone
    plain = stiffness_matrix(packing, contacts.with_normal_force(0.0)).toarray() * scale[:, None] * scale[None, :]
    assert np.linalg.eigvalsh(plain)[0] > -1e-3 * predicted**2


@pytest.mark.parametrize("name, ratio, mid_arm_error", [
    ("fcc", 1.0, 0.005),  # rotational top mode: the arm matters (R^2 / I -> R (R - delta/2) / I)
    ("bcc", 0.1, -0.0042),  # translational top mode: the pre-load's softening matters
])
def test_lammps_conventions_at_a_one_percent_overlap(lmp, name, ratio, mid_arm_error):
    """At overlap 1e-2 R the conventions show: dtcrit with LAMMPS's full-radius arm and the
    pre-load's geometric stiffness gives LAMMPS's threshold to 1e-6; the mid-overlap arm without
    the pre-load term (dtcrit's default on a snapshot) is off by about delta0 / (2R)."""
    from dataclasses import replace

    from dtcrit.packing import analyse

    case = LatticeCase(ContactLaw(KN, kt=ratio * KN), name, CELLS[name], SPHERE, overlap=1e-2)
    packing, contacts = _overlapped(name, ratio, case)
    full = replace(contacts, arm_i=R * contacts.normal, arm_j=-R * contacts.normal)
    lammps_like = analyse(packing, contacts=full.with_normal_force(KN * contacts.overlap), with_estimates=False)
    default = analyse(packing, contacts=contacts, with_estimates=False)
    dt = lammps_like.dt_integrator
    threshold, _ = extrapolated_threshold(case, [dt * (1 + e) for e in (2e-5, 5e-5, 1e-4, 2e-4)], lmp=lmp)
    assert dt / threshold == pytest.approx(1.0, abs=1e-6)
    assert default.dt_integrator / threshold - 1.0 == pytest.approx(mid_arm_error, abs=3e-4)


def test_dtcrit_packing_command_prints_the_step_used():
    """The step used above is the one `dtcrit packing --lattice ... --json` prints."""
    out = subprocess.run(
        [sys.executable, "-m", "dtcrit", "packing", "--lattice", "bcc", "--cells", "2", "--kn", repr(KN),
         "--ks", repr(0.1 * KN), "--radius", repr(R), "--density", repr(RHO), "--json"],
        capture_output=True, text=True, check=True,
    )
    assert json.loads(out.stdout)["dt_integrator"] == pytest.approx(dtcrit_step("bcc", 0.1), rel=1e-12)
