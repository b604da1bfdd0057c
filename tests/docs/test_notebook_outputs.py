"""The teaching notebooks as the site's build executed them: every one ran end to end (its cells
assert its key claims), kept its plots as PNG outputs and wrote nothing to standard error.

The executions are myst-nb's, read back from the build's jupyter-cache, which is keyed on the package's
sources (``docs/_gen/notebook_cache.py``): they are executions of the current code, made once for the
site and checked here without running the notebooks again.
"""
from __future__ import annotations

import base64

import pytest

from dtcrit.notebooks import sources

SOURCES = sources()
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def _outputs(nb):
    return [o for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", [])]


def test_there_are_seven_notebooks():
    assert len(SOURCES) >= 7


@pytest.mark.parametrize("source", SOURCES, ids=lambda p: p.stem)
def test_the_notebook_ran_with_figures_and_no_warnings(source, executed_notebook):
    nb = executed_notebook(source.stem)
    assert nb is not None, f"{source.stem}: the build's cache holds no execution of it"
    code_cells = [c for c in nb.cells if c.cell_type == "code"]
    assert code_cells and all(c.get("execution_count") for c in code_cells), "a cell did not run"
    outputs = _outputs(nb)
    assert not [o for o in outputs if o.get("output_type") == "error"]
    stderr = [o.get("text", "") for o in outputs if o.get("output_type") == "stream" and o.get("name") == "stderr"]
    assert not stderr, stderr
    warned = [o for o in outputs if "warning" in str(o.get("text", "")).lower()
              or "warning" in str(o.get("data", {}).get("text/plain", "")).lower()]
    assert not warned, warned
    images = [o["data"]["image/png"] for o in outputs
              if o.get("output_type") in ("display_data", "execute_result") and "image/png" in o.get("data", {})]
    assert images, f"{source.stem}: no figure kept in the executed notebook"
    assert all(base64.b64decode(img)[:8] == PNG_SIGNATURE for img in images)
    reprs = [o for o in outputs if "<Figure size" in str(o.get("data", {}).get("text/plain", ""))
             and "image/png" not in o.get("data", {})]
    assert not reprs, reprs
