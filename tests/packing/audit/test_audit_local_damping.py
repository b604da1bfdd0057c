"""Local (Cundall) damping in ``dtcrit audit``: a YADE export's ``newton_damping``, ``--local-damping``
and ``--local-damping-law``, checked against a direct eigen-solve and against time-stepping the
packing's ``K`` and ``M`` with both laws (``dtcrit.integrators.local_damping``, leapfrog with YADE's
and PFC's sign rules), and the refusals of what is not modelled (one line, exit 2).
"""
from __future__ import annotations

import json
import math

import jsonschema
import numpy as np
import pytest

from dtcrit.cli import main
from dtcrit.errors import InputError
from dtcrit.integrators import local_damping as L
from support.paths import REPO_ROOT as ROOT

SCHEMA = json.loads((ROOT / "src" / "dtcrit" / "schemas" / "dtcrit-audit-1.json").read_text())
R, RHO = 1e-3, 2650.0
MASS = 4.0 / 3.0 * math.pi * R**3 * RHO
D = 2 * R - 2e-6  # centre distance: overlap 2e-6
POS = [(0.0, 0.0, 0.0), (D, 0.0, 0.0), (2 * D, 0.0, 0.0), (D, D, 0.0), (D, 0.6 * D, 0.8 * D)]
PAIRS = [(0, 1), (1, 2), (1, 3), (1, 4)]


def _export(path, damping, *, clump=False, dashpot=False, springs=((1e5, 3e4), (2e5, 5e4), (7e4, 6e4), (1.5e5, 2e4))):
    bodies = [{"id": k, "pos": list(p), "radius": R, "mass": MASS * (1 + 0.3 * k), "inertia": [0.4 * MASS * (1 + 0.3 * k) * R * R] * 3,
               "clump_id": None, "is_clump": False, "fixed": False, "ori": [1, 0, 0, 0]} for k, p in enumerate(POS)]
    inters = [{"id1": a, "id2": b, "kn": kn, "ks": ks, "kr": None, "ktw": None, "cn": None, "cs": None, "fn": 0.0,
               "penetration": 2e-6, "shift2": [0.0, 0.0, 0.0]} for (a, b), (kn, ks) in zip(PAIRS, springs)]
    if dashpot:
        inters[1]["cn"] = 0.05
    if clump:
        bodies[3]["clump_id"] = 5
        bodies[4]["clump_id"] = 5
        bodies.append({"id": 5, "pos": [D, 0.8 * D, 0.4 * D], "radius": None, "mass": 2 * MASS, "inertia": [1e-11] * 3,
                       "clump_id": None, "is_clump": True, "fixed": False, "ori": [1, 0, 0, 0]})
        inters = inters[:3]
    doc = {"schema": "dtcrit-yade-export/1", "yade_version": "2023.02a", "dt": 1e-7, "iter": 3,
           "newton_damping": damping, "periodic": False, "cell_hsize": None, "avoid_granular_ratcheting": True,
           "bodies": bodies, "interactions": inters}
    path.write_text(json.dumps(doc))
    return str(path)


def _k_and_inverse_mass(path):
    """The packing's stiffness ``K`` (dense, 6N x 6N) and the inverse of its diagonal mass."""
    from dtcrit.packing.audit.run import read_snapshot
    from dtcrit.packing.operators.assembly import mass_diagonal, stiffness_matrix

    snap = read_snapshot(path)
    return stiffness_matrix(snap.packing, snap.contacts).toarray(), 1.0 / mass_diagonal(snap.packing)


def _json(capsys, *argv):
    rc = main(["audit", *map(str, argv), "--json"])
    out, err = capsys.readouterr()
    assert rc == 0, err
    doc = json.loads(out)
    jsonschema.validate(doc, SCHEMA)
    return doc


@pytest.mark.parametrize("alpha", [0.2, 0.7])
def test_dt_crit_is_the_flip_threshold_of_the_eigen_solved_omega_max(tmp_path, capsys, alpha):
    path = _export(tmp_path / "e.json", alpha)
    K, inv_mass = _k_and_inverse_mass(path)
    omega = L.omega_max(K, inv_mass)  # numpy.linalg.eigvalsh of M^-1/2 K M^-1/2
    doc = _json(capsys, path)
    assert doc["dt_crit"] == pytest.approx(2.0 / (omega * math.sqrt(1.0 + alpha)), rel=1e-9)
    assert doc["dt_undamped"] == pytest.approx(2.0 / omega, rel=1e-9)
    assert doc["local_damping"] == {"alpha": alpha, "law": "yade", "status": "onset",
                                    "factor": pytest.approx(1.0 / math.sqrt(1.0 + alpha), rel=1e-15),
                                    "statement": doc["local_damping"]["statement"]}
    assert "windows" in doc["local_damping"]["statement"]
    assert 0.0 < doc["dt_safe"] <= doc["dt_crit"]


@pytest.mark.parametrize("law", ["pfc", "yade"])
@pytest.mark.parametrize("alpha", [0.2, 0.7])
def test_time_stepping_is_bounded_below_and_grows_above_the_printed_step(tmp_path, capsys, law, alpha):
    """Leapfrog with the law on the packing's K and M: 16 random starts and the top mode's flip start stay
    bounded at 0.999 x dt_crit; the flip start grows at 1.001 x (both laws: derivations/records/local_damping.md)."""
    if law == "yade":  # the export's newton_damping
        path = _export(tmp_path / "e.json", alpha)
        doc = _json(capsys, path)
    else:  # an export without a NewtonIntegrator, the coefficient and law from the flags
        path = _export(tmp_path / "e.json", None)
        doc = _json(capsys, path, "--local-damping", alpha, "--local-damping-law", law)
    assert doc["local_damping"]["law"] == law and doc["local_damping"]["status"] == {"pfc": "proved", "yade": "onset"}[law]
    dt = doc["dt_crit"]
    K, inv_mass = _k_and_inverse_mass(path)
    s = np.sqrt(inv_mass)
    w, v = np.linalg.eigh(s[:, None] * K * s[None, :])
    phi = s * v[:, -1]
    rng = np.random.default_rng(3)
    x0 = np.vstack([rng.standard_normal((16, phi.size)) * 1e-9, phi])
    u0 = np.vstack([rng.standard_normal((16, phi.size)) * 1e-9 * np.sqrt(w[-1]), 2.0 * phi / (0.999 * dt)])
    assert not L.grows(x0, u0, 0.999 * dt, K, inv_mass, alpha, law, 4000).any()
    flip = L.grows(phi[None], 2.0 * phi[None] / (1.001 * dt), 1.001 * dt, K, inv_mass, alpha, law, 4000)
    assert flip.all()


def test_the_users_step_and_the_estimators_are_rated_against_the_damped_step(tmp_path, capsys):
    alpha = 0.7
    path = _export(tmp_path / "e.json", alpha)
    undamped = _json(capsys, _export(tmp_path / "u.json", 0.0))
    assert undamped["local_damping"] is None
    dt = 0.95 * undamped["dt_crit"]  # stable without local damping, not with it
    doc = _json(capsys, path, "--dt", dt)
    assert doc["stable"] is False and doc["dt_user_ratio"] == pytest.approx(dt / doc["dt_crit"], rel=1e-12)
    for name, row in doc["estimators"].items():
        if row["dt"] is None:  # a row that does not apply has no value, damped or not
            assert undamped["estimators"][name]["dt"] is None and row["ratio"] is None
            continue
        assert row["dt"] == pytest.approx(undamped["estimators"][name]["dt"], rel=1e-12)  # what the codes compute
        assert row["ratio"] == pytest.approx(row["dt"] / doc["dt_crit"], rel=1e-12)
    rc = main(["audit", path, "--dt", str(dt)])
    out, _ = capsys.readouterr()
    assert rc == 0 and "UNSTABLE" in out and "local damping alpha = 0.7" in out and "windows" in out


def test_zero_damping_changes_nothing(tmp_path, capsys):
    a = _json(capsys, _export(tmp_path / "a.json", 0.0))
    b = _json(capsys, _export(tmp_path / "b.json", None))
    assert a["dt_crit"] == b["dt_crit"] and a["local_damping"] is None is b["local_damping"]


def test_a_lammps_dump_takes_the_flag_with_its_law(capsys):
    dump = str(ROOT / "examples" / "packings" / "random_lognormal_60.dump")
    style = "gran/hooke/history 1e5 NULL 0 NULL 0.5 0"
    plain = _json(capsys, dump, "--pair-style", style, "--integrator", "leapfrog")
    doc = _json(capsys, dump, "--pair-style", style, "--integrator", "leapfrog", "--local-damping", "0.3",
                "--local-damping-law", "pfc")
    assert doc["local_damping"]["status"] == "proved"
    assert doc["dt_crit"] == pytest.approx(plain["dt_crit"] / math.sqrt(1.3), rel=1e-12)
    assert doc["dt_safe"] == pytest.approx(plain["dt_safe"] / math.sqrt(1.3), rel=1e-12)


def _refusals(tmp_path):
    dump = str(ROOT / "examples" / "packings" / "random_lognormal_60.dump")
    style = ("--pair-style", "gran/hooke/history 1e5 NULL 0 NULL 0.5 0")
    e = _export(tmp_path / "e.json", 0.7)
    return [
        ([_export(tmp_path / "d.json", 0.2, dashpot=True)], "newton_damping", "dashpots"),
        ([_export(tmp_path / "c.json", 0.2, clump=True)], "newton_damping", "clumps"),
        ([e, "--local-damping", "0.5"], "--local-damping", "disagrees"),
        ([e, "--local-damping-law", "pfc"], "--local-damping-law", "YADE's law"),
        ([dump, *style, "--integrator", "leapfrog", "--local-damping", "0.3"], "--local-damping", "--local-damping-law"),
        ([dump, *style, "--local-damping", "0.3", "--local-damping-law", "pfc"], "--local-damping", "velocity-verlet"),
        ([dump, *style, "--integrator", "leapfrog", "--local-damping", "1.0", "--local-damping-law", "pfc"],
         "--local-damping", "[0, 1)"),
        ([dump, *style, "--integrator", "leapfrog", "--local-damping", "nan", "--local-damping-law", "pfc"],
         "--local-damping", "[0, 1)"),
        ([dump, *style, "--local-damping-law", "pfc"], "--local-damping-law", "--local-damping ALPHA"),
    ]


def test_what_is_not_modelled_is_refused_in_one_line(tmp_path, capsys):
    for argv, key, words in _refusals(tmp_path):
        rc = main(["audit", *argv])
        out, err = capsys.readouterr()
        assert rc == 2 and out == "", argv
        assert err.count("\n") == 1 and err.startswith("dtcrit: ") and key in err and words in err, (argv, err)


def test_the_api_names_the_parameter(tmp_path):
    from dtcrit.packing.audit.run import audit_snapshot

    with pytest.raises(InputError) as exc:
        audit_snapshot(_export(tmp_path / "e.json", None), local_damping=-0.1)
    assert exc.value.key == "local_damping"
    with pytest.raises(InputError) as exc:
        audit_snapshot(_export(tmp_path / "e.json", None), local_damping=0.1, local_damping_law="cundall")
    assert exc.value.key == "local_damping_law"
    a = audit_snapshot(_export(tmp_path / "e.json", None), local_damping=0.4)  # no NewtonIntegrator: YADE's law
    assert a.local_damping is not None and a.local_damping["law"] == "yade"


def test_yades_law_at_high_damping_is_refused(tmp_path, capsys):
    """derivations/records/local_damping.md: with YADE's law at alpha 0.8-0.9 runs on a 5-mass chain grew at
    0.93-0.95 of the onset, so no safe step is established there: refused in one line from 0.8 on (export,
    flag and scene alike); PFC's law, proved for every alpha, is not."""
    assert main(["audit", _export(tmp_path / "w0.7.json", 0.7)]) == 0
    capsys.readouterr()
    assert main(["audit", _export(tmp_path / "w0.85.json", 0.85)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "newton_damping" in err and "0.93-0.95" in err
    dump = str(ROOT / "examples" / "packings" / "random_lognormal_60.dump")
    base = ["audit", dump, "--pair-style", "gran/hooke/history 1e5 NULL 0 NULL 0.5 0", "--integrator", "leapfrog",
            "--local-damping", "0.8", "--local-damping-law"]
    assert main(base + ["yade"]) == 2 and "--local-damping" in capsys.readouterr().err
    assert main(base + ["pfc"]) == 0
    capsys.readouterr()


def test_dt_safe_is_not_called_a_proved_step_under_yades_law(capsys):
    """Under YADE's law nothing is proved below the onset (derivations/records/local_damping.md): the text
    says what dt_safe bounds; under PFC's law it stays the rigorous lower bound of a proved interval."""
    dump = str(ROOT / "examples" / "packings" / "random_lognormal_60.dump")
    style = "gran/hooke/history 1e5 NULL 0 NULL 0.5 0"
    lines = {}
    for law in ("yade", "pfc"):
        assert main(["audit", dump, "--pair-style", style, "--integrator", "leapfrog", "--local-damping", "0.3",
                     "--local-damping-law", law]) == 0
        lines[law] = next(x for x in capsys.readouterr().out.splitlines() if x.startswith("dt_safe"))
    assert "shown by simulation only" in lines["yade"] and "on the onset" in lines["yade"]
    assert "(rigorous lower bound; " in lines["pfc"] and "simulation" not in lines["pfc"]
