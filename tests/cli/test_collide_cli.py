"""``dtcrit collide`` on the examples: text and JSON (schema dtcrit-collide/1), each value checked
independently: t_c and the peak overlap from the Hertz closed form (mpmath quadrature), the resolution
step as t_c/N_res of the core's ``resolution_step`` for the same law, the stability step by the spectral
radius of the integrator's update rule on the 12-DOF two-sphere system at the peak's tangent stiffness,
and the codes' rules from their formulas.
"""
from __future__ import annotations

import json
import math

import jsonschema
import mpmath as mp
import pytest
from support.multidof import spectral_radius, sphere_on_wall, two_spheres
from support.paths import REPO_ROOT as ROOT

from dtcrit.cli import main
from dtcrit.collisions import resolution_step

SCHEMA = json.loads((ROOT / "src" / "dtcrit" / "schemas" / "dtcrit-collide-1.json").read_text())
GLASS = ROOT / "examples" / "glass_spheres_hertz.toml"
FLOOR = ROOT / "examples" / "spheres_on_a_floor.toml"
STABLE, GROWS = 1.0 + 1e-6, 1.0 + 1e-4


def _json(capsys, *argv):
    assert main(["collide", *map(str, argv), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    jsonschema.validate(doc, SCHEMA)
    return doc


def _glass():
    """Glass beads of the example: E* = E/(2(1 - nu^2)), G* = G/(2(2 - nu)), R* = R/2, m* = m/2."""
    R, rho, E, nu, v, e = mp.mpf("1e-3"), mp.mpf(2500), mp.mpf("63e9"), mp.mpf("0.22"), mp.mpf(1), mp.mpf("0.9")
    m = rho * 4 * mp.pi * R ** 3 / 3
    G = E / (2 * (1 + nu))
    return dict(R=R, m=m, ms=m / 2, Rs=R / 2, Es=E / (2 * (1 - nu ** 2)), Gs=G / (2 * (2 - nu)), v=v, e=e)


def test_schema_is_valid():
    jsonschema.Draft202012Validator.check_schema(SCHEMA)


def test_hertz_example_against_the_closed_form(capsys):
    doc = _json(capsys, GLASS)
    (p,) = doc["pairs"]
    g = _glass()
    delta = (15 * g["ms"] * g["v"] ** 2 / (16 * g["Es"] * mp.sqrt(g["Rs"]))) ** mp.mpf("0.4")
    # energy: m v^2/2 (1 - x^(5/2)) = m xdot^2/2 with x = delta/delta_max; t_c = 2 (delta_max/v) int_0^1 dx/sqrt(1 - x^(5/2))
    t_c = 2 * delta / g["v"] * mp.quad(lambda x: 1 / mp.sqrt(1 - x ** mp.mpf("2.5")), [0, 1])
    assert p["peak_overlap"] == pytest.approx(float(delta), rel=1e-10)
    assert p["t_c"] == pytest.approx(float(t_c), rel=1e-9)
    res = resolution_step(engine="velocity-verlet", normal="hertz", damping="liggghts", restitution=0.9, tol=0.01)
    assert p["dt_resolution"] == pytest.approx(float(t_c) / res.steps_per_collision, rel=1e-9)
    assert p["binding"] == ("resolution" if p["dt_resolution"] <= p["dt_stability"] else "stability")
    assert p["dt"] == pytest.approx(min(p["dt_resolution"], p["dt_stability"]), rel=1e-15)
    rules = {r["key"]: r for r in p["rules"]}
    t_h = mp.mpf("2.87") * (g["ms"] ** 2 / (g["Rs"] * g["Es"] ** 2 * g["v"])) ** mp.mpf("0.2")
    assert rules["liggghts-hertz-0.1"]["dt"] == pytest.approx(float(t_h / 10), rel=1e-9)
    assert rules["tc-over-50"]["dt"] == pytest.approx(float(t_c / 50), rel=1e-9)
    for r in p["rules"]:
        assert r["verdict"] == ("safe" if r["dt"] <= p["dt"] else "UNSAFE")
        assert r["ratio"] == pytest.approx(r["dt"] / p["dt"], rel=1e-12)


def test_hertz_stability_step_by_the_update_rule(capsys):
    (p,) = _json(capsys, GLASS)["pairs"]
    g = _glass()
    delta = (15 * g["ms"] * g["v"] ** 2 / (16 * g["Es"] * mp.sqrt(g["Rs"]))) ** mp.mpf("0.4")
    kn, ks = (float(c * mp.sqrt(g["Rs"] * delta)) for c in (2 * g["Es"], 8 * g["Gs"]))
    le = mp.log(g["e"])
    zeta = float(-le / mp.sqrt(le ** 2 + mp.pi ** 2))
    ms = float(g["ms"])
    cn, cs = (2 * math.sqrt(5 / 6) * zeta * math.sqrt(k * ms) for k in (kn, ks))  # LIGGGHTS normal_model_hertz.h
    m, R = float(g["m"]), float(g["R"])
    M, K, C = two_spheres(m, 0.4 * m * R * R, R, m, 0.4 * m * R * R, R, kn, ks, cn, cs)
    dt = p["dt_stability"]
    assert spectral_radius("velocity-verlet", 0.999 * dt, M, K, C) <= STABLE
    assert spectral_radius("velocity-verlet", 1.001 * dt, M, K, C) > GROWS


def test_linear_example_with_v_max(capsys):
    doc = _json(capsys, FLOOR, "--v-max", "2")
    m = 7800.0 * 4.0 / 3.0 * math.pi * 0.002 ** 3
    kn = 2.0e5
    by = {p["pair"]: p for p in doc["pairs"]}
    assert set(by) == {"1-1", "1-wall1"}
    for label, meff in (("1-1", m / 2), ("1-wall1", m)):
        p = by[label]
        assert p["t_c"] == pytest.approx(math.pi * math.sqrt(meff / kn), rel=1e-12)
        assert p["peak_overlap"] == pytest.approx(2.0 * math.sqrt(meff / kn), rel=1e-12)
        assert p["restitution"] == pytest.approx(0.7, rel=1e-12)
        res = resolution_step(engine="velocity-verlet", normal="hooke", damping="liggghts", restitution=0.7, tol=0.01)
        assert p["dt_resolution"] == pytest.approx(p["t_c"] / res.steps_per_collision, rel=1e-9)
    w = by["1-wall1"]
    zeta = -math.log(0.7) / math.sqrt(math.pi ** 2 + math.log(0.7) ** 2)
    cn = 2 * zeta * math.sqrt(kn * m)
    M, K, C = sphere_on_wall(m, 0.4 * m * 0.002 ** 2, 0.002, kn, 2.0e5, cn, cn / 2)  # fix wall/gran: gammat = gamman/2
    assert spectral_radius("velocity-verlet", 0.999 * w["dt_stability"], M, K, C) <= STABLE
    assert spectral_radius("velocity-verlet", 1.001 * w["dt_stability"], M, K, C) > GROWS


def test_text_output(capsys):
    assert main(["collide", str(GLASS)]) == 0
    out = capsys.readouterr().out
    assert "binding: resolution" in out and "Burns, Piiroinen & Hanley (2019) eq. 68" in out
    assert out.strip().splitlines()[-1].startswith("step for every collision:")


def test_step_points_to_collide(capsys):
    assert main(["step", str(GLASS)]) == 0
    assert capsys.readouterr().out.strip().splitlines()[-1].startswith("impacts at 1 m/s: `dtcrit collide SCENE`")


@pytest.mark.parametrize("argv, needle", [
    ([ROOT / "examples" / "bonded_pair.toml"], "contact.model"),
    ([ROOT / "examples" / "rolling_resistance.toml"], "contact.rolling"),
    ([FLOOR], "contact.velocity"),
    ([GLASS, "--tol", "1"], "--tol"),
    ([GLASS, "--tol", "0"], "--tol"),
    ([GLASS, "--tol", "1e-6"], "--tol: 1-1: no step resolves"),  # never a fall-back to the stability step
    ([GLASS, "--v-max", "3000"], "--v-max: 1-1: the peak overlap"),  # beyond the radius: not Hertz
    ([GLASS, "--engine", "foo"], "--engine"),
])
def test_bad_input_is_one_line(argv, needle, capsys):
    try:
        code = main(["collide", *map(str, argv)])
    except SystemExit as exc:  # argparse's own refusal
        code = exc.code
    assert code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and needle in err


def test_unsupported_hertz_damping_convention_is_named(tmp_path, capsys):
    scene = tmp_path / "pfc.toml"
    scene.write_text(GLASS.read_text().replace("restitution = 0.9", 'restitution = 0.9\ndamping_convention = "pfc"'))
    assert main(["collide", str(scene)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "'pfc'" in err


def test_plot_is_written(tmp_path, capsys):
    out = tmp_path / "c.png"
    assert main(["collide", str(GLASS), "--plot", str(out)]) == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_the_docs_figure_is_made_by_the_dev_py_command():
    """The collisions how-to page (``docs/howto/collide.md``) shows the command ``python3 dev.py collide-figure`` runs, the committed PNG it writes, and the
    console output the example gives today."""
    import importlib.util
    import shlex

    spec = importlib.util.spec_from_file_location("dev_tasks", ROOT / "dev.py")
    assert spec is not None and spec.loader is not None
    dev = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(dev)
    readme = (ROOT / "docs" / "howto" / "collide.md").read_text()
    args = dev.COLLIDE_FIGURE
    assert "$ dtcrit " + " ".join(shlex.quote(a) for a in args) + "\n" in readme
    png = args[args.index("--plot") + 1]
    assert f"](../../{png})" in readme and (ROOT / png).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    section = readme
    block = section.split("$ dtcrit collide examples/glass_spheres_hertz.toml\n", 1)[1].split("```", 1)[0]
    import contextlib
    import io

    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        assert main(["collide", str(GLASS)]) == 0
    assert block == buf.getvalue()


def test_hertz_wall_against_the_closed_form(tmp_path, capsys):
    """A Hertz wall of another material: R* = R, m* = m, E* = 1/((1 - nu^2)/E + (1 - nu_w^2)/E_w)."""
    scene = tmp_path / "wall.toml"
    scene.write_text(GLASS.read_text() + '\n[[wall]]\nmodel = "hertz"\nyoungs_modulus = 200e9\npoisson_ratio = 0.3\nrestitution = 0.5\n')
    by = {p["pair"]: p for p in _json(capsys, scene)["pairs"]}
    g = _glass()
    es = 1 / ((1 - mp.mpf("0.22") ** 2) / mp.mpf("63e9") + (1 - mp.mpf("0.3") ** 2) / mp.mpf("200e9"))
    delta = (15 * g["m"] * g["v"] ** 2 / (16 * es * mp.sqrt(g["R"]))) ** mp.mpf("0.4")
    t_c = 2 * delta / g["v"] * mp.quad(lambda x: 1 / mp.sqrt(1 - x ** mp.mpf("2.5")), [0, 1])
    w = by["1-wall1"]
    assert w["peak_overlap"] == pytest.approx(float(delta), rel=1e-10)
    assert w["t_c"] == pytest.approx(float(t_c), rel=1e-9)
    assert w["restitution"] == pytest.approx(0.5, rel=1e-12)
    res = resolution_step(engine="velocity-verlet", normal="hertz", damping="liggghts", restitution=0.5, tol=0.01)
    assert w["dt_resolution"] == pytest.approx(float(t_c) / res.steps_per_collision, rel=1e-9)


def test_the_collision_table_gives_the_speed(tmp_path, capsys):
    """``[collision] v_max`` is the largest impact speed: the same entries as ``--v-max`` (t_c from the
    closed form pi sqrt(m*/k) is speed-free; the peak overlap v sqrt(m*/k) scales with it), and
    ``dtcrit step`` points to ``dtcrit collide`` at that speed."""
    scene = tmp_path / "floor.toml"
    scene.write_text(FLOOR.read_text() + "\n[collision]\nv_max = 3.0\n")
    flag = _json(capsys, FLOOR, "--v-max", "3")
    table = _json(capsys, scene)
    assert table["v_max"] == 3.0 and table["pairs"] == flag["pairs"]
    m = 7800.0 * 4.0 / 3.0 * math.pi * 0.002 ** 3
    wall = next(p for p in table["pairs"] if p["pair"] == "1-wall1")
    assert wall["peak_overlap"] == pytest.approx(3.0 * math.sqrt(m / 2.0e5), rel=1e-12)
    assert _json(capsys, scene, "--v-max", "1.5")["v_max"] == 1.5  # the flag overrides the table
    assert main(["step", str(scene)]) == 0
    assert capsys.readouterr().out.strip().splitlines()[-1].startswith("impacts at 3 m/s: `dtcrit collide SCENE`")


@pytest.mark.parametrize("table, needle", [("v_max = -1", "collision.v_max"), ("v_mx = 1", "collision.v_mx"),
                                           ("", "collision.v_max"), ("v_max = nan", "collision.v_max")])
def test_a_bad_collision_table_is_one_line(tmp_path, capsys, table, needle):
    scene = tmp_path / "floor.toml"
    scene.write_text(FLOOR.read_text() + f"\n[collision]\n{table}\n")
    assert main(["collide", str(scene)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and needle in err
