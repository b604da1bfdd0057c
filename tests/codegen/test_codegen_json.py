"""`dtcrit codegen SCENE --lang L --json`: the metadata document (schema dtcrit-codegen/1) validates against
src/dtcrit/schemas/dtcrit-codegen-1.json for every example and language, starts with the envelope, carries
the source the command emits, and the schema refuses malformed documents."""
import json

import jsonschema
import pytest

from dtcrit.cli import main
from support.paths import REPO_ROOT as ROOT

SCHEMA = json.loads((ROOT / "src" / "dtcrit" / "schemas" / "dtcrit-codegen-1.json").read_text())
REFUSED = {"bonded_pair.toml", "rolling_resistance.toml"}
"""Scenes with rotational springs or bonds, which the kernel does not carry: codegen refuses them
(tests/codegen/test_codegen_cli.py::test_scenes_whose_springs_the_kernel_lacks_are_refused)."""
EXAMPLES = sorted(p.name for p in (ROOT / "examples").glob("*.toml") if p.name not in REFUSED)


def _doc(capsys, scene, lang):
    assert main(["codegen", str(ROOT / "examples" / scene), "--lang", lang, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


@pytest.mark.parametrize("lang", ["c", "numpy", "fortran"])
@pytest.mark.parametrize("scene", EXAMPLES)
def test_metadata_validates(scene, lang, capsys):
    doc = _doc(capsys, scene, lang)
    jsonschema.validate(doc, SCHEMA)
    assert doc["language"] == lang and doc["source"].endswith("\n")
    assert f"Derivation hash: {doc['kernel_hash']}" in doc["source"]


def test_envelope_and_source_match_the_plain_output(capsys):
    import dtcrit
    from dtcrit.json_meta import derivation_hashes

    scene = "damped_ellipsoids.toml"
    doc = _doc(capsys, scene, "c")
    assert list(doc)[:4] == ["schema", "dtcrit_version", "units", "derivation_hashes"]
    assert doc["schema"] == "dtcrit-codegen/1" and doc["dtcrit_version"] == dtcrit.__version__
    assert doc["derivation_hashes"] == derivation_hashes()
    assert doc["integrator"] == "velocity-verlet" and [a["name"] for a in doc["arguments"]][:2] == ["m", "I_xx"]
    assert main(["codegen", str(ROOT / "examples" / scene), "--lang", "c"]) == 0
    assert capsys.readouterr().out == doc["source"]


def test_json_with_out_writes_the_file(tmp_path, capsys):
    out = tmp_path / "k.f90"
    assert main(["codegen", str(ROOT / "examples" / "mixed_pair.toml"), "--lang", "fortran", "--out", str(out), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert out.read_text() == doc["source"]


def test_the_schema_rejects_what_it_should(capsys):
    jsonschema.Draft202012Validator.check_schema(SCHEMA)
    good = _doc(capsys, "glass_spheres_hertz.toml", "numpy")
    mutations = (lambda d: d.pop("kernel_hash"), lambda d: d.update(language="rust"), lambda d: d.update(integrator="rk4"),
                 lambda d: d["arguments"][0].update(unit="furlong"), lambda d: d.update(kernel_hash="xyz"),
                 lambda d: d.pop("units"), lambda d: d["formulas"].update(equations=[]),
                 lambda d: d.update(source=d["source"].rstrip("\n")), lambda d: d["step_hashes"].update(other="0" * 16))
    for mutate in mutations:
        doc = json.loads(json.dumps(good))
        mutate(doc)
        with pytest.raises(jsonschema.ValidationError):
            jsonschema.validate(doc, SCHEMA)
