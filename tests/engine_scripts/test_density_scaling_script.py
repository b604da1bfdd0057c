"""The engine script that applies planned mass factors (``dtcrit/engine_scripts/density_scaling.py``),
outside the engines: the forms of factors it reads, the LAMMPS ``atomfile`` it writes, and input lines
in which nothing the caller gives ends a line or escapes its double quotes.  In LAMMPS and YADE:
``tests/engines/test_engine_density_scaling.py``.
"""
from __future__ import annotations

import json
import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dtcrit.engine_scripts import density_scaling as ds


@pytest.mark.parametrize("source", [
    {3: 2.0, 7: 1.0},
    {"density_scaling": {"factors": {"3": 2.0, "7": 1.0}}},
    {"density_scaling": {"factors": [{"id": 3, "factor": 2.0}, {"id": 7, "factor": 1.0}]}},
    {"density_scaling": {"factors": [2.0, 1.0], "ids": [3, 7]}},
    [(3, 2.0), (7, 1.0)],
])
def test_read_factors_accepts_each_form(source):
    """A mapping, a plan document in each of its layouts, or pairs: the same ``{id: factor}``."""
    assert ds.read_factors(source) == {3: 2.0, 7: 1.0}


def test_read_factors_from_a_plan_file(tmp_path):
    """A ``dtcrit plan --json`` file is read by path."""
    path = tmp_path / "plan.json"
    path.write_text(json.dumps({"density_scaling": {"factors": [1.5, 4.0], "ids": [1, 2]}}))
    assert ds.read_factors(str(path)) == {1: 1.5, 2: 4.0}


@pytest.mark.parametrize("source, words", [
    ({1: 0.0}, "finite and positive"),
    ({1: float("nan")}, "finite and positive"),
    ({1: "heavy"}, "must be a number"),
    ([(True, 2.0)], "must be an integer"),
    ([(1.5, 2.0)], "must be an integer"),
    ([(1, 2.0), ("1", 3.0)], "listed twice"),
    ({"density_scaling": {"factors": [2.0, 1.0]}}, "needs 'ids'"),
])
def test_read_factors_refuses(source, words):
    """A factor that is not a finite positive number, an id that is not an integer, one listed twice."""
    with pytest.raises(ValueError, match=words):
        ds.read_factors(source)


def test_factor_file_is_lammps_atomfile_format():
    """A comment line, the count, then ``id factor`` lines in id order, factors to the last bit."""
    text = ds.lammps_factor_file({12: 1.0 / 3.0, 2: 5.0})
    lines = text.splitlines()
    assert lines[0].startswith("#") and lines[1] == "2"
    assert [ln.split()[0] for ln in lines[2:]] == ["2", "12"]
    assert float(lines[3].split()[1]) == 1.0 / 3.0


def test_commands_set_the_masses_then_the_step():
    """The step is ``safety * dt`` written with ``repr`` (LAMMPS reads that double exactly)."""
    lines = ds.lammps_commands("f.txt", 3e-6, safety=0.9)
    assert lines[0] == 'variable dtcrit_factor atomfile "f.txt"'
    assert lines[2] == "set group all mass v_dtcrit_mass"
    assert lines[-1] == f"timestep {0.9 * 3e-6!r}"
    assert not any(ln.startswith("timestep") for ln in ds.lammps_commands("f.txt"))


@pytest.mark.parametrize("kwargs, words", [
    ({"factor_file": 'a"b'}, "double quote"),
    ({"factor_file": "a\nb"}, "line break"),
    ({"factor_file": "f", "label": "x y"}, "label"),
    ({"factor_file": "f", "dt": 1e-6, "safety": 1.5}, "safety"),
    ({"factor_file": "f", "dt": math.inf}, "finite and positive"),
])
def test_commands_refuse(kwargs, words):
    """A path that would end its quotes or its line, a label that is not a LAMMPS id, a bad step."""
    with pytest.raises(ValueError, match=words):
        ds.lammps_commands(**kwargs)


@settings(max_examples=200, deadline=None, derandomize=True)
@given(st.text(min_size=1, max_size=40).filter(lambda t: not any(c in t for c in '"\n\r\0')))
def test_a_path_stays_inside_its_quotes(path):
    """Any path without quote or line break: every command is one line, the path only between its quotes."""
    lines = ds.lammps_commands(path, 1e-6)
    assert all("\n" not in ln and "\r" not in ln for ln in lines)
    first = lines[0]
    assert first == f'variable dtcrit_factor atomfile "{path}"' and first.count('"') == 2
    assert all('"' not in ln for ln in lines[1:])


def test_read_plan_gives_the_factors_and_the_target(tmp_path):
    """The plan file's ``density_scaling`` and ``target_dt``; a document without either is refused."""
    path = tmp_path / "plan.json"
    path.write_text(json.dumps({"target_dt": 2.5e-6, "density_scaling": {"ids": [4, 9], "factors": [3.0, 1.25]}}))
    assert ds.read_plan(path) == ({4: 3.0, 9: 1.25}, 2.5e-6)
    with pytest.raises(ValueError, match="density_scaling"):
        ds.read_plan({"target_dt": 1e-6})
    with pytest.raises(ValueError, match="planned step"):
        ds.read_plan({"density_scaling": {"ids": [1], "factors": [2.0]}})


def test_write_lammps_include_from_a_plan_file(tmp_path):
    """``python3 density_scaling.py PLAN SCALED.in``: the include names its atomfile by base name."""
    import subprocess
    import sys

    plan = tmp_path / "plan.json"
    plan.write_text(json.dumps({"target_dt": 4e-6, "density_scaling": {"ids": [1, 2], "factors": [2.0, 1.0]}}))
    done = subprocess.run([sys.executable, ds.__file__, str(plan), str(tmp_path / "scaled.in")], capture_output=True,
                          text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    lines = (tmp_path / "scaled.in").read_text().splitlines()
    assert lines[0].startswith("#") and lines[1] == 'variable dtcrit_factor atomfile "scaled.in.factors"'
    assert lines[-1] == "timestep 4e-06"
    assert ds.read_factors([tuple(r.split()) for r in (tmp_path / "scaled.in.factors").read_text().splitlines()[2:]]) \
        == {1: 2.0, 2: 1.0}
