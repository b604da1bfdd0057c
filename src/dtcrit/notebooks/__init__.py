"""The teaching notebooks: render the jupytext sources in ``notebooks/`` into executed ``.ipynb`` files."""
from dtcrit.notebooks.render import render, sources

__all__ = ["render", "sources"]
