"""``dtcrit packing`` and ``dtcrit audit`` refuse what they cannot answer in one line, at once.

Each case runs the command line in a subprocess with a timeout: exit status 2, one line on standard
error naming the flag (``--flag: reason``) or the file's key (``FILE:key: reason``), no traceback,
nothing on standard output and no output file written.  The typed non-convergence error is checked
against a dense eigen-solve (``numpy.linalg.eigvalsh`` of the assembled matrix, an independent route).
"""
from __future__ import annotations

import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from support.paths import REPO_ROOT as ROOT

DUMP = ROOT / "examples" / "packings" / "random_lognormal_60.dump"
TIMEOUT = 60.0  # generous for a loaded machine; each refusal takes a few seconds


def _cli(args, tmp_path, *, limit_kib: int | None = None):
    """Run ``dtcrit ARGS --write-dump OUT`` (packing) or ``dtcrit ARGS`` (audit): (rc, out, err, out written)."""
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"))
    out_file = tmp_path / "written.dump"
    argv = [sys.executable, "-m", "dtcrit", *args]
    if args[0] == "packing":
        argv += ["--write-dump", str(out_file)]
    preexec = None
    if limit_kib is not None:
        import resource

        def preexec():
            resource.setrlimit(resource.RLIMIT_AS, (limit_kib * 1024, limit_kib * 1024))
    done = subprocess.run(argv, capture_output=True, text=True, timeout=TIMEOUT, env=env, preexec_fn=preexec)
    return done.returncode, done.stdout, done.stderr, out_file.exists()


def _one_line(rc, out, err, written, start: str):
    assert rc == 2, (rc, err[-2000:])
    assert out == "" and not written
    assert "Traceback" not in err and len(err.splitlines()) == 1, err[-2000:]
    assert err.startswith(start), err


def _one_sphere_dump(tmp_path) -> Path:
    path = tmp_path / "one.dump"
    path.write_text("ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS pp pp pp\n"
                    "0 1e-5\n0 1e-5\n0 1e-5\nITEM: ATOMS id type x y z radius mass\n1 1 5e-6 5e-6 5e-6 1e-3 1e-5\n",
                    encoding="ascii")
    return path


@pytest.mark.parametrize("lattice", ["fcc", "hcp", "bcc"])
def test_hertz_on_touching_lattice_names_youngs(lattice, tmp_path):
    """FCC: every overlap exactly zero (was ``ArpackError: Starting vector is zero``); HCP and BCC
    (4 cells): overlaps of ~1e-18 m, rounding noise of the coordinates, whose Hertz stiffness is noise."""
    rc, out, err, written = _cli(["packing", "--lattice", lattice, "--cells", "4", "--youngs", "63e9"], tmp_path)
    _one_line(rc, out, err, written, "dtcrit: --youngs: ")
    assert "zero overlap" in err


def test_zero_matrix_with_stored_zeros_is_not_given_to_arpack():
    """A sparse matrix whose stored entries are all zero (Hertz contacts at zero overlap) has
    omega_max = 0; ARPACK is never started on it (it would start from a zero vector)."""
    import scipy.sparse as sps

    from dtcrit.packing.solvers.largest_mode import largest_mode

    a = sps.random(900, 900, density=0.01, random_state=1, format="csr")
    a.data[:] = 0.0
    top = largest_mode(a, "eigsh")
    assert top.value == 0.0 and top.matvecs == 0


@pytest.mark.parametrize("command", ["packing", "audit"])
def test_sphere_wider_than_its_periodic_box_is_refused(command, tmp_path):
    """One 1 mm sphere in a 10 um periodic box: was a hang (self-images without end, +12 MiB/s)."""
    path = _one_sphere_dump(tmp_path)
    law = ["--kn", "1e5"] if command == "packing" else ["--pair-style", "gran/hooke/history 1e5 NULL 0 NULL 0.5 0"]
    rc, out, err, written = _cli([command, str(path), *law], tmp_path)
    _one_line(rc, out, err, written, f"dtcrit: {path}:10: ")  # the dump reader names the sphere's line
    assert "exceeds the periodic box length 1e-05 along x" in err


def test_sphere_touching_its_own_image_is_kept():
    """A box exactly one diameter wide (the sphere touches its images at zero overlap) stays valid."""
    from dtcrit.packing.detection.overlaps import find_sphere_contacts
    from dtcrit.packing.generators.lattices import lattice

    assert find_sphere_contacts(lattice("sc", 1)).count == 3


def test_not_converged_bracket_holds_the_dense_value():
    """ARPACK stopped after one restart: ``NotConvergedError`` carries a bracket on omega_max^2 that
    holds the value of a dense eigen-solve of the same matrix (the independent route)."""
    from dtcrit.errors import NotConvergedError
    from dtcrit.packing.operators.assembly import mass_diagonal, scale_symmetric, stiffness_matrix
    from dtcrit.packing.detection.overlaps import find_sphere_contacts
    from dtcrit.packing.solvers.largest_mode import largest_mode
    from dtcrit.packing.model import LinearLaw, apply_law
    from dtcrit.packing.generators.lattices import lattice

    p = lattice("fcc", 3, radius=1e-3, density=2650.0)
    c = apply_law(find_sphere_contacts(p), LinearLaw(1e5, 3e4))
    a = scale_symmetric(stiffness_matrix(p, c), mass_diagonal(p))
    true = float(np.linalg.eigvalsh(a.toarray())[-1])
    with pytest.raises(NotConvergedError) as caught:
        largest_mode(a, "eigsh", maxiter=1)
    exc = caught.value
    assert exc.lower <= true <= exc.upper and exc.lower > 0 and math.isfinite(exc.upper)


def test_not_converged_in_the_cli_reports_the_dt_bracket(monkeypatch, capsys):
    """Through ``dtcrit packing``: one line naming --solver with the bracket on dt_crit, which holds
    2/omega_max from the dense eigen-solve."""
    import re

    import dtcrit.packing.report as report
    from dtcrit.cli import main
    from dtcrit.packing.operators.assembly import mass_diagonal, scale_symmetric, stiffness_matrix
    from dtcrit.packing.detection.overlaps import find_sphere_contacts
    from dtcrit.packing.generators.lattices import lattice
    from dtcrit.packing.model import LinearLaw, apply_law

    real = report.largest_mode
    monkeypatch.setattr(report, "largest_mode", lambda a, method, **k: real(a, "eigsh", tol=k["tol"], maxiter=1))
    assert main(["packing", "--lattice", "bcc", "--cells", "4", "--kn", "1e5", "--ks", "3e4"]) == 2
    out, err = capsys.readouterr()
    assert out == "" and len(err.splitlines()) == 1 and err.startswith("dtcrit: --solver: ")
    lower, upper = map(float, re.search(r"dt_crit \[s\] lies in \[([^,]+), ([^\]]+)\]", err).groups())
    p = lattice("bcc", 4, radius=1e-3, density=2650.0)
    c = apply_law(find_sphere_contacts(p), LinearLaw(1e5, 3e4))
    a = scale_symmetric(stiffness_matrix(p, c), mass_diagonal(p))
    dt_true = 2.0 / math.sqrt(float(np.linalg.eigvalsh(a.toarray())[-1]))
    assert lower * (1 - 1e-5) <= dt_true <= upper * (1 + 1e-5)  # 6 printed digits


PRELOADED_STYLE = "gran/hooke/history 1e5 NULL 2e4 NULL 0.5 1"


def test_forward_euler_on_a_statically_unstable_packing_is_refused(tmp_path):
    """The pre-loaded LAMMPS packing has an indefinite K~: its exact motion grows whatever the step
    (independent check: a positive real part among the dense continuous-time eigenvalues), so the
    spectral-radius route has no critical step to give.  It was 7.6e-10 s (the step where the physical
    growth per step reached the slack), then a step that let stiff modes grow as fast as the physical
    one; now one line naming the flag that set the contact law."""
    from dtcrit.errors import InputError
    from dtcrit.packing.solvers.damped_step import damped_critical_dt, scaled_matrices
    from dtcrit.packing.readers.lammps_dump import read_dump
    from dtcrit.packing.conventions.engines import engine_convention, engine_sphere_contacts, with_arms
    from dtcrit.packing.conventions.pair_styles import apply_terms, parse_pair_style

    packing = read_dump(DUMP)
    style = parse_pair_style(PRELOADED_STYLE)
    convention = engine_convention("lammps")
    contacts = with_arms(packing, engine_sphere_contacts(packing, convention), style.arm)
    contacts = apply_terms(contacts, style.terms(packing, contacts), preload=convention.preload)
    k, c = scaled_matrices(packing, contacts, "assembled")
    kd, cd = k.toarray(), c.toarray()
    n = kd.shape[0]
    continuous = np.block([[np.zeros((n, n)), np.eye(n)], [-kd, -cd]])
    assert float(np.max(np.linalg.eigvals(continuous).real)) > 0  # the physical instability
    with pytest.raises(InputError) as err:
        damped_critical_dt(packing, contacts, "forward-euler")
    assert err.value.key == "stiffness" and "statically unstable" in err.value.reason
    rc, out, err_text, written = _cli(["audit", str(DUMP), "--pair-style", PRELOADED_STYLE,
                                       "--integrator", "forward-euler"], tmp_path)
    _one_line(rc, out, err_text, written, "dtcrit: --pair-style: ")


def test_memory_guard_reads_the_address_space_limit(tmp_path):
    """``ulimit -v 1500000``: fcc --cells 60 (864,000 spheres) was a MemoryError traceback."""
    rc, out, err, written = _cli(["packing", "--lattice", "fcc", "--cells", "60", "--kn", "1e5"], tmp_path,
                                 limit_kib=1_500_000)
    _one_line(rc, out, err, written, "dtcrit: --cells: ")
    assert "ulimit -v" in err


def test_available_bytes_is_the_least_of_the_limits(monkeypatch, tmp_path):
    import dtcrit.packing.solvers.memory as memory

    monkeypatch.setattr(memory, "_meminfo", lambda: 8e9)
    monkeypatch.setattr(memory, "_rlimit_as", lambda: 3e9)
    monkeypatch.setattr(memory, "_cgroup_room", lambda: 5e9)
    assert memory.available_bytes() == 3e9
    monkeypatch.setattr(memory, "_rlimit_as", lambda: None)
    assert memory.available_bytes() == 5e9
    # cgroup files: v2 "max" is no limit, v1's huge number too; a set limit counts less its usage
    (tmp_path / "memory.max").write_text("max\n")
    assert memory._read_number(tmp_path / "memory.max") is None
    (tmp_path / "memory.limit_in_bytes").write_text("9223372036854771712\n")
    assert memory._read_number(tmp_path / "memory.limit_in_bytes") is None
    (tmp_path / "memory.limit_in_bytes").write_text("1000000\n")
    assert memory._read_number(tmp_path / "memory.limit_in_bytes") == 1e6


def test_a_random_packing_that_would_not_finish_is_refused(tmp_path):
    """--random 3000000: was still generating after 120 s with no progress shown."""
    rc, out, err, written = _cli(["packing", "--random", "3000000", "--kn", "1e5"], tmp_path)
    _one_line(rc, out, err, written, "dtcrit: --random: ")
    assert "min to generate" in err


def test_random_packing_draws_progress_on_a_terminal(monkeypatch, capsys):
    import importlib

    rp = importlib.import_module("dtcrit.packing.generators.random_packing")
    monkeypatch.setattr(rp, "PROGRESS_SPHERES", 10)
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True, raising=False)
    rp.random_packing(40, cn=6.0, max_steps=5)
    assert "random packing: relaxation" in capsys.readouterr().err


def test_default_certificate_costs_a_few_eigen_solves():
    """The automatic certificate is skipped when its factorisation would cost more than
    CERTIFY_BUDGET eigen-solves (FCC at 24k DOFs: was 107 s and 3.4 GiB)."""
    from dtcrit.packing.solvers.certificate import factor_bytes, factor_seconds
    from dtcrit.packing.report import CERTIFY_BUDGET, auto_certifies

    assert auto_certifies(3000, 12.0, 0.01)  # the sparse route: under a second (measured 0.8 s)
    assert not auto_certifies(24000, 12.0, 2.0)
    assert factor_seconds(24000, 12.0) > CERTIFY_BUDGET * 2.0 and factor_bytes(24000, 12.0) > 2**30
    assert factor_seconds(12000, 6.0) < factor_seconds(12000, 12.0)


BAD_FLAGS = [
    (["packing", "--lattice", "fcc", "--cells", "0", "--kn", "1e5"], "--cells: "),
    (["packing", "--random", "0", "--kn", "1e5"], "--random: "),
    (["packing", "--random", "50", "--kn", "1e5", "--cn", "1e9"], "--cn: "),
    (["packing", "--random", "50", "--kn", "1e5", "--spread", "nan"], "--spread: "),
    (["packing", "--random", "50", "--kn", "1e5", "--seed", "-1"], "--seed: "),
    (["packing", "--random", "50", "--kn", "1e5", "--radius", "1e300"], "--radius: "),
    (["packing", "--lattice", "fcc", "--cells", "2", "--kn", "1e5", "--radius", "1e300"], "--radius: "),
    (["packing", "--lattice", "fcc", "--cells", "2", "--kn", "1e308"], "--kn: "),
    (["packing", "--lattice", "fcc", "--cells", "2", "--kn", "1e5", "--snapshot", "3"], "--snapshot: "),
    (["packing", "--lattice", "fcc", "--cells", "2", "--kn", "1e5", "--integrator", "nope"], "--integrator: "),
    (["audit", str(DUMP), "--pair-style", "gran/hooke/history 1e308 NULL 0 NULL 0.5 0"], "--pair-style: "),
    (["audit", str(DUMP), "--pair-style", "gran/hooke/history 1e5 NULL 1e300 NULL 0.5 0"], "--pair-style: "),
    (["audit", str(DUMP), "--pair-style", "gran/hooke/history 1e5 NULL 0 NULL 0.5 0", "--integrator", "x"],
     "--integrator: "),
]


@pytest.mark.parametrize("args,start", BAD_FLAGS, ids=[" ".join(a[1:]) for a, _ in BAD_FLAGS])
def test_bad_values_name_the_flag(args, start, tmp_path):
    """Non-finite, zero, negative and huge values: the flag is named, no library text leaks."""
    rc, out, err, written = _cli(args, tmp_path)
    _one_line(rc, out, err, written, f"dtcrit: {start}")
    for leak in ("np.float64", "infs or NaNs", "expected non-negative integer", "GiB"):
        assert leak not in err


def test_damped_newton_not_converged_keeps_a_valid_bracket(monkeypatch):
    """The lagged (velocity-Verlet) route stopped early: the bracket it reports holds the step found
    when the eigen-solver is allowed to converge (Newton from above; the rigorous lower bound below)."""
    import dtcrit.packing.solvers.damped_step as damped
    from dtcrit.errors import NotConvergedError
    from dtcrit.packing.generators.lattices import lattice
    from dtcrit.packing.detection.overlaps import find_sphere_contacts
    from dtcrit.packing.model import LinearLaw, apply_law

    p = lattice("fcc", 3, radius=1e-3, density=2650.0)
    c = apply_law(find_sphere_contacts(p), LinearLaw(1e5, 3e4)).with_damping(0.5, 0.2)
    true = damped.damped_critical_dt(p, c, "velocity-verlet", method="dense").dt
    real = damped.largest_mode
    calls = []

    def failing(a, method="auto", **k):
        calls.append(1)
        return real(a, method) if len(calls) < 3 else real(a, "eigsh", maxiter=1)

    monkeypatch.setattr(damped, "largest_mode", failing)
    with pytest.raises(NotConvergedError) as caught:
        damped.damped_critical_dt(p, c, "velocity-verlet", method="dense")
    exc = caught.value
    assert exc.quantity == "dt_crit [s]" and 0 < exc.lower <= true <= exc.upper * (1 + 1e-12)


def test_forward_euler_without_dashpots_is_refused_at_once(tmp_path):
    """Forward Euler on a packing without dashpots has no stable step: was a bisection ARPACK could
    not converge on (ArpackNoConvergence traceback after 17 s)."""
    rc, out, err, written = _cli(["audit", str(DUMP), "--pair-style", "gran/hooke/history 1e5 NULL 0 NULL 0.5 0",
                                  "--integrator", "forward-euler"], tmp_path)
    _one_line(rc, out, err, written, "dtcrit: --integrator: ")
    assert "no stable step" in err


@pytest.mark.parametrize("command", ["packing", "audit"])
def test_memory_error_is_one_line(command, monkeypatch, capsys):
    """A MemoryError the guard did not foresee (another process took the memory) is one line, exit 2."""
    import dtcrit.packing.audit.snapshot as audit_module
    import dtcrit.packing.report as report
    from dtcrit.cli import main

    def boom(*args, **kwargs):
        raise MemoryError

    monkeypatch.setattr(report, "analyse", boom)
    monkeypatch.setattr(audit_module, "audit", boom)
    argv = (["packing", "--lattice", "sc", "--cells", "2", "--kn", "1e5"] if command == "packing"
            else ["audit", str(DUMP), "--pair-style", "gran/hooke/history 1e5 NULL 0 NULL 0.5 0"])
    assert main(argv) == 2
    out, err = capsys.readouterr()
    assert out == "" and len(err.splitlines()) == 1 and "ran out of memory" in err
    assert err.startswith("dtcrit: --cells: " if command == "packing" else f"dtcrit: {DUMP}: ")
