"""Fuzz: arbitrary TOML documents (and mangled scene files) never produce a traceback.

Every run of ``dtcrit step`` on them ends with exit status 0 (a valid scene) or 2 with exactly one
line ``SCENE:key: reason`` on stderr.  The documents are built from the scene vocabulary mixed with
random keys and values of every TOML type (including inf, nan, huge integers, dates, nested
arrays and tables) and written with a small TOML writer below.
"""
import datetime as dt
import json
import math

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from dtcrit.cli import main
from dtcrit.scenes.model import CONTACT_ALL, PARTICLE_ALL, SHAPE_KEYS, TOP_KEYS
from support.paths import REPO_ROOT as ROOT

EXAMPLE_TEXTS = [p.read_text() for p in sorted((ROOT / "examples").glob("*.toml"))]
NAMES = list(TOP_KEYS) + list(PARTICLE_ALL) + list(CONTACT_ALL) + ["model", "linear", "hertz"]


# ----------------------------------------------------------------------------------------------
# a minimal TOML writer (inline tables and arrays: every document is one table)
# ----------------------------------------------------------------------------------------------
def toml_string(text: str) -> str:
    """A TOML basic string (JSON escapes are TOML escapes; DEL must be escaped too)."""
    return json.dumps(text, ensure_ascii=False).replace("\x7f", "\\u007f")


def toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return toml_string(v)
    if isinstance(v, (dt.datetime, dt.date, dt.time)):
        return v.isoformat()
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{toml_string(k)} = {toml_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(type(v))


def toml_document(doc: dict) -> str:
    return "".join(f"{toml_string(k)} = {toml_value(v)}\n" for k, v in doc.items())


text = st.text(alphabet=st.characters(blacklist_categories=("Cs",)), max_size=20)  # valid Unicode scalars
keys = st.one_of(st.sampled_from(NAMES), text.filter(bool))
scalars = st.one_of(
    st.booleans(),
    st.integers(min_value=-(2**63), max_value=2**63 - 1),
    st.floats(allow_nan=True, allow_infinity=True),
    st.floats(min_value=1e-320, max_value=1e308),
    st.sampled_from(["velocity-verlet", "leapfrog", "sphere", "ellipsoid", "superquadric", "box", "polyhedron",
                     "linear", "hertz", "all", "unlike", ""]),
    text,
    st.dates(),
    st.datetimes(min_value=dt.datetime(1, 1, 1), max_value=dt.datetime(9999, 12, 31)),
    st.times(),
)
values = st.recursive(
    scalars,
    lambda inner: st.one_of(st.lists(inner, max_size=5), st.dictionaries(keys, inner, max_size=5)),
    max_leaves=25,
)
positive = st.floats(min_value=1e-300, max_value=1e300)
triple = st.lists(st.one_of(positive, values), min_size=0, max_size=4)

particle_tables = st.fixed_dictionaries(
    {"shape": st.one_of(st.sampled_from(sorted(SHAPE_KEYS)), values)},
    optional={
        "radius": st.one_of(positive, values),
        "semi_axes": triple,
        "half_lengths": triple,
        "exponents": st.lists(st.one_of(st.floats(0.0, 3.0), values), max_size=3),
        "vertices": st.lists(st.lists(st.one_of(st.floats(-2, 2), values), min_size=2, max_size=4), max_size=10),
        "density": st.one_of(positive, values),
        "mass": st.one_of(positive, values),
        "youngs_modulus": st.one_of(positive, values),
        "poisson_ratio": st.one_of(st.floats(-1.5, 0.7), values),
    },
)
contact_tables = st.fixed_dictionaries(
    {"model": st.one_of(st.sampled_from(["linear", "hertz"]), values)},
    optional={k: st.one_of(positive, st.floats(-1, 2), values) for k in CONTACT_ALL if k != "model"},
)
scene_like = st.fixed_dictionaries(
    {},
    optional={
        "integrator": st.one_of(st.sampled_from(["velocity-verlet", "paper-eq40", "forward-euler", "leapfrog-centred"]), values),
        "omega_max": st.one_of(positive, values),
        "safety": st.one_of(st.floats(0, 2), values),
        "pairs": st.one_of(st.sampled_from(["all", "unlike"]), values),
        "particle": st.one_of(st.lists(particle_tables, max_size=3), particle_tables, values),
        "contact": st.one_of(contact_tables, values),
    },
).flatmap(lambda d: st.dictionaries(keys, values, max_size=2).map(lambda extra: {**extra, **d}))


def _check(tmp_path, capsys, data: bytes):
    path = tmp_path / "fuzz.toml"
    path.write_bytes(data)
    rc = main(["step", str(path)])
    out, err = capsys.readouterr()
    assert rc in (0, 2)
    if rc == 2:
        lines = err.splitlines()
        assert len(lines) == 1 and lines[0].startswith(f"{path}:") and ": " in lines[0][len(str(path)) + 1:], err
        assert out == ""
    else:
        assert "dt_crit" in out
        assert all(line.startswith(f"{path}:") and ": warning: " in line for line in err.splitlines())


SETTINGS = settings(max_examples=60, suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])


@SETTINGS
@given(doc=scene_like)
def test_scene_shaped_documents(tmp_path, capsys, doc):
    _check(tmp_path, capsys, toml_document(doc).encode())


@SETTINGS
@given(doc=st.dictionaries(keys, values, max_size=6))
def test_arbitrary_documents(tmp_path, capsys, doc):
    _check(tmp_path, capsys, toml_document(doc).encode())


@SETTINGS
@given(base=st.sampled_from(EXAMPLE_TEXTS), data=st.data())
def test_mangled_example_files(tmp_path, capsys, base, data):
    raw = bytearray(base.encode())
    for _ in range(data.draw(st.integers(1, 4))):
        op = data.draw(st.sampled_from(["delete", "insert", "replace"]))
        i = data.draw(st.integers(0, len(raw) - 1))
        if op == "delete":
            del raw[i: i + data.draw(st.integers(1, 8))]
        elif op == "insert":
            raw[i:i] = data.draw(st.binary(min_size=1, max_size=6) | st.sampled_from([b"[", b"]", b"=", b'"', b"\n", b"-", b"e9"]))
        else:
            raw[i] = data.draw(st.integers(0, 255))
    _check(tmp_path, capsys, bytes(raw))


decade = lambda lo, hi: st.floats(lo, hi).map(lambda e: 10.0**e)  # noqa: E731


@st.composite
def valid_scenes(draw):
    kind = draw(st.sampled_from(["sphere", "ellipsoid", "superquadric", "box", "polyhedron"]))
    size = draw(decade(-6, 3))
    r = sorted((size * draw(st.floats(0.2, 1.0)) for _ in range(3)), reverse=True)
    r[0] = size
    table = {"shape": kind}
    if kind == "sphere":
        table["radius"] = size
    elif kind in ("ellipsoid", "superquadric"):
        table["semi_axes"] = r
        if kind == "superquadric":
            table["exponents"] = [draw(st.floats(0.2, 1.0)), draw(st.floats(0.2, 1.0))]
    elif kind == "box":
        table["half_lengths"] = r
    else:
        table["vertices"] = [[sx * r[0], sy * r[1], sz * r[2]] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]
    table["density"] = draw(decade(-1, 5))
    contact = {"model": draw(st.sampled_from(["linear", "hertz"]))}
    doc = {"integrator": draw(st.sampled_from(["velocity-verlet", "paper-eq40", "forward-euler", "symplectic-euler",
                                               "leapfrog", "leapfrog-centred", "velocity-verlet-predicted"]))}
    if contact["model"] == "linear":
        contact["kn"] = draw(decade(-3, 15))
        contact["ks"] = contact["kn"] * draw(st.floats(0.1, 1.0))
    else:
        contact.update(youngs_modulus=draw(decade(5, 12)), poisson_ratio=draw(st.floats(0.0, 0.49)),
                       velocity=draw(decade(-3, 2)))
        if kind != "sphere":
            contact["curvature_radius"] = size
    damping = draw(st.sampled_from(["none", "restitution", "damping_ratio"]))
    if damping == "restitution":
        contact["restitution"] = draw(st.floats(0.01, 1.0))
    elif damping == "damping_ratio":
        contact["damping_ratio"] = draw(decade(-6, 2))
    if draw(st.booleans()):
        doc["omega_max"] = draw(decade(-3, 6))
    doc["particle"] = [table]
    doc["contact"] = contact
    return doc


@settings(max_examples=60, suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(doc=valid_scenes())
def test_valid_scenes_across_decades_give_finite_results(tmp_path, capsys, doc):
    path = tmp_path / "valid.toml"
    path.write_text(toml_document(doc))
    rc = main(["step", str(path), "--json"])
    out, err = capsys.readouterr()
    assert rc == 0, err
    result = json.loads(out)
    assert math.isfinite(result["dt_crit"]) and result["dt_crit"] >= 0
    if result["dt_crit"] == 0:
        assert result["integrator"] in ("forward-euler", "paper-eq40")
    for e in result["estimators"].values():
        assert e["dt"] is None or (math.isfinite(e["dt"]) and e["dt"] > 0)
