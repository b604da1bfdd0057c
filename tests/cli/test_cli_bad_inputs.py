"""A list of bad inputs to ``dtcrit step`` (scene files with wrong types, keys and values, bad files and flags):
each is one line on standard error naming the key (``SCENE:key: reason``), exit status 2, nothing on standard
output, and never a traceback.  The few inputs that look odd but are valid give a finite answer instead."""
from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from dtcrit.cli import main
from support.paths import REPO_ROOT as ROOT


TOP = 'integrator = "velocity-verlet"\n'
SPHERE = '[[particle]]\nshape = "sphere"\nradius = 0.001\ndensity = 2500.0\n'
LINEAR = '[contact]\nmodel = "linear"\nkn = 1e5\nks = 1e4\n'


def scene(top: str = TOP, particles: str = SPHERE, contact: str = LINEAR, tail: str = "") -> str:
    return top + particles + contact + tail


def particle(body: str) -> str:
    return "[[particle]]\n" + body


def contact(body: str) -> str:
    return "[contact]\n" + body


ELL = 'shape = "ellipsoid"\nsemi_axes = [3.0, 2.0, 1.0]\ndensity = 1000.0\n'
CUBE = "[[-1, -1, -1], [1, -1, -1], [-1, 1, -1], [1, 1, -1], [-1, -1, 1], [1, -1, 1], [-1, 1, 1], [1, 1, 1]]"
HERTZ = 'model = "hertz"\nyoungs_modulus = 7e10\npoisson_ratio = 0.25\nvelocity = 1.0\n'
YADE = 'model = "yade"\nyoungs_modulus = 7e10\nks_ratio = 0.25\n'
WALL = "[[wall]]\nkn = 1e5\nks = 1e4\n"

# (id, scene text, the key the one line must name)
BAD_SCENES = [
    # top level
    ("no-integrator", scene(top=""), "integrator"),
    ("unknown-integrator", scene(top='integrator = "rk4"\n'), "integrator"),
    ("integrator-number", scene(top="integrator = 3\n"), "integrator"),
    ("integrator-empty", scene(top='integrator = ""\n'), "integrator"),
    ("integrator-array", scene(top='integrator = ["leapfrog"]\n'), "integrator"),
    ("safety-zero", scene(top=TOP + "safety = 0\n"), "safety"),
    ("safety-negative", scene(top=TOP + "safety = -0.5\n"), "safety"),
    ("safety-above-one", scene(top=TOP + "safety = 1.5\n"), "safety"),
    ("safety-subnormal", scene(top=TOP + "safety = 1e-320\n"), "safety"),
    ("safety-absurd", scene(top=TOP + "safety = 5e-7\n"), "safety"),
    ("safety-nan", scene(top=TOP + "safety = nan\n"), "safety"),
    ("safety-inf", scene(top=TOP + "safety = inf\n"), "safety"),
    ("safety-string", scene(top=TOP + 'safety = "0.5"\n'), "safety"),
    ("safety-bool", scene(top=TOP + "safety = true\n"), "safety"),
    ("safety-date", scene(top=TOP + "safety = 2024-01-01\n"), "safety"),
    ("omega-zero", scene(top=TOP + "omega_max = 0\n"), "omega_max"),
    ("omega-negative", scene(top=TOP + "omega_max = -1.0\n"), "omega_max"),
    ("omega-inf", scene(top=TOP + "omega_max = inf\n"), "omega_max"),
    ("omega-nan", scene(top=TOP + "omega_max = nan\n"), "omega_max"),
    ("omega-string", scene(top=TOP + 'omega_max = "fast"\n'), "omega_max"),
    ("omega-huge-int", scene(top=TOP + "omega_max = 9223372036854775807\n" + "x = 1\n"), "x"),
    ("pairs-unknown", scene(top=TOP + 'pairs = "some"\n'), "pairs"),
    ("pairs-unlike-one-type", scene(top=TOP + 'pairs = "unlike"\n'), "pairs"),
    ("pairs-number", scene(top=TOP + "pairs = 1\n"), "pairs"),
    ("title-number", scene(top=TOP + "title = 5\n"), "title"),
    ("title-too-long", scene(top=TOP + f'title = "{"t" * 201}"\n'), "title"),
    ("coordination-zero", scene(top=TOP + "coordination_max = 0\n"), "coordination_max"),
    ("coordination-fraction", scene(top=TOP + "coordination_max = 6.5\n"), "coordination_max"),
    ("coordination-bool", scene(top=TOP + "coordination_max = true\n"), "coordination_max"),
    ("coordination-huge", scene(top=TOP + "coordination_max = 1000000\n"), "coordination_max"),
    ("coordination-negative", scene(top=TOP + "coordination_max = -3\n"), "coordination_max"),
    ("coordination-string", scene(top=TOP + 'coordination_max = "12"\n'), "coordination_max"),
    ("overlap-one", scene(top=TOP + "coordination_max = 6\noverlap_max = 1.0\n"), "overlap_max"),
    ("overlap-negative", scene(top=TOP + "coordination_max = 6\noverlap_max = -0.1\n"), "overlap_max"),
    ("overlap-nan", scene(top=TOP + "coordination_max = 6\noverlap_max = nan\n"), "overlap_max"),
    ("forward-euler-dense", scene(top='integrator = "forward-euler"\ncoordination_max = 6\n'), "coordination_max"),
    ("paper-eq40-dense", scene(top='integrator = "paper-eq40"\ncoordination_max = 6\n'), "coordination_max"),
    ("dense-warning-then-error", scene(top='integrator = "forward-euler"\ncoordination_max = 6\n',
                                       contact=contact('model = "linear"\nkn = 1e4\nks = 1e5\n')), "coordination_max"),
    ("unknown-top-key", scene(top=TOP + "integrater = 1\n"), "integrater"),
    ("top-key-case", scene(top=TOP + "Safety = 0.5\n"), "Safety"),
    ("no-particle", scene(particles=""), "particle"),
    ("particle-number", scene(top=TOP + "particle = 5\n", particles=""), "particle"),
    ("particle-empty-array", scene(top=TOP + "particle = []\n", particles=""), "particle"),
    ("particle-array-of-numbers", scene(top=TOP + "particle = [1, 2]\n", particles=""), "particle[1]"),
    ("no-contact", scene(contact=""), "contact"),
    ("contact-string", TOP + 'contact = "linear"\n' + SPHERE, "contact"),
    # particles
    ("shape-missing", scene(particles=particle("radius = 0.001\ndensity = 2500.0\n")), "particle[1].shape"),
    ("shape-unknown", scene(particles=particle('shape = "cube"\nradius = 1.0\ndensity = 1.0\n')), "particle[1].shape"),
    ("shape-number", scene(particles=particle("shape = 1\nradius = 1.0\ndensity = 1.0\n")), "particle[1].shape"),
    ("radius-missing", scene(particles=particle('shape = "sphere"\ndensity = 1.0\n')), "particle[1].radius"),
    ("radius-zero", scene(particles=particle('shape = "sphere"\nradius = 0\ndensity = 1.0\n')), "particle[1].radius"),
    ("radius-negative", scene(particles=particle('shape = "sphere"\nradius = -1.0\ndensity = 1.0\n')), "particle[1].radius"),
    ("radius-string", scene(particles=particle('shape = "sphere"\nradius = "1mm"\ndensity = 1.0\n')), "particle[1].radius"),
    ("radius-array", scene(particles=particle('shape = "sphere"\nradius = [1.0, 2.0]\ndensity = 1.0\n')),
     "particle[1].radius"),
    ("radius-inf", scene(particles=particle('shape = "sphere"\nradius = inf\ndensity = 1.0\n')), "particle[1].radius"),
    ("radius-nan", scene(particles=particle('shape = "sphere"\nradius = nan\ndensity = 1.0\n')), "particle[1].radius"),
    ("density-and-mass", scene(particles=particle('shape = "sphere"\nradius = 1.0\ndensity = 1.0\nmass = 1.0\n')),
     "particle[1].mass"),
    ("no-density-no-mass", scene(particles=particle('shape = "sphere"\nradius = 1.0\n')), "particle[1].density"),
    ("density-zero", scene(particles=particle('shape = "sphere"\nradius = 1.0\ndensity = 0\n')), "particle[1].density"),
    ("density-negative", scene(particles=particle('shape = "sphere"\nradius = 1.0\ndensity = -2500.0\n')),
     "particle[1].density"),
    ("density-nan", scene(particles=particle('shape = "sphere"\nradius = 1.0\ndensity = nan\n')), "particle[1].density"),
    ("mass-zero", scene(particles=particle('shape = "sphere"\nradius = 1.0\nmass = 0.0\n')), "particle[1].mass"),
    ("mass-with-distribution", scene(particles=particle('shape = "sphere"\nradii = [1.0, 2.0]\nfractions = [0.5, 0.5]\n'
                                                        "mass = 1.0\n")), "particle[1].mass"),
    ("semi-axes-missing", scene(particles=particle('shape = "ellipsoid"\ndensity = 1.0\n')), "particle[1].semi_axes"),
    ("semi-axes-two", scene(particles=particle('shape = "ellipsoid"\nsemi_axes = [1.0, 2.0]\ndensity = 1.0\n')),
     "particle[1].semi_axes"),
    ("semi-axes-unsorted", scene(particles=particle('shape = "ellipsoid"\nsemi_axes = [1.0, 2.0, 3.0]\ndensity = 1.0\n')),
     "particle[1].semi_axes"),
    ("semi-axes-zero", scene(particles=particle('shape = "ellipsoid"\nsemi_axes = [3.0, 2.0, 0.0]\ndensity = 1.0\n')),
     "particle[1].semi_axes"),
    ("semi-axes-string-entry", scene(particles=particle('shape = "ellipsoid"\nsemi_axes = [3.0, 2.0, "1"]\n'
                                                        "density = 1.0\n")), "particle[1].semi_axes[3]"),
    ("semi-axes-string", scene(particles=particle('shape = "ellipsoid"\nsemi_axes = "3,2,1"\ndensity = 1.0\n')),
     "particle[1].semi_axes"),
    ("exponents-missing", scene(particles=particle('shape = "superquadric"\nsemi_axes = [3.0, 2.0, 1.0]\n'
                                                   "density = 1.0\n")), "particle[1].exponents"),
    ("exponents-zero", scene(particles=particle('shape = "superquadric"\nsemi_axes = [3.0, 2.0, 1.0]\n'
                                                "exponents = [0.0, 1.0]\ndensity = 1.0\n")), "particle[1].exponents"),
    ("exponents-non-convex", scene(particles=particle('shape = "superquadric"\nsemi_axes = [3.0, 2.0, 1.0]\n'
                                                      "exponents = [3.0, 3.0]\ndensity = 1.0\n")), "particle[1]"),
    ("box-two-lengths", scene(particles=particle('shape = "box"\nhalf_lengths = [1.0, 1.0]\ndensity = 1.0\n')),
     "particle[1].half_lengths"),
    ("box-negative", scene(particles=particle('shape = "box"\nhalf_lengths = [1.0, 1.0, -1.0]\ndensity = 1.0\n')),
     "particle[1].half_lengths"),
    ("vertices-empty", scene(particles=particle('shape = "polyhedron"\nvertices = []\ndensity = 1.0\n')),
     "particle[1].vertices"),
    ("vertices-three", scene(particles=particle('shape = "polyhedron"\nvertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]\n'
                                                "density = 1.0\n")), "particle[1].vertices"),
    ("vertices-coplanar", scene(particles=particle('shape = "polyhedron"\n'
                                                   "vertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]\n"
                                                   "density = 1.0\n")), "particle[1].vertices"),
    ("vertices-short-point", scene(particles=particle('shape = "polyhedron"\n'
                                                      "vertices = [[0, 0, 0], [1, 0], [0, 1, 0], [0, 0, 1]]\n"
                                                      "density = 1.0\n")), "particle[1].vertices[2]"),
    ("vertices-string", scene(particles=particle('shape = "polyhedron"\n'
                                                 'vertices = [[0, 0, 0], [1, 0, "a"], [0, 1, 0], [0, 0, 1]]\n'
                                                 "density = 1.0\n")), "particle[1].vertices[2][3]"),
    ("vertices-one-point", scene(particles=particle('shape = "polyhedron"\n'
                                                    "vertices = [[1, 1, 1], [1, 1, 1], [1, 1, 1], [1, 1, 1]]\n"
                                                    "density = 1.0\n")), "particle[1].vertices"),
    ("vertices-inf", scene(particles=particle('shape = "polyhedron"\n'
                                              "vertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, inf]]\n"
                                              "density = 1.0\n")), "particle[1].vertices[4][3]"),
    ("sphere-with-semi-axes", scene(particles=particle('shape = "sphere"\nradius = 1.0\nsemi_axes = [1, 1, 1]\n'
                                                       "density = 1.0\n")), "particle[1].semi_axes"),
    ("particle-typo", scene(particles=particle('shape = "sphere"\nradus = 1.0\ndensity = 1.0\n')), "particle[1].radus"),
    ("poisson-half", scene(particles=particle('shape = "sphere"\nradius = 1.0\ndensity = 1.0\npoisson_ratio = 0.5\n')),
     "particle[1].poisson_ratio"),
    ("poisson-minus-one", scene(particles=particle('shape = "sphere"\nradius = 1.0\ndensity = 1.0\n'
                                                   "poisson_ratio = -1.0\n")), "particle[1].poisson_ratio"),
    ("youngs-zero", scene(particles=particle('shape = "sphere"\nradius = 1.0\ndensity = 1.0\nyoungs_modulus = 0\n')),
     "particle[1].youngs_modulus"),
    ("name-number", scene(particles=particle('shape = "sphere"\nradius = 1.0\ndensity = 1.0\nname = 3\n')),
     "particle[1].name"),
    ("second-particle-bad", scene(particles=SPHERE + particle('shape = "sphere"\nradius = -1.0\ndensity = 1.0\n')),
     "particle[2].radius"),
    ("radii-empty", scene(particles=particle('shape = "sphere"\nradii = []\nfractions = []\ndensity = 1.0\n')),
     "particle[1].radii"),
    ("radii-negative", scene(particles=particle('shape = "sphere"\nradii = [0.001, -0.002]\nfractions = [0.5, 0.5]\n'
                                                "density = 1.0\n")), "particle[1].radii"),
    ("fractions-sum", scene(particles=particle('shape = "sphere"\nradii = [0.001, 0.002]\nfractions = [0.5, 0.6]\n'
                                               "density = 1.0\n")), "particle[1].fractions"),
    ("fractions-length", scene(particles=particle('shape = "sphere"\nradii = [0.001, 0.002]\nfractions = [1.0]\n'
                                                  "density = 1.0\n")), "particle[1].fractions"),
    ("lognormal-incomplete", scene(particles=particle('shape = "sphere"\nlognormal = {median = 0.001}\ndensity = 1.0\n')),
     "particle[1].lognormal"),
    ("lognormal-sigma-negative", scene(particles=particle('shape = "sphere"\nlognormal = {median = 0.001, sigma = -0.2, '
                                                          "min = 0.0005, max = 0.002}\ndensity = 1.0\n")),
     "particle[1].lognormal"),
    ("lognormal-min-above-max", scene(particles=particle('shape = "sphere"\nlognormal = {median = 0.001, sigma = 0.2, '
                                                         "min = 0.002, max = 0.0005}\ndensity = 1.0\n")),
     "particle[1].lognormal"),
    ("lognormal-number", scene(particles=particle('shape = "sphere"\nlognormal = 5\ndensity = 1.0\n')),
     "particle[1].lognormal"),
    ("radius-and-radii", scene(particles=particle('shape = "sphere"\nradius = 1.0\nradii = [1.0]\nfractions = [1.0]\n'
                                                  "density = 1.0\n")), "particle[1]"),
    # contact
    ("model-missing", scene(contact=contact("kn = 1e5\nks = 1e4\n")), "contact.model"),
    ("model-unknown", scene(contact=contact('model = "hooke"\nkn = 1e5\nks = 1e4\n')), "contact.model"),
    ("kn-missing", scene(contact=contact('model = "linear"\nks = 1e4\n')), "contact.kn"),
    ("kn-zero", scene(contact=contact('model = "linear"\nkn = 0\nks = 1e4\n')), "contact.kn"),
    ("kn-negative", scene(contact=contact('model = "linear"\nkn = -1e5\nks = 1e4\n')), "contact.kn"),
    ("kn-overflow", scene(contact=contact('model = "linear"\nkn = 1e309\nks = 1e4\n')), "contact.kn"),
    ("kn-string", scene(contact=contact('model = "linear"\nkn = "1e5"\nks = 1e4\n')), "contact.kn"),
    ("integrator-upper-case", scene(top='integrator = "LEAPFROG"\n'), "integrator"),
    ("ks-missing", scene(contact=contact('model = "linear"\nkn = 1e5\n')), "contact.ks"),
    ("ks-negative", scene(contact=contact('model = "linear"\nkn = 1e5\nks = -1.0\n')), "contact.ks"),
    ("cn-negative", scene(contact=LINEAR + "cn = -1.0\n"), "contact.cn"),
    ("restitution-zero", scene(contact=LINEAR + "restitution = 0.0\n"), "contact.restitution"),
    ("restitution-above-one", scene(contact=LINEAR + "restitution = 1.5\n"), "contact.restitution"),
    ("restitution-and-ratio", scene(contact=LINEAR + "restitution = 0.5\ndamping_ratio = 0.1\n"), "contact."),
    ("ratio-negative", scene(contact=LINEAR + "damping_ratio = -0.1\n"), "contact.damping_ratio"),
    ("cn-and-restitution", scene(contact=LINEAR + "cn = 1.0\nrestitution = 0.5\n"), "contact."),
    ("convention-unknown", scene(contact=LINEAR + 'restitution = 0.5\ndamping_convention = "foo"\n'),
     "contact.damping_convention"),
    ("convention-edem-linear", scene(contact=LINEAR + 'restitution = 0.5\ndamping_convention = "edem"\n'),
     "contact.damping_convention"),
    ("hertz-no-velocity", scene(contact=contact('model = "hertz"\nyoungs_modulus = 7e10\npoisson_ratio = 0.25\n')),
     "contact.velocity"),
    ("hertz-no-youngs", scene(contact=contact('model = "hertz"\npoisson_ratio = 0.25\nvelocity = 1.0\n')),
     "contact.youngs_modulus"),
    ("hertz-with-cn", scene(contact=contact(HERTZ + "cn = 1.0\n")), "contact.cn"),
    ("hertz-ellipsoid-no-curvature", scene(particles=particle(ELL), contact=contact(HERTZ)), "contact.curvature_radius"),
    ("hertz-velocity-zero", scene(contact=contact(HERTZ.replace("velocity = 1.0", "velocity = 0.0"))), "contact.velocity"),
    ("yade-no-ks-ratio", scene(contact=contact('model = "yade"\nyoungs_modulus = 7e10\n')), "contact.ks_ratio"),
    ("yade-ellipsoid", scene(particles=particle(ELL), contact=contact(YADE)), "contact.model"),
    ("yade-no-youngs", scene(contact=contact('model = "yade"\nks_ratio = 0.25\n')), "contact.youngs_modulus"),
    ("youngs-twice", scene(particles=particle('shape = "sphere"\nradius = 1.0\ndensity = 1.0\nyoungs_modulus = 1e9\n'),
                           contact=contact(HERTZ)), "contact.youngs_modulus"),
    ("youngs-array-length", scene(contact=contact(HERTZ.replace("youngs_modulus = 7e10", "youngs_modulus = [7e10, 1e9]"))),
     "contact.youngs_modulus"),
    ("friction-negative", scene(contact=LINEAR + "friction = -1.0\n"), "contact.friction"),
    ("friction-string", scene(contact=LINEAR + 'friction = "high"\n'), "contact.friction"),
    ("contact-typo", scene(contact=LINEAR + "kt = 1e4\n"), "contact.kt"),
    ("top-key-after-table", scene(contact=LINEAR + "safety = 0.5\n"), "contact.safety"),
    ("linear-key-in-hertz", scene(contact=contact(HERTZ + "kn = 1e5\n")), "contact.kn"),
    # walls
    ("wall-no-kn", scene(tail="[[wall]]\nks = 1e4\n"), "wall[1].kn"),
    ("wall-number", scene(top=TOP + "wall = 5\n"), "wall"),
    ("wall-unknown-particle", scene(tail=WALL + "particles = [3]\n"), "wall[1].particles"),
    ("wall-kn-negative", scene(tail="[[wall]]\nkn = -1e5\nks = 1e4\n"), "wall[1].kn"),
    ("wall-typo", scene(tail=WALL + "restitutoin = 0.5\n"), "wall[1].restitutoin"),
    # not TOML, not text
    ("not-toml", "integrator = [\n", "toml"),
    ("duplicate-key", scene(top=TOP + TOP), "toml"),
    ("bare-word", scene(top="integrator = leapfrog\n"), "toml"),
    ("deep-nesting", "x = " + "[" * 5000 + "]" * 5000 + "\n", "toml"),
]

VALID_ODDITIES = [
    ("bom", "\ufeff" + scene()),
    ("crlf-line-ends", scene().replace("\n", "\r\n")),
    ("friction-accepted-with-a-note", scene(contact=LINEAR + "friction = 0.5\n")),
    ("tiny-omega", scene(top=TOP + "omega_max = 1e-320\n")),
    ("smallest-safety", scene(top=TOP + "safety = 1e-6\n")),
    ("subnormal-stiffness", scene(contact=contact('model = "linear"\nkn = 1e-320\nks = 0.0\n'))),
    ("huge-stiffness", scene(contact=contact('model = "linear"\nkn = 1e300\nks = 1e300\n'))),
    ("zero-shear-spring", scene(contact=contact('model = "linear"\nkn = 1e5\nks = 0.0\n'))),
    ("integer-values", scene(contact=contact('model = "linear"\nkn = 100000\nks = 10000\n'))),
    ("huge-integer-stiffness", scene(contact=contact('model = "linear"\nkn = 99999999999999999999\nks = 1e4\n'))),
    ("wall-and-dense", scene(top=TOP + "coordination_max = 6\n", tail=WALL)),
]


def _run(capsys, argv):
    capsys.readouterr()
    try:
        rc = main(argv)
    except SystemExit as exc:
        rc = exc.code
    out, err = capsys.readouterr()
    assert "Traceback" not in err
    return rc, out, err


@pytest.mark.parametrize("name,text,key", BAD_SCENES, ids=[c[0] for c in BAD_SCENES])
def test_bad_scene_is_one_line_naming_the_key(name, text, key, tmp_path, capsys):
    path = tmp_path / f"{name}.toml"
    path.write_text(text, encoding="utf-8")
    rc, out, err = _run(capsys, ["step", str(path)])
    assert rc == 2 and out == "", (rc, out[:200], err)
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith(f"{path}:{key}"), lines[0]
    assert len(lines[0]) < 600  # the reason is short: nothing echoes a whole file or a huge value


BAD_FILES = [
    ("missing", lambda tmp: str(tmp / "nope.toml"), "file"),
    ("folder", lambda tmp: str(tmp), "file"),
    ("dev-null", lambda tmp: "/dev/null", "integrator"),  # an empty document
    ("dev-zero", lambda tmp: "/dev/zero", "file"),
    ("binary", lambda tmp: _write(tmp / "b.toml", bytes(range(256))), "file"),
    ("latin-1", lambda tmp: _write(tmp / "l.toml", 'title = "caf\xe9"\n'.encode("latin-1")), "file"),
    ("too-large", lambda tmp: _write(tmp / "big.toml", b"# " + b"x" * (8 << 20) + b"\n"), "file"),
    ("nul-in-name", lambda tmp: "a\x00b.toml", "file"),
    ("name-too-long", lambda tmp: "x" * 5000 + ".toml", "file"),
    ("newline-in-name", lambda tmp: str(tmp / "a\nb.toml"), "file"),
]


def _write(path: Path, data: bytes) -> str:
    path.write_bytes(data)
    return str(path)


@pytest.mark.parametrize("name,make,key", BAD_FILES, ids=[c[0] for c in BAD_FILES])
def test_bad_file_is_one_line(name, make, key, tmp_path, capsys):
    rc, out, err = _run(capsys, ["step", make(tmp_path)])
    assert rc == 2 and out == ""
    (line,) = err.splitlines()
    assert f":{key}: " in line and len(line) < 600, line


BAD_FLAGS = [
    ["step"],
    ["step", "a.toml", "b.toml"],
    ["step", "examples/paper_ellipsoids.toml", "--jsn"],
    ["step", "examples/paper_ellipsoids.toml", "--json=yes"],
    ["step", "--json"],
    ["stpe", "examples/paper_ellipsoids.toml"],
    ["--verbose", "step", "examples/paper_ellipsoids.toml"],
    [],
    ["step", "examples/paper_ellipsoids.toml", "\x00"],
    ["step", "examples/paper_ellipsoids.toml", "--json", "--json", "extra"],
]


@pytest.mark.parametrize("argv", BAD_FLAGS, ids=[" ".join(a).replace("\x00", "NUL") or "nothing" for a in BAD_FLAGS])
def test_bad_flags_are_one_line(argv, capsys, monkeypatch):
    monkeypatch.chdir(ROOT)
    rc, out, err = _run(capsys, argv)
    assert rc == 2 and out == ""
    assert len(err.splitlines()) == 1, err


@pytest.mark.parametrize("name,text", VALID_ODDITIES, ids=[c[0] for c in VALID_ODDITIES])
def test_odd_but_valid_scenes_give_a_finite_answer(name, text, tmp_path, capsys):
    path = tmp_path / f"{name}.toml"
    path.write_text(text, encoding="utf-8", newline="")
    rc, out, err = _run(capsys, ["step", str(path), "--json"])
    assert rc == 0, err
    doc = json.loads(out)
    assert math.isfinite(doc["dt_crit"]) and doc["dt_crit"] > 0
    assert math.isfinite(doc["dt_recommended"]) and doc["dt_recommended"] > 0
    assert all(line.startswith(f"{path}:") for line in err.splitlines())


def test_the_list_is_long_enough():
    assert len(BAD_SCENES) + len(BAD_FILES) + len(BAD_FLAGS) >= 100
