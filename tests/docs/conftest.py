"""The documentation site, built once per test run: the ``built_site`` fixture.

The site is built with ``sphinx-build`` and ``dev.py``'s options (``DOCS_BUILD``: warnings as errors,
``--keep-going``, nitpicky, every page re-read) into a fresh ``docs/_build/html``, the folder
``python3 dev.py docs`` writes; the notebooks' executions come from the jupyter-cache in
``docs/_build/.jupyter_cache`` when their code is unchanged.  Under pytest-xdist the first worker to
ask builds while the others wait on a lock, then every worker reuses that build (the run is
identified by ``PYTEST_XDIST_TESTRUNUID``), so one ``python3 dev.py test`` builds the site once.
"""
from __future__ import annotations

import importlib.util
import json
import os
import shutil
import subprocess
import sys
from contextlib import contextmanager
from pathlib import Path

import pytest
from support.paths import REPO_ROOT

DOCS = REPO_ROOT / "docs"
BUILD = DOCS / "_build"
HTML = BUILD / "html"
RECORD = BUILD / "test-build.json"  # {"run": ..., "returncode": ..., "warnings": ..., "seconds": ...}
TIMEOUT = 900  # seconds; the cold build (every notebook executed) takes about a minute on 2 cores


def docs_build_options() -> tuple[str, ...]:
    """``dev.py``'s ``DOCS_BUILD`` (the options of ``python3 dev.py docs``).

    Returns
    -------
    tuple of str
        The ``sphinx-build`` options.
    """
    spec = importlib.util.spec_from_file_location("dtcrit_dev", REPO_ROOT / "dev.py")
    dev = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(dev)
    return tuple(dev.DOCS_BUILD)


@contextmanager
def _locked(path: Path):
    """Hold an exclusive lock on ``path`` (POSIX ``flock``; no lock elsewhere)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "a") as handle:
        try:
            import fcntl
        except ImportError:  # pragma: no cover - Windows
            yield
            return
        fcntl.flock(handle, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(handle, fcntl.LOCK_UN)


def _this_run() -> str:
    return os.environ.get("PYTEST_XDIST_TESTRUNUID") or f"pid-{os.getpid()}"


def build_site() -> dict:
    """Build the site into ``docs/_build/html``; record and return the outcome.

    Returns
    -------
    dict
        ``run`` (this test run's id), ``returncode`` of sphinx-build, ``warnings`` (its warning
        log), ``output`` (the tail of its output) and ``seconds`` (wall time).
    """
    import time

    warnings = BUILD / "warnings.txt"
    shutil.rmtree(HTML, ignore_errors=True)  # no page of an earlier build survives
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, [str(REPO_ROOT / "src"),
                                                                     os.environ.get("PYTHONPATH")])))
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "sphinx", *docs_build_options(), "-w", str(warnings),
                           str(DOCS), str(HTML)], capture_output=True, text=True, env=env, timeout=TIMEOUT,
                          cwd=REPO_ROOT)
    record = {"run": _this_run(), "returncode": done.returncode, "seconds": time.perf_counter() - start,
              "warnings": warnings.read_text() if warnings.is_file() else "",
              "output": (done.stdout + done.stderr)[-4000:]}
    RECORD.write_text(json.dumps(record))
    return record


def site_build_record() -> dict:
    """The outcome of this run's build (``build_site``), building the site if no worker did yet.

    Returns
    -------
    dict
        As ``build_site`` returns.
    """
    with _locked(BUILD / ".test-build.lock"):
        if RECORD.is_file():
            record = json.loads(RECORD.read_text())
            if record.get("run") == _this_run():
                return record
        return build_site()


@pytest.fixture(scope="session")
def site_build() -> dict:
    """The build of the site in this run: ``returncode``, ``warnings``, ``output``, ``seconds``."""
    return site_build_record()


def _notebook_cache_module():
    """``docs/_gen/notebook_cache.py``, loaded from its path."""
    spec = importlib.util.spec_from_file_location("dtcrit_docs_notebook_cache", DOCS / "_gen" / "notebook_cache.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="session")
def executed_notebook(built_site):
    """A function ``stem -> notebook``: the teaching notebook the site's build executed (from its cache)."""
    return _notebook_cache_module().executed


@pytest.fixture(scope="session")
def built_site(site_build) -> Path:
    """The built site's HTML folder (``docs/_build/html``), built once per test run."""
    if not (HTML / "index.html").is_file():
        pytest.fail("the documentation site did not build:\n" + site_build["output"])
    return HTML
