"""``dtcrit.notebooks.render`` executes a teaching notebook end to end (its cells assert its key claims),
keeps its plots as PNG outputs (the kernel draws with the inline backend) and writes nothing to
standard error: no warning, no error.

Only the first notebook runs here: every notebook is executed once by the docs build (myst-nb, cached
on the package's sources) and its execution is checked by ``tests/docs/test_notebook_outputs.py``, so a
test run executes each notebook once, not twice.
"""
import pytest

from dtcrit.notebooks import render, sources

SOURCES = sources()
PNG_MAGIC = "iVBORw0KGgo"  # base64 of the PNG signature


def _outputs(nb):
    return [o for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", [])]


def test_there_are_notebooks():
    assert len(SOURCES) >= 7


@pytest.mark.parametrize("source", SOURCES[:1], ids=lambda p: p.stem)
def test_notebook_executes_with_figures_and_no_warnings(source, tmp_path, monkeypatch):
    # The calling process's backend must not leak into the kernel (Agg would drop every figure).
    monkeypatch.setenv("MPLBACKEND", "Agg")
    nb = render(source, tmp_path, timeout=120)
    assert (tmp_path / f"{source.stem}.ipynb").exists()
    outputs = _outputs(nb)
    errors = [o for o in outputs if o.get("output_type") == "error"]
    assert not errors, errors
    stderr = [o.get("text", "") for o in outputs if o.get("output_type") == "stream" and o.get("name") == "stderr"]
    assert not stderr, stderr
    warned = [o for o in outputs if "warning" in str(o.get("text", "")).lower()
              or "warning" in str(o.get("data", {}).get("text/plain", "")).lower()]
    assert not warned, warned
    images = [o["data"]["image/png"] for o in outputs
              if o.get("output_type") in ("display_data", "execute_result") and "image/png" in o.get("data", {})]
    assert images, f"{source.stem}: no figure kept in the executed notebook"
    assert all(str(img).lstrip().startswith(PNG_MAGIC) for img in images)
    # A figure left as its repr means a plot that was not drawn inline.
    reprs = [o for o in outputs if "<Figure size" in str(o.get("data", {}).get("text/plain", ""))
             and "image/png" not in o.get("data", {})]
    assert not reprs, reprs
