"""The README is a short entry point: at most 200 lines, real example output, no generated tables.

Its ``dtcrit step``, ``dtcrit audit`` and ``dtcrit plan`` examples must be what the commands print today; its only
table is the verified-steps table (the reference tables are generated on the site); every relative
link names a file of the repository.
"""
from __future__ import annotations

import contextlib
import io
import re
import shlex

import pytest
from support.paths import REPO_ROOT

from dtcrit.cli import main

README = (REPO_ROOT / "README.md").read_text()
ALLOWED_TABLES = ["| integrator | damping force uses | exact ω·dt_crit | note |"]


def _console_blocks() -> list[tuple[list[str], str]]:
    """(dtcrit arguments, printed output) of each ``$ dtcrit ...`` console block."""
    blocks = re.findall(r"```console\n\$ dtcrit (.*?)\n(.*?)```", README, flags=re.S)
    return [(shlex.split(command), output) for command, output in blocks]


def test_the_readme_is_short():
    assert len(README.splitlines()) <= 200


def test_the_readme_shows_a_step_and_an_audit():
    assert [args[0] for args, _ in _console_blocks()] == ["step", "audit", "plan"]


@pytest.mark.parametrize("args, output", _console_blocks(), ids=lambda v: v[0] if isinstance(v, list) else None)
def test_the_readme_output_is_what_the_command_prints(args, output, monkeypatch):
    monkeypatch.chdir(REPO_ROOT)
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        assert main(args) == 0
    assert output == buf.getvalue()


def test_the_readme_has_no_generated_table():
    headers = [line for i, line in enumerate(README.splitlines()[:-1])
               if line.startswith("|") and README.splitlines()[i + 1].startswith("| ---")]
    assert headers == ALLOWED_TABLES


def test_the_readme_links_resolve():
    targets = re.findall(r"\]\(([^)#:]+)\)", README)
    assert targets
    missing = [t for t in targets if not (REPO_ROOT / t).exists()]
    assert not missing, missing
