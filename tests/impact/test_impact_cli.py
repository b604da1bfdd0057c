"""``dtcrit impact``: JSON contents, figures, and one-line errors with exit status 2."""
import json
import math

import pytest

import dtcrit.impact as imp
from dtcrit.cli import main


def _json(capsys, argv):
    assert main(argv) == 0
    return json.loads(capsys.readouterr().out)


def test_single_step_json(capsys):
    data = _json(capsys, ["impact", "--integrator", "velocity-verlet", "--zeta", "0.2", "--omega-dt", "1.3",
                          "--phases", "16", "--json"])
    z = 0.2
    assert data["exact"]["duration"] == pytest.approx(math.pi / math.sqrt(1 - z * z), rel=1e-14)
    assert data["exact"]["exit_ratio"] == pytest.approx(math.exp(-z * math.pi / math.sqrt(1 - z * z)), rel=1e-14)
    (row,) = data["numerical"]
    assert set(row) >= {"omega_dt", "min", "mean", "max", "on_step"}
    r = imp.simulate_impacts("velocity-verlet", [1.3], imp.entry_phases(16), z).ratios[0]
    assert row["omega_dt"] == 1.3
    assert row["min"] == r.min() and row["max"] == r.max() and row["on_step"] == r[0]
    assert row["mean"] == pytest.approx(r.mean(), rel=1e-15)
    assert data["critical_omega_dt"] == pytest.approx(2 * (math.sqrt(z * z + 1) - z), rel=1e-14)
    assert "hertz" not in data and "by_zeta" not in data


def test_sweep_writes_json_and_figures(capsys, tmp_path):
    data = _json(capsys, ["impact", "--integrator", "leapfrog", "--zeta", "0.1", "--sweep", "--step", "0.1",
                          "--phases", "16", "--out", str(tmp_path), "--json"])
    assert len(data["numerical"]) == 22
    assert data["numerical"][-1]["omega_dt"] == 2.2
    assert [s["zeta"] for s in data["by_zeta"]] == [0.0, 0.05, 0.1, 0.2]
    assert data["hertz"]["linearised_bound"] == pytest.approx(2.0)
    names = sorted(p.name for p in tmp_path.iterdir())
    assert names == ["impact_leapfrog_hertz.png", "impact_leapfrog_zeta0.1.json", "impact_leapfrog_zeta0.1_ratio.png"]
    assert json.loads((tmp_path / "impact_leapfrog_zeta0.1.json").read_text()) == data
    for p in tmp_path.glob("*.png"):
        assert p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_undamped_text_output_and_closed_form(capsys):
    assert main(["impact", "--integrator", "symplectic-euler", "--step", "0.1", "--phases", "16", "--no-hertz"]) == 0
    out = capsys.readouterr().out
    assert "undamped closed form" in out and "exact impact (geometric separation)" in out
    data = _json(capsys, ["impact", "--integrator", "symplectic-euler", "--step", "0.1", "--phases", "16",
                          "--no-hertz", "--json"])
    cf = data["undamped_closed_form"]
    assert cf["max_relative_difference_from_simulation"] < 1e-12
    assert cf["bounds_hold_on_grid_below_2"] is True
    assert all(p["max_abs_ratio_minus_one"] < 1e-11 for p in cf["unit_ratio_steps"])


def test_phase_figure_for_single_step(capsys, tmp_path):
    main(["impact", "--integrator", "leapfrog-centred", "--zeta", "0.05", "--omega-dt", "0.9", "--phases", "8",
          "--out", str(tmp_path)])
    assert (tmp_path / "impact_leapfrog-centred_zeta0.05_omegadt0.9_phases.png").exists()


@pytest.mark.parametrize(
    "argv,needle",
    [
        (["--integrator", "leapfrg"], "did you mean 'leapfrog'"),
        (["--integrator", "leapfrog", "--zeta", "-1"], "zeta"),
        (["--integrator", "leapfrog", "--zeta", "nan"], "zeta"),
        (["--integrator", "leapfrog", "--omega-dt", "0"], "omega-dt"),
        (["--integrator", "leapfrog", "--phases", "0"], "phases"),
        (["--integrator", "leapfrog", "--energy-threshold", "2"], "--energy-threshold: must lie in (0, 1)"),
        (["--integrator", "leapfrog", "--omega-dt", "1", "--sweep"], "not allowed"),
        (["--zeta", "0.1"], "required"),
    ],
)
def test_bad_arguments_one_line_exit_2(capsys, argv, needle):
    try:
        code = main(["impact", "--step", "0.5", "--phases", "4", *argv])
    except SystemExit as exc:  # argparse's own errors
        code = exc.code
    err = capsys.readouterr().err
    assert code == 2
    assert needle in err and err.count("\n") == 1, err
