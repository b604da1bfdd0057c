"""A LIGGGHTS input read into the same step as its LAMMPS equivalent, and that step against LAMMPS's threshold.

There is no LIGGGHTS binary here.  LIGGGHTS ``model hertz`` with ``coefficientFriction 0``
(``normal_model_hertz.h``: force ``4/3 Y* a delta``, dashpot ``-2 sqrt(5/6) beta sqrt(2 Y* a m*)``) is
LAMMPS ``pair_style granular hertz/material E e_L nu ... damping tsuji`` with ``alpha(e_L) = sqrt(5) |beta|``
(``tests/packing/audit/test_liggghts_lammps_equivalent.py``): the same force and dashpot on every contact.
With friction the two differ in the slip velocity's arm (LIGGGHTS ``R - delta/2``, LAMMPS ``R``), so
the engine case is frictionless.

The packing is LAMMPS's own (``support.engines.lammps_packing.compress``, Hertz), relaxed once more under
the damped law (frictionless packings keep residual motion otherwise, which the growth measure would
read as growth).  The kick is 1e-8 of the smallest radius: the damped critical mode sits on lightly
loaded contacts (overlaps down to 1e-4 R), which a larger kick opens before the growth shows.  Checks:
``dtcrit audit --liggghts-input`` equals ``--pair-style`` of the LAMMPS equivalent to 1e-12, and LAMMPS's
bisected threshold (relative bracket 1e-4) of the equivalent run puts the LIGGGHTS-read step within
[0.999, 1] of it, damped (e = 0.5) and elastic (e = 1).

Growth measure (``kinetic_growth``: largest kinetic energy over the initial one).  A bounded damped run
only loses energy (1.0 exactly, measured at 0.9999x and 1.0001x); above the threshold the growth stops
at a level that rises with the step, as the Hertz stiffness of the lightly loaded contacts changes with
the amplitude (after 20000 steps: 3.1 at 1.0003x, 115 at 1.001x, 832 at 1.002x, measured), so the damped
run counts as growing above 10.  An elastic run near its threshold keeps a large bounded response
(``support.engines.lammps_lattice``: ``1.3/sqrt(1 - dt/dt_c)``): its limit is the harness's 1e3.
"""
from __future__ import annotations

import json
import tempfile
from pathlib import Path

import pytest

from support.engines import require_engine
from support.engines.lammps_packing import PackingSpec, _data_file, _header, _read_dump, _run, compress, kinetic_growth

from dtcrit.cli import main

SPEC = PackingSpec(solid_fraction=0.66, seed=5, style="gran/hertz/history", kn=2e8, stiffness=2e4)
YOUNG, NU = 2.73e8, 0.3  # 4/3 Y* = 4/3 E/(2 (1 - nu^2)) = 2e8: the compression's own Hertz law
E_LAMMPS = {0.5: "0.36665136156871792"}  # alpha(e_L) = sqrt(5)|beta(0.5)| (mpmath, test_liggghts_lammps_equivalent)
EPS = 1e-8
RTOL = 1e-4
LIMIT = {0.5: 10.0, 1.0: 1e3}


def _lammps_style(e: float) -> str:
    if e == 1.0:
        return f"granular hertz/material {YOUNG!r} 0 {NU!r} tangential linear_nohistory 0 0 damping velocity"
    return f"granular hertz/material {YOUNG!r} {E_LAMMPS[e]} {NU!r} tangential linear_nohistory 0 0 damping tsuji"


def _liggghts_input(path: Path, e: float) -> Path:
    path.write_text("units si\natom_style granular\n"
                    f"fix m1 all property/global youngsModulus peratomtype {YOUNG!r}\n"
                    f"fix m2 all property/global poissonsRatio peratomtype {NU!r}\n"
                    f"fix m3 all property/global coefficientRestitution peratomtypepair 1 {e!r}\n"
                    "fix m4 all property/global coefficientFriction peratomtypepair 1 0.0\n"
                    "pair_style gran model hertz tangential history\npair_coeff * *\n")
    return path


@pytest.fixture(scope="module")
def relaxed(tmp_path_factory) -> str:
    """LAMMPS's Hertz packing, relaxed 40000 steps more under the damped equivalent law."""
    require_engine("lammps")
    dump = compress(SPEC, tmp_path_factory.mktemp("compress"))
    x, radii, masses, length = _read_dump(dump)
    script = _header(_lammps_style(0.5)) + [
        "fix integ all nve/sphere", "timestep 5e-6", "run 40000",
        "write_dump all custom packing.dump id type x y z radius mass modify format float %.17g"]
    with tempfile.TemporaryDirectory() as tmp:
        _run("\n".join(script) + "\n", {"case.data": _data_file(x, radii, masses, length, masses=True)}, Path(tmp))
        return (Path(tmp) / "packing.dump").read_text()


def _audit(capsys, *args: str) -> dict:
    assert main(["audit", *args, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def _threshold(dump: str, e: float, lo: float, hi: float, steps: int) -> float:
    def grows(dt: float) -> bool:
        return kinetic_growth(dump, _lammps_style(e), dt, steps, eps=EPS) > LIMIT[e]

    assert not grows(lo) and grows(hi), "threshold not bracketed"
    while hi - lo > RTOL * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if grows(mid) else (mid, hi)
    return 0.5 * (lo + hi)


@pytest.mark.parametrize("e, steps", [(0.5, 20000), (1.0, 3000)])
def test_liggghts_input_reads_the_lammps_equivalent_step(e, steps, relaxed, capsys, tmp_path):
    """Same step as the LAMMPS equivalent; within [0.999, 1] of LAMMPS's bisected threshold."""
    dump = tmp_path / "packing.dump"
    dump.write_text(relaxed)
    liggghts = _audit(capsys, str(dump), "--engine", "liggghts", "--liggghts-input",
                      str(_liggghts_input(tmp_path / "in.liggghts", e)))
    lammps = _audit(capsys, str(dump), "--pair-style", _lammps_style(e))
    dt = liggghts["dt_crit"]
    assert liggghts["damped"] == (e < 1) and abs(dt / lammps["dt_crit"] - 1) < 1e-12
    threshold = _threshold(relaxed, e, 0.999 * dt, 1.01 * dt, steps)
    print(f"e={e}: LIGGGHTS-read dt_crit {dt:.9e}, LAMMPS threshold {threshold:.9e}, ratio {dt / threshold:.6f}")
    assert 0.999 <= dt / threshold <= 1.0 + RTOL
