"""Every name of the public API carries a numpydoc ``Examples`` section (``tests/test_doctests.py`` runs them).

Data constants (``INTEGRATORS``) are described in their module's docstring instead.
"""
from __future__ import annotations

import doctest
import inspect

import pytest

import dtcrit



def _doctests(name: str) -> list[doctest.DocTest]:
    obj = getattr(dtcrit, name)
    if inspect.ismodule(obj):
        return [t for t in doctest.DocTestFinder().find(obj) if t.examples]
    module = inspect.getmodule(obj) if not isinstance(obj, dict) else None
    globs = dict(vars(module)) if module is not None else {}
    return [t for t in doctest.DocTestFinder(recurse=inspect.isclass(obj)).find(obj, name, globs=globs)
            if t.examples]


@pytest.mark.parametrize("name", dtcrit.__all__)
def test_every_public_name_has_examples(name):
    obj = getattr(dtcrit, name)
    if not (callable(obj) or inspect.ismodule(obj)):
        pytest.skip(f"{name} is data (its meaning is in its module's docstring), not a function, class or module")
    doc = inspect.getdoc(obj) or ""
    assert "\nExamples\n--------\n" in f"\n{doc}\n" and _doctests(name), f"{name}: no Examples section"
