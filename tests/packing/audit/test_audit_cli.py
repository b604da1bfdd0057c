"""``dtcrit audit`` without an engine: the two-sphere answer, contact tables, which pairs count, the
JSON schema, and bad input (one line ``FILE:LINE: reason`` or ``--flag: reason``, exit 2).

The real-engine checks are in ``tests/engines/test_audit_lammps.py`` (LAMMPS) and ``tests/engines/test_engine_yade.py``.
"""
from __future__ import annotations

import copy
import json
import math
from pathlib import Path

import jsonschema
import mpmath as mp
import pytest

from dtcrit.cli import main
from support.paths import REPO_ROOT as ROOT

SCHEMA = json.loads((ROOT / "src" / "dtcrit" / "schemas" / "dtcrit-audit-1.json").read_text())
R, RHO = 1e-3, 2500.0
MASS = 4.0 / 3.0 * math.pi * R**3 * RHO


def _dump(rows, box=(0.0, 0.1), flags="pp pp pp", columns="id type x y z radius mass", tilt=""):
    lines = ["ITEM: TIMESTEP", "0", "ITEM: NUMBER OF ATOMS", str(len(rows)), f"ITEM: BOX BOUNDS {flags}{tilt}"]
    lines += [f"{box[0]!r} {box[1]!r}" + (" 0.0" if tilt else "") for _ in range(3)]
    lines.append(f"ITEM: ATOMS {columns}")
    lines += [" ".join(repr(v) if isinstance(v, float) else str(v) for v in row) for row in rows]
    return "\n".join(lines) + "\n"


def _pair_rows(gap=-2e-9, third_gap=None):
    rows = [(7, 1, 0.05, 0.05, 0.05, R, MASS), (9, 1, 0.05 + 2 * R + gap, 0.05, 0.05, R, MASS)]
    if third_gap is not None:
        rows.append((12, 1, 0.05 + 4 * R + gap + third_gap, 0.05, 0.05, R, MASS))
    return rows


def _run(capsys, *argv):
    rc = main(["audit", *map(str, argv)])
    out, err = capsys.readouterr()
    return rc, out, err


def _json(capsys, *argv) -> dict:
    rc, out, err = _run(capsys, *argv, "--json")
    assert rc == 0, err
    return json.loads(out)


def test_two_spheres_give_the_closed_form_of_their_two_modes(tmp_path, capsys):
    """Normal mode k_n (2/m), tangential mode k_t (7/m with the full-radius arm, I = 2/5 m R^2): the
    undamped step is 2/omega of the stiffer, here in mpmath; the normal dashpot c = m_eff gamma_n
    lowers the normal mode's step to 2/(omega (zeta + sqrt(zeta^2 + 1)))."""
    mp.mp.dps = 50
    path = tmp_path / "pair.dump"
    path.write_text(_dump(_pair_rows()))
    kn, kt, gamma = 1e4, 8e3, 3e4
    doc = _json(capsys, path, "--pair-style", f"gran/hooke/history {kn} {kt} {gamma} 0 0.5 1")
    m = mp.mpf(MASS)
    normal_w = mp.sqrt(kn * 2 / m)
    zeta = (m / 2) * gamma * (2 / m) / (2 * normal_w)
    normal = 2 / (normal_w * (zeta + mp.sqrt(zeta**2 + 1)))
    tangential = 2 / mp.sqrt(kt * 7 / m)
    assert abs(doc["dt_crit"] / float(min(normal, tangential)) - 1) < 1e-6  # pre-load F/r ~ 1e-6 kn
    assert doc["limiting"]["ids"][:2] in ([7, 9], [9, 7])
    assert doc["n_contacts"] == 1 and doc["damped"]
    jsonschema.validate(doc, SCHEMA)


def test_a_pair_at_a_tiny_gap_is_not_a_contact(tmp_path, capsys):
    """LAMMPS counts a pair only when r < R_i + R_j: the third sphere, 1.4e-11 m away, carries no force."""
    path = tmp_path / "three.dump"
    path.write_text(_dump(_pair_rows(third_gap=2e-9 + 1.4e-11)))
    doc = _json(capsys, path, "--pair-style", "gran/hooke/history 1e4 NULL 0 NULL 0.5 0")
    assert doc["n_contacts"] == 1


def test_granular_hooke_pair_matches_gran_hooke_history(tmp_path, capsys):
    """Two equal spheres: pair granular (hooke, linear_history, damping mass_velocity) is the same contact
    as gran/hooke/history, up to its torque arm R - delta/2 (here delta = 2e-9 m: 1e-6 relative)."""
    dump = tmp_path / "pair.dump"
    dump.write_text(_dump(_pair_rows()))
    granular = _json(capsys, dump, "--pair-style",
                     "granular hooke 1e4 3e4 tangential linear_history 8e3 0.5 0.5 damping mass_velocity")
    gran = _json(capsys, dump, "--pair-style", "gran/hooke/history 1e4 8e3 3e4 1.5e4 0.5 1")
    assert abs(granular["dt_crit"] / gran["dt_crit"] - 1) < 1e-5


def test_a_contact_table_gives_the_pair_style_answer(tmp_path, capsys):
    dump = tmp_path / "pair.dump"
    dump.write_text(_dump(_pair_rows()))
    table = tmp_path / "contacts.csv"
    fn = 1e4 * 2e-9
    table.write_text(f"# id1, id2, kn, ks, fn, note\n9, 7, 1e4, 8e3, {fn!r}, x\n")
    by_table = _json(capsys, dump, "--contacts", table)
    by_style = _json(capsys, dump, "--pair-style", "gran/hooke/history 1e4 8e3 0 0 0.5 0")
    assert abs(by_table["dt_crit"] / by_style["dt_crit"] - 1) < 1e-12


def test_the_users_step_is_rated(tmp_path, capsys):
    path = tmp_path / "pair.dump"
    path.write_text(_dump(_pair_rows()))
    doc = _json(capsys, path, "--pair-style", "gran/hooke/history 1e4 NULL 0 NULL 0.5 0", "--dt", "1e-5")
    assert doc["dt_user"] == 1e-5 and doc["dt_user_ratio"] == pytest.approx(1e-5 / doc["dt_crit"])
    assert doc["stable"] is (doc["dt_user_ratio"] < 1)
    rc, out, _ = _run(capsys, path, "--pair-style", "gran/hooke/history 1e4 NULL 0 NULL 0.5 0", "--dt", "1e-5")
    assert rc == 0 and "x dt_crit" in out and "yade_gsts" in out


def test_the_schema_is_not_vacuous(tmp_path, capsys):
    path = tmp_path / "pair.dump"
    path.write_text(_dump(_pair_rows()))
    doc = _json(capsys, path, "--pair-style", "gran/hooke/history 1e4 NULL 0 NULL 0.5 0")
    jsonschema.Draft202012Validator.check_schema(SCHEMA)
    jsonschema.validate(doc, SCHEMA)
    for key, value in (("dt_crit", -1.0), ("engine", "edem"), ("schema", "dtcrit-step/1"), ("limiting", [])):
        bad = copy.deepcopy(doc)
        bad[key] = value
        with pytest.raises(jsonschema.ValidationError):
            jsonschema.validate(bad, SCHEMA)
    bad = copy.deepcopy(doc)
    del bad["estimators"]["yade_gsts"]
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate(bad, SCHEMA)


GOOD_STYLE = "gran/hooke/history 1e4 NULL 0 NULL 0.5 0"


def _bad_cases(tmp: Path):
    good = tmp / "good.dump"
    good.write_text(_dump(_pair_rows()))
    text = _dump(_pair_rows())
    (tmp / "truncated.dump").write_text(text.rsplit("\n", 2)[0] + "\n")
    (tmp / "triclinic.dump").write_text(_dump(_pair_rows(), flags="pp pp pp", tilt=" xy xz yz"))
    (tmp / "ids.local").write_text("ITEM: TIMESTEP\n0\nITEM: NUMBER OF ENTRIES\n1\nITEM: BOX BOUNDS pp pp pp\n"
                                   "0 1\n0 1\n0 1\nITEM: ENTRIES c_p[1] c_p[2]\n7 44\n")
    (tmp / "short.local").write_text("ITEM: TIMESTEP\n0\nITEM: NUMBER OF ENTRIES\n3\nITEM: BOX BOUNDS pp pp pp\n"
                                     "0 1\n0 1\n0 1\nITEM: ENTRIES c_p[1] c_p[2]\n7 9\n")
    (tmp / "ids.csv").write_text("id1 id2 kn ks\n7 10 1e4 1e4\n")
    (tmp / "negative.csv").write_text("id1 id2 kn ks\n7 9 -1e4 1e4\n")
    (tmp / "header.csv").write_text("a b kn ks\n7 9 1e4 1e4\n")
    (tmp / "export.json").write_text('{"schema": "dtcrit-yade-export/1", "bodies": [], "interactions": []}\n')
    return [
        (["truncated.dump", "--pair-style", GOOD_STYLE], "truncated.dump:"),
        (["triclinic.dump", "--pair-style", GOOD_STYLE], "triclinic.dump:5: triclinic"),
        (["good.dump", "--pair-style", GOOD_STYLE, "--local", "ids.local"], "ids.local:10: particle id 44"),
        (["good.dump", "--pair-style", GOOD_STYLE, "--local", "short.local"], "short.local:11:"),
        (["good.dump", "--contacts", "ids.csv"], "ids.csv:2: particle id 10"),
        (["good.dump", "--contacts", "negative.csv"], "negative.csv:2: kn must be"),
        (["good.dump", "--contacts", "header.csv"], "header.csv:1: the header"),
        (["good.dump", "--pair-style", "gran/hookey 1e4 NULL 0 NULL 0.5 0"], "--pair-style: unknown"),
        (["good.dump", "--pair-style", "gran/hooke/history 1e4 NULL 0 NULL 0.5"], "--pair-style: gran/hooke/history takes 6"),
        (["good.dump", "--pair-style", "gran/hooke/history -1e4 NULL 0 NULL 0.5 0"], "--pair-style: Kn must be"),
        (["good.dump", "--pair-style", "gran/hooke/history 1e4 NULL 0 NULL 0.5 2"], "--pair-style: dampflag"),
        (["good.dump"], "--pair-style: give the contact law"),
        (["good.dump", "--pair-style", GOOD_STYLE, "--contacts", "ids.csv"], "--contacts:"),
        (["good.dump", "--pair-style", GOOD_STYLE, "--engine", "yade"], "--engine:"),
        (["good.dump", "--pair-style", GOOD_STYLE, "--dt", "-1"], "--dt:"),
        (["missing.dump", "--pair-style", GOOD_STYLE], "SNAPSHOT:"),
        (["export.json"], "export.json: bodies"),
        (["good.dump", "--pair-style", "granular jkr 1e4 50 0.3 10 tangential mindlin NULL 1 0.5"], "jkr is not supported"),
        (["good.dump", "--pair-style", "granular hooke 1e4 50"], "tangential model is required"),
        (["good.dump", "--pair-style", "granular hooke 1e4 tangential linear_history 1e4 1 0.5"], "hooke eta must be"),
        (["good.dump", "--pair-style", "granular hooke 1e4 5 tangential linear_history 1e4 1 0.5 damping sticky"],
         "damping 'sticky' is not modelled"),
        (["good.dump", "--pair-style", "granular hooke 1e4 5 tangential mindlin NULL 1 0.5"], "needs a material"),
    ]


@pytest.mark.parametrize("case", range(22))
def test_bad_input_is_one_line_and_exit_2(case, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    argv, expected = _bad_cases(tmp_path)[case]
    before = sorted(p.name for p in tmp_path.iterdir())
    rc, out, err = _run(capsys, *argv)
    assert rc == 2 and out == ""
    lines = err.splitlines()
    assert len(lines) == 1 and expected in lines[0], err
    assert "Traceback" not in err
    assert sorted(p.name for p in tmp_path.iterdir()) == before  # nothing written


def test_a_material_law_adds_the_rayleigh_time(tmp_path, capsys):
    """T_R = pi R sqrt(rho/G)/(0.1631 nu + 0.8766) (Li et al. 2005), G = E/(2(1 + nu)), from the dump's
    radius and mass; EDEM's 20 % and 40 % of it beside; a law of spring constants has none."""
    path = tmp_path / "pair.dump"
    path.write_text(_dump(_pair_rows()))
    e, nu = 7e10, 0.25
    doc = _json(capsys, path, "--pair-style", f"granular hertz/material {e} 0.3 {nu} tangential mindlin NULL 1 0.5")
    rho = MASS / (4.0 / 3.0 * math.pi * R**3)
    t_r = math.pi * R * math.sqrt(rho / (e / (2 * (1 + nu)))) / (0.1631 * nu + 0.8766)
    est = doc["estimators"]
    assert est["rayleigh_time"]["dt"] == pytest.approx(t_r, rel=1e-12)
    assert est["rayleigh_20"]["dt"] == pytest.approx(0.2 * t_r, rel=1e-12)
    assert est["rayleigh_40"]["dt"] == pytest.approx(0.4 * t_r, rel=1e-12)
    jsonschema.validate(doc, SCHEMA)
    plain = _json(capsys, path, "--pair-style", GOOD_STYLE)
    assert "rayleigh_time" not in plain["estimators"]


def _fcc_rows(n=3):
    """A periodic n x n x n FCC lattice of equal spheres, touching to 1e-6 of R (every sphere alike)."""
    a = 2 * math.sqrt(2) * R * (1 - 1e-6)
    basis = ((0, 0, 0), (0.5, 0.5, 0), (0.5, 0, 0.5), (0, 0.5, 0.5))
    cells = [(i, j, k) for i in range(n) for j in range(n) for k in range(n)]
    rows = [((i + b[0]) * a, (j + b[1]) * a, (k + b[2]) * a) for i, j, k in cells for b in basis]
    return [(p + 1, 1, x, y, z, R, MASS) for p, (x, y, z) in enumerate(rows)], n * a


def test_a_spread_out_mode_is_described_by_its_participation_ratio(tmp_path, capsys):
    """In a periodic FCC lattice every sphere is alike, so the governing mode is spread over all of them:
    no ids are named (six of 108 hold ~6 % of its energy), its participation ratio is given instead."""
    rows, length = _fcc_rows()
    path = tmp_path / "fcc.dump"
    path.write_text(_dump(rows, box=(0.0, length)))
    doc = _json(capsys, path, "--pair-style", "gran/hooke/history 1e5 NULL 2e4 NULL 0.5 1")
    lim = doc["limiting"]
    assert lim["ids"] == [] and lim["energy_share"] < 0.5 and lim["participation_ratio"] > 0.25
    jsonschema.validate(doc, SCHEMA)
    rc, out, _ = _run(capsys, path, "--pair-style", "gran/hooke/history 1e5 NULL 2e4 NULL 0.5 1")
    assert rc == 0 and "limiting particles" not in out and "spread out, participation ratio" in out


def test_each_bound_row_says_what_it_bounds(tmp_path, capsys):
    """The block-diagonal and Gershgorin rows bound the undamped step 2/omega_max from below; with dashpots
    the label says so (dt_crit is lower), without them they bound dt_crit itself."""
    path = tmp_path / "pair.dump"
    path.write_text(_dump(_pair_rows()))
    damped = _json(capsys, path, "--pair-style", "gran/hooke/history 1e4 8e3 3e4 0 0.5 1")
    plain = _json(capsys, path, "--pair-style", "gran/hooke/history 1e4 8e3 0 0 0.5 0")
    for name in ("block_diagonal", "gershgorin"):
        e, f = damped["estimators"][name], plain["estimators"][name]
        assert "undamped step 2/omega_max" in e["kind"] and e["dt"] <= damped["dt_undamped"] * (1 + 1e-12)
        assert f["kind"].startswith("lower bound on dt_crit") and f["safe"]
