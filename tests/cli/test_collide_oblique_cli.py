"""``dtcrit collide`` with an impact angle: the scene keys, the flag, and every refusal in one line (exit 2)."""
from __future__ import annotations

import json
import math

import pytest
from support.paths import REPO_ROOT as ROOT

from dtcrit.cli import main

GLASS = ROOT / "examples" / "glass_spheres_hertz.toml"
ELASTIC = """
integrator = "velocity-verlet"
[[particle]]
shape = "sphere"
radius = 1.0e-3
density = 2500.0
youngs_modulus = 63.0e9
poisson_ratio = 0.22
[contact]
model = "hertz"
velocity = 1.0
friction = 0.1
"""


def _scene(tmp_path, text, name="scene.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def _one_line_error(capsys, *argv):
    try:
        code = main(["collide", *map(str, argv)])
    except SystemExit as exc:  # argparse's own refusal
        code = exc.code
    assert code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err
    return err


def _oblique(capsys, *argv):
    assert main(["collide", *map(str, argv), "--json"]) == 0
    (pair,) = json.loads(capsys.readouterr().out)["pairs"]
    return pair["oblique"]


def test_the_scene_keys_and_the_flag_ask_for_the_same_impact(tmp_path, capsys):
    """angle_deg = 60, tangential_ratio = tan(60 deg) and --angle 60 give one answer; --angle 0 none."""
    by_angle = _oblique(capsys, _scene(tmp_path, ELASTIC + "[collision]\nangle_deg = 60\n", "a.toml"))
    by_ratio = _oblique(capsys, _scene(tmp_path, ELASTIC + f"[collision]\ntangential_ratio = {math.tan(math.pi / 3)!r}\n", "r.toml"))
    by_flag = _oblique(capsys, _scene(tmp_path, ELASTIC, "f.toml"), "--angle", "60")
    assert by_angle["angle_deg"] == 60.0 and by_ratio["angle_deg"] == pytest.approx(60.0, rel=1e-14)
    assert by_ratio["tangential_ratio"] == pytest.approx(math.sqrt(3.0), rel=1e-14)
    for other in (by_ratio, by_flag):
        assert other["steps_resolution"] == pytest.approx(by_angle["steps_resolution"], rel=1e-9)
    assert by_angle["regime"] == "sliding" and by_angle["friction"] == 0.1
    assert main(["collide", str(tmp_path / "a.toml"), "--angle", "0", "--json"]) == 0
    assert "oblique" not in json.loads(capsys.readouterr().out)["pairs"][0]


def test_text_output_names_the_oblique_step(tmp_path, capsys):
    """The text report carries the oblique line."""
    assert main(["collide", str(_scene(tmp_path, ELASTIC)), "--angle", "60"]) == 0
    out = capsys.readouterr().out
    assert "oblique at 60 deg" in out and "dt_oblique = " in out and "sliding" in out


WALL = '\n[[wall]]\nmodel = "hertz"\nyoungs_modulus = 200e9\npoisson_ratio = 0.3\n'
UNEQUAL = ELASTIC.replace("[contact]", '[[particle]]\nshape = "sphere"\nradius = 2.0e-3\ndensity = 2500.0\n'
                          'youngs_modulus = 63.0e9\npoisson_ratio = 0.22\n[contact]')


@pytest.mark.parametrize("text, argv, needle", [
    (ELASTIC, ["--angle", "90"], "--angle: must be less than 90"),
    (ELASTIC, ["--angle", "-1"], "--angle: must be non-negative"),
    (ELASTIC, ["--angle", "nan"], "--angle: must be finite"),
    (ELASTIC + "[collision]\nangle_deg = 95\n", [], "collision.angle_deg: must be less than 90"),
    (ELASTIC + "[collision]\ntangential_ratio = -1\n", [], "collision.tangential_ratio: must be non-negative"),
    (ELASTIC + "[collision]\nangle_deg = 30\ntangential_ratio = 0.5\n", [], "not both"),
    (ELASTIC + WALL, ["--angle", "30"], "wall[1]: an oblique impact"),
    (UNEQUAL, ["--angle", "30"], "particle[2]: pair 1-2: an oblique impact (angle = 30 deg) is modelled for two equal spheres"),
    (ELASTIC.replace("friction = 0.1\n", ""), ["--angle", "30"], "contact.friction"),
    (ELASTIC.replace("friction = 0.1", "friction = 0"), ["--angle", "30"], "contact.friction"),
    (ELASTIC, ["--angle", "30", "--engine", "chrono"], "--engine"),
    (ELASTIC.replace("friction = 0.1", "friction = 0.5"), ["--angle", "5", "--engine", "yade"],
     "--engine: an oblique impact (angle = 5 deg) that sticks is not modelled for YADE"),
    (ELASTIC.replace("friction = 0.1", 'friction = 0.1\ndamping_convention = "lammps-viscoelastic"\ndamping_coefficient = 1e5\ntangential_damping_factor = 0'),
     ["--angle", "60"], "contact.damping_coefficient: an oblique impact"),
    (ELASTIC, ["--angle", "30"], "--angle: v_t/v_n = 0.5774: the contact slides at first touch and can stick later"),
    (ELASTIC.replace("friction = 0.1", "friction = 0.5\nrestitution = 0.9"), ["--angle", "10"],
     "--angle: v_t/v_n = 0.1763: the contact sticks at first touch and slides before the last 1 %"),
])
def test_bad_input_is_one_line(tmp_path, capsys, text, argv, needle):
    """Angle out of [0, 90), both keys, walls, unequal spheres, no friction, another map, stick-slip."""
    err = _one_line_error(capsys, _scene(tmp_path, text), *argv)
    assert needle in err


def test_a_linear_law_is_refused(capsys):
    """The linear example (with a wall) asked for an angle."""
    err = _one_line_error(capsys, ROOT / "examples" / "spheres_on_a_floor.toml", "--v-max", "1", "--angle", "30")
    assert "wall[1]" in err or "contact.model" in err


def test_a_linear_law_without_walls_is_refused(tmp_path, capsys):
    """Mindlin's spring needs a Hertz law."""
    text = ('integrator = "velocity-verlet"\n[[particle]]\nshape = "sphere"\nradius = 1e-3\ndensity = 2500.0\n'
            '[contact]\nmodel = "linear"\nkn = 1e5\nks = 1e5\nfriction = 0.3\n')
    err = _one_line_error(capsys, _scene(tmp_path, text), "--v-max", "1", "--angle", "30")
    assert "contact.model: an oblique impact" in err
