"""`dtcrit step --json` validates against its published JSON schema (src/dtcrit/schemas/dtcrit-step-1.json),
for every example and for the scene kinds the examples do not cover (walls, dashpot-only modes, dense packings,
size distributions, Hertz, a tiny omega_max)."""
from __future__ import annotations

import json

import jsonschema
import pytest
from support.json_keys import numeric_keys

from dtcrit.cli import main
from support.paths import REPO_ROOT as ROOT

SCHEMA = json.loads((ROOT / "src" / "dtcrit" / "schemas" / "dtcrit-step-1.json").read_text())
SPHERE = '[[particle]]\nshape = "sphere"\nradius = 0.001\ndensity = 2500.0\n'
EXTRA = {
    "dashpot": f'integrator = "velocity-verlet"\n{SPHERE}[contact]\nmodel = "linear"\nkn = 1e5\nks = 0.0\nrestitution = 0.5\n',
    "free-shear": f'integrator = "leapfrog-centred"\n{SPHERE}[contact]\nmodel = "linear"\nkn = 1e5\nks = 0.0\n',
    "wall-dense": (f'integrator = "leapfrog"\ncoordination_max = 6\n{SPHERE}[contact]\nmodel = "linear"\nkn = 1e5\nks = 1e4\n'
                   'damping_ratio = 0.2\n[[wall]]\nkn = 1e5\nks = 0.0\ncs = 0.01\n'),
    "sizes-hertz": ('integrator = "velocity-verlet"\ncoordination_max = 12\n[[particle]]\nshape = "sphere"\n'
                    'lognormal = {median = 0.001, sigma = 0.3, min = 0.0005, max = 0.002}\ndensity = 2500.0\n'
                    '[contact]\nmodel = "hertz"\nyoungs_modulus = 7e10\npoisson_ratio = 0.25\nvelocity = 1.0\nrestitution = 0.8\n'),
    "tiny-omega": ('integrator = "velocity-verlet"\nomega_max = 1e-320\n[[particle]]\nshape = "ellipsoid"\n'
                   'semi_axes = [3.0, 2.0, 1.0]\ndensity = 1000.0\n[contact]\nmodel = "linear"\nkn = 1e10\nks = 1e10\n'),
}


def _doc(capsys, path):
    assert main(["step", str(path), "--json"]) == 0
    return json.loads(capsys.readouterr().out)


@pytest.mark.parametrize("scene", sorted(p.name for p in (ROOT / "examples").glob("*.toml")))
def test_examples_validate(scene, capsys):
    jsonschema.validate(_doc(capsys, ROOT / "examples" / scene), SCHEMA)


@pytest.mark.parametrize("name", sorted(EXTRA))
def test_other_scenes_validate(name, tmp_path, capsys):
    path = tmp_path / f"{name}.toml"
    path.write_text(EXTRA[name])
    jsonschema.validate(_doc(capsys, path), SCHEMA)


def test_the_schema_rejects_what_it_should(capsys):
    """The schema is not vacuous: a missing key, an unknown governing value or a negative step are refused."""
    jsonschema.Draft202012Validator.check_schema(SCHEMA)
    good = _doc(capsys, ROOT / "examples" / "glass_spheres_hertz.toml")
    for mutate in (lambda d: d.pop("dt_isolated"), lambda d: d.update(governing="banana"),
                   lambda d: d.update(dt_crit=-1.0), lambda d: d["pairs"][0].update(method="guess")):
        doc = json.loads(json.dumps(good))
        mutate(doc)
        with pytest.raises(jsonschema.ValidationError):
            jsonschema.validate(doc, SCHEMA)


DIMENSIONLESS = {"zeta", "zeta_mode", "zeta_normal", "zeta_shear", "damping_ratio", "restitution", "safety", "ks_ratio",
                 "fractions", "sigma", "B_max", "B_sum", "4", "6", "12", "number", "coordination_max", "particles",
                 "attained_at", "overlap_max", "poisson_ratio"}
"""Numbers of a step document without a unit (ratios, factors, counts); every other number must be in ``units``."""


def _all_docs(capsys, tmp_path):
    docs = [_doc(capsys, p) for p in sorted((ROOT / "examples").glob("*.toml"))]
    for name, text in EXTRA.items():
        path = tmp_path / f"{name}.toml"
        path.write_text(text)
        docs.append(_doc(capsys, path))
    return docs


def test_envelope_version_and_derivation_hashes(capsys):
    """The envelope of every --json: the package version and, per generated module, the hash its header names."""
    import re

    import dtcrit

    doc = _doc(capsys, ROOT / "examples" / "paper_ellipsoids.toml")
    assert list(doc)[:4] == ["schema", "dtcrit_version", "units", "derivation_hashes"]
    assert doc["dtcrit_version"] == dtcrit.__version__
    expected = {}
    for f in sorted((ROOT / "src" / "dtcrit" / "_generated").glob("*.py")):
        m = re.search(r"^# Derivation hash: (\S+)$", f.read_text(), re.M)
        if m:
            expected[f.stem] = m.group(1)
    assert expected and doc["derivation_hashes"] == expected


def test_every_dimensional_number_has_its_unit(capsys, tmp_path):
    docs = _all_docs(capsys, tmp_path)
    seen = set().union(*(numeric_keys(d) for d in docs))
    units = docs[0]["units"]
    missing = seen - set(units) - DIMENSIONLESS
    assert not missing, f"numbers without a unit: {sorted(missing)}"
    assert not (set(units) & DIMENSIONLESS)
    assert units["dt_crit"] == "s" and units["kn"] == "N/m" and units["cn"] == "N s/m" and units["A"] == "1/kg"
    assert units["lambda_k"] == "1/s^2" and units["inertia"] == "kg m^2" and units["omega_max"] == "rad/s"


def test_the_schema_requires_the_envelope(capsys):
    good = _doc(capsys, ROOT / "examples" / "paper_ellipsoids.toml")
    for mutate in (lambda d: d.pop("units"), lambda d: d.pop("derivation_hashes"), lambda d: d.update(dtcrit_version=1),
                   lambda d: d["units"].pop("dt_crit"), lambda d: d.update(derivation_hashes={})):
        doc = json.loads(json.dumps(good))
        mutate(doc)
        with pytest.raises(jsonschema.ValidationError):
            jsonschema.validate(doc, SCHEMA)
