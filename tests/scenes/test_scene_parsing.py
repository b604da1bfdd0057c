"""Scene files: the examples parse to the intended particles and contact laws; every malformed
scene gives exactly one line ``SCENE:key: reason`` on stderr and exit status 2 (never a traceback)."""
import math

import pytest

from dtcrit.cli import main
from dtcrit.errors import InputError
from dtcrit.scenes.laws import resolve_pair
from dtcrit.scenes.scene import load_scene, parse_scene
from support.paths import REPO_ROOT as ROOT

EXAMPLES = sorted((ROOT / "examples").glob("*.toml"))

GOOD = """
integrator = "velocity-verlet"
[[particle]]
shape = "ellipsoid"
semi_axes = [3.0, 2.0, 1.0]
density = 1000.0
[contact]
model = "linear"
kn = 1.0e10
ks = 1.0e10
"""


def test_examples_exist_and_parse():
    names = {p.name for p in EXAMPLES}
    assert {"paper_ellipsoids.toml", "glass_spheres_hertz.toml", "superquadric.toml", "polyhedron_cube.toml",
            "mixed_pair.toml", "damped_ellipsoids.toml"} <= names
    for path in EXAMPLES:
        scene = load_scene(path)
        assert scene.particles and scene.integrator


def test_paper_scene_values():
    """Peng et al. 2020, Section 6: a = 3, b = 2, c = 1 m, rho = 1000: m = 1000 * 4/3 pi abc."""
    s = load_scene(ROOT / "examples" / "paper_ellipsoids.toml")
    p = s.particles[0]
    assert p.shape.mass == pytest.approx(1000 * 4 / 3 * math.pi * 6, rel=1e-14)
    # I_xx = m (b^2 + c^2)/5 etc., computed here from the definition's closed form for ellipsoids
    m = p.shape.mass
    assert p.shape.inertia == pytest.approx((m * 5 / 5, m * 10 / 5, m * 13 / 5), rel=1e-13)
    pc = resolve_pair(s, 1, 1)
    assert (pc.kn, pc.ks, pc.cn, pc.cs) == (1e10, 1e10, 0.0, 0.0)
    assert pc.m_star == pytest.approx(m / 2, rel=1e-15)
    assert s.omega_max == 1.0 and s.safety == 1.0 and s.identical


def test_two_tables_make_three_pairs_unless_unlike():
    s = load_scene(ROOT / "examples" / "mixed_pair.toml")
    assert s.pair_numbers() == ((1, 1), (1, 2), (2, 2))
    second = '[[particle]]\nshape = "sphere"\nradius = 1.0\nmass = 2.0\n'
    unlike = parse_scene('pairs = "unlike"\n' + GOOD + second)  # the array of tables may continue after [contact]
    assert unlike.pair_numbers() == ((1, 2),)
    assert unlike.particle(2).shape.mass == 2.0


def test_damping_from_restitution_matches_the_reference_formula():
    s = parse_scene(GOOD + "restitution = 0.5\n")
    pc = resolve_pair(s, 1, 1)
    zeta = -math.log(0.5) / math.sqrt(math.pi**2 + math.log(0.5) ** 2)
    assert pc.zeta == pytest.approx(zeta, rel=1e-15)
    assert pc.cn == pytest.approx(2 * zeta * math.sqrt(1e10 * pc.m_star), rel=1e-14)


# ----------------------------------------------------------------------------------------------
# The table of bad scenes
# ----------------------------------------------------------------------------------------------
def _edit(old, new):
    assert old in GOOD, old
    return GOOD.replace(old, new)


BAD = [
    # (scene text, key, part of the reason)
    (_edit('integrator = "velocity-verlet"', 'integrater = "velocity-verlet"'), "integrater", "did you mean 'integrator'"),
    (_edit('integrator = "velocity-verlet"', ""), "integrator", "missing"),
    (_edit('"velocity-verlet"', '"velocity-verlett"'), "integrator", "did you mean 'velocity-verlet'"),
    (_edit('"velocity-verlet"', "3"), "integrator", "must be a string"),
    (_edit('semi_axes = [3.0, 2.0, 1.0]', 'semi_axis = [3.0, 2.0, 1.0]'), "particle[1].semi_axis", "did you mean 'semi_axes'"),
    (_edit('semi_axes = [3.0, 2.0, 1.0]', ''), "particle[1].semi_axes", "missing"),
    (_edit('semi_axes = [3.0, 2.0, 1.0]', 'semi_axes = [3.0, 2.0]'), "particle[1].semi_axes", "3 entries"),
    (_edit('semi_axes = [3.0, 2.0, 1.0]', 'semi_axes = [3.0, "2", 1.0]'), "particle[1].semi_axes[2]", "must be a number"),
    (_edit('semi_axes = [3.0, 2.0, 1.0]', 'semi_axes = [3.0, -2.0, 1.0]'), "particle[1].semi_axes[2]", "positive"),
    (_edit('semi_axes = [3.0, 2.0, 1.0]', 'semi_axes = [3.0, inf, 1.0]'), "particle[1].semi_axes[2]", "finite"),
    (_edit('semi_axes = [3.0, 2.0, 1.0]', 'semi_axes = [3.0, nan, 1.0]'), "particle[1].semi_axes[2]", "finite"),
    (_edit('semi_axes = [3.0, 2.0, 1.0]', 'semi_axes = [1.0, 2.0, 3.0]'), "particle[1].semi_axes", "a >= b >= c"),
    (_edit('semi_axes = [3.0, 2.0, 1.0]', 'semi_axes = [3.0, 2.0, 1.0]\nradius = 1.0'), "particle[1].radius", "not used by a ellipsoid"),
    (_edit('shape = "ellipsoid"', 'shape = "ellipse"'), "particle[1].shape", "did you mean 'ellipsoid'"),
    (_edit('shape = "ellipsoid"', 'shape = "torus"'), "particle[1].shape", "unknown shape"),
    (_edit('shape = "ellipsoid"', ''), "particle[1].shape", "missing"),
    (_edit('density = 1000.0', ''), "particle[1].density", "missing"),
    (_edit('density = 1000.0', 'density = 1000.0\nmass = 3.0'), "particle[1].mass", "not both"),
    (_edit('density = 1000.0', 'density = 0.0'), "particle[1].density", "positive"),
    (_edit('density = 1000.0', 'density = -1e3'), "particle[1].density", "positive"),
    (_edit('density = 1000.0', 'density = true'), "particle[1].density", "must be a number"),
    (_edit('density = 1000.0', 'density = 1e308'), "particle[1].density", "not a positive finite mass"),
    (_edit('kn = 1.0e10', ''), "contact.kn", "missing"),
    (_edit('kn = 1.0e10', 'kn = "1e10"'), "contact.kn", "must be a number"),
    (_edit('kn = 1.0e10', 'kn = 0'), "contact.kn", "positive"),
    (_edit('kn = 1.0e10', 'kn = -inf'), "contact.kn", "finite"),
    (_edit('kn = 1.0e10', 'k_n = 1.0e10'), "contact.k_n", "did you mean 'kn'"),
    (_edit('model = "linear"', 'model = "hooke"'), "contact.model", "unknown contact model"),
    (_edit('model = "linear"', ''), "contact.model", "missing"),
    (GOOD + "cn = 1.0\nrestitution = 0.5\n", "contact.restitution", "conflicting damping"),
    (GOOD + "restitution = 0.5\ndamping_ratio = 0.2\n", "contact.damping_ratio", "conflicting damping"),
    (GOOD + "restitution = 1.5\n", "contact.restitution", "at most 1"),
    (GOOD + "restitution = 0\n", "contact.restitution", "positive"),
    (GOOD + "cn = -1.0\n", "contact.cn", "non-negative"),
    (GOOD.replace("[contact]", "[contactt]"), "contactt", "did you mean 'contact'"),
    (GOOD.split("[contact]")[0], "contact", "missing"),
    ('integrator = "velocity-verlet"\n[contact]\nmodel = "linear"\nkn = 1.0\nks = 1.0\n', "particle", "missing"),
    (GOOD.replace("[[particle]]", "particle = 5\n[unused]"), "unused", "unknown key"),
    ("particle = 3\n" + GOOD.split("[[particle]]")[0], "particle", "must be one or more"),
    ("particle = []\n" + GOOD.split("[[particle]]")[0], "particle", "must be one or more"),
    ("omega_max = 0\n" + GOOD, "omega_max", "positive"),
    ("omega_max = -1.0\n" + GOOD, "omega_max", "positive"),
    ("safety = 1.5\n" + GOOD, "safety", "at most 1"),
    ("safety = 0\n" + GOOD, "safety", "positive"),
    ('pairs = "unlike"\n' + GOOD, "pairs", "needs two"),
    ('pairs = "some"\n' + GOOD, "pairs", "unknown pairs setting"),
    (_edit('semi_axes = [3.0, 2.0, 1.0]', 'semi_axes = [3.0, 2.0, 1.0]\nexponents = [1.0, 1.0]'), "particle[1].exponents", "not used"),
    (_edit('shape = "ellipsoid"\nsemi_axes = [3.0, 2.0, 1.0]', 'shape = "superquadric"\nsemi_axes = [3.0, 2.0, 1.0]\nexponents = [1.0, 2.5]'),
     "particle[1].exponents", "convex"),
    (_edit('shape = "ellipsoid"\nsemi_axes = [3.0, 2.0, 1.0]', 'shape = "polyhedron"\nvertices = [[0,0,0],[1,0,0],[0,1,0],[0,0,1]]'),
     "particle[1].vertices", "centrally symmetric"),
    (_edit('shape = "ellipsoid"\nsemi_axes = [3.0, 2.0, 1.0]', 'shape = "polyhedron"\nvertices = [[0,0,0],[1,0,0]]'),
     "particle[1].vertices", "at least 4"),
    (_edit('shape = "ellipsoid"\nsemi_axes = [3.0, 2.0, 1.0]', 'shape = "polyhedron"\nvertices = [[1,1,1],[1,-1,1],[-1,1,1],[-1,-1,1],[1,1,-1],[1,-1,-1],[-1,1,-1],[-1,-1,-1],[0,0,0]]'),
     "particle[1].vertices", "not convex"),
    (_edit('shape = "ellipsoid"\nsemi_axes = [3.0, 2.0, 1.0]', 'shape = "polyhedron"\nvertices = [[0,0,0],[1,0,0],[0,1,0],"x"]'),
     "particle[1].vertices[4]", "[x, y, z]"),
    (_edit('shape = "ellipsoid"\nsemi_axes = [3.0, 2.0, 1.0]', 'shape = "box"\nhalf_lengths = [1.0, 2.0, 3.0]'), "particle[1].half_lengths", "a >= b >= c"),
    (_edit('shape = "ellipsoid"\nsemi_axes = [3.0, 2.0, 1.0]', 'shape = "sphere"\nradius = [1.0]'), "particle[1].radius", "must be a number"),
    (_edit('model = "linear"\nkn = 1.0e10\nks = 1.0e10', 'model = "hertz"\nkn = 1.0e10'), "contact.kn", "not used by the hertz"),
    (_edit('model = "linear"\nkn = 1.0e10\nks = 1.0e10', 'model = "hertz"\nvelocity = 1.0\nyoungs_modulus = 1e9\npoisson_ratio = 0.3'),
     "contact.curvature_radius", "missing"),
    (_edit('model = "linear"\nkn = 1.0e10\nks = 1.0e10', 'model = "hertz"\nvelocity = 1.0\npoisson_ratio = 0.3\ncurvature_radius = 1.0'),
     "contact.youngs_modulus", "missing"),
    (_edit('model = "linear"\nkn = 1.0e10\nks = 1.0e10', 'model = "hertz"\nyoungs_modulus = 1e9\npoisson_ratio = 0.6\nvelocity = 1.0\ncurvature_radius = 1.0'),
     "contact.poisson_ratio", "less than 0.5"),
    (_edit('model = "linear"\nkn = 1.0e10\nks = 1.0e10', 'model = "hertz"\nyoungs_modulus = [1e9, 2e9, 3e9]\npoisson_ratio = 0.3\nvelocity = 1.0\ncurvature_radius = 1.0'),
     "contact.youngs_modulus", "one per [[particle]]"),
    (_edit('density = 1000.0', 'density = 1000.0\nyoungs_modulus = 1e9').replace("ks = 1.0e10", "ks = 1.0e10\nyoungs_modulus = 1e9"),
     "contact.youngs_modulus", "one place only"),
    ("integrator = [\n", "toml", "not a valid TOML document"),
    ('integrator = "a"\nintegrator = "b"\n', "toml", "not a valid TOML document"),
    ("[[particle]]\n[particle]\n", "toml", "not a valid TOML document"),
    ("= 3\n", "toml", "not a valid TOML document"),
]


def _run(tmp_path, text=None, path=None, extra=()):
    if path is None:
        path = tmp_path / "scene.toml"
        path.write_bytes(text if isinstance(text, bytes) else text.encode())
    return main(["step", str(path), *extra]), str(path)


@pytest.mark.parametrize("text,key,reason", BAD, ids=[f"{n:02d}-{k}" for n, (_, k, _) in enumerate(BAD)])
def test_bad_scene_gives_one_line(tmp_path, capsys, text, key, reason):
    rc, path = _run(tmp_path, text)
    out, err = capsys.readouterr()
    assert rc == 2
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith(f"{path}:{key}: "), lines[0]
    assert reason in lines[0], lines[0]
    assert "Traceback" not in err and out == ""


def test_unreadable_and_non_text_files(tmp_path, capsys):
    rc, _ = _run(tmp_path, path=tmp_path / "missing.toml")
    assert rc == 2 and capsys.readouterr().err.startswith(f"{tmp_path / 'missing.toml'}:file: cannot read")
    rc, _ = _run(tmp_path, path=tmp_path)  # a directory
    assert rc == 2 and ":file: cannot read" in capsys.readouterr().err
    rc, _ = _run(tmp_path, b"\xff\xfe\x00binary")
    err = capsys.readouterr().err
    assert rc == 2 and ":file: not UTF-8" in err and len(err.splitlines()) == 1


def test_ks_above_kn_is_a_warning_not_an_error(tmp_path, capsys):
    rc, path = _run(tmp_path, GOOD.replace("ks = 1.0e10", "ks = 2.0e10"))
    out, err = capsys.readouterr()
    assert rc == 0
    assert err.splitlines() == [line for line in err.splitlines() if line.startswith(f"{path}:contact.ks: warning: ks = 2e+10 exceeds kn")]
    assert len(err.splitlines()) == 1 and "dt_crit" in out


def test_library_errors_are_input_errors_with_keys():
    with pytest.raises(InputError) as exc:
        parse_scene(GOOD.replace("kn = 1.0e10", "kn = -1.0"))
    assert exc.value.key == "contact.kn" and isinstance(exc.value, ValueError)
