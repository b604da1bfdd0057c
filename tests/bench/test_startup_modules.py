"""Which modules ``dtcrit step EXAMPLE`` imports (module sets, never times): none of the heavy ones
(``dtcrit.bench.startup.HEAVY_MODULES``: SymPy, SciPy's spatial, sparse, special, linalg, optimize)
on any example scene, nor ``numpy.ma`` (which ``numpy.unique`` loads), nor the dense-packing bound's
branch and bound where its generated table holds the scene's cases (``dtcrit.scenes.dense_tables``).
"""
from __future__ import annotations

import ast
import json
import os
import subprocess
import sys

import pytest

from dtcrit.bench.startup import HEAVY_MODULES, example_scenes
from support.paths import REPO_ROOT, SRC

WATCHED = (*HEAVY_MODULES, "scipy", "dtcrit.scenes.dense_phi", "mpmath", "numpy.ma")
PROBE = (
    "import contextlib, io, json, sys\n"
    "from dtcrit.cli import main\n"
    "out = {{}}\n"
    "for scene in sys.argv[1:]:\n"
    "    with contextlib.redirect_stdout(io.StringIO()):\n"
    "        assert main(['step', scene]) == 0\n"
    "    out[scene] = sorted(m for m in {watched!r} if m in sys.modules)\n"
    "print(json.dumps(out))\n"
)


@pytest.fixture(scope="module")
def loaded() -> dict:
    """Each example, in one fresh interpreter: the watched modules loaded after its ``dtcrit step``
    (cumulative, so an empty set after the last one means none loaded any)."""
    scenes = [str(s) for s in example_scenes(REPO_ROOT)]
    assert len(scenes) >= 10
    proc = subprocess.run([sys.executable, "-c", PROBE.format(watched=WATCHED), *scenes], capture_output=True,
                          text=True, env={**os.environ, "PYTHONPATH": str(SRC)}, timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return json.loads(proc.stdout)


def test_no_example_imports_a_heavy_module(loaded):
    assert all(mods == [] for mods in loaded.values()), loaded


def test_each_example_alone_imports_no_heavy_module():
    """The polyhedron (a hull) and the dense-packing example, each in its own interpreter."""
    for name in ("polyhedron_cube.toml", "dense_glass_beads.toml", "superquadric.toml"):
        code = PROBE.format(watched=WATCHED)
        proc = subprocess.run([sys.executable, "-c", code, str(REPO_ROOT / "examples" / name)], capture_output=True,
                              text=True, env={**os.environ, "PYTHONPATH": str(SRC)}, timeout=300)
        assert proc.returncode == 0, proc.stderr[-3000:]
        assert list(json.loads(proc.stdout).values()) == [[]], name


UNUSED_BY_AN_ELLIPSOID_PAIR = ("dtcrit.cli.packing", "dtcrit.cli.plan", "dtcrit.cli.impact", "dtcrit.packing.step",
                               "dtcrit.scenes.walls", "dtcrit.scenes.sizes", "dtcrit.scenes.rotational",
                               "dtcrit.bodies.clump", "dtcrit.bodies.hull", "dtcrit.bodies.polyhedra", "json", "difflib",
                               "shutil", "pathlib")
"""Modules a scene loads only when it uses them: another command's parser, walls, sphere sizes,
rotational springs, clumps, polyhedra, JSON output, a "did you mean" message; and two the standard
library would load at every start (``shutil`` for argparse's help width, ``pathlib`` to open a file)."""


def _modules_after_step(name: str, watched: tuple[str, ...]) -> list[str]:
    """The modules of ``watched`` loaded after ``dtcrit step`` on example ``name`` (a probe that itself
    imports nothing but ``sys``, ``io`` and ``contextlib``)."""
    code = ("import contextlib, io, sys\nfrom dtcrit.cli import main\n"
            "with contextlib.redirect_stdout(io.StringIO()):\n    assert main(['step', sys.argv[1]]) == 0\n"
            f"print(sorted(m for m in {watched!r} if m in sys.modules))\n")
    proc = subprocess.run([sys.executable, "-c", code, str(REPO_ROOT / "examples" / name)], capture_output=True,
                          text=True, env={**os.environ, "PYTHONPATH": str(SRC)}, timeout=300)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return ast.literal_eval(proc.stdout.strip())


def test_a_scene_imports_only_the_parts_it_uses():
    """An ellipsoid pair loads none of ``UNUSED_BY_AN_ELLIPSOID_PAIR``; spheres on a floor, with walls
    and a size, and the rolling-resistance scene load the walls, sizes and rotational modules they use
    (so the probe does see a module loaded on first use)."""
    assert _modules_after_step("paper_ellipsoids.toml", UNUSED_BY_AN_ELLIPSOID_PAIR) == []
    assert _modules_after_step("spheres_on_a_floor.toml", ("dtcrit.scenes.walls", "dtcrit.scenes.sizes")) == [
        "dtcrit.scenes.sizes", "dtcrit.scenes.walls"]
    assert _modules_after_step("rolling_resistance.toml", ("dtcrit.scenes.rotational",)) == ["dtcrit.scenes.rotational"]
