"""Scenes name their integrator by scheme, by the DEM code that runs it, or by its own update rules.

References: the built-in schemes' own steps (a user-written symplectic Euler must give exactly the
built-in one's), the closed forms of the README table for the code names, and a marker file that a
hostile rule must not create.
"""
from __future__ import annotations

import json

import pytest

from dtcrit.cli import main

BODY = ('[[particle]]\nshape = "sphere"\nradius = 0.001\ndensity = 2500.0\n'
        '[contact]\nmodel = "linear"\nkn = 1e5\nks = 2e4\ndamping_ratio = 0.1\n')
USER = '[integrator]\nname = "my-symplectic"\nstate = ["x", "v"]\nupdate = ["v = v + h*f(x, v)", "x = x + h*v"]\n'


def _run(tmp_path, capsys, text, *extra):
    path = tmp_path / "scene.toml"
    path.write_text(text)
    rc = main(["step", str(path), *extra])
    return rc, *capsys.readouterr()


def _dt(tmp_path, capsys, text) -> float:
    rc, out, err = _run(tmp_path, capsys, text, "--json")
    assert rc == 0, err
    return json.loads(out)["dt_isolated"]  # a user-written scheme has no packing bound: compare one contact


def test_a_user_written_symplectic_euler_gives_the_built_in_step(tmp_path, capsys):
    user = _dt(tmp_path, capsys, USER + BODY)
    built_in = _dt(tmp_path, capsys, 'integrator = "symplectic-euler"\n' + BODY)
    assert user == pytest.approx(built_in, rel=1e-12)


@pytest.mark.parametrize("code, scheme", [("chrono", "extended-taylor"), ("lammps", "velocity-verlet"),
                                          ("yade", "leapfrog"), ("mfix-ab2", "adams-bashforth-2")])
def test_a_code_name_means_its_scheme_and_says_so(code, scheme, tmp_path, capsys):
    rc, out, err = _run(tmp_path, capsys, f'integrator = "{code}"\n' + BODY, "--json")
    assert rc == 0 and f"'{code}' integrates with '{scheme}'" in err
    assert json.loads(out)["dt_isolated"] == _dt(tmp_path, capsys, f'integrator = "{scheme}"\n' + BODY)


def test_chrono_has_no_stable_step_undamped(tmp_path, capsys):
    undamped = BODY.replace("damping_ratio = 0.1\n", "")
    assert _dt(tmp_path, capsys, 'integrator = "chrono"\n' + undamped) == 0.0


@pytest.mark.parametrize("text, key", [
    ('integrator = "edem"\n', "integrator: 'edem' is ambiguous"),
    (USER.replace('"x = x + h*v"', '"x = x + h*v*v"'), "integrator.update[2]"),
    (USER.replace('"x = x + h*v"', "\"__import__('os').system('touch MARKER')\""), "integrator.update[2]"),
    (USER.replace('"v = v + h*f(x, v)"', '"v = v + h*f(x, w)"'), "integrator.update[1]"),
    ('[integrator]\nname = "x"\nstate = ["x", "v"]\n', "integrator.update"),
])
def test_bad_integrators_are_one_line_and_nothing_runs(text, key, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    rc, out, err = _run(tmp_path, capsys, text + BODY)
    assert rc == 2 and out == "" and len(err.splitlines()) == 1 and key in err, err
    assert not (tmp_path / "MARKER").exists()
