"""The quick bench (``dtcrit bench --quick``) run once; its accuracy claims asserted, never its times.

* dtcrit's own routes (``critical_dt_array``, the scalar ``critical_dt`` -- both through
  ``dtcrit.integrators.precise`` -- the fused kernel and the emitted C) are within 4 ulp of the 50-digit reference on the
  batch sample and on the whole extreme-case suite, or refuse the input;
* so is the emitted careful C step (``dtcrit.codegen.step``, compiled; a step outside float64 is refused
  by the route; tests/codegen/test_kernels_extreme_suite.py checks the C, Fortran and NumPy steps themselves);
* mpmath eigenvalues at 30 and 50 digits + bisection agree with the reference (an independent
  route: no closed form, no polynomial) to half an ulp;
* the direct routes and the paper's forms lose digits where the analysis says they must;
* the simulation check (section 3) never disagrees with the reference step;
* the report files and the ``--json`` summary have the documented content.
"""
import csv
import json

import pytest

from dtcrit.bench.report import json_summary, write_report
from dtcrit.bench.runner import QUICK, run_bench
from dtcrit.bench.suite import SUITE
from dtcrit.integrators.schemes import NAMES
from support.paths import REPO_ROOT

OWN_ROUTES = ("closed-form-numpy", "closed-form-scalar", "closed-form-c")

@pytest.fixture(scope="module")
def result():
    return run_bench(QUICK)


def _entries(result, route):
    return [e for e in result["suite"] if e["route"] == route]


def _route(result, name):
    return next(r for r in result["routes"] if r["name"] == name)


def test_fused_route_within_4_ulp_or_refuses_everywhere(result):
    r = _route(result, "closed-form-fused")
    assert r["failures"] == 0 and r["max_ulp"] <= 4.0
    bad = [(e["case"], e["integrator"], e["outcome"], e["ulp"], e["note"]) for e in _entries(result, "closed-form-fused")
           if e["outcome"] not in ("ok", "refused")]
    assert not bad
    refused = {(e["case"], e["integrator"]) for e in _entries(result, "closed-form-fused") if e["outcome"] == "refused"}
    # it refuses exactly the steps float64 cannot hold
    assert refused == {(e["case"], e["integrator"]) for e in _entries(result, "closed-form-fused")
                       if not e["step_representable"]}


@pytest.mark.parametrize("route", OWN_ROUTES)
def test_own_routes_within_4_ulp_or_refuse_everywhere(result, route):
    bad = [(e["case"], e["integrator"], e["outcome"], e["ulp"]) for e in _entries(result, route)
           if e["outcome"] not in ("ok", "refused")]
    assert not bad
    for name, e in _route(result, route)["by_integrator"].items():
        assert e["failures"] == 0
        assert e["max_ulp"] <= 4.0, (route, name, e["max_ulp"])


def test_the_suite_covers_every_case_integrator_and_route(result):
    seen = {(e["case"], e["integrator"], e["route"]) for e in result["suite"]}
    for case in SUITE:
        for name in NAMES:
            for route in ("closed-form-numpy", "closed-form-fused", "closed-form-c", "closed-form-scalar",
                          "eigvals+bisection", "eigenvalues-closed+bisection"):
                assert (case.name, name, route) in seen
            if name == "paper-eq40":
                assert (case.name, name, "paper-cardano+bisection") in seen


def test_high_precision_eigenvalue_routes_agree_with_the_reference(result):
    """mpmath.eig at 30 and 50 digits + bisection: no closed form involved, within half an ulp
    (batch sample and the quick run's suite subset; the full run also shows where eigenvalue
    routes lose digits even at 50 digits: the defective double eigenvalue -1 of undamped
    velocity Verlet at tau = 2)."""
    for name in ("mpmath-eig-30", "mpmath-eig-50"):
        r = _route(result, name)
        assert r["failures"] == 0 and r["max_ulp"] <= 0.5
        entries = _entries(result, name)
        assert entries and all(e["outcome"] == "ok" and e["ulp"] <= 0.5 for e in entries), name


def test_float64_eigenvalue_routes_lose_digits_where_expected(result):
    by = {(e["case"], e["integrator"], e["route"]): e for e in result["suite"]}
    for route in ("eigvals+bisection", "eigenvalues-closed+bisection"):
        # forward Euler at zeta = 1e-12: rho - 1 ~ tau (tau - 2 zeta) / 2 ~ 1e-24, invisible in float64
        assert by[("zeta-1e-12", "forward-euler", route)]["digits_lost"] >= 10
        # undamped forward Euler has no stable step; rounding makes tiny steps look stable
        assert by[("zeta-0", "forward-euler", route)]["outcome"] == "failed"
    # the paper's Cardano route (Eqs. 42-43): D -> 0 and cancellation wreck it at ordinary damping
    lost = [e for e in _entries(result, "paper-cardano+bisection") if e["outcome"] == "digits_lost" and e["digits_lost"] >= 10]
    assert {"zeta-10", "zeta-1e3"} <= {e["case"] for e in lost}
    assert _route(result, "paper-cardano+bisection")["median_ulp"] > 1e3


def test_the_paper_forms_lose_digits_where_expected(result):
    by = {(e["case"], e["route"]): e for e in result["paper_forms"]}
    # Eq. (58) at its pole beta = 2/sqrt(7): 28 - 49 beta^2 cancels every digit
    assert by[("eq58-asymptote", "eq58-printed")]["digits_lost"] >= 12
    assert by[("eq58-asymptote-1e-9", "eq58-printed")]["digits_lost"] >= 6
    # Eq. (59) at its pole beta = 2 sqrt(2)
    assert by[("eq59-asymptote-1e-9", "eq59-printed")]["digits_lost"] >= 6
    # the CFL note's sqrt(zeta^2 + 1) - zeta at heavy damping
    assert by[("zeta-1e6", "cfl-note-printed")]["digits_lost"] >= 8
    # Eq. (46) as printed overflows in c^2 A^2 and k A; dtcrit's hypot form does not
    for case in ("c2A2-overflow", "kA-overflow", "kA-underflow"):
        assert by[(case, "eq46-printed")]["outcome"] == "failed"
        assert by[(case, "eq46-dtcrit")]["outcome"] == "ok"
    # Eqs. (34) and (58) have no real value beyond critical damping
    assert by[("zeta-10", "eq34-printed")]["outcome"] == "undefined"
    # as a *bound*, Eq. (46) exceeds the verified velocity-Verlet step once damped
    assert by[("zeta-0.5", "eq46-printed")]["ratio_to_velocity_verlet_bound"] > 2


def test_simulation_agrees_with_the_reference_step(result):
    rows = result["simulation"]
    assert len(rows) == len(SUITE) * len(NAMES)  # no row dropped
    assert not [r for r in rows if r["outcome"] == "disagrees"]
    counts = {o: sum(r["outcome"] == o for r in rows) for o in ("agrees", "no-stable-step", "unobservable")}
    assert counts["agrees"] >= 200 and counts["no-stable-step"] >= 8
    for r in rows:
        if r["outcome"] == "unobservable":
            assert "needs" in r["note"]


def test_json_summary_has_the_documented_keys(result):
    doc = json.loads(json.dumps(json_summary(result)))
    assert {"routes", "suite", "speedup_vs_eig", "kernel_vs_floor"} <= set(doc)
    for r in doc["routes"]:
        assert {"name", "max_ulp", "median_ulp", "seconds_per_scene", "failures"} <= set(r)
    assert {r["name"] for r in doc["routes"]} >= {"closed-form-numpy", "closed-form-c", "paper-cardano+bisection",
                                                  "eigvals+bisection", "mpmath-eig-15", "mpmath-eig-30", "mpmath-eig-50"}
    for e in doc["suite"]:
        assert {"case", "route", "outcome", "ulp"} <= set(e)
        assert e["outcome"] in ("ok", "digits_lost", "refused", "failed", "undefined")
    assert isinstance(doc["speedup_vs_eig"], float) and isinstance(doc["kernel_vs_floor"], float)


def test_startup_figures_cover_every_example_and_no_heavy_import(result):
    """The start-up section reports a figure per example scene (never asserted: machines are shared)
    and, structurally, that `dtcrit step` loads none of the heavy modules (SymPy, SciPy's spatial,
    sparse, special, linalg, optimize) on any example: the polyhedron's hull of a few corners is
    found in NumPy (``dtcrit.bodies.small_hull``)."""
    startup = result["startup"]
    assert {r["scene"] for r in startup["scenes"]} >= {"paper_ellipsoids.toml", "superquadric.toml",
                                                       "polyhedron_cube.toml", "glass_spheres_hertz.toml"}
    for r in startup["scenes"]:
        assert r["heavy_modules"] == [], r
        assert 0 < r["best_seconds"] <= r["median_seconds"] and r["best_over_numpy_import"] > 0
    assert json_summary(result)["startup"] == startup


def test_report_files(result, tmp_path):
    paths = write_report(result, tmp_path)
    names = {p.name for p in paths}
    assert {"bench.md", "routes.csv", "suite.csv", "paper_forms.csv", "simulation.csv", "work_precision.png"} <= names
    md = (tmp_path / "bench.md").read_text()
    for text in ("## Routes", "speedup_vs_eig", "kernel_vs_floor", "## Start-up of `dtcrit step`", "paper_ellipsoids.toml",
                 "## Machine", "numpy:", "mpmath:", "sympy:"):
        assert text in md
    with (tmp_path / "routes.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert {r["route"] for r in rows} >= {"closed-form-numpy", "eigvals+bisection"}
    assert (tmp_path / "work_precision.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_cli_prints_json_and_writes_the_report(result, tmp_path, monkeypatch, capsys):
    import dtcrit.bench.runner as runner
    from dtcrit.cli import main

    monkeypatch.setattr(runner, "run_bench", lambda config: result)
    assert main(["bench", "--quick", "--json", "--out", str(tmp_path)]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["routes"] and doc["suite"]
    assert (tmp_path / "bench.md").exists()
    assert main(["bench", "--quick", "--out", str(tmp_path)]) == 0
    assert "speedup_vs_eig" in capsys.readouterr().out


def test_cli_rejects_a_batch_smaller_than_the_samples(capsys):
    from dtcrit.cli import main

    assert main(["bench", "--quick", "--scenes", "3"]) == 2
    assert "scenes" in capsys.readouterr().err


def _bench_schema():

    root = REPO_ROOT
    return json.loads((root / "src" / "dtcrit" / "schemas" / "dtcrit-bench-1.json").read_text())


def test_json_summary_validates_against_its_schema(result):
    """`dtcrit bench --json` starts with the envelope and validates against dtcrit-bench/1."""
    import jsonschema

    import dtcrit

    schema = _bench_schema()
    jsonschema.Draft202012Validator.check_schema(schema)
    doc = json.loads(json.dumps(json_summary(result)))
    assert list(doc)[:4] == ["schema", "dtcrit_version", "units", "derivation_hashes"]
    assert doc["schema"] == "dtcrit-bench/1" and doc["dtcrit_version"] == dtcrit.__version__
    jsonschema.validate(doc, schema)
    # the section-4 ratios are reported per integrator (figures only: never a threshold on time)
    rat = doc["ratios"]
    assert set(rat["speedup_vs_eig_by_integrator"]) == set(NAMES) == set(rat["kernel_vs_floor_by_integrator"])
    assert set(rat["speedup_vs_eig_c_by_integrator"]) == set(NAMES)


def test_the_bench_schema_rejects_what_it_should(result):
    """Not vacuous: a missing key, a wrong schema name, an unknown outcome, a negative time, an unknown integrator."""
    import jsonschema

    schema = _bench_schema()
    good = json.loads(json.dumps(json_summary(result)))
    mutations = (lambda d: d.pop("derivation_hashes"), lambda d: d.update(schema="dtcrit-step/1"),
                 lambda d: d["suite"][0].update(outcome="fine"), lambda d: d["routes"][0].update(seconds_per_scene=-1.0),
                 lambda d: d["ratios"]["speedup_vs_eig_by_integrator"].update(euler=3.0),
                 lambda d: d["ratios"].pop("kernel_vs_memory_floor"), lambda d: d["units"].pop("seconds_per_scene"))
    for mutate in mutations:
        doc = json.loads(json.dumps(good))
        mutate(doc)
        with pytest.raises(jsonschema.ValidationError):
            jsonschema.validate(doc, schema)
