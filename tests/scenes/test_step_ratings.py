"""The estimator table of ``dtcrit step``: ratios never read as 1 unless they are 1, the Hertz contact duration with
the fractions LIGGGHTS steps with, and the codes' estimates rated once, against the headline (the packing step
unless the scene sets ``isolated = true``)."""
from __future__ import annotations

import dataclasses
import json
import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from dtcrit.cli import main
from dtcrit.cli.step import format_text, ratio_text
from dtcrit.physics import rules_of_thumb as est
from dtcrit.scenes.scene import load_scene
from dtcrit.physics.estimate import Estimate, RatedEstimate
from dtcrit.scenes.timestep import critical_step
from support.paths import REPO_ROOT as ROOT

EXAMPLES = ROOT / "examples"


@pytest.mark.parametrize("r,text", [(1.0024, "1.002"), (1.0, "1"), (0.5, "0.5"), (1.00004, "1.00004"),
                                    (0.99996, "0.99996"), (1 + 2**-52, "1.0000000000000002"), (1 - 2**-53, "0.9999999999999999")])
def test_ratio_text_examples(r, text):
    assert ratio_text(r) == text


@given(st.floats(-30, 30).map(lambda e: 10.0**e) | st.floats(0.99, 1.01))
def test_a_ratio_reads_as_one_only_when_it_is_one(r):
    text = ratio_text(r)
    assert (float(text) == 1.0) == (r == 1.0)
    assert abs(float(text) - r) <= 5e-4 * r  # at least 4 significant digits, never fewer


def test_a_ratio_just_above_one_is_printed_with_its_digits_and_flag():
    """An estimate 1.0024 x dt_crit (the issue's case) and one 4e-5 above it are printed as such beside UNSAFE."""
    result = critical_step(load_scene(EXAMPLES / "glass_spheres_hertz.toml"))
    extra = tuple(RatedEstimate(Estimate(f"probe_{n}", result.dt_crit * f, label="probe"), result.dt_crit)
                  for n, f in ((1, 1.0024), (2, 1.00004)))
    text = format_text(dataclasses.replace(result, estimates=result.estimates + extra))
    line1 = next(line for line in text.splitlines() if "probe_1" in line)
    line2 = next(line for line in text.splitlines() if "probe_2" in line)
    assert " 1.002 x dt_crit  UNSAFE" in line1 and " 1.00004 x dt_crit  UNSAFE" in line2


def _json(capsys, path):
    assert main(["step", str(path), "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_hertz_duration_and_the_fractions_codes_apply(capsys):
    doc = _json(capsys, EXAMPLES / "glass_spheres_hertz.toml")
    e = doc["estimators"]
    pair = doc["pairs"][0]
    # the Hertz duration of the example's pair from its own m*, R*, E*, v (the constant is checked against time
    # integration in test_step_estimators.py)
    t = 2.87 * (pair["m_star"] ** 2 / (pair["r_star"] * pair["e_star"] ** 2 * pair["velocity"])) ** 0.2
    assert e["hertz_time"]["dt"] == pytest.approx(t, rel=1e-13)
    assert e["hertz_10"]["dt"] == pytest.approx(0.1 * t, rel=1e-13)
    assert e["hertz_20"]["dt"] == pytest.approx(0.2 * t, rel=1e-13)
    assert "duration" in e["hertz_time"]["label"] and "LIGGGHTS" in e["hertz_10"]["label"]
    for key in ("hertz_time", "hertz_10", "hertz_20"):
        assert e[key]["unsafe"] is (e[key]["dt"] > doc["dt_crit"] * (1 + 1e-9))
    text = (main(["step", str(EXAMPLES / "glass_spheres_hertz.toml")]), capsys.readouterr().out)[1]
    assert "hertz_10" in text and "hertz_20" in text


def test_no_hertz_fractions_without_a_hertz_contact(capsys):
    e = _json(capsys, EXAMPLES / "paper_ellipsoids.toml")["estimators"]
    assert e["hertz_time"]["dt"] is e["hertz_10"]["dt"] is e["hertz_20"]["dt"] is None
    assert e["hertz_10"]["unsafe"] is None


def test_estimates_are_rated_against_the_dense_step_when_one_is_given(capsys):
    """With coordination_max the flags compare with dt_dense (here below dt_isolated), not with the isolated
    contact: an estimate between the two is UNSAFE."""
    doc = _json(capsys, EXAMPLES / "dense_glass_beads.toml")
    dense, isolated = doc["dt_dense"], doc["dt_isolated"]
    assert doc["dt_crit"] == dense < isolated
    between = []
    for key, e in doc["estimators"].items():
        if e["dt"] is None:
            continue
        assert e["unsafe"] is (e["dt"] > dense * (1 + 1e-9)), key
        assert e["unsafe_dense"] is e["unsafe"], key
        if dense < e["dt"] < isolated:
            between.append(key)
    assert "yade_gsts" in between  # 3.19e-7 s: safe for an isolated contact, not for the packing
    assert all(doc["estimators"][k]["unsafe"] for k in between)


def test_yade_stepper_constants_are_those_of_its_source():
    """GlobalStiffnessTimeStepper.cpp: dt = 1.41044 * timestepSafetyCoefficient * sqrt(min(...)); .hpp: default 0.8."""
    assert est.YADE_GSTS_CONSTANT == 1.41044 and est.YADE_GSTS_SAFETY == 0.8
    assert math.isclose(est.YADE_GSTS_CONSTANT / math.sqrt(2), 0.99733, rel_tol=1e-5)


def test_one_reference_and_one_verdict_per_row(capsys):
    """The text rates each estimate once, against dt_crit; the JSON's legacy unsafe_dense repeats that verdict
    for a packing headline and is null for an isolated one (whose verdicts are against the isolated step)."""
    text = (main(["step", str(EXAMPLES / "glass_spheres_hertz.toml")]), capsys.readouterr().out)[1]
    rows = [line for line in text.splitlines() if " x dt_crit " in line]
    assert rows and all(line.count(" ok ") + line.count(" UNSAFE ") == 1 for line in rows)
    assert "dense above" not in text and "dense within" not in text
    scene = load_scene(EXAMPLES / "glass_spheres_hertz.toml")
    iso = critical_step(dataclasses.replace(scene, isolated=True)).to_json()
    assert iso["headline_basis"] == "isolated" and iso["dt_crit"] == iso["dt_isolated"]
    for key, e in iso["estimators"].items():
        assert e["unsafe_dense"] is None
        if e["dt"] is not None:
            assert e["unsafe"] is (e["dt"] > iso["dt_isolated"] * (1 + 1e-9)), key
