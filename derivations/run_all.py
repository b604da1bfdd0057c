"""Rebuild every derivation record under ``derivations/records`` (``python3 dev.py generate``).

Each script ``derivations/secN_*.py`` defines ``RECORD`` (a file name under ``records/``) and
``build() -> str`` (the Markdown text).  ``tests/test_records_drift.py`` rebuilds them and fails
on any difference from the committed records.
"""
from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
RECORDS = HERE / "records"


def scripts() -> list[Path]:
    return sorted(p for p in HERE.glob("sec*.py"))


def load(path: Path):
    if str(path.parent) not in sys.path:  # the scripts share helper modules (derivations/_*.py)
        sys.path.insert(0, str(path.parent))
    spec = importlib.util.spec_from_file_location(f"derivations_{path.stem}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def main(names: list[str]) -> int:
    RECORDS.mkdir(exist_ok=True)
    for path in scripts():
        if names and path.stem not in names:
            continue
        module = load(path)
        text = module.build()
        target = RECORDS / module.RECORD
        if not target.exists() or target.read_text() != text:
            target.write_text(text)
            print(f"wrote derivations/records/{module.RECORD}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
