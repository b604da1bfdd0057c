"""The examples in dtcrit's docstrings run and print what they show.

Every module of ``dtcrit`` is walked (``pkgutil.walk_packages``) and its docstrings collected with
``doctest.DocTestFinder``, so a new Examples section anywhere is picked up without a change here; one
test per module that has examples.  ``__main__`` modules are skipped (importing one runs the command line).
"""
from __future__ import annotations

import doctest
import importlib
import pkgutil

import pytest

import dtcrit
from support.paths import REPO_ROOT

FLAGS = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE


def _modules_with_examples() -> dict[str, list[doctest.DocTest]]:
    finder = doctest.DocTestFinder()
    found = {}
    for info in pkgutil.walk_packages(dtcrit.__path__, "dtcrit."):
        if info.name.rsplit(".", 1)[-1] == "__main__":
            continue
        tests = [t for t in finder.find(importlib.import_module(info.name)) if t.examples]
        if tests:
            found[info.name] = sorted(tests, key=lambda t: t.name)
    return found


MODULES = _modules_with_examples()


@pytest.mark.parametrize("module", sorted(MODULES))
def test_docstring_examples_run(module, monkeypatch):
    """Each example of the module's docstrings prints its shown output (ellipsis and whitespace relaxed)."""
    monkeypatch.chdir(REPO_ROOT)  # examples read examples/
    failures = []
    for test in MODULES[module]:
        out: list[str] = []
        runner = doctest.DocTestRunner(optionflags=FLAGS)
        result = runner.run(test, out=out.append, clear_globs=True)
        if result.failed:
            failures.append("".join(out))
    assert not failures, "\n".join(failures)


def test_the_public_package_has_examples():
    """The walk finds the examples there are (an empty walk would pass every test above vacuously)."""
    assert MODULES, "no docstring examples found under dtcrit"
