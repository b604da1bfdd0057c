"""A standard ``pip install`` of dtcrit works: the sdist and the wheel build (``python -m build``: the sdist
from a copy of the sources, the wheel from that sdist, with the build backend setuptools fetched from the
package registry into an isolated environment), the wheel installs into a clean virtual environment with
its runtime dependencies only, and ``dtcrit`` runs from there, outside the checkout, with the same answer as
the checkout.  Run by ``python3 dev.py test`` (CI); it never skips under ``CI=true``.
"""
from __future__ import annotations

import importlib.util
import json
import os
import shutil
import subprocess
import sys
import tarfile
import zipfile
from pathlib import Path

import pytest

import dtcrit
from dtcrit.cli import main
from support.paths import REPO_ROOT as ROOT

SCENE = ROOT / "examples" / "paper_ellipsoids.toml"
RUNTIME = {"numpy", "scipy", "sympy", "mpmath", "tqdm"}
PACKAGE_DATA = ["dtcrit/py.typed", "dtcrit/schemas/dtcrit-step-1.json", "dtcrit/schemas/dtcrit-impact-1.json",
                "dtcrit/_generated/critical_steps.py", "dtcrit/_generated/impact.py"]
TEST_ONLY = ["pytest", "hypothesis", "jupytext", "nbclient", "ipykernel", "matplotlib"]

pytestmark = pytest.mark.slow


def _env() -> dict:
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME", "VIRTUAL_ENV")}
    env["PYTHONDONTWRITEBYTECODE"] = "1"
    return env


def _call(*cmd, cwd) -> subprocess.CompletedProcess:
    p = subprocess.run([str(c) for c in cmd], cwd=cwd, capture_output=True, text=True, env=_env(), timeout=600)
    assert p.returncode == 0, f"{' '.join(map(str, cmd))}\n{p.stdout[-2000:]}\n{p.stderr[-3000:]}"
    return p


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    if importlib.util.find_spec("build") is None:
        if os.environ.get("CI"):
            pytest.fail("the 'build' package is missing: install the test extra (python3 dev.py test)")
        pytest.skip("the 'build' package is not installed (python3 dev.py test installs the test extra)")
    tmp = tmp_path_factory.mktemp("packaging")
    source = tmp / "source"  # a copy: building writes egg-info and build/ into the source tree
    source.mkdir()
    for name in ("pyproject.toml", "README.md"):
        shutil.copy2(ROOT / name, source / name)
    shutil.copytree(ROOT / "src", source / "src", ignore=shutil.ignore_patterns("__pycache__", "*.egg-info", "*.pyc"))
    dist = tmp / "dist"
    _call(sys.executable, "-m", "build", "--outdir", dist, source, cwd=tmp)
    (sdist,) = dist.glob("dtcrit-*.tar.gz")
    (wheel,) = dist.glob("dtcrit-*.whl")
    return tmp, sdist, wheel


def test_sdist_and_wheel_hold_the_package_data(built):
    _, sdist, wheel = built
    names = set(zipfile.ZipFile(wheel).namelist())
    for f in PACKAGE_DATA:
        assert f in names, f
    with tarfile.open(sdist) as tar:
        members = {m.name.split("/", 1)[1] for m in tar.getmembers() if "/" in m.name}
    for f in PACKAGE_DATA + ["pyproject.toml", "README.md"]:
        assert (f if f in ("pyproject.toml", "README.md") else f"src/{f}") in members, f


def test_the_wheel_requires_the_runtime_dependencies_only(built):
    _, _, wheel = built
    with zipfile.ZipFile(wheel) as z:
        meta = z.read(next(n for n in z.namelist() if n.endswith(".dist-info/METADATA"))).decode()
    requires = [line.split(":", 1)[1].strip() for line in meta.splitlines() if line.startswith("Requires-Dist:")]
    plain = {r.split(";")[0].split(">")[0].split("=")[0].split("<")[0].strip().lower() for r in requires if ";" not in r}
    assert plain == RUNTIME
    extra_test = {r.split(";")[0].split(">")[0].strip().lower() for r in requires if 'extra == "test"' in r}
    assert {"pytest", "hypothesis"} <= extra_test
    assert f"Version: {dtcrit.__version__}" in meta


def test_the_wheel_installs_into_a_clean_venv_and_dtcrit_runs_there(built, capsys):
    tmp, _, wheel = built
    venv = tmp / "venv"
    _call(sys.executable, "-m", "venv", venv, cwd=tmp)
    bin_dir = venv / ("Scripts" if os.name == "nt" else "bin")
    py = bin_dir / ("python.exe" if os.name == "nt" else "python")
    _call(py, "-m", "pip", "install", "-q", "-c", ROOT / "constraints.txt", wheel, cwd=tmp)

    where = tmp / "elsewhere"  # not the checkout: nothing can be imported from src/
    where.mkdir()
    origin = _call(py, "-c", "import dtcrit, sys; print(dtcrit.__file__)", cwd=where).stdout.strip()
    assert Path(origin).resolve().is_relative_to(venv.resolve()), origin
    script = bin_dir / ("dtcrit.exe" if os.name == "nt" else "dtcrit")
    assert _call(script, "--version", cwd=where).stdout.strip() == f"dtcrit {dtcrit.__version__}"
    installed = json.loads(_call(script, "step", SCENE, "--json", cwd=where).stdout)
    assert main(["step", str(SCENE), "--json"]) == 0
    here = json.loads(capsys.readouterr().out)
    assert installed == here  # the same numbers, envelope and derivation hashes as the checkout
    text = _call(script, "step", SCENE, cwd=where).stdout
    assert "dt_crit = " in text

    # runtime only: none of the test and notebook tools came along
    found = _call(py, "-c", "import importlib.util as u, json; print(json.dumps([m for m in %r if u.find_spec(m)]))"
                  % TEST_ONLY, cwd=where).stdout
    assert json.loads(found) == []
