"""The function name of emitted code (``dtcrit.codegen.names.check_name`` and the kernel's own names):
refused when it is no identifier over its whole text, or names something the emitted file or its
compiler already has -- found here independently of the list in the code: every macro and function
the system C compiler's ``<math.h>`` defines in GNU mode (from ``cc -dM -E`` and ``cc -E``), every
function the emitted C calls, every module-level or built-in name the emitted NumPy reads (Python's
``ast``), every keyword of Python."""
import ast
import keyword
import re
import subprocess

import pytest
from hypothesis import given
from hypothesis import strategies as st
from support.codegen import CC

from dtcrit.codegen import build_kernel, general_structure, render
from dtcrit.codegen.names import check_name
from dtcrit.errors import InputError
from dtcrit.integrators.schemes import NAMES


def _refused(name, kernel=None) -> bool:
    try:
        check_name(name) if kernel is None else render(kernel, "c", name)
    except InputError as exc:
        return exc.key == "name"
    return False


@pytest.fixture(scope="module")
def math_h_names(tmp_path_factory):
    src = tmp_path_factory.mktemp("mathh") / "m.c"
    src.write_text("#include <math.h>\n")
    macros = subprocess.run([CC, "-std=gnu17", "-dM", "-E", str(src)], capture_output=True, text=True, check=True).stdout
    names = {m.group(1) for m in re.finditer(r"^#define ([A-Za-z]\w*)", macros, flags=re.M)}
    decls = subprocess.run([CC, "-std=gnu17", "-E", str(src)], capture_output=True, text=True, check=True).stdout
    names |= set(re.findall(r"\bextern\b[^;(]*?\b([A-Za-z]\w*)\s*\(", " ".join(decls.split())))
    assert {"sqrt", "hypot", "isnan", "M_PI", "j0"} <= names  # the scan found <math.h>
    return names


def test_every_name_of_math_h_is_refused(math_h_names):
    assert sorted(n for n in math_h_names if not _refused(n)) == []


@pytest.mark.parametrize("integrator", NAMES)
def test_every_function_the_c_calls_and_every_global_the_numpy_reads_is_refused(integrator):
    kernel = build_kernel(general_structure(integrator))
    c = re.sub(r"/\*.*?\*/", "", render(kernel, "c"), flags=re.S)
    called = set(re.findall(r"\b([A-Za-z]\w*)\s*\(", c)) - {"dtcrit_dt_crit"}
    called = {n for n in called if not n.startswith("dtcrit_dt_crit_")}  # the helpers carry the name as prefix
    tree = ast.parse(render(kernel, "numpy"))
    local = {a.arg for f in ast.walk(tree) if isinstance(f, ast.FunctionDef) for a in f.args.args} | {
        t.id for f in ast.walk(tree) if isinstance(f, ast.FunctionDef) for n in ast.walk(f)
        if isinstance(n, (ast.Assign, ast.For, ast.AugAssign, ast.comprehension))
        for t in ast.walk(n.targets[0] if isinstance(n, ast.Assign) else n.target) if isinstance(t, ast.Name)}
    read = {n.id for n in ast.walk(tree) if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Load)} - local
    assert "np" in read and called
    assert sorted(n for n in (called | read) if not n.startswith("_") and not _refused(n, kernel)) == []


def test_python_keywords_and_case_variants_are_refused():
    assert all(_refused(w) for w in keyword.kwlist)
    assert all(_refused(w) for w in ("While", "SQRT", "Main", "LINUX", "range", "Float"))


@given(st.text(max_size=60))
def test_a_name_is_accepted_only_as_a_whole_identifier_of_the_three_languages(text):
    ok = not _refused(text)
    whole = re.fullmatch(r"[A-Za-z][A-Za-z0-9_]{0,47}", text) is not None
    assert ok <= whole  # nothing but a letter-first ASCII identifier of at most 48 characters gets through
    if ok:
        assert text.isidentifier() and not keyword.iskeyword(text)


@pytest.mark.parametrize("text", ["abc\n", "abc\r", "a" * 49, "_x", "x-y", "x y", "\u00e9t\u00e9", "x*/"])
def test_near_identifiers_are_refused(text):
    assert _refused(text)
