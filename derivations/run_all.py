"""Rebuild every derivation record under ``derivations/records`` (``python3 dev.py generate``).

Each script ``derivations/<topic>.py`` writes the record ``records/<topic>.md``: it defines ``RECORD``
(that file name) and ``build() -> str`` (the Markdown text).  The scripts' helpers live in the package
``derivations/_shared``.  ``tests/test_records_drift.py`` rebuilds the records and fails on any
difference from the committed ones.
"""
from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
RECORDS = HERE / "records"


def scripts() -> list[Path]:
    """Every derivation script, sorted: the modules of ``derivations/`` other than this one."""
    return sorted(p for p in HERE.glob("*.py") if p.stem != "run_all" and not p.stem.startswith("_"))


def load(path: Path):
    """Import the script at ``path`` (its helpers, the package ``_shared``, are imported beside it)."""
    if str(path.parent) not in sys.path:  # the scripts import their helpers from derivations/_shared
        sys.path.insert(0, str(path.parent))
    spec = importlib.util.spec_from_file_location(f"derivations_{path.stem}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def main(names: list[str]) -> int:
    """Rebuild the records of the scripts named in ``names`` (all when empty); write those that changed."""
    RECORDS.mkdir(exist_ok=True)
    for path in scripts():
        if names and path.stem not in names:
            continue
        module = load(path)
        if module.RECORD != path.stem + ".md":
            raise SystemExit(f"derivations/{path.name} writes {module.RECORD}: a script and its record share a name")
        text = module.build()
        target = RECORDS / module.RECORD
        if not target.exists() or target.read_text() != text:
            target.write_text(text)
            print(f"wrote derivations/records/{module.RECORD}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
