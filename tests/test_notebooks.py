"""Every teaching notebook executes end to end (its cells assert its key claims)."""
import os

import pytest

from dtcrit.notebooks import render, sources

SOURCES = sources()


def test_there_are_notebooks():
    assert SOURCES


@pytest.mark.parametrize("source", SOURCES, ids=lambda p: p.stem)
def test_notebook_executes(source, tmp_path):
    os.environ["MPLBACKEND"] = "Agg"
    nb = render(source, tmp_path, timeout=120)
    assert (tmp_path / f"{source.stem}.ipynb").exists()
    errors = [o for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", []) if o.get("output_type") == "error"]
    assert not errors
