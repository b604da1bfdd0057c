"""``dtcrit collide --angle``: a damped contact that slides at first touch is refused for what it is (one line, exit 2)."""
from __future__ import annotations

import math

import pytest
from support.paths import REPO_ROOT as ROOT

from dtcrit.cli import main

TSUJI = ROOT / "examples" / "glass_spheres_lammps_tsuji.toml"
FRICTION = 0.1
POISSON = 0.22  # the example's poisson_ratio


def _damped_scene(tmp_path):
    text = TSUJI.read_text()
    assert "\n[contact]\n" in text
    path = tmp_path / "tsuji_friction.toml"
    path.write_text(text.replace("\n[contact]\n", f"\n[contact]\nfriction = {FRICTION}\n"))
    return path


def _onset_ratio(angle_deg):
    """Mindlin's k_t/k_n = 2 (1 - nu)/(2 - nu) of the scene; the onset slides when (3/2)(k_t/k_n) v_t/v_n > mu."""
    return 1.5 * 2.0 * (1.0 - POISSON) / (2.0 - POISSON) * math.tan(math.radians(angle_deg))


@pytest.mark.parametrize("angle", [80.0, 5.0])
def test_damped_contact_sliding_at_first_touch_is_refused_as_sliding(tmp_path, capsys, angle):
    """The tsuji dashpot with mu = 0.1: at 80 deg (onset ratio ~ 7.4) and 5 deg (~ 0.115) the onset slides."""
    assert _onset_ratio(angle) > FRICTION
    code = main(["collide", str(_damped_scene(tmp_path)), "--angle", str(angle)])
    err = capsys.readouterr().err
    assert code == 2
    assert err.count("\n") == 1, err
    assert err.startswith("dtcrit: --angle:")
    assert "slides at first touch; damped sliding impacts are not modelled" in err
    assert "sticks at first touch and slides" not in err


def test_damped_contact_sticking_at_first_touch_keeps_its_own_refusal(tmp_path, capsys):
    """At 3 deg the onset sticks ((3/2)(k_t/k_n) tan 3 deg ~ 0.069 < mu) and Coulomb's limit binds early."""
    assert _onset_ratio(3.0) < FRICTION
    code = main(["collide", str(_damped_scene(tmp_path)), "--angle", "3"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1, err
    assert "sticks at first touch and slides before the last 1 %" in err
