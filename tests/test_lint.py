"""ruff and mypy over ``src/``, with the configuration in ``pyproject.toml``.

Each tool is run as a subprocess from the repository root and the test fails with the tool's own
list of findings.  A tool that is not installed skips the test, except under ``CI=true``, where a
missing tool is a failure (the ``test`` extra pins both).
"""
from __future__ import annotations

import importlib.util
import shutil
import subprocess
import sys

import pytest
from support.ci import in_ci
from support.paths import REPO_ROOT as ROOT




def _command(tool: str) -> list[str]:
    """The command that runs ``tool``: the module of this interpreter, else the executable on PATH."""
    if importlib.util.find_spec(tool) is not None:
        return [sys.executable, "-m", tool]
    exe = shutil.which(tool)
    if exe is not None:
        return [exe]
    message = f"{tool} is not installed (pip install -e '.[test]')"
    if in_ci():
        pytest.fail(message)
    pytest.skip(message)


def _run(args: list[str]) -> subprocess.CompletedProcess[str]:
    return subprocess.run(args, cwd=ROOT, capture_output=True, text=True, timeout=900)


def test_ruff_check_is_clean():
    """``ruff check src`` reports nothing."""
    result = _run(_command("ruff") + ["check", "--no-fix", "--output-format", "concise", "src"])
    assert result.returncode == 0, "ruff check src found:\n" + result.stdout + result.stderr


def test_mypy_is_clean():
    """``mypy`` over src/dtcrit reports no error."""
    # the file list ("files = src/dtcrit") and the options come from [tool.mypy] in pyproject.toml
    result = _run(_command("mypy"))
    assert result.returncode == 0, "mypy found:\n" + result.stdout + result.stderr
