"""``dtcrit figures``: the default run writes every PNG + CSV and a strict-JSON document (the envelope of
every dtcrit JSON, then the summary) that validates against src/dtcrit/schemas/dtcrit-figures-1.json; its
quaternions are body to world, as dtcrit.coefficient_matrix takes them; bad input is one line on standard
error with exit status 2."""
from __future__ import annotations

import copy
import csv
import fnmatch
import io
import json
import math
import re
from contextlib import redirect_stdout

import jsonschema
import numpy as np
import pytest

from dtcrit.cli import main
from support.paths import SRC

EXPECTED = [
    "fig3_damping", "fig4_stiffness", "fig5_density", "fig6_aspect_ratio",
    "figA2_centre_moved", "figA4_orientation_changed", "figA_shapes",
]


def _strict(text):
    def bad(name):
        raise ValueError(f"non-finite JSON constant {name}")

    return json.loads(text, parse_constant=bad)


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    out = tmp_path_factory.mktemp("figs")
    buf = io.StringIO()
    with redirect_stdout(buf):
        code = main(["figures", "--out", str(out), "--json"])
    return code, _strict(buf.getvalue()), out


def test_default_run_writes_every_figure_and_csv(run):
    code, _, out = run
    assert code == 0
    for stem in EXPECTED:
        png = out / f"{stem}.png"
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", stem
        rows = list(csv.reader((out / f"{stem}.csv").open()))
        assert len(rows) > 2 and all(len(r) == len(rows[0]) for r in rows), stem


def test_json_summary_keys(run):
    _, summary, _ = run
    assert summary["schema"] == "dtcrit-figures/1"
    ap = summary["appendix_a"]
    for key in ("orthogonal", "max_found", "max_config", "orthogonal_is_max"):
        assert key in ap
    assert ap["orthogonal_is_max"] is False and ap["max_found"] > ap["orthogonal"]
    ar = summary["aspect_ratio"]
    for key in ("min_ratio", "max_ratio", "fraction_over_1e4"):
        assert isinstance(ar[key], float)
    assert 0.0 < ar["fraction_over_1e4"] < 0.01 and ar["min_ratio"] < 1e4
    assert summary["fig4"]["eq46_trend_with_N"] == "increases"
    assert summary["fig4"]["verified_trend_with_N"]["velocity-verlet"] == "decreases"


def test_fig4_csv_undamped_point_is_eq48(run):
    """Row k_n = 1e10, N = 0: Eq. (46) = Eq. (48) = 2/sqrt(k_n A_max), A_max = 20/m, m = 8000 pi kg."""
    _, _, out = run
    rows = list(csv.DictReader((out / "fig4_stiffness.csv").open()))
    row = next(r for r in rows if float(r["k_n"]) == 1e10 and r["N"] == "0")
    expected = 2.0 / math.sqrt(1e10 * 20.0 / (1000.0 * 8.0 * math.pi))
    assert float(row["dt_eq46_printed"]) == pytest.approx(expected, rel=1e-12)
    assert float(row["dt_velocity-verlet_A_max"]) == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("argv, key", [
    (["figures", "--only", "fig9"], "only"),
    (["figures", "--only", ","], "only"),
])
def test_bad_input_is_one_line(argv, key, capsys, tmp_path):
    code = main(argv + ["--out", str(tmp_path)])
    err = capsys.readouterr().err
    assert code == 2
    assert err.count("\n") == 1 and key in err


def test_out_must_be_a_folder(tmp_path, capsys):
    f = tmp_path / "file.txt"
    f.write_text("x")
    assert main(["figures", "--only", "fig3", "--out", str(f)]) == 2
    assert "out" in capsys.readouterr().err


# ---------------------------------------------------------------------------------- JSON: envelope and schema

SCHEMA_PATH = SRC / "dtcrit" / "schemas" / "dtcrit-figures-1.json"


def _schema():
    return json.loads(SCHEMA_PATH.read_text())


def test_json_starts_with_the_envelope(run):
    import dtcrit
    from dtcrit.json_meta import derivation_hashes

    _, doc, _ = run
    assert list(doc)[:4] == ["schema", "dtcrit_version", "units", "derivation_hashes"]
    assert doc["schema"] == "dtcrit-figures/1" and doc["dtcrit_version"] == dtcrit.__version__
    # the hashes are the ones the generated modules' headers name, read here independently
    expected = {}
    for f in sorted((SCHEMA_PATH.parents[1] / "_generated").glob("*.py")):
        m = re.search(r"^# Derivation hash: (\S+)$", f.read_text(), re.M)
        if m:
            expected[f.stem] = m.group(1)
    assert expected and doc["derivation_hashes"] == expected == derivation_hashes()


def test_json_validates_against_its_schema(run):
    _, doc, _ = run
    jsonschema.Draft202012Validator.check_schema(_schema())
    jsonschema.validate(doc, _schema())


def test_a_subset_validates_too(tmp_path):
    buf = io.StringIO()
    with redirect_stdout(buf):
        assert main(["figures", "--only", "fig3,fig4", "--out", str(tmp_path), "--json"]) == 0
    doc = _strict(buf.getvalue())
    assert set(doc) == {"schema", "dtcrit_version", "units", "derivation_hashes", "fig3", "fig4"}
    jsonschema.validate(doc, _schema())


@pytest.mark.parametrize("mutate", [
    lambda d: d.pop("units"),
    lambda d: d.update(schema="dtcrit-figures/2"),
    lambda d: d.update(derivation_hashes={}),
    lambda d: [d.pop(k) for k in ("fig3", "fig4", "fig5", "aspect_ratio", "appendix_a")],
    lambda d: d["fig3"].pop("verified"),
    lambda d: d["fig4"].update(eq46_trend_with_N="up"),
    lambda d: d["fig5"]["verified_a_max"]["velocity-verlet"].__setitem__(0, -1.0),
    lambda d: d["aspect_ratio"].update(fraction_over_1e4=1.5),
    lambda d: d["aspect_ratio"]["verified"].pop("a_bound_below_a_max"),
    lambda d: d["appendix_a"]["orthogonal_config"].pop("quaternion_2_body_to_world_wxyz"),
    lambda d: d["appendix_a"]["max_config"].update(quaternion_2_body_to_world_wxyz=[-0.5, 0.5, 0.5, 0.5]),
    lambda d: d["appendix_a"]["max_config"]["r1"].pop(),
    lambda d: d["appendix_a"]["shapes"]["box"].update(eq26_is_upper_bound_lambda="no"),
    lambda d: d["appendix_a"]["scenarios"].pop("centre_moved"),
], ids=lambda f: f.__code__.co_firstlineno)
def test_the_schema_rejects_broken_documents(run, mutate):
    """The schema is not vacuous: each of these damaged documents is refused."""
    _, good, _ = run
    doc = copy.deepcopy(good)
    mutate(doc)
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate(doc, _schema())


def _numeric_paths(x, path=""):
    if isinstance(x, dict):
        for k, v in x.items():
            yield from _numeric_paths(v, f"{path}.{k}" if path else str(k))
    elif isinstance(x, list):
        for v in x:
            yield from _numeric_paths(v, path)
    elif isinstance(x, (int, float)) and not isinstance(x, bool):
        yield path


def test_every_number_has_exactly_one_unit(run):
    _, doc, _ = run
    units = doc["units"]
    body = {k: v for k, v in doc.items() if k not in ("schema", "dtcrit_version", "units", "derivation_hashes")}
    paths = set(_numeric_paths(body))
    assert len(paths) > 100
    for path in sorted(paths):
        hits = [u for u in units if fnmatch.fnmatchcase(path, u)]
        assert len(hits) == 1, (path, hits)
    assert units["fig4.eq46_printed"] == "s" and units["fig4.first_point.k_n"] == "N/m"
    assert units["appendix_a.*.accel"] == "m/s^2" and units["appendix_a.*.lambda_max"] == "1/kg"


# ---------------------------------------------------------------------------------- one rotation convention

def _rigid_body_matrix(m, inertia, Q2, r1, r2):
    """A by unit forces through the rigid-body equations (Eqs. 1-19), particle 1 axis aligned, particle 2's
    body-to-world orientation Q2 (body components of a world vector: Q2^T v)."""
    cols = []
    for F in np.eye(3):
        wd1 = np.cross(r1, -F) / inertia
        wd2 = Q2 @ ((Q2.T @ np.cross(r2, F)) / inertia)
        cols.append((np.cross(wd2, r2) + F / m) - (np.cross(wd1, r1) - F / m))
    return np.column_stack(cols)


@pytest.mark.parametrize("key", ["orthogonal_config", "max_config", "max_lambda_config"])
def test_json_quaternion_round_trip(run, key):
    """The quaternion of a configuration, passed back to coefficient_matrix, gives the reported |A F|
    (0.520778 for the orthogonal one); SciPy's from_quat (body to world, (x, y, z, w)) and a rigid-body
    evaluation by unit forces agree; the conjugate quaternion (the other convention) does not."""
    from scipy.spatial.transform import Rotation

    import dtcrit
    from dtcrit.bodies import Ellipsoid

    _, doc, _ = run
    cfg = doc["appendix_a"][key]
    q = np.array(cfg["quaternion_2_body_to_world_wxyz"])
    e = Ellipsoid(3.0, 2.0, 1.0, density=1.0)
    r1, r2 = np.array(cfg["r1"]), np.array(cfg["r2"])
    force = np.ones(3)
    A = dtcrit.coefficient_matrix(e, e, r1, r2, body_to_world=(None, q))
    assert np.linalg.norm(A @ force) == pytest.approx(cfg["accel"], rel=2e-6)
    assert np.linalg.eigvalsh(A)[-1] == pytest.approx(cfg["lambda_max"], rel=2e-6)
    np.testing.assert_allclose(A, np.array(cfg["matrix"]), rtol=0, atol=2e-6 * np.max(np.abs(A)))
    Q2 = Rotation.from_quat(np.roll(q, -1)).as_matrix()
    np.testing.assert_allclose(dtcrit.coefficient_matrix(e, e, r1, r2, body_to_world=(np.eye(3), Q2)), A, rtol=0, atol=1e-12)
    np.testing.assert_allclose(_rigid_body_matrix(e.mass, np.array(e.inertia), Q2, r1, r2), A, rtol=0,
                               atol=1e-12 * np.max(np.abs(A)))
    conj = dtcrit.coefficient_matrix(e, e, r1, r2, body_to_world=(None, q * np.array([1.0, -1.0, -1.0, -1.0])))
    if key == "orthogonal_config":
        assert doc["appendix_a"]["orthogonal"] == pytest.approx(0.5207776, rel=1e-6)
        assert np.linalg.norm(conj @ force) == pytest.approx(0.620, abs=5e-4)  # what the conjugate would give
    if key != "max_lambda_config":  # that one is all but axis aligned: its conjugate is the same rotation
        assert abs(np.linalg.norm(conj @ force) - cfg["accel"]) > 1e-3
