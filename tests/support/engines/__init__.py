"""Harness for running real DEM engines on small cases from the test suite.

Only the engine's own executable is used (run in a temporary directory); nothing
here imports the project under test, so the thresholds measured with it are an
independent check.

``engine_available(name)`` tells whether an engine can be run here;
``require_engine(name)`` is for tests: it returns the executable's path, skips
the test with an installation hint when the engine is missing, and *fails*
instead when the environment variable ``CI`` is ``true`` (engine tests must
never be skipped silently in CI).
"""
from __future__ import annotations

import os
import shutil

from support.ci import in_ci

__all__ = ["ENGINES", "engine_available", "engine_executable", "require_engine", "in_ci"]

# name -> (environment variable that may point at the executable, candidate names on PATH,
#          installation hint)
ENGINES: dict[str, tuple[str, tuple[str, ...], str]] = {
    "lammps": (
        "LAMMPS_BINARY",
        ("lmp", "lmp_serial", "lmp_mpi"),
        "apt-get install lammps  (Debian/Ubuntu; provides the `lmp` binary with the GRANULAR package)",
    ),
    "yade": (
        "YADE_BINARY",
        ("yade",),
        "apt-get install yade",
    ),
}


def _spec(name: str) -> tuple[str, tuple[str, ...], str]:
    try:
        return ENGINES[name.lower()]
    except KeyError:
        raise ValueError(f"unknown engine {name!r}; known: {sorted(ENGINES)}") from None


def engine_executable(name: str) -> str | None:
    """Absolute path of the engine's executable, or None when it is not installed.

    The environment variable named in ``ENGINES`` (e.g. ``LAMMPS_BINARY``) takes precedence
    over a search of ``PATH``.
    """
    env_var, candidates, _ = _spec(name)
    override = os.environ.get(env_var)
    if override:
        found = shutil.which(override)
        return found if found else None
    for cand in candidates:
        found = shutil.which(cand)
        if found:
            return found
    return None


def engine_available(name: str) -> bool:
    """True when the engine's executable can be found."""
    return engine_executable(name) is not None


def require_engine(name: str) -> str:
    """Executable of engine `name` for a test; skip (locally) or fail (in CI) when missing."""
    import pytest

    exe = engine_executable(name)
    if exe is not None:
        return exe
    env_var, candidates, hint = _spec(name)
    msg = (
        f"{name} engine not found (looked for {', '.join(candidates)} on PATH and ${env_var}); "
        f"install it with: {hint}"
    )
    if in_ci():
        pytest.fail(msg + " -- engine tests are never skipped in CI (CI=true)", pytrace=False)
    pytest.skip(msg)
