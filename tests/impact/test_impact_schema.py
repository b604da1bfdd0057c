"""`dtcrit impact --json` carries the envelope of every dtcrit JSON and validates against its schema
(src/dtcrit/schemas/dtcrit-impact-1.json): single steps and sweeps, damped and undamped, every integrator; the schema
refuses what it should (it is not vacuous)."""
from __future__ import annotations

import json

import jsonschema
import pytest
from support.json_keys import numeric_keys

import dtcrit
from dtcrit.cli import main
from dtcrit.integrators.schemes import NAMES
from dtcrit.json_meta import derivation_hashes
from support.paths import REPO_ROOT as ROOT

SCHEMA = json.loads((ROOT / "src" / "dtcrit" / "schemas" / "dtcrit-impact-1.json").read_text())
SMALL = ["--step", "0.1", "--phases", "8"]


def _doc(capsys, *argv):
    assert main(["impact", *argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


CASES = {
    "single-damped": ["--integrator", "velocity-verlet", "--zeta", "0.2", "--omega-dt", "1.3", "--phases", "16"],
    "single-undamped": ["--integrator", "leapfrog", "--omega-dt", "1.9", "--phases", "16"],
    "beyond-the-bound": ["--integrator", "leapfrog", "--omega-dt", "2.5", "--phases", "8"],  # ratios above 1
    "sweep-with-hertz": ["--integrator", "leapfrog", "--zeta", "0.1", *SMALL],
    "sweep-undamped": ["--integrator", "symplectic-euler", *SMALL, "--no-hertz"],
    "overdamped": ["--integrator", "leapfrog-centred", "--zeta", "3", *SMALL, "--no-hertz"],
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_outputs_validate(name, capsys):
    doc = _doc(capsys, *CASES[name])
    jsonschema.validate(doc, SCHEMA)
    assert doc["schema"] == "dtcrit-impact/1" and doc["dtcrit_version"] == dtcrit.__version__
    assert doc["derivation_hashes"] == derivation_hashes() and "impact" in doc["derivation_hashes"]
    assert list(doc)[:4] == ["schema", "dtcrit_version", "units", "derivation_hashes"]


@pytest.mark.parametrize("integrator", NAMES)
def test_every_integrator_validates(integrator, capsys):
    jsonschema.validate(_doc(capsys, "--integrator", integrator, "--zeta", "0.05", "--step", "0.2", "--phases", "4",
                             "--no-hertz"), SCHEMA)


def test_beyond_the_bound_the_rows_show_energy_created(capsys):
    """Above omega*dt = 2 undamped leapfrog leaves the impact faster than it came (the schema has no upper limit)."""
    doc = _doc(capsys, *CASES["beyond-the-bound"])
    (row,) = doc["numerical"]
    assert row["max"] > 1 and row["diverged"] == 0 and doc["critical_omega_dt"] == 2.0


RATIO_KEYS = {"zeta", "phases", "separated", "diverged", "energy_error", "energy_threshold", "energy_error_at_bound",
              "linear_contact_energy_error_at_bound", "max_relative_difference_from_simulation", "compared_runs", "N",
              "max_abs_ratio_minus_one"}
"""Counts, fractions, damping ratios and relative errors: the numbers of an impact document without a scale."""


def test_every_scaled_number_has_its_unit(capsys):
    docs = [_doc(capsys, *argv) for argv in CASES.values()]
    seen = set().union(*(numeric_keys(d) for d in docs))
    missing = seen - set(docs[0]["units"]) - RATIO_KEYS
    assert not missing, sorted(missing)


def test_the_schema_rejects_what_it_should(capsys):
    jsonschema.Draft202012Validator.check_schema(SCHEMA)
    good = _doc(capsys, *CASES["sweep-with-hertz"])
    for mutate in (lambda d: d.pop("units"), lambda d: d.update(schema="dtcrit-step/1"), lambda d: d.pop("exact"),
                   lambda d: d["numerical"][0].update(max=-1.0), lambda d: d["numerical"][0].pop("omega_dt"),
                   lambda d: d["energy_created"]["above_one"].append([1.0]), lambda d: d.update(integrator="rk4"),
                   lambda d: d["by_zeta"][0].update(exact_exit_ratio=1.5), lambda d: d["hertz"].pop("verdict"),
                   lambda d: d.update(phases=0)):
        doc = json.loads(json.dumps(good))
        mutate(doc)
        with pytest.raises(jsonschema.ValidationError):
            jsonschema.validate(doc, SCHEMA)
