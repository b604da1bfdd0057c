"""Regenerate every committed file under ``dtcrit/_generated`` (``python3 dev.py generate``).

Each producer module listed in ``PRODUCERS`` exposes ``generated_files() -> dict[str, str]`` mapping
a path relative to ``src/dtcrit/_generated`` to its full text.  ``tests/symbolic/test_generated_drift.py``
calls the same function and fails on any difference from the committed files.
"""
from __future__ import annotations

import importlib
import sys
from pathlib import Path

GENERATED_DIR = Path(__file__).resolve().parents[1] / "_generated"

PRODUCERS: tuple[str, ...] = (
    "dtcrit.symbolic.mass_properties",
    "dtcrit.symbolic.impact",
    "dtcrit.symbolic.stability_codegen",
    "dtcrit.symbolic.roots_codegen",
    "dtcrit.symbolic.contact_codegen",
    "dtcrit.symbolic.rotational_modes",
)


def all_generated_files() -> dict[str, str]:
    """The text of every generated file, as the producers make it now.

    Returns
    -------
    dict of str to str
        Path relative to ``src/dtcrit/_generated`` -> full text, from every producer of ``PRODUCERS``.
    """
    files: dict[str, str] = {}
    for name in PRODUCERS:
        produced = importlib.import_module(name).generated_files()
        clash = set(produced) & set(files)
        if clash:
            raise RuntimeError(f"{name} regenerates {sorted(clash)} already produced elsewhere")
        files.update(produced)
    return files


def main() -> int:
    """Write every generated file whose text changed and report how many did.

    Returns
    -------
    int
        The exit status (0).
    """
    changed = 0
    for rel, text in sorted(all_generated_files().items()):
        path = GENERATED_DIR / rel
        old = path.read_text() if path.exists() else None
        if old != text:
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(text)
            changed += 1
            print(f"wrote src/dtcrit/_generated/{rel}")
    print(f"{changed} generated file(s) changed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
