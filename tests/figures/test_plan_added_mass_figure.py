"""The density-scaling figure (``dtcrit.figures.plan_added_mass``): a PNG of a real plan of a small
polydisperse chain, whose drawn added masses are ``m_p (f_p - 1)`` of the test's own masses and whose
scaled chain is stable at the target by a direct ``eigh`` of the hand-assembled dense ``K``, ``M``
(``support.dense_packing``); data that do not fit and an unwritable path are refused with one line.
"""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from dtcrit.errors import InputError
from dtcrit.figures.plan_added_mass import added_mass_data, write_added_mass_figure
from support.dense_packing import DensePacking

RHO = 2500.0
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def _chain() -> DensePacking:
    """Six spheres of radii 0.5 to 1.5 mm in a bent chain, unequal springs."""
    radii = np.array([1.0e-3, 0.5e-3, 1.5e-3, 0.7e-3, 1.2e-3, 0.9e-3])
    x = np.zeros((6, 3))
    turns = [(1.0, 0.1, 0.0), (0.3, 1.0, 0.2), (0.2, -0.1, 1.0), (1.0, 0.4, -0.3), (-0.2, 1.0, 0.5)]
    for p, d in enumerate(turns, start=1):
        d = np.array(d) / np.linalg.norm(d)
        x[p] = x[p - 1] + (radii[p - 1] + radii[p] - 3e-9) * d
    masses = 4.0 / 3.0 * math.pi * radii**3 * RHO
    contacts = [(k, k + 1, kn, 0.6 * kn, 0.0, 0.0) for k, kn in enumerate([1.0e4, 1.4e4, 0.8e4, 1.2e4, 2.0e4])]
    return DensePacking([1, 2, 3, 4, 5, 6], x, radii, masses, contacts)


def _critical_step(dense: DensePacking, factors) -> float:
    k = sum(dense.stiffness_terms().values())
    m = np.diag(dense.mass()) * np.repeat(factors, 6)
    s = 1.0 / np.sqrt(m)
    return 2.0 / math.sqrt(float(np.linalg.eigvalsh(k * s[:, None] * s[None, :])[-1]))


def test_the_figure_is_a_png_of_the_plan(tmp_path):
    """The plan's factors reach the target (direct eigh); the figure draws m (f - 1) per particle."""
    from dtcrit.plan import plan_density_scaling

    dense = _chain()
    dump, table = tmp_path / "chain.dump", tmp_path / "chain.txt"
    dump.write_text(dense.dump_text())
    table.write_text(dense.table_text())
    target = 2.0 * _critical_step(dense, np.ones(6))
    plan = plan_density_scaling(dump, target, contact_table=table)
    assert _critical_step(dense, plan.factors) >= target
    out = tmp_path / "added_mass.png"
    data = write_added_mass_figure(plan, dense.radii, out)
    assert out.read_bytes()[:8] == PNG_SIGNATURE and out.stat().st_size > 10_000
    assert data.radius == pytest.approx(dense.radii, rel=0, abs=0)
    assert data.added["dtcrit plan"] == pytest.approx(dense.masses * (np.asarray(plan.factors) - 1.0), rel=1e-12)
    assert data.fraction("dtcrit plan") == pytest.approx(
        float(np.sum(dense.masses * (np.asarray(plan.factors) - 1.0)) / dense.masses.sum()), rel=1e-12)
    assert data.target_dt == target


def test_rules_present_are_drawn_and_fixed_bodies_left_out():
    """A plan-like object: YADE's rule and the uniform factor join the plan; a fixed body is not drawn."""
    plan = SimpleNamespace(factors=[1.0, 2.0, 3.0], masses=[1.0, 2.0, 4.0], free=[True, True, False],
                           yade_factors=[1.5, 2.5, 1.0], uniform_factor=2.0, target_dt=None)
    data = added_mass_data(plan, [1e-3, 2e-3, 3e-3])
    assert list(data.added) == ["dtcrit plan", "YADE rule", "uniform"]
    assert data.added["dtcrit plan"].tolist() == [0.0, 2.0]
    assert data.added["YADE rule"].tolist() == [0.5, 3.0]
    assert data.added["uniform"].tolist() == [1.0, 2.0]
    assert data.fraction("YADE rule") == pytest.approx(3.5 / 3.0)


@pytest.mark.parametrize("radii", [[1e-3, 2e-3], [1e-3, float("nan"), 1e-3]])
def test_radii_that_do_not_fit_the_plan_are_refused(radii):
    """Radii of another length, or not finite: one ``InputError`` naming ``plan``."""
    plan = SimpleNamespace(factors=[1.0, 2.0, 3.0], masses=[1.0, 2.0, 4.0])
    with pytest.raises(InputError) as err:
        added_mass_data(plan, radii)
    assert err.value.key == "plan" and "radii" in str(err.value)


def test_an_unwritable_path_is_refused(tmp_path):
    """A PNG in a folder that does not exist: one ``InputError`` naming ``plot``."""
    plan = SimpleNamespace(factors=[1.0, 2.0], masses=[1.0, 2.0])
    with pytest.raises(InputError) as err:
        write_added_mass_figure(plan, [1e-3, 2e-3], tmp_path / "missing" / "fig.png")
    assert err.value.key == "plot"
