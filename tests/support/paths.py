"""Paths of the repository, for tests that read examples, sources or derivation scripts."""
from __future__ import annotations

from pathlib import Path

#: The repository's root (the folder holding ``pyproject.toml``).
REPO_ROOT = Path(__file__).resolve().parents[2]
#: The example scenes, packings and bodies files.
EXAMPLES = REPO_ROOT / "examples"
#: The source tree (``src/``, holding the ``dtcrit`` package).
SRC = REPO_ROOT / "src"
#: The derivation scripts and their committed records.
DERIVATIONS = REPO_ROOT / "derivations"
#: The engine-side scripts shipped with dtcrit (LAMMPS and YADE hooks).
ENGINE_SCRIPTS = SRC / "dtcrit" / "engine_scripts"
