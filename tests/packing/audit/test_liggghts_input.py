"""``dtcrit audit --liggghts-input``: LIGGGHTS's mixing, springs and dashpots per atom-type pair, against
literals computed here in mpmath from the formulas of LIGGGHTS-PUBLIC ``src/`` (``global_properties.cpp``
``createYeff``/``createGeff``/``createBetaEff``; ``normal_model_hertz.h``, ``normal_model_hooke.h``,
``tangential_model_history.h``, ``rolling_model_epsd*.h``), and the refusals (one line naming FILE:LINE).

The same-step checks against the LAMMPS equivalents are in ``test_liggghts_lammps_equivalent.py``; the
real-engine check in ``tests/engines/test_engine_liggghts_input.py``.
"""
from __future__ import annotations

import mpmath as mp
import numpy as np
import pytest

from dtcrit import read_snapshot
from dtcrit.cli import main

# (id, type, x, y, z, R, m): A(1)-B(2) along x, B(2)-C(2) along y; ids out of order in the file
RA, RB, RC = 1.0e-3, 1.2e-3, 0.8e-3
MA, MB, MC = 1.1e-5, 1.9e-5, 0.6e-5
DAB, DBC = RA + RB - 2.3e-5, RB + RC - 1.7e-5
ROWS = [(5, 2, 0.05 + DAB, 0.05, 0.05, RB, MB), (2, 1, 0.05, 0.05, 0.05, RA, MA),
        (9, 2, 0.05 + DAB, 0.05 + DBC, 0.05, RC, MC)]
Y, NU = (6e7, 2.5e8), (0.25, 0.4)
E = ((0.9, 0.6), (0.6, 0.3))
MU = ((0.5, 0.3), (0.3, 0.0))  # the 2-2 pair is frictionless: no tangential terms there
MUR = ((0.2, 0.1), (0.1, 0.05))
ETAR = ((0.3, 0.2), (0.2, 0.1))


def _dump(tmp_path, rows=ROWS):
    lines = ["ITEM: TIMESTEP", "0", "ITEM: NUMBER OF ATOMS", str(len(rows)), "ITEM: BOX BOUNDS ff ff ff",
             "0.0 0.1", "0.0 0.1", "0.0 0.1", "ITEM: ATOMS id type x y z radius mass"]
    lines += [" ".join(repr(v) if isinstance(v, float) else str(v) for v in row) for row in rows]
    path = tmp_path / "p.dump"
    path.write_text("\n".join(lines) + "\n")
    return path


def _pair(name, m):
    return f"fix {name} all property/global {name} peratomtypepair 2 " + " ".join(repr(v) for r in m for v in r)


def _input(tmp_path, style, *extra, materials=True):
    lines = ["# a LIGGGHTS script", "atom_style granular", "variable Yb equal 2.5e8"]
    if materials:
        lines += ["fix m1 all property/global youngsModulus peratomtype 6e7 ${Yb}",
                  "fix m2 all property/global poissonsRatio peratomtype 0.25 &", "   0.4",
                  _pair("coefficientRestitution", E), _pair("coefficientFriction", MU)]
    lines += [*extra, f"pair_style {style}", "pair_coeff * *", "run 1000"]
    path = tmp_path / "in.liggghts"
    path.write_text("\n".join(lines) + "\n")
    return path


def _expected(law, **kw):
    """Per contact (keyed by the ids), the terms from LIGGGHTS's formulas in mpmath (30 digits)."""
    with mp.workdps(30):
        return _expected_mp(law, **kw)


def _expected_mp(law, tangential="history", rolling=None, v_char=None, kt_factor=1, torsion=False):
    out = {}
    pos = {r[0]: (mp.mpf(r[2]), mp.mpf(r[3]), mp.mpf(r[4])) for r in ROWS}
    for a, b in ((2, 5), (5, 9)):
        ra, rb = (next(r for r in ROWS if r[0] == k) for k in (a, b))
        ti, tj = ra[1] - 1, rb[1] - 1
        d = mp.sqrt(sum((p - q) ** 2 for p, q in zip(pos[a], pos[b])))
        ri, rj, mi, mj = mp.mpf(ra[5]), mp.mpf(rb[5]), mp.mpf(ra[6]), mp.mpf(rb[6])
        delta, reff, meff = ri + rj - d, ri * rj / (ri + rj), mi * mj / (mi + mj)
        yi, yj, vi, vj = mp.mpf(Y[ti]), mp.mpf(Y[tj]), mp.mpf(NU[ti]), mp.mpf(NU[tj])
        yeff = 1 / ((1 - vi**2) / yi + (1 - vj**2) / yj)
        geff = 1 / (2 * (2 - vi) * (1 + vi) / yi + 2 * (2 - vj) * (1 + vj) / yj)
        log_e = mp.log(mp.mpf(E[ti][tj]))
        beta = log_e / mp.sqrt(log_e**2 + mp.pi**2)
        if law == "hertz":
            sqrtval = mp.sqrt(reff * delta)
            sn, st = 2 * yeff * sqrtval, 8 * geff * sqrtval
            kn_lig, kt = mp.mpf(4) / 3 * yeff * sqrtval, st
            gn = -2 * mp.sqrt(mp.mpf(5) / 6) * beta * mp.sqrt(sn * meff)
            gt = -2 * mp.sqrt(mp.mpf(5) / 6) * beta * mp.sqrt(st * meff)
            tangent = sn
        else:
            v = mp.mpf(v_char)
            kn_lig = mp.mpf(16) / 15 * mp.sqrt(reff) * yeff * (15 * meff * v * v / (16 * mp.sqrt(reff) * yeff)) ** 0.2
            kt, tangent = kn_lig * kt_factor, kn_lig
            gn = gt = mp.sqrt(4 * meff * kn_lig * log_e**2 / (log_e**2 + mp.pi**2))
        sticking = MU[ti][tj] > 0
        t = {"kn": tangent, "cn": gn, "force_n": kn_lig * delta,
             "ks": kt if sticking and tangential == "history" else 0, "cs": gt if sticking else 0}
        if rolling in ("epsd", "epsd3"):
            f = mp.mpf("2.25") if rolling == "epsd" else mp.mpf("1.7")
            kr = f * kn_lig * mp.mpf(MUR[ti][tj]) ** 2 * reff**2
            i_i, i_j = mi * ri**2, mj * rj**2
            t["kr"], t["cr"] = kr, mp.mpf(ETAR[ti][tj]) * 2 * mp.sqrt(mp.mpf("1.4") * i_i * i_j / (i_i + i_j) * kr)
        elif rolling == "epsd2":
            t["kr"], t["cr"] = kt * reff**2, 0
        if torsion:
            t["ktw"], t["ctw"] = t["kr"], t["cr"]
        out[(a, b)] = t
    return out


def _check(snapshot, expected):
    c, p = snapshot.contacts, snapshot.packing
    assert c.count == 2
    for k in range(c.count):
        key = tuple(sorted((int(p.particle_id(c.i[k])), int(p.particle_id(c.j[k])))))
        for name, want in expected[key].items():
            got = float(getattr(c, name)[k])
            assert abs(got - float(want)) <= 1e-12 * abs(float(want)), (key, name, got, float(want))


def test_hertz_history_mixing_and_dashpots(tmp_path):
    """Two types: Y*, G*, beta mixed per pair; S_n, S_t, both dashpots and the force per contact."""
    s = read_snapshot(_dump(tmp_path), engine="liggghts",
                      liggghts_input=_input(tmp_path, "gran model hertz tangential history"))
    _check(s, _expected("hertz"))
    assert s.convention.name == "liggghts" and "materials per atom type" in s.law


def test_hertz_mid_overlap_arms(tmp_path):
    """surface_model_default.h: cri = radi - 0.5 deltan for the slip velocity and the torque."""
    s = read_snapshot(_dump(tmp_path), liggghts_input=_input(tmp_path, "gran model hertz tangential history"))
    c, p = s.contacts, s.packing
    for arm, r in ((c.arm_i, p.radii[c.i]), (c.arm_j, p.radii[c.j])):
        assert np.allclose(np.linalg.norm(arm, axis=1), r - 0.5 * c.overlap, rtol=1e-15, atol=0)


def test_tangential_damping_off_and_no_history(tmp_path):
    """``tangential_damping off`` drops gamma_t; ``no_history`` keeps the dashpot only."""
    off = read_snapshot(_dump(tmp_path), liggghts_input=_input(
        tmp_path, "gran model hertz tangential history tangential_damping off"))
    exp = _expected("hertz")
    for t in exp.values():
        t["cs"] = 0
    _check(off, exp)
    no_hist = read_snapshot(_dump(tmp_path), liggghts_input=_input(tmp_path, "gran model hertz tangential no_history"))
    _check(no_hist, _expected("hertz", tangential="no_history"))


@pytest.mark.parametrize("kt_user", [False, True])
def test_hooke(tmp_path, kt_user):
    """``model hooke``: the characteristic-velocity spring, k_t = k_n (or 0.285714286 k_n), gamma_t = gamma_n."""
    style = "gran model hooke tangential history" + (" ktToKnUser on" if kt_user else "")
    s = read_snapshot(_dump(tmp_path), liggghts_input=_input(
        tmp_path, style, "fix cv all property/global characteristicVelocity scalar 1.5"))
    _check(s, _expected("hooke", v_char=1.5, kt_factor=mp.mpf("0.285714286") if kt_user else 1))


@pytest.mark.parametrize("model, torsion", [("epsd", False), ("epsd2", False), ("epsd3", True)])
def test_rolling_models(tmp_path, model, torsion):
    """EPSD, EPSD2, EPSD3 rolling springs and dashpots per type pair (``torsionTorque on``: also twisting)."""
    style = f"gran model hertz tangential history rolling_friction {model}" + (" torsionTorque on" if torsion else "")
    extra = [_pair("coefficientRollingFriction", MUR), _pair("coefficientRollingViscousDamping", ETAR),
             "fix rs all property/global rollingStiffness scalar 1.7"]
    s = read_snapshot(_dump(tmp_path), liggghts_input=_input(tmp_path, style, *extra))
    _check(s, _expected("hertz", rolling=model, torsion=torsion))


def test_cdt_adds_no_spring_and_says_so(tmp_path):
    """``cdt`` is a constant-size moment: no spring or dashpot, named in the law."""
    s = read_snapshot(_dump(tmp_path), liggghts_input=_input(
        tmp_path, "gran model hertz tangential history rolling_friction cdt", _pair("coefficientRollingFriction", MUR)))
    _check(s, _expected("hertz"))
    assert s.contacts.kr is None and "cdt" in s.law


REFUSED = [
    ("gran model hertz tangential history cohesion sjkr", (), ":9: cohesion sjkr is not modelled"),
    ("gran model hertz tangential history surface multicontact", (), ":9: surface multicontact is not modelled"),
    ("gran model hertz tangential history limitForce on", (), ":9: limitForce on is not modelled"),
    ("gran model hertz tangential history heating_normal_hertz on", (), ":9: heating_normal_hertz on is not modelled"),
    ("gran model hertz tangential history fancyOption on", (), ":9: pair_style gran: unknown keyword 'fancyOption'"),
    ("gran model hooke tangential history viscous on", ("fix cv all property/global characteristicVelocity scalar 1",),
     ":10: viscous on is not modelled"),
    ("gran model hertz/stiffness tangential history", (), ":9: model hertz/stiffness is not modelled"),
    ("gran model hertz tangential history rolling_friction epsd", (),
     ": the pair style at IN:9 needs 'fix ... property/global coefficientRollingFriction"),
    ("gran/hertz/history 2e8 NULL 0 NULL 0.5 0", (), ":9: pair_style gran/hertz/history is not LIGGGHTS's 'gran'"),
    ("gran model hertz tangential history", ("pair_style gran model hooke",), ":10: a second pair_style"),
    ("gran model hertz tangential history", ("fix m9 all property/global youngsModulus peratomtype 1e8 1e8",),
     ":9: youngsModulus is given twice"),
    ("gran model hertz tangential history",
     ("fix m3 all property/global coefficientRestitution peratomtypepair 1 0.5",), ":9: coefficientRestitution is "),
]


@pytest.mark.parametrize("style, extra, message", REFUSED)
def test_refusals_name_the_line(tmp_path, capsys, style, extra, message):
    """Every term that is not modelled is refused in one line naming FILE:LINE."""
    path = _input(tmp_path, style, *extra)
    assert main(["audit", str(_dump(tmp_path)), "--liggghts-input", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and message.replace("IN", str(path)) in err, err


def test_a_type_without_materials_is_refused(tmp_path, capsys):
    """A dump type beyond the materials' types is refused at the property's line."""
    rows = [*ROWS, (11, 3, 0.02, 0.02, 0.02, RA, MA)]
    path = _input(tmp_path, "gran model hertz tangential history")
    assert main(["audit", str(_dump(tmp_path, rows)), "--liggghts-input", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert f"{path}:4: atom type 3 of the dump has no youngsModulus" in err and len(err.splitlines()) == 1


@pytest.mark.parametrize("flag", [["--pair-style", "gran/hooke/history 1e4 NULL 0 NULL 0.5 0"], ["--contacts", "T"]])
def test_exclusive_with_pair_style_and_contacts(tmp_path, capsys, flag):
    """The LIGGGHTS input is the law: with --pair-style or --contacts it is refused."""
    (tmp_path / "T").write_text("id1 id2 kn ks\n2 5 1 1\n")
    flag = [flag[0], str(tmp_path / "T")] if flag[0] == "--contacts" else flag
    path = _input(tmp_path, "gran model hertz tangential history")
    assert main(["audit", str(_dump(tmp_path)), "--liggghts-input", str(path), *flag]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("dtcrit: --liggghts-input: a LIGGGHTS input gives the contact law") and len(err.splitlines()) == 1


def test_undefined_variable_and_missing_pair_style(tmp_path, capsys):
    """An undefined ``${VAR}`` and a missing ``pair_style gran`` are refused."""
    bad = tmp_path / "bad.in"
    bad.write_text("fix m1 all property/global youngsModulus peratomtype ${Y}\npair_style gran model hertz\n")
    assert main(["audit", str(_dump(tmp_path)), "--liggghts-input", str(bad)]) == 2
    assert f"{bad}:1: variable 'Y' is not defined" in capsys.readouterr().err
    bad.write_text("fix m1 all property/global youngsModulus peratomtype 1e8\n")
    assert main(["audit", str(_dump(tmp_path)), "--liggghts-input", str(bad)]) == 2
    assert f"{bad}: no 'pair_style gran model ...' line" in capsys.readouterr().err


@pytest.mark.parametrize("line, message", [
    ("fix w all wall/gran model hertz tangential history primitive type 1 zplane 0.0", "fix wall/gran is not modelled"),
    ("fix v all viscous 0.1", "fix viscous is not modelled"),
    ("fix ms all multisphere", "fix multisphere is not modelled"),
    ("dimension 2", "'dimension 2' is not modelled"),
    ("include walls.in", "'include walls.in' is not modelled"),
])
def test_commands_that_change_the_dynamics_are_refused(tmp_path, capsys, line, message):
    """Walls, other forces and integrators, 2-D and included files are refused at their line."""
    path = _input(tmp_path, "gran model hertz tangential history", line)
    assert main(["audit", str(_dump(tmp_path)), "--liggghts-input", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert f"{path}:9: {message}" in err and "to audit the contacts alone" in err and len(err.splitlines()) == 1


def test_bookkeeping_commands_are_skipped(tmp_path):
    """Integrator, gravity, insertion, meshes and averages do not change the contact law: read through."""
    lines = ["fix integr all nve/sphere", "fix gr all gravity 9.81 vector 0 0 -1",
             "fix pts all particletemplate/sphere 15485863 atom_type 1 density constant 2500 radius constant 1e-3",
             "fix ins all insert/pack seed 32452843 distributiontemplate pdd1 insert_every once",
             "fix cad all mesh/surface file meshes/cad.stl type 1", "fix at all ave/time 1 1 1 c_x",
             "dimension 3", "atom_style granular"]
    s = read_snapshot(_dump(tmp_path), liggghts_input=_input(tmp_path, "gran model hertz tangential history", *lines))
    _check(s, _expected("hertz"))


def test_the_engine_defaults_to_liggghts(tmp_path):
    """Without --engine, a LIGGGHTS input applies LIGGGHTS's conventions (velocity Verlet, pre-load)."""
    s = read_snapshot(_dump(tmp_path), liggghts_input=_input(tmp_path, "gran model hertz tangential history"))
    assert s.convention.name == "liggghts" and s.convention.integrator == "velocity-verlet"
