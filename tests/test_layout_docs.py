"""The documentation's layout page and the package docstrings name modules that exist.

The layout block (``docs/explanation/code_layout.md``, "How the code is laid out") gives one path per
line, nested by indentation, with the modules of a package listed in square brackets (every module and
subpackage of a listed package is listed or has an entry of its own); every package docstring's ``Modules``
paragraph names its modules in double back-quotes (names in parentheses describe, they are not
modules), and every ``:mod:`` reference in a package docstring resolves to a module.
"""
from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest
from support.paths import REPO_ROOT, SRC

PACKAGE = SRC / "dtcrit"
INITS = sorted(PACKAGE.rglob("__init__.py"))
DESCRIPTION_COLUMN = 21  # the layout block's descriptions start in this column
LAYOUT_PAGE = REPO_ROOT / "docs" / "explanation" / "code_layout.md"


def _exists(folder: Path, name: str) -> bool:
    return (folder / f"{name}.py").is_file() or (folder / name / "__init__.py").is_file()


def _layout_block() -> list[str]:
    return LAYOUT_PAGE.read_text().split("```", 2)[1].splitlines()[1:]


def _layout_entries() -> list[tuple[Path, list[str], str]]:
    """(path, listed modules, text) of each entry of the layout block.

    An entry starts with its path (nested under the entry above it that is indented less); lines
    indented to the description column continue it; ``[a, b]`` lists the modules of the entry's path.
    """
    entries: list[tuple[Path, str]] = []
    stack: list[tuple[int, Path]] = []
    for line in _layout_block():
        indent = len(line) - len(line.lstrip())
        if not line.strip():
            continue
        if indent >= DESCRIPTION_COLUMN and entries:
            entries[-1] = (entries[-1][0], entries[-1][1] + " " + line.strip())
            continue
        while stack and stack[-1][0] >= indent:
            stack.pop()
        path = (stack[-1][1] if stack else REPO_ROOT) / line.split()[0].rstrip("/")
        stack.append((indent, path))
        entries.append((path, line.strip()))
    return [(path, [n.strip() for group in re.findall(r"\[([^\]]*)\]", text) for n in group.split(",") if n.strip()],
             text) for path, text in entries]


def test_the_layout_block_is_found():
    """A missing or empty block would pass every check below vacuously."""
    entries = _layout_entries()
    assert len(entries) > 20 and sum(len(listed) for _, listed, _ in entries) > 50


@pytest.mark.parametrize("path, listed, line", _layout_entries(), ids=lambda v: str(v)[-40:] if isinstance(v, str) else None)
def test_each_layout_entry_exists_with_its_modules(path, listed, line):
    assert path.exists(), f"the layout page names {path.relative_to(REPO_ROOT)}, which does not exist: {line!r}"
    missing = [n for n in listed if not _exists(path, n)]
    assert not missing, f"{path.relative_to(REPO_ROOT)}: the layout page lists modules that do not exist: {missing}"


def _modules(folder: Path) -> set[str]:
    """The public modules and subpackages of a package folder (names without a leading underscore)."""
    return ({p.stem for p in folder.glob("*.py") if not p.stem.startswith("_")}
            | {p.name for p in folder.iterdir() if (p / "__init__.py").is_file() and not p.name.startswith("_")})


def test_the_layout_lists_every_module():
    """Every module of a package whose modules the page lists, and every top-level module or
    package of ``dtcrit``, is on the page (listed, or an entry of its own): a new module must be added."""
    entries = _layout_entries()
    paths = {path for path, _, _ in entries}
    unlisted = [f"{folder.relative_to(REPO_ROOT)}/{name}" for folder, listed, _ in entries if listed
                for name in sorted(_modules(folder)) if name not in listed and folder / name not in paths]
    top = {p.with_suffix("") if p.suffix == ".py" else p for p in paths}
    unlisted += [f"src/dtcrit/{name}" for name in sorted(_modules(PACKAGE)) if PACKAGE / name not in top]
    assert not unlisted, "modules missing from docs/explanation/code_layout.md: " + ", ".join(unlisted)


def _top_level_names(paragraph: str) -> list[str]:
    depth, names = 0, []
    for token in re.split(r"(``[^`]+``|[()])", paragraph):
        if token == "(":
            depth += 1
        elif token == ")":
            depth -= 1
        elif depth == 0 and token.startswith("``") and re.fullmatch(r"``\w+``", token):
            names.append(token.strip("`"))
    return names


def _docstring(init: Path) -> str:
    return ast.get_docstring(ast.parse(init.read_text())) or ""


@pytest.mark.parametrize("init", INITS, ids=lambda p: str(p.parent.relative_to(SRC)))
def test_package_docstrings_name_modules_that_exist(init):
    doc, folder = _docstring(init), init.parent
    bad = []
    for paragraph in re.findall(r"Modules:(.*?)(?:\n\s*\n|\Z)", doc, flags=re.S):
        bad += [n for n in _top_level_names(paragraph) if not _exists(folder, n)]
    for ref in re.findall(r":mod:`~?([\w.]+)`", doc):
        parts = ref.lstrip(".").split(".") if ref.startswith(".") else ref.split(".")[1:]
        base = folder if ref.startswith(".") else PACKAGE
        if not (_exists(base / Path(*parts[:-1]), parts[-1]) if parts else True):
            bad.append(ref)
    assert not bad, f"{init.relative_to(REPO_ROOT)}: names modules that do not exist: {bad}"


def test_the_package_docstrings_list_modules():
    """The walk reads real lists (an empty one would pass vacuously)."""
    listed = sum(len(_top_level_names(p)) for init in INITS
                 for p in re.findall(r"Modules:(.*?)(?:\n\s*\n|\Z)", _docstring(init), flags=re.S))
    assert listed > 30


def _named_test_files() -> list[tuple[str, str]]:
    """(file, named test path) for every ``tests/...py`` path the README, the docs, the sources and dev.py name."""
    docs = sorted(p for p in (REPO_ROOT / "docs").rglob("*.md") if not {"_build", "_generated"} & set(p.parts))
    texts = [REPO_ROOT / "README.md", REPO_ROOT / "dev.py", *docs,
             *sorted(PACKAGE.rglob("*.py"))]
    return [(str(p.relative_to(REPO_ROOT)), m) for p in texts
            for m in sorted(set(re.findall(r"tests/[\w/]+\.py", p.read_text())))]


def test_named_test_files_exist():
    named = _named_test_files()
    assert named, "no test file named anywhere: the search pattern is broken"
    missing = [f"{where}: {path}" for where, path in named if not (REPO_ROOT / path).is_file()]
    assert not missing, "test files named but missing:\n" + "\n".join(missing)
