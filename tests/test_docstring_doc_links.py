"""Where the source's docstrings send a reader exists: a ``README`` mention names one of the README's
sections, a ``docs/...md`` page exists and holds the sections quoted after it, a generated reference page
(``docs/reference/generated/NAME``) is one the docs extension writes; and a module-level string documents
the assignment right above it (an attribute docstring), never another string.
"""
from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest
from support.paths import REPO_ROOT, SRC

MODULES = sorted((SRC / "dtcrit").rglob("*.py"))
DOCS_PAGE = re.compile(r"docs/[\w/.-]+\.md")
SECTIONS = re.compile(r'``?,?\s+(?:sections?\s+)?("[^"]+"(?:\s*(?:,|and)\s*"[^"]+")*)')
GENERATED = re.compile(r"docs/reference/generated/([\w-]+)")
ORPHANS_KNOWN: set[str] = set()  # modules with a known orphan attribute docstring (none)


def _rel(path: Path) -> str:
    return path.relative_to(SRC / "dtcrit").as_posix()


def _headings(text: str) -> set[str]:
    """Markdown headings and bold run-in headings (``**Name.**``) of a page, whitespace normalised."""
    found = {m.group(1) for m in re.finditer(r"^#+\s+(.+?)\s*$", text, re.M)}
    found |= {m.group(1) for m in re.finditer(r"\*\*([^*]+?)\.?\*\*", text)}
    return {" ".join(h.split()) for h in found}


def _generated_pages() -> set[str]:
    """The pages ``docs/_ext/dtcrit_docs.py`` writes: its ``_write("name", ...)`` calls and one per schema."""
    ext = (REPO_ROOT / "docs" / "_ext" / "dtcrit_docs.py").read_text()
    names = set(re.findall(r'_write\("([\w-]+)"', ext))
    return names | {f"json-{p.stem}" for p in (SRC / "dtcrit" / "schemas").glob("*.json")}


def _readme_problems(path: Path, text: str, readme: set[str]) -> list[str]:
    out = []
    for m in re.finditer(r"README", text):
        after = " ".join(text[m.end():m.end() + 80].split())
        if not any(h in after for h in readme):
            out.append(f"{_rel(path)}:{text.count(chr(10), 0, m.start()) + 1}: README {after[:60]!r}")
    return out


def _docs_problems(path: Path, text: str, generated: set[str]) -> list[str]:
    out = []
    for m in DOCS_PAGE.finditer(text):
        line = f"{_rel(path)}:{text.count(chr(10), 0, m.start()) + 1}"
        page = REPO_ROOT / m.group(0)
        if not page.is_file():
            out.append(f"{line}: no page {m.group(0)}")
            continue
        quoted = SECTIONS.match(text, m.end())
        heads = _headings(page.read_text())
        for name in re.findall(r'"([^"]+)"', quoted.group(1)) if quoted else ():
            name = " ".join(name.split())
            if not any(h == name or h.startswith(name + " (") for h in heads):  # a heading, less its aside
                out.append(f"{line}: {m.group(0)} has no section {name!r}")
    out += [f"{_rel(path)}: no generated page {g}" for g in GENERATED.findall(text) if g not in generated]
    return out


def test_docstrings_point_to_pages_and_sections_that_exist():
    """Every README mention, docs page, quoted section and generated page named in ``src/dtcrit`` exists."""
    readme = {h for h in _headings((REPO_ROOT / "README.md").read_text()) if h != "dtcrit"}  # its sections, not its title
    generated = _generated_pages()
    problems = []
    for path in MODULES:
        text = path.read_text()
        problems += _readme_problems(path, text, readme) + _docs_problems(path, text, generated)
    assert not problems, "\n".join(problems)


def _orphans(path: Path) -> list[int]:
    """Lines of module-level strings that follow neither the module's start nor an assignment."""
    body = ast.parse(path.read_text()).body
    return [node.lineno for prev, node in zip(body, body[1:])
            if isinstance(node, ast.Expr) and isinstance(node.value, ast.Constant) and isinstance(node.value.value, str)
            and not isinstance(prev, (ast.Assign, ast.AnnAssign))]


@pytest.mark.parametrize("path", MODULES, ids=_rel)
def test_attribute_docstrings_sit_under_their_assignment(path):
    """A module-level string after the first statement follows an assignment (the one it documents)."""
    if _rel(path) in ORPHANS_KNOWN:
        pytest.xfail("a known orphan attribute docstring, to be moved beside its constant")
    assert not _orphans(path), f"{_rel(path)}: strings not under an assignment at lines {_orphans(path)}"
