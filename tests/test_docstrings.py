"""Every public name of dtcrit carries a numpydoc docstring with its sections.

Checked with ``numpydoc.validate`` over every public function, class and public method (and
property) defined in a dtcrit module, the emitted ``_generated`` modules and the engine scripts
excepted.  The codes: GL08 (no docstring), PR01 (a parameter not documented), PR02 (a documented
parameter that does not exist), RT01 (no ``Returns`` section).  A property needs only a docstring.
"""
from __future__ import annotations

import importlib
import inspect
import pkgutil
from collections.abc import Iterator
from types import ModuleType

import pytest

import dtcrit

validate = pytest.importorskip("numpydoc.validate").validate

CODES = {"GL08", "PR01", "PR02", "RT01"}
SKIPPED = ("._generated", ".engine_scripts")


def _modules() -> Iterator[ModuleType]:
    for info in pkgutil.walk_packages(dtcrit.__path__, "dtcrit."):
        if any(part in info.name for part in SKIPPED) or info.name.endswith("__main__"):
            continue
        yield importlib.import_module(info.name)


def _public(module: ModuleType) -> Iterator[str]:
    for name, obj in vars(module).items():
        if name.startswith("_") or getattr(obj, "__module__", None) != module.__name__:
            continue
        if inspect.isfunction(obj):
            yield f"{module.__name__}.{name}"
        elif inspect.isclass(obj):
            yield f"{module.__name__}.{name}"
            for member, value in vars(obj).items():
                if not member.startswith("_") and (inspect.isfunction(value) or isinstance(value, property)):
                    yield f"{module.__name__}.{name}.{member}"


def _offences(qualname: str) -> list[str]:
    result = validate(qualname)
    codes = {"GL08"} if result.get("type") == "property" else CODES
    return [f"{code} {message}" for code, message in result["errors"] if code in codes]


def test_the_walk_reaches_the_packages():
    """The module walk imports the main packages, so an empty walk cannot pass the check below."""
    names = {module.__name__ for module in _modules()}
    assert {"dtcrit.scenes", "dtcrit.packing", "dtcrit.codegen", "dtcrit.impact"} <= names


def test_every_public_name_has_its_numpydoc_sections():
    """No public name misses its docstring, a parameter, or its Returns section."""
    offenders = []
    for module in _modules():
        for qualname in _public(module):
            offences = _offences(qualname)
            if offences:
                offenders.append(f"{qualname}: " + "; ".join(offences))
    assert not offenders, f"{len(offenders)} public names miss sections:\n" + "\n".join(offenders)


def test_every_name_of_the_public_api_has_examples():
    """Each function and class of ``dtcrit.__all__`` shows an Examples section (run by ``tests/test_doctests.py``)."""
    missing = []
    for name in dtcrit.__all__:
        obj = getattr(dtcrit, name)
        if inspect.ismodule(obj) or not (inspect.isfunction(obj) or inspect.isclass(obj)):
            continue
        result = validate(f"{obj.__module__}.{obj.__qualname__}")
        if any(code == "EX01" for code, _ in result["errors"]):
            missing.append(name)
    assert len(dtcrit.__all__) > 20
    assert not missing, f"public API names without an Examples section: {missing}"
