"""``dtcrit plan`` on the command line: the JSON schema, the ``--write-dump`` round trip through
``dtcrit audit`` (its critical step meets the target), the stiffness reduction checked by a dense
eigen-solve, and bad input (one line, exit status 2).
"""
from __future__ import annotations

import json
import math

import jsonschema
import numpy as np
import pytest
import scipy.linalg as sla

from dtcrit.cli import main
from dtcrit.packing.audit.run import read_snapshot
from dtcrit.packing.operators.assembly import mass_diagonal, stiffness_matrix
from support.paths import REPO_ROOT as ROOT

EXAMPLE = str(ROOT / "examples" / "packings" / "random_lognormal_60.dump")
HOOKE = "gran/hooke/history 1e5 NULL 0 NULL 0.5 0"
SCHEMA = json.loads((ROOT / "src" / "dtcrit" / "schemas" / "dtcrit-plan-1.json").read_text())


def _dt_dense(snapshot, stiffness_factor=1.0) -> float:
    k = stiffness_factor * stiffness_matrix(snapshot.packing, snapshot.contacts).toarray()
    s = 1.0 / np.sqrt(mass_diagonal(snapshot.packing))
    return 2.0 / math.sqrt(float(sla.eigh(s[:, None] * k * s[None, :], eigvals_only=True)[-1]))


@pytest.fixture(scope="module")
def dt_now():
    """Today's critical step of the example packing, by a dense solve."""
    return _dt_dense(read_snapshot(EXAMPLE, pair_style=HOOKE))


def _run(capsys, *argv):
    try:
        code = main(list(argv))
    except SystemExit as exc:  # argparse's refusal of a flag's value
        code = exc.code
    out, err = capsys.readouterr()
    return code, out, err


def test_json_validates_and_write_dump_round_trips_through_audit(capsys, tmp_path, dt_now):
    """The JSON fits its schema; dtcrit audit of the written dump meets the target, ids and masses kept."""
    target = 2.5 * dt_now
    dump = tmp_path / "scaled.dump"
    code, out, err = _run(capsys, "plan", EXAMPLE, "--pair-style", HOOKE, "--target-dt", repr(target), "--json",
                          "--duration", "0.01", "--strain-rate", "5", "--write-dump", str(dump))
    assert code == 0, err
    doc = json.loads(out)
    jsonschema.validate(doc, SCHEMA)
    d = doc["density_scaling"]
    assert d["dt_crit_scaled"] >= target and len(d["factors"]) == 60
    assert d["added_mass_fraction"] < d["yade_rule_added_mass_fraction"]
    assert doc["cost"]["steps_after"] == math.ceil(0.01 / target)
    code, out, err = _run(capsys, "audit", str(dump), "--pair-style", HOOKE, "--json")
    assert code == 0, err
    assert json.loads(out)["dt_crit"] >= target
    # the dump carries the planned masses by the original ids
    scaled, original = read_snapshot(dump, pair_style=HOOKE), read_snapshot(EXAMPLE, pair_style=HOOKE)
    assert np.array_equal(scaled.packing.ids, original.packing.ids)
    np.testing.assert_allclose(scaled.packing.masses / original.packing.masses, d["factors"], rtol=1e-15)


def test_stiffness_factor_reaches_the_target(capsys, dt_now):
    """Linear springs: s = (dt_now/target)^2, and the dense solve with K times s meets the target."""
    target = 4.0 * dt_now
    code, out, err = _run(capsys, "plan", EXAMPLE, "--pair-style", HOOKE, "--target-dt", repr(target), "--json")
    assert code == 0, err
    s = json.loads(out)["stiffness_reduction"]
    assert s["factor"] == pytest.approx(1.0 / 16.0, rel=1e-5)  # (dt_now / target)^2 for linear springs
    assert _dt_dense(read_snapshot(EXAMPLE, pair_style=HOOKE), s["factor"]) >= target
    assert s["contact_duration_factor"] == pytest.approx(4.0, rel=1e-5)


def test_text_names_the_binding_particles(capsys, dt_now):
    """The text has the binding step, both options and the gravity warning."""
    code, out, err = _run(capsys, "plan", EXAMPLE, "--pair-style", HOOKE, "--target-dt", repr(2 * dt_now),
                          "--gravity", "9.81")
    assert code == 0, err
    assert "binding step today" in out and "density scaling" in out and "stiffness reduction" in out
    assert "warning: gravity 9.81" in out


def _one_line_error(capsys, *argv) -> str:
    code, out, err = _run(capsys, *argv)
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and "Traceback" not in err
    return err


def test_target_already_met_is_nothing_to_do(capsys, dt_now):
    """A target below today's critical step: nothing to do, one line, exit 2."""
    err = _one_line_error(capsys, "plan", EXAMPLE, "--pair-style", HOOKE, "--target-dt", repr(0.5 * dt_now))
    assert err.startswith("dtcrit: --target-dt: nothing to do: the current critical step")


def test_target_unreachable_within_max_factor(capsys, dt_now):
    """5x the step needs a factor of 25: refused under --max-factor 10."""
    err = _one_line_error(capsys, "plan", EXAMPLE, "--pair-style", HOOKE, "--target-dt", repr(5 * dt_now),
                          "--max-factor", "10")
    assert err.startswith("dtcrit: --max-factor: ") and "unreachable" in err


def test_snapshot_without_masses(capsys, tmp_path):
    """A dump without a mass column and no --density: one line naming both."""
    text = open(EXAMPLE).read().replace("radius mass", "radius")
    rows = [line.rsplit(" ", 1)[0] if line[:1].isdigit() and len(line.split()) == 7 else line
            for line in text.splitlines()]
    bare = tmp_path / "bare.dump"
    bare.write_text("\n".join(rows) + "\n")
    err = _one_line_error(capsys, "plan", str(bare), "--pair-style", HOOKE, "--target-dt", "1e-5")
    assert "mass" in err and "--density" in err


@pytest.mark.parametrize("argv", [("--target-dt", "0"), ("--target-dt", "1e-5", "--max-factor", "-3"),
                                  ("--target-dt", "nan")])
def test_bad_numbers(capsys, argv):
    """Zero, negative and NaN values are refused while parsing, naming the flag."""
    err = _one_line_error(capsys, "plan", EXAMPLE, "--pair-style", HOOKE, *argv)
    assert "--target-dt" in err or "--max-factor" in err


def test_write_dump_into_missing_directory_writes_nothing(capsys, tmp_path, dt_now):
    """A dump path in a missing directory is refused before any work; nothing is created."""
    err = _one_line_error(capsys, "plan", EXAMPLE, "--pair-style", HOOKE, "--target-dt", repr(2 * dt_now),
                          "--write-dump", str(tmp_path / "no" / "such.dump"))
    assert err.startswith("dtcrit: --write-dump: ")
    assert not (tmp_path / "no").exists()


def test_a_scene_is_refused(capsys):
    """A scene has no packing whose exact step could confirm the masses: one line naming SNAPSHOT."""
    err = _one_line_error(capsys, "plan", str(ROOT / "examples" / "glass_spheres_hertz.toml"), "--target-dt", "1e-5")
    assert err.startswith("dtcrit: SNAPSHOT: plan needs a snapshot")


def test_impact_resolution_with_a_velocity(capsys, dt_now):
    """With --velocity: the shortest linear contact pi sqrt(m_eff/kn) over the resolution step's N_res."""
    from dtcrit.collisions import resolution_step

    code, out, err = _run(capsys, "plan", EXAMPLE, "--pair-style", HOOKE, "--target-dt", repr(2 * dt_now),
                          "--velocity", "0.3", "--json")
    assert code == 0, err
    doc = json.loads(out)
    jsonschema.validate(doc, SCHEMA)
    c = doc["collisions"]
    snap = read_snapshot(EXAMPLE, pair_style=HOOKE)
    m = snap.packing.masses
    m_eff = m[snap.contacts.i] * m[snap.contacts.j] / (m[snap.contacts.i] + m[snap.contacts.j])
    t_c = float(np.min(math.pi * np.sqrt(m_eff / snap.contacts.kn)))
    assert c["contact_time_now"] == pytest.approx(t_c, rel=1e-12)
    n_res = resolution_step(engine="lammps", normal="hooke", damping="none", restitution=1.0).steps_per_collision
    assert c["resolution_dt_now"] == pytest.approx(t_c / n_res, rel=1e-12)
    assert any("impacts at 0.3 m/s" in w for w in doc["warnings"])
