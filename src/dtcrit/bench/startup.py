"""Start-up of ``dtcrit step`` on the example scenes: wall time of the whole command, as a ratio
to a bare ``python -c "import numpy"`` measured in the same run, and the heavy modules it loads.

Each measurement is a fresh interpreter (``sys.executable -m dtcrit step SCENE``), so it
includes interpreter start, imports, scene parsing, the bounds and printing: what a user waits
for.  Best and median of ``repeats`` runs; the bench reports the figures, it never fails on them.
"""
from __future__ import annotations

import json
import statistics
import subprocess
import sys
import time
from pathlib import Path

HEAVY_MODULES = ("sympy", "scipy.spatial", "scipy.sparse", "scipy.special", "scipy.linalg", "scipy.optimize")
"""Modules whose import alone costs a sizeable part of the start-up budget."""

_PROBE = (
    "import json, sys\n"
    "from dtcrit.cli import main\n"
    "rc = main(['step', sys.argv[1]])\n"
    "sys.stderr.write('\\nDTCRIT-MODULES ' + json.dumps(sorted(m for m in {heavy!r} if m in sys.modules)) + '\\n')\n"
    "sys.exit(rc)\n"
)


def example_scenes(root: Path | None = None) -> list[Path]:
    """The example scene files shipped in ``examples/`` (sorted), if the source tree is at hand.

    Parameters
    ----------
    root : pathlib.Path, optional
        Root of the source tree (found from this file when omitted).

    Returns
    -------
    list of pathlib.Path
        The scene files (empty when not at hand).
    """
    root = Path(__file__).resolve().parents[3] if root is None else Path(root)
    return sorted((root / "examples").glob("*.toml"))


def _wall(cmd: list[str]) -> float:
    t = time.perf_counter()
    subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
    return time.perf_counter() - t


def heavy_modules_loaded(scene: Path) -> list[str]:
    """Which of ``HEAVY_MODULES`` a ``dtcrit step`` run on ``scene`` imports.

    Parameters
    ----------
    scene : pathlib.Path
        A scene file.

    Returns
    -------
    list of str
        The heavy modules imported.
    """
    code = _PROBE.format(heavy=HEAVY_MODULES)
    out = subprocess.run([sys.executable, "-c", code, str(scene)], capture_output=True, text=True, check=False)
    for line in out.stderr.splitlines():
        if line.startswith("DTCRIT-MODULES "):
            return json.loads(line.split(" ", 1)[1])
    raise RuntimeError(f"dtcrit step {scene} failed: {out.stderr.strip().splitlines()[-1:]}")


def measure(scenes: list[Path], repeats: int = 5) -> dict:
    """Best and median wall seconds of ``dtcrit step`` per scene and of the ``import numpy`` floor.

    Parameters
    ----------
    scenes : list of pathlib.Path
        Scene files.
    repeats : int
        Fresh-interpreter runs per scene.

    Returns
    -------
    dict
        Best and median seconds per scene and of the floor.
    """
    floor = [_wall([sys.executable, "-c", "import numpy"]) for _ in range(repeats)]
    rows = []
    for scene in scenes:
        times = [_wall([sys.executable, "-m", "dtcrit", "step", str(scene)]) for _ in range(repeats)]
        rows.append({
            "scene": scene.name,
            "best_seconds": min(times),
            "median_seconds": statistics.median(times),
            "best_over_numpy_import": min(times) / min(floor),
            "heavy_modules": heavy_modules_loaded(scene),
        })
    return {"repeats": repeats, "numpy_import_best_seconds": min(floor), "scenes": rows}


def markdown(startup: dict) -> list[str]:
    """The start-up section of the bench report.

    Parameters
    ----------
    startup : dict
        The result of ``measure``.

    Returns
    -------
    list of str
        Lines of the section.
    """
    lines = [
        f"Fresh interpreter per run, best and median of {startup['repeats']}; the floor is "
        f"`python -c \"import numpy\"` (best {startup['numpy_import_best_seconds']:.3f} s in this run).",
        "",
        "| scene | best [s] | median [s] | best / numpy import | heavy modules loaded |",
        "|---|---:|---:|---:|---|",
    ]
    for r in startup["scenes"]:
        mods = ", ".join(r["heavy_modules"]) or "none"
        lines.append(f"| {r['scene']} | {r['best_seconds']:.3f} | {r['median_seconds']:.3f} | "
                     f"{r['best_over_numpy_import']:.2f} | {mods} |")
    return lines
