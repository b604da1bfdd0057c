"""``dtcrit audit`` on packings that LAMMPS itself compressed, against LAMMPS's own threshold.

Each packing is made by LAMMPS (``support.engines.lammps_packing.compress``: random polydisperse
spheres shrunk in a periodic box and relaxed), read by ``dtcrit audit`` from LAMMPS's dump with the
user's pair style, and run again in LAMMPS from that dump: bounded at 0.99 x dtcrit's step, growing
at 1.01 x, and dtcrit's step within [0.999, 1.0] of LAMMPS's bisected threshold (never above it by
more than the bisection's width).
"""
from __future__ import annotations

import json
import math

import pytest

from support.engines import require_engine
from support.engines.lammps_packing import PackingSpec, bisect_threshold, compress, engine_contact_list, grows

from dtcrit.cli import main

HOOKE = "gran/hooke/history 1e4 NULL 0 NULL 0.5 0"
BISECT_RTOL = 2e-5
SPECS = {
    "hooke-overlap-0.7%": (PackingSpec(solid_fraction=0.65, seed=7), HOOKE),
    "hooke-overlap-3.6%": (PackingSpec(solid_fraction=0.70, seed=11), HOOKE),
    "hertz": (PackingSpec(solid_fraction=0.66, seed=5, style="gran/hertz/history", kn=2e8, stiffness=2e4),
              "gran/hertz/history 2e8 NULL 0 NULL 0.5 0"),
}
_CACHE: dict[str, str] = {}


def _dump(name: str, tmp_path_factory) -> str:
    require_engine("lammps")
    if name not in _CACHE:
        _CACHE[name] = compress(SPECS[name][0], tmp_path_factory.mktemp(name.replace("%", "")))
    return _CACHE[name]


def _audit(capsys, tmp_path, dump: str, *args: str) -> dict:
    path = tmp_path / "packing.dump"
    path.write_text(dump)
    assert main(["audit", str(path), *args, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def _damped_style(dump_path, normal: float, tangential: float) -> str:
    """gran/hooke/history with dashpots: ``gamma_n`` giving the median pair the normal contact damping
    ratio ``normal``, ``gamma_t`` the same size times ``tangential``.  ``xmu = 1e4`` (LAMMPS's
    largest): with strong dashpots the growing mode of an unstable step sits on lightly loaded
    contacts, whose Coulomb limit at ``xmu = 0.5`` caps its growth after a factor ~1e6 in energy
    (measured), which a linear analysis does not describe."""
    from dtcrit.packing.readers.lammps_dump import read_dump

    p = read_dump(dump_path)
    m_eff = float(sorted(p.masses)[p.n // 2]) / 2
    gamma = 2 * math.sqrt(1e4 / m_eff)
    return f"gran/hooke/history 1e4 NULL {gamma * normal!r} {gamma * tangential!r} 1e4 1"


@pytest.mark.parametrize("name", sorted(SPECS))
def test_lammps_packing_bounded_below_growing_above_and_bisected(name, capsys, tmp_path, tmp_path_factory):
    dump = _dump(name, tmp_path_factory)
    style = SPECS[name][1]
    doc = _audit(capsys, tmp_path, dump, "--pair-style", style)
    dt = doc["dt_crit"]
    assert not grows(dump, style, 0.99 * dt)
    assert grows(dump, style, 1.01 * dt)
    threshold = bisect_threshold(dump, style, 0.995 * dt, 1.005 * dt, rel_tol=BISECT_RTOL)
    assert 0.999 <= dt / threshold <= 1.0 + BISECT_RTOL
    assert 0 < doc["dt_safe"] <= dt


@pytest.mark.parametrize("normal, tangential", [(0.5, 0.0), (0.05, 0.025), (0.0, 0.5)])
def test_lammps_packing_with_dashpots(normal, tangential, capsys, tmp_path, tmp_path_factory):
    """Per-contact dashpots in the damping matrix.  Near the threshold of a damped packing the growing
    mode hides in the full-step velocities and grows slowly, so a short run reads the threshold high
    (0.27 % at 3000 steps, 0.025 % at 30000, measured): the bisection runs 30000 steps."""
    dump = _dump("hooke-overlap-3.6%", tmp_path_factory)
    (tmp_path / "p.dump").write_text(dump)
    style = _damped_style(tmp_path / "p.dump", normal, tangential)
    doc = _audit(capsys, tmp_path, dump, "--pair-style", style)
    assert doc["damped"] and doc["dt_crit"] < 0.99 * doc["dt_undamped"]
    threshold = bisect_threshold(dump, style, 0.999 * doc["dt_crit"], 1.01 * doc["dt_crit"], rel_tol=1e-4,
                                 steps=30000)
    assert 0.999 <= doc["dt_crit"] / threshold <= 1.0 + 1e-4


def test_the_engines_own_contact_list_gives_the_same_step(capsys, tmp_path, tmp_path_factory):
    dump = _dump("hooke-overlap-3.6%", tmp_path_factory)
    local = tmp_path / "contacts.local"
    local.write_text(engine_contact_list(dump, HOOKE))
    found = _audit(capsys, tmp_path, dump, "--pair-style", HOOKE)
    listed = _audit(capsys, tmp_path, dump, "--pair-style", HOOKE, "--local", str(local))
    assert listed["n_contacts"] == found["n_contacts"]
    assert abs(listed["dt_crit"] / found["dt_crit"] - 1) < 1e-12


def test_mid_overlap_arms_would_be_unsafe_on_lammps(tmp_path_factory):
    """Why the engine's arm matters: dtcrit's scene convention (arm R - delta/2) on the 3.6 %-overlap
    packing gives a step above LAMMPS's threshold."""
    from dtcrit.packing.solvers.damped_step import damped_critical_dt
    from dtcrit.packing.readers.lammps_dump import read_dump
    from dtcrit.packing.conventions.engines import ENGINES, engine_sphere_contacts, with_arms
    from dtcrit.packing.conventions.pair_styles import apply_terms, parse_pair_style

    dump = _dump("hooke-overlap-3.6%", tmp_path_factory)
    path = tmp_path_factory.mktemp("mid") / "p.dump"
    path.write_text(dump)
    p = read_dump(path)
    c = engine_sphere_contacts(p, ENGINES["lammps"])
    terms = parse_pair_style(HOOKE).terms(p, c)
    mid = apply_terms(with_arms(p, c, "mid-overlap"), terms, preload=False)
    dt_mid = damped_critical_dt(p, mid).dt
    assert grows(dump, HOOKE, dt_mid * (1 - 5e-4))


GRANULAR = {
    "hooke-linear-history": ("hooke-overlap-3.6%", "granular hooke 1e4 0 tangential linear_history 2857 0 0.5 "
                                                   "damping mass_velocity"),
    "hooke-rolling-twisting": ("hooke-overlap-3.6%", "granular hooke 1e4 0 tangential linear_history 5000 0 1e4 "
                                                     "damping mass_velocity rolling sds 5000 0 1e4 twisting marshall"),
    "hertz-mindlin-viscoelastic": ("hertz", "granular hertz 2e8 0 tangential mindlin 2e8 0 1e4 damping viscoelastic"),
}


@pytest.mark.parametrize("name", sorted(GRANULAR))
def test_pair_style_granular(name, capsys, tmp_path, tmp_path_factory):
    """``pair_style granular``: torque arm R - delta/2 with the full-radius slip velocity, rolling and
    twisting springs; LAMMPS's bisected threshold within 1e-4 (the bisection's width) of dtcrit's step."""
    packing, style = GRANULAR[name]
    dump = _dump(packing, tmp_path_factory)
    doc = _audit(capsys, tmp_path, dump, "--pair-style", style)
    dt = doc["dt_crit"]
    threshold = bisect_threshold(dump, style, 0.98 * dt, 1.02 * dt, rel_tol=1e-4, steps=4000)
    assert 0.999 <= dt / threshold <= 1.0 + 1e-4
