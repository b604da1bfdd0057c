"""`dtcrit packing --json` validates against its published schema (src/dtcrit/schemas/dtcrit-packing-1.json)
for lattices, random packings, dumps, Hertz and a damped integrator, and the schema refuses broken documents."""
from __future__ import annotations

import copy
import json

import jsonschema
import pytest

from dtcrit.cli import main
from support.paths import REPO_ROOT as ROOT

SCHEMA = json.loads((ROOT / "src" / "dtcrit" / "schemas" / "dtcrit-packing-1.json").read_text())
CASES = {
    "lattice": ["--lattice", "fcc", "--cells", "2", "--kn", "1e5", "--ks", "3e4"],
    "random": ["--random", "40", "--cn", "5", "--kn", "1e5", "--sizes", "lognormal", "--spread", "0.3"],
    "dump-hertz": [str(ROOT / "examples" / "packings" / "random_lognormal_60.dump"), "--youngs", "7e10"],
    "damped": ["--lattice", "bcc", "--cells", "2", "--kn", "1e5", "--damping-ratio", "0.3",
               "--integrator", "forward-euler"],
}


def _doc(capsys, args) -> dict:
    assert main(["packing", *args, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


@pytest.mark.parametrize("name", sorted(CASES))
def test_outputs_validate(name, capsys):
    doc = _doc(capsys, CASES[name])
    jsonschema.validate(doc, SCHEMA)
    assert list(doc)[:4] == ["schema", "dtcrit_version", "units", "derivation_hashes"]


def test_the_schema_rejects_what_it_should(capsys):
    jsonschema.Draft202012Validator.check_schema(SCHEMA)
    good = _doc(capsys, CASES["lattice"])
    for key, value in (("dt_crit", -1.0), ("mode", "wobbly"), ("schema", "dtcrit-step/1"), ("n_contacts", 0)):
        bad = copy.deepcopy(good)
        bad[key] = value
        with pytest.raises(jsonschema.ValidationError):
            jsonschema.validate(bad, SCHEMA)
    bad = copy.deepcopy(good)
    del bad["units"]["dt_crit"]
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate(bad, SCHEMA)


def test_certificate_and_bracket_keys(capsys):
    """The certificate and the bracket are in the JSON and hold together: a certified lower end
    2/sqrt(sigma) below dt_crit, and dt_safe (a rigorous lower bound) below both."""
    doc = _doc(capsys, CASES["random"])
    jsonschema.validate(doc, SCHEMA)
    cert, br = doc["certificate"], doc["dt_bracket"]
    assert cert["certified"] is True and cert["sigma"] > doc["omega_max"] ** 2
    assert br["lower_from"] == "certificate" and br["upper"] == doc["dt_crit"]
    assert doc["dt_safe"] <= br["lower"] <= br["upper"]
    doc = _doc(capsys, CASES["lattice"] + ["--certify", "no", "--route", "matrix-free"])
    jsonschema.validate(doc, SCHEMA)
    assert doc["route"] == "matrix-free" and doc["certificate"]["certified"] is False
    assert doc["dt_bracket"]["lower_from"] == "dt_safe" and doc["dt_bracket"]["lower"] == doc["dt_safe"]
