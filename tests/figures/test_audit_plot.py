"""``dtcrit audit --plot FILE.png``: a valid PNG whose drawn data are those of a direct ``eigh`` of the
hand-assembled dense ``K``, ``M`` (``support.dense_packing``); a bad path is one line and exit 2; a
failed write leaves no file behind.
"""
from __future__ import annotations

import importlib.util
import math
import shlex

import numpy as np
import pytest

from dtcrit import audit_snapshot
from dtcrit.cli import main
from dtcrit.errors import InputError
from dtcrit.figures import audit_plot
from support.dense_packing import DensePacking
from support.paths import REPO_ROOT as ROOT

RHO = 2500.0
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def _chain() -> DensePacking:
    """Five unequal spheres, bent chain, unequal springs (with rolling and twisting)."""
    radii = np.array([1.0e-3, 0.8e-3, 1.2e-3, 0.9e-3, 1.1e-3])
    x = np.zeros((5, 3))
    turns = [(1.0, 0.1, 0.0), (0.3, 1.0, 0.2), (0.2, -0.1, 1.0), (1.0, 0.4, -0.3)]
    for p, d in enumerate(turns, start=1):
        d = np.array(d) / np.linalg.norm(d)
        x[p] = x[p - 1] + (radii[p - 1] + radii[p] - 3e-9) * d
    masses = 4.0 / 3.0 * math.pi * radii**3 * RHO
    contacts = [(0, 1, 1.0e4, 7e3, 3e-3, 1e-3), (1, 2, 1.4e4, 9e3, 2e-3, 4e-3),
                (2, 3, 0.8e4, 5e3, 5e-3, 2e-3), (3, 4, 1.2e4, 6e3, 1e-3, 3e-3)]
    return DensePacking([3, 5, 8, 13, 21], x, radii, masses, contacts)


def _files(tmp_path, dense):
    dump, table = tmp_path / "chain.dump", tmp_path / "chain.txt"
    dump.write_text(dense.dump_text())
    table.write_text(dense.table_text())
    return dump, table


def test_the_plot_is_a_png_of_the_direct_eigen_solve(tmp_path):
    """The ten largest omega^2 and their steps 2/omega_k are eigh's; each particle's share is the top
    eigenvector's phi^T M phi on it; dt_crit and dt_safe are marked at the audit's values.
    """
    dense = _chain()
    dump, table = _files(tmp_path, dense)
    audit = audit_snapshot(dump, contact_table=table, dt=1e-7)
    out = tmp_path / "audit.png"
    data = audit_plot.write_audit_plot(audit, out)
    assert out.read_bytes()[:8] == PNG_SIGNATURE and out.stat().st_size > 10_000
    k = sum(dense.stiffness_terms().values())
    s = 1 / np.sqrt(np.diag(dense.mass()))
    values, vectors = np.linalg.eigh(s[:, None] * k * s[None, :])
    top = values[::-1][:10]
    np.testing.assert_allclose(data.spectrum.omega2, top, rtol=1e-9)
    np.testing.assert_allclose(data.spectrum.steps, 2 / np.sqrt(top), rtol=1e-9)
    assert values[-2] < (1 - 1e-3) * values[-1]  # an isolated top mode: its vector is defined
    energy = (vectors[:, -1] ** 2).reshape(-1, 6).sum(axis=1)
    np.testing.assert_allclose(data.share, energy / energy.sum(), atol=1e-8)
    assert data.mode == "governing mode" and data.spectrum.damped_steps is None
    marks = dict(data.marks)
    assert marks["dt_crit"] == audit.dt_crit == pytest.approx(2 / math.sqrt(values[-1]), rel=1e-9)
    assert marks["dt_safe"] == audit.dt_safe and marks["your dt"] == 1e-7
    drawn = {e.estimate.name for e in audit.estimators if e.estimate.dt is not None}
    assert drawn and drawn <= set(marks)  # a row with no value (YADE's stepper on a scene it cannot read) is not drawn
    assert not {e.estimate.name for e in audit.estimators if e.estimate.dt is None} & set(marks)
    assert list(data.ids) == dense.ids
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".audit.png")] == []


def test_with_dashpots_each_mode_carries_its_modal_damped_step(tmp_path):
    """With dashpots the lagged scheme's step of mode k alone, 4/(c_k + sqrt(c_k^2 + 4 omega_k^2)),
    lies below 2/omega_k; the undamped 2/omega_max is marked too.
    """
    dense = _chain()
    dump, _ = _files(tmp_path, dense)
    audit = audit_snapshot(dump, pair_style="gran/hooke/history 1e4 NULL 3e4 NULL 0.5 1")
    data = audit_plot.audit_figure_data(audit, count=6)
    assert data.spectrum.damped_steps is not None and data.spectrum.steps.size == 6
    assert np.all(data.spectrum.damped_steps < data.spectrum.steps)
    assert dict(data.marks)["2/omega_max (undamped)"] == audit.dt_undamped


@pytest.mark.parametrize("name, reason", [("no/such/folder/a.png", "does not exist"), ("a.jpg", "does not end in .png")])
def test_a_bad_plot_path_is_one_line_and_exit_2(tmp_path, capsys, monkeypatch, name, reason):
    """Checked before the audit runs: one line naming --plot, exit 2, nothing on standard output."""
    dense = _chain()
    dump, table = _files(tmp_path, dense)
    monkeypatch.chdir(tmp_path)
    rc = main(["audit", str(dump), "--contacts", str(table), "--plot", name])
    out, err = capsys.readouterr()
    assert rc == 2 and out == "" and err.count("\n") == 1 and err.startswith("dtcrit: --plot: ") and reason in err


def test_a_failed_write_leaves_nothing(tmp_path, monkeypatch):
    """An error while saving leaves neither the PNG nor its temporary file."""
    dense = _chain()
    dump, table = _files(tmp_path, dense)
    audit = audit_snapshot(dump, contact_table=table)

    class Broken:
        def savefig(self, *args, **kwargs):
            raise OSError(28, "No space left on device")

    monkeypatch.setattr(audit_plot, "draw_audit_plot", lambda data: Broken())
    monkeypatch.setattr(audit_plot, "pyplot", lambda: type("P", (), {"close": staticmethod(lambda fig: None)}))
    before = set(tmp_path.iterdir())
    with pytest.raises(InputError, match="No space left"):
        audit_plot.write_audit_plot(audit, tmp_path / "a.png")
    assert set(tmp_path.iterdir()) == before


def test_labels_are_pushed_apart_and_kept_in_order():
    """Crowded labels end at least the gap apart, in their order, and below the top of the axes."""
    y = audit_plot.label_positions([0.1, 0.1, 0.11, 0.5, 0.99, 1.0], gap=0.05)
    assert np.all(np.diff(y) >= 0.05 - 1e-12) and y[-1] <= 1.0 + 1e-12


def test_the_docs_figure_is_made_by_the_dev_py_command():
    """The audit how-to page (``docs/howto/audit.md``) shows the command ``python3 dev.py audit-figure`` runs, the committed PNG it writes, and the
    governing mode's figures the audit gives today.
    """
    spec = importlib.util.spec_from_file_location("dev_tasks", ROOT / "dev.py")
    assert spec is not None and spec.loader is not None
    dev = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(dev)
    readme = (ROOT / "docs" / "howto" / "audit.md").read_text()
    args = dev.AUDIT_FIGURE
    assert "$ dtcrit " + " ".join(shlex.quote(a) for a in args) + "\n" in readme
    png = args[args.index("--plot") + 1]
    assert f"](../../{png})" in readme and (ROOT / png).read_bytes()[:8] == PNG_SIGNATURE
    audit = audit_snapshot(ROOT / args[1], pair_style=args[args.index("--pair-style") + 1])
    g = audit.governing_mode
    assert g is not None
    described = readme.split("![dtcrit audit --plot", 1)[1].split("###", 1)[0]
    for text in (f"{100 * g.normal:.3g} % of its strain energy in the normal", f"ratio {g.participation_ratio:.3g}",
                 f"{100 * g.rotational_kinetic:.1g} % of its kinetic energy", f"{100 * audit.limiting_share:.3g} %",
                 ", ".join(str(i) for i in audit.limiting)):
        assert text in described


def test_a_file_name_with_mathtext_signs_is_drawn_as_text(tmp_path, capsys):
    """The snapshot's name is the figure's title: ``$...$`` in it is text, not a mathtext formula that
    Matplotlib would fail to parse after the audit has run."""
    dump = tmp_path / "run_$\\frac$.dump"
    dump.write_bytes((ROOT / "examples" / "packings" / "random_lognormal_60.dump").read_bytes())
    png = tmp_path / "a.png"
    assert main(["audit", str(dump), "--pair-style", "gran/hertz/history 1e9 NULL 0 NULL 0.5 0",
                 "--plot", str(png)]) == 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and "dt_crit" in capsys.readouterr().out
