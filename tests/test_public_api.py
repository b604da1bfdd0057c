"""The public Python API: each function gives the numbers its command prints, results are frozen, and
``import dtcrit`` exposes the curated names only.

The command line's JSON is parsed from its printed output (``dtcrit.cli.main``), the paper's printed
formulas are checked against the formulas as printed, evaluated with mpmath.
"""
from __future__ import annotations

import dataclasses
import json
import subprocess
import sys

import mpmath
import pytest

import dtcrit
from support.paths import REPO_ROOT as ROOT
from dtcrit.cli import main

EXAMPLES = ROOT / "examples"
DUMP = EXAMPLES / "packings" / "random_lognormal_60.dump"
BODIES = EXAMPLES / "packings" / "ellipsoids.json"
HOOKE = "gran/hooke/history 1e5 NULL 0 NULL 0.5 0"


def _cli(capsys, argv: list[str]):
    assert main(argv) == 0
    out = capsys.readouterr().out
    return out


def _cli_json(capsys, argv: list[str]) -> dict:
    return json.loads(_cli(capsys, argv))


def _same(api: dict, cli: dict) -> None:
    """The API's JSON document equals the command's, after the same JSON round trip."""
    assert json.loads(json.dumps(api)) == cli


@pytest.mark.parametrize("scene", ["mixed_pair", "paper_ellipsoids"])
def test_the_step_of_a_scene_is_the_one_dtcrit_step_prints(scene, capsys):
    path = str(EXAMPLES / f"{scene}.toml")
    cli = _cli_json(capsys, ["step", path, "--json"])
    result = dtcrit.critical_step(dtcrit.load_scene(path))
    assert result.dt_crit == cli["dt_crit"]
    _same(result.to_json(), cli)
    with pytest.raises(dataclasses.FrozenInstanceError):
        result.dt_crit = 1.0  # type: ignore[misc]


@pytest.mark.parametrize("argv, kwargs", [
    ([str(DUMP), "--kn", "1e5", "--ks", "1e5"], {"source": str(DUMP), "kn": 1e5, "ks": 1e5}),
    (["--lattice", "sc", "--cells", "3", "--kn", "1e6", "--ks", "5e5"],
     {"lattice": "sc", "cells": 3, "kn": 1e6, "ks": 5e5}),
    ([str(BODIES), "--kn", "1e5", "--ks", "8e4"], {"source": str(BODIES), "kn": 1e5, "ks": 8e4}),
], ids=["dump", "lattice", "bodies"])
def test_packing_step_gives_the_numbers_dtcrit_packing_prints(argv, kwargs, capsys):
    cli = _cli_json(capsys, ["packing", *argv, "--json"])
    step = dtcrit.packing_step(**kwargs)
    assert (step.omega_max, step.dt_crit, step.dt_safe) == (cli["omega_max"], cli["dt_crit"], cli["dt_safe"])
    assert {e.name: e.dt for e in step.estimates} == {k: v["dt"] for k, v in cli["estimates"].items()}
    _same(step.to_json(), cli)
    assert step.to_text() == _cli(capsys, ["packing", *argv]).rstrip("\n")
    with pytest.raises(dataclasses.FrozenInstanceError):
        step.dt_crit = 1.0  # type: ignore[misc]


def test_read_and_audit_a_snapshot_give_what_dtcrit_audit_prints(capsys):
    argv = ["audit", str(DUMP), "--pair-style", HOOKE, "--dt", "1e-6"]
    cli = _cli_json(capsys, [*argv, "--json"])
    snapshot = dtcrit.read_snapshot(str(DUMP), pair_style=HOOKE)
    assert snapshot.packing.n == cli["n_particles"] and snapshot.contacts.count == cli["n_contacts"]
    audit = dtcrit.audit_snapshot(snapshot, dt=1e-6)
    assert (audit.dt_crit, audit.dt_safe, audit.ratio) == (cli["dt_crit"], cli["dt_safe"], cli["dt_user_ratio"])
    _same(audit.to_json(), cli)
    assert audit.to_text() == _cli(capsys, argv).rstrip("\n")
    assert dtcrit.audit_snapshot(str(DUMP), pair_style=HOOKE, dt=1e-6) == audit
    for frozen in (snapshot, audit):
        with pytest.raises(dataclasses.FrozenInstanceError):
            frozen.source = "x"  # type: ignore[misc]


def test_audit_snapshot_refuses_read_options_with_a_snapshot_already_read():
    snapshot = dtcrit.read_snapshot(str(DUMP), pair_style=HOOKE)
    with pytest.raises(dtcrit.MisuseError, match="pair_style") as exc:
        dtcrit.audit_snapshot(snapshot, pair_style=HOOKE)
    assert isinstance(exc.value, TypeError) and isinstance(exc.value, dtcrit.DtcritError)


def test_emit_code_is_the_source_dtcrit_codegen_prints(capsys):
    path = str(EXAMPLES / "mixed_pair.toml")
    cli = _cli(capsys, ["codegen", path, "--lang", "c", "--name", "contact_dt"])
    command = f"dtcrit codegen {path} --lang c --name contact_dt"
    assert dtcrit.emit_code(path, "c", "contact_dt", command=command) == cli
    code = dtcrit.emitted_code(dtcrit.load_scene(path), "c", "contact_dt", command=command)
    assert code.source == cli and code.to_json()["function"] == "contact_dt"
    with pytest.raises(dataclasses.FrozenInstanceError):
        code.source = ""  # type: ignore[misc]


def test_bad_input_is_an_input_error_naming_the_parameter():
    with pytest.raises(dtcrit.InputError) as exc:
        dtcrit.packing_step(lattice="sc", kn=1.0, damping_ratio=-1.0)
    assert exc.value.key == "damping_ratio"
    with pytest.raises(dtcrit.InputError) as exc:
        dtcrit.packing_step(lattice="sc")
    assert exc.value.key == "kn"
    with pytest.raises(dtcrit.InputError) as exc:
        dtcrit.read_snapshot(str(DUMP))
    assert exc.value.key == "pair_style"
    with pytest.raises(dtcrit.InputError) as exc:
        dtcrit.emit_code(str(EXAMPLES / "mixed_pair.toml"), "c", "for")
    assert exc.value.key == "name"
    with pytest.raises(dtcrit.InputError) as exc:
        dtcrit.emit_code(str(EXAMPLES / "mixed_pair.toml"), "rust")
    assert exc.value.key == "lang"


def test_the_paper_module_keeps_the_printed_formulas_beside_the_verified_ones():
    from dtcrit import paper

    k, c, a = 3.0e5, 2.0, 7.0e2
    mpmath.mp.dps = 50
    printed = (c * a + mpmath.sqrt(c**2 * a**2 + 4 * k * a)) / (k * a)  # Eq. (46) as printed
    assert paper.eq46_dt(k, c, a) == pytest.approx(float(printed), rel=1e-15)
    assert paper.eq40_critical_dt(k, c, a) < paper.eq46_dt(k, c, a)
    sphere = dtcrit.Sphere(2.0e-3, density=2500.0)
    m = 2500.0 * 4.0 / 3.0 * mpmath.pi * mpmath.mpf(2.0e-3) ** 3
    eq26 = 2 * (1 / m + mpmath.mpf(2.0e-3) ** 2 / (mpmath.mpf(2) / 5 * m * mpmath.mpf(2.0e-3) ** 2))
    assert paper.eq26_a_max(sphere) == pytest.approx(float(eq26), rel=1e-13)
    assert {f.printed for f in paper.FORMS} <= set(dir(paper)) and {f.verified for f in paper.FORMS} <= set(dir(paper))


def test_dir_lists_the_api_only_and_every_name_imports():
    names = dir(dtcrit)
    assert not {"annotations", "importlib", "_importlib", "_API", "_MODULES"} & set(names)
    assert set(names) == set(dtcrit.__all__) | {"__version__"}
    for name in dtcrit.__all__:
        assert getattr(dtcrit, name) is not None
    with pytest.raises(AttributeError):
        dtcrit.no_such_name  # noqa: B018


def test_import_dtcrit_stays_cheap():
    code = "import sys, dtcrit; print(sorted(m for m in ('numpy', 'sympy', 'scipy') if m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         env={"PYTHONPATH": str(ROOT / "src"), "PATH": ""}).stdout
    assert out.strip() == "[]"
