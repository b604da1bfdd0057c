"""``dtcrit packing`` command line: sources, JSON keys, one-line errors."""
import json
import math

import pytest

from dtcrit.cli import main

KEYS = ("omega_max", "dt_crit", "alpha", "cn_mean", "cn_max", "n_particles", "dofs", "estimates")


def _json(capsys, argv):
    assert main(argv + ["--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_lattice_json(capsys):
    out = _json(capsys, ["packing", "--lattice", "sc", "--cells", "2", "--kn", "1e6", "--ks", "1e6",
                         "--density", "1000", "--radius", "0.01"])
    for key in KEYS:
        assert key in out
    m = 4 / 3 * math.pi * 0.01**3 * 1000
    assert out["omega_max"] == pytest.approx(math.sqrt(20 * 1e6 / m), rel=1e-10)  # co-rotation, (10/3) CN k/m
    assert out["alpha"] == pytest.approx(math.sqrt(1.2 / 6), rel=1e-10)
    assert out["cn_max"] == 6 and out["n_particles"] == 8 and out["dofs"] == 48
    assert set(out["estimates"]) == {"gershgorin", "block_diagonal", "diagonal", "two_particle_amax", "two_particle_exact", "rayleigh"}
    assert out["estimates"]["gershgorin"]["safe"] is True


def test_random_text_report(capsys):
    assert main(["packing", "--random", "40", "--cn", "5", "--sizes", "uniform", "--spread", "0.2", "--seed", "3",
                 "--kn", "1e5"]) == 0
    text = capsys.readouterr().out
    assert "dt_crit = 2/omega_max" in text and "gershgorin" in text and "coordination mean 5" in text


def test_damped_integrator_bound(capsys):
    pytest.importorskip("dtcrit.integrators.stability")
    out = _json(capsys, ["packing", "--lattice", "fcc", "--cells", "1", "--damping-ratio", "0.1", "--kn", "1e5"])
    assert out["dt_integrator"] < out["dt_crit"]
    assert out["dt_integrator"] == pytest.approx(out["dt_crit"] / (0.1 + math.sqrt(1.01)), rel=1e-9)


@pytest.mark.parametrize("argv,words", [
    (["packing", "--kn", "1"], "give exactly one of FILE, --lattice or --random"),
    (["packing", "--lattice", "sc"], "kn: give the contact stiffness"),
    (["packing", "--kn", "1", "--lattice", "sc", "--random", "10"], "give exactly one"),
    (["packing", "--lattice", "sc", "--kn", "-1"], "kn: must be a finite number >= 0"),
    (["packing", "--kn", "1", "--lattice", "sc", "--cells", "0"], "cells"),
    (["packing", "--lattice", "sc", "--youngs", "1e9", "--kn", "1e5"], "either --kn/--ks or --youngs"),
    (["packing", "--kn", "1", "--lattice", "sc", "--damping-ratio", "-0.1"], "damping-ratio"),
    (["packing", "--kn", "1", "--lattice", "sc", "--radius", "0"], "radius"),
    (["packing", "--kn", "1", "--random", "10", "--cn", "30"], "cn"),
    (["packing", "--scale", "1e3,abc"], "scale"),
])
def test_bad_input_is_one_line_exit_2(capsys, argv, words):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and words in err and "Traceback" not in err


def test_hertz_on_a_touching_lattice_has_no_stiffness(capsys):
    """Hertz tangent stiffness vanishes at zero overlap: a touching lattice has no vibrating mode, said in one line."""
    assert main(["packing", "--lattice", "sc", "--youngs", "7e10"]) == 2
    out, err = capsys.readouterr()
    assert out == "" and len(err.splitlines()) == 1 and "zero overlap" in err


def test_a_packing_without_contacts_is_refused(tmp_path, capsys):
    from dtcrit.packing import Packing, write_dump

    path = tmp_path / "apart.dump"
    write_dump(path, Packing.spheres([[0.0, 0, 0], [10.0, 0, 0]], [1.0, 1.0], density=1.0))
    assert main(["packing", str(path), "--kn", "1"]) == 2
    out, err = capsys.readouterr()
    assert out == "" and "no two particles touch" in err and len(err.splitlines()) == 1


def test_progress_lines_when_asked(monkeypatch, capsys):
    """On a terminal, long assemblies draw a tqdm bar and the eigen-solve a counter; chunked
    assembly gives the same matrix as one chunk."""
    import sys

    import numpy as np

    import dtcrit.packing.operators.assembly as assembly
    import dtcrit.packing.solvers.largest_mode as eigen
    from dtcrit.packing import LinearLaw, apply_law, find_sphere_contacts, largest_mode, lattice, stiffness_matrix

    monkeypatch.setattr(sys.stderr, "isatty", lambda: True, raising=False)
    monkeypatch.setattr(eigen, "LONG_WORK", 0)
    monkeypatch.setattr(assembly, "LONG_WORK", 0)
    p = lattice("fcc", 2, mass=1.0)
    c = apply_law(find_sphere_contacts(p), LinearLaw(1.0, 0.5))
    k16 = stiffness_matrix(p, c, chunk=16)
    mode = largest_mode(k16, "eigsh")
    err = capsys.readouterr().err
    assert "assembly" in err and "eigen-solve" in err and "matrix-vector products" in err
    assert mode.matvecs > 0
    assert np.allclose(k16.toarray(), stiffness_matrix(p, c).toarray(), rtol=1e-13, atol=1e-13)


def test_no_progress_when_piped(capsys):
    """Off a terminal nothing is drawn, whatever the size of the work."""
    from dtcrit.packing import LinearLaw, apply_law, find_sphere_contacts, largest_mode, lattice, stiffness_matrix

    p = lattice("fcc", 2, mass=1.0)
    largest_mode(stiffness_matrix(p, apply_law(find_sphere_contacts(p), LinearLaw(1.0, 0.5)), chunk=16), "eigsh")
    assert capsys.readouterr().err == ""


def test_scaling_helpers():
    from dtcrit.bench.packing_scaling import fit_exponent, parse_sizes, run_one

    assert parse_sizes("1e3,2000") == [1000, 2000]
    assert fit_exponent([1e3, 1e4, 1e5], [2.0, 20.0, 200.0]) == pytest.approx(1.0)
    row = run_one(100, "fcc")
    assert row["n"] == 108 and row["dense_rel_diff"] < 1e-7
    assert row["estimates"]["block_diagonal"] >= row["omega2"] * (1 - 1e-9)  # omega^2 bounds: above
    assert row["estimates"]["rayleigh"] <= row["omega2"] * (1 + 1e-9)


def test_the_scale_benchmark_reports_each_stage_against_its_floor():
    """A matrix-free row carries each stage's floor, worked out here again from the operator's bytes,
    the products and the bandwidth the row reports, and a stage line naming every stage."""
    from dtcrit.bench.packing_scaling import run_one, stage_line

    row = run_one(500, "fcc", route="matrix-free")
    per_pass = row["contact_bytes"] / (row["bandwidth_gbs"] * 1e9)
    floors = row["floor_s_by_stage"]
    assert floors["eigen"] == pytest.approx(row["matvecs"] * per_pass, rel=1e-12)
    assert floors["bounds"] == pytest.approx((row["bounds_products"] + 2) * per_pass, rel=1e-12)
    assert row["bounds_products"] == 3  # the co-rotations; the local trials take no product
    assert floors["search"] > 0
    assert row["floor_ratio_by_stage"]["eigen"] == pytest.approx(row["t_eigen"] / floors["eigen"])
    assert row["memory_floor_bytes"] == row["contact_bytes"] + 9 * 8 * row["dofs"]
    peaks = row["peak_after_mib"]
    assert list(peaks) == ["generate", "search", "operator", "eigen", "bounds"]
    assert all(a <= b for a, b in zip(list(peaks.values()), list(peaks.values())[1:]))
    line = stage_line(row)
    assert all(word in line for word in ("search", "operator", "eigen-solve", "bounds", "x floor", "GiB"))


def test_a_packing_too_big_for_the_memory_is_refused_before_any_work(capsys, monkeypatch):
    """fcc --cells 200 is 32 million spheres: refused at once with the estimate, not a MemoryError after
    a minute (the estimate is per sphere as measured by the scale benchmark)."""
    import time

    import dtcrit.packing.solvers.memory as memory

    monkeypatch.setattr(memory, "available_bytes", lambda: 24.0 * 2**30)
    start = time.perf_counter()
    assert main(["packing", "--lattice", "fcc", "--cells", "200", "--kn", "1"]) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and "32,000,000 spheres need about" in err and "GiB available" in err
    assert time.perf_counter() - start < 5.0
    assert main(["packing", "--random", "100000000", "--kn", "1"]) == 2
    assert "100,000,000 spheres" in capsys.readouterr().err
    # a packing that fits is not refused, and the estimate grows with the size
    assert memory.estimated_bytes(10**6, 12) < 24.0 * 2**30 < memory.estimated_bytes(32 * 10**6, 12)
