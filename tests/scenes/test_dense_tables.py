"""The dense-packing bound's generated table (``_generated/dense_phi_nodes.json``): written from the
current sources, every entry recomputed by the branch and bound equals the stored value, ``dtcrit
step`` prints the same report with the table as without it, and a case proportional to an entry is
answered from it within rounding of the branch and bound run on that case.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from dtcrit.scenes import dense_tables
from dtcrit.scenes.dense_phi import _phi_bound
from dtcrit.scenes.dense_spheres import _domination
from support.paths import EXAMPLES, SRC

DOC = json.loads(dense_tables.TABLE_PATH.read_text())


def test_the_table_was_generated_from_the_current_sources():
    assert DOC["derivation_hash"] == dense_tables.source_hash(), "dense table drifted: run `python3 dev.py generate`"
    assert dense_tables.load() == tuple(DOC["entries"]) and DOC["entries"]


@pytest.mark.parametrize("index", range(len(DOC["entries"])))
def test_entries_recompute(index):
    e = DOC["entries"][index]
    assert _phi_bound(e["z_eff"], e["psi"], tuple(e["pars"]), e["rtol"], e["n_theta"])[0] == e["phi"]


def _step(scene, **env) -> str:
    proc = subprocess.run([sys.executable, "-m", "dtcrit", "step", str(scene)], capture_output=True, text=True,
                          env={**os.environ, "PYTHONPATH": str(SRC), **env}, timeout=300, check=True)
    return proc.stdout


@pytest.mark.parametrize("scene", ["dense_glass_beads.toml", "glass_spheres_hertz.toml"])
def test_step_prints_the_same_with_and_without_the_table(scene):
    assert _step(EXAMPLES / scene) == _step(EXAMPLES / scene, **{dense_tables.DISABLE: "1"})


def test_a_proportional_case_is_answered_from_the_table(monkeypatch):
    e = DOC["entries"][0]
    pars = tuple(3.0 * t for t in e["pars"][:5]) + tuple(e["pars"][5:])
    computed = _phi_bound(e["z_eff"], e["psi"], pars, e["rtol"], e["n_theta"])[0]
    calls = []
    monkeypatch.setattr("dtcrit.scenes.dense_phi._phi_bound", lambda *a: calls.append(a) or (0.0, 0.0, 0))
    answer = dense_tables.phi_upper(e["z_eff"], e["psi"], pars, e["rtol"], e["n_theta"], _domination)
    assert not calls and answer == pytest.approx(computed, rel=1e-9) and answer >= 3.0 * e["phi"]
    dense_tables.phi_upper(e["z_eff"] + 1, e["psi"], pars, e["rtol"], e["n_theta"], _domination)  # not tabulated: computed
    assert len(calls) == 1
