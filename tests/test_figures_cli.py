"""``dtcrit figures``: the default run writes every PNG + CSV and a strict-JSON summary; bad input
is one line on standard error with exit status 2."""
from __future__ import annotations

import csv
import io
import json
import math
from contextlib import redirect_stdout

import pytest

from dtcrit.cli import main

EXPECTED = [
    "fig3_damping", "fig4_stiffness", "fig5_density", "fig6_aspect_ratio",
    "figA2_centre_moved", "figA4_orientation_changed", "figA_shapes",
]


def _strict(text):
    def bad(name):
        raise ValueError(f"non-finite JSON constant {name}")

    return json.loads(text, parse_constant=bad)


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    out = tmp_path_factory.mktemp("figs")
    buf = io.StringIO()
    with redirect_stdout(buf):
        code = main(["figures", "--out", str(out), "--json"])
    return code, _strict(buf.getvalue()), out


def test_default_run_writes_every_figure_and_csv(run):
    code, _, out = run
    assert code == 0
    for stem in EXPECTED:
        png = out / f"{stem}.png"
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", stem
        rows = list(csv.reader((out / f"{stem}.csv").open()))
        assert len(rows) > 2 and all(len(r) == len(rows[0]) for r in rows), stem


def test_json_summary_keys(run):
    _, summary, _ = run
    ap = summary["appendix_a"]
    for key in ("orthogonal", "max_found", "max_config", "orthogonal_is_max"):
        assert key in ap
    assert ap["orthogonal_is_max"] is False and ap["max_found"] > ap["orthogonal"]
    ar = summary["aspect_ratio"]
    for key in ("min_ratio", "max_ratio", "fraction_over_1e4"):
        assert isinstance(ar[key], float)
    assert 0.0 < ar["fraction_over_1e4"] < 0.01 and ar["min_ratio"] < 1e4
    assert summary["fig4"]["eq46_trend_with_N"] == "increases"
    assert summary["fig4"]["verified_trend_with_N"]["velocity-verlet"] == "decreases"


def test_fig4_csv_undamped_point_is_eq48(run):
    """Row k_n = 1e10, N = 0: Eq. (46) = Eq. (48) = 2/sqrt(k_n A_max), A_max = 20/m, m = 8000 pi kg."""
    _, _, out = run
    rows = list(csv.DictReader((out / "fig4_stiffness.csv").open()))
    row = next(r for r in rows if float(r["k_n"]) == 1e10 and r["N"] == "0")
    expected = 2.0 / math.sqrt(1e10 * 20.0 / (1000.0 * 8.0 * math.pi))
    assert float(row["dt_eq46_printed"]) == pytest.approx(expected, rel=1e-12)
    assert float(row["dt_velocity-verlet_A_max"]) == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("argv, key", [
    (["figures", "--only", "fig9"], "only"),
    (["figures", "--only", ","], "only"),
])
def test_bad_input_is_one_line(argv, key, capsys, tmp_path):
    code = main(argv + ["--out", str(tmp_path)])
    err = capsys.readouterr().err
    assert code == 2
    assert err.count("\n") == 1 and key in err


def test_out_must_be_a_folder(tmp_path, capsys):
    f = tmp_path / "file.txt"
    f.write_text("x")
    assert main(["figures", "--only", "fig3", "--out", str(f)]) == 2
    assert "out" in capsys.readouterr().err
