"""Golden outputs of ``dtcrit codegen`` and ``dtcrit step`` on every example scene.

The outputs are made in-process (``dtcrit.cli.main`` with standard output captured), which keeps the
whole set to seconds.  ``python3 dev.py golden`` rewrites ``tests/golden/`` from the current code;
``tests/test_golden.py`` compares with it.

Comparison rule (why two kinds): generated code (C, NumPy, Fortran) is pure formatting of symbolic
expressions, so it must match byte for byte.  The step reports print numbers computed with NumPy and
SciPy, whose last bits depend on the processor's SIMD dispatch (AVX-512 or not); there every number
of the text is compared at a relative tolerance of ``RTOL`` (1e-9) and everything between the
numbers (words, units, layout, the count of numbers) must be identical.
"""
from __future__ import annotations

import contextlib
import difflib
import io
import math
import re
from dataclasses import dataclass
from pathlib import Path

from support.paths import EXAMPLES, REPO_ROOT

#: Where the golden files live.
GOLDEN = REPO_ROOT / "tests" / "golden"
#: Relative tolerance on the numbers of a step report (they carry the last bits of NumPy/SciPy).
RTOL = 1e-9
#: The example scenes (``examples/*.toml``), in name order.
SCENES = tuple(sorted(p.name for p in EXAMPLES.glob("*.toml")))
LANGUAGES = {"c": "c", "numpy": "py", "fortran": "f90"}

_NUMBER = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?|[-+]?(?:inf|nan)\b")


@dataclass(frozen=True)
class Case:
    """One golden file: the command line that makes it and how it is compared.

    Parameters
    ----------
    name : str
        File name under ``tests/golden``: ``codegen/<scene>.<c|py|f90>.golden`` or
        ``step/<scene>.<txt|json>.golden`` (the ``.golden`` suffix keeps linters and copy finders off them).
    argv : tuple of str
        Arguments of ``dtcrit`` (scene paths relative to the repository root).
    exact : bool
        True for generated code (byte-exact), False for reports with computed numbers.
    """

    name: str
    argv: tuple[str, ...]
    exact: bool


def cases() -> list[Case]:
    """Every golden case: each example under each codegen language, and ``step`` in text and JSON.

    Returns
    -------
    list of Case
        In a fixed order (scene, then kind).
    """
    out = []
    for scene in SCENES:
        stem, path = scene.removesuffix(".toml"), f"examples/{scene}"
        for lang, ext in LANGUAGES.items():
            out.append(Case(f"codegen/{stem}.{ext}.golden", ("codegen", path, "--lang", lang), True))
        out.append(Case(f"step/{stem}.txt.golden", ("step", path), False))
        out.append(Case(f"step/{stem}.json.golden", ("step", path, "--json"), False))
    return out


def run(case: Case) -> str:
    """Run one case's command in-process from the repository root.

    Parameters
    ----------
    case : Case
        The command to run.

    Returns
    -------
    str
        Standard output, then (if any) ``[exit N]`` and the standard error, so that a refusal is golden too.
    """
    from dtcrit.cli import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.chdir(REPO_ROOT), contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            rc = main(list(case.argv))
        except SystemExit as exc:
            rc = exc.code if isinstance(exc.code, int) else 1
    text = out.getvalue()
    if rc or err.getvalue():
        text += f"[exit {rc}]\n{err.getvalue()}"
    return text


def _close(a: str, b: str) -> bool:
    if a == b:
        return True
    x, y = float(a), float(b)
    if math.isnan(x) or math.isnan(y) or math.isinf(x) or math.isinf(y):
        return False
    return abs(x - y) <= RTOL * max(abs(x), abs(y))


def same(expected: str, got: str, exact: bool) -> bool:
    """Tell whether an output equals its golden text under the comparison rule (module docstring).

    Parameters
    ----------
    expected, got : str
        The golden text and the new output.
    exact : bool
        Byte-exact comparison when True; numbers at relative ``RTOL`` otherwise.

    Returns
    -------
    bool
        True when they agree.
    """
    if exact or expected == got:
        return expected == got
    if _NUMBER.split(expected) != _NUMBER.split(got):
        return False
    a, b = _NUMBER.findall(expected), _NUMBER.findall(got)
    return len(a) == len(b) and all(_close(x, y) for x, y in zip(a, b))


def unified_diff(expected: str, got: str, name: str) -> str:
    """The unified diff from the golden text to the new output, for a failure message.

    Parameters
    ----------
    expected, got : str
        The golden text and the new output.
    name : str
        The golden file's name under ``tests/golden``.

    Returns
    -------
    str
        The diff (``difflib.unified_diff``) and how to accept the change.
    """
    diff = difflib.unified_diff(expected.splitlines(keepends=True), got.splitlines(keepends=True),
                                f"tests/golden/{name}", f"{name} (now)")
    return "".join(diff) + "\n(if the change is intended: python3 dev.py golden)\n"


def write_all(root: Path = GOLDEN) -> int:
    """Rewrite every golden file from the current code.

    Parameters
    ----------
    root : Path
        The folder of the golden files.

    Returns
    -------
    int
        The number of files whose content changed.
    """
    changed = 0
    for case in cases():
        path = root / case.name
        path.parent.mkdir(parents=True, exist_ok=True)
        text = run(case)
        if not path.exists() or path.read_text() != text:
            path.write_text(text)
            changed += 1
    return changed


if __name__ == "__main__":
    print(f"golden files rewritten: {write_all()} changed of {len(cases())} in {GOLDEN.relative_to(REPO_ROOT)}")
