"""``dtcrit codegen`` with hostile outside text: a scene title, a directory and a file name (the
"Regenerate with" line and the "Scene" line of the header) and a user scheme's rules carrying code
for each language behind a comment terminator or a newline.  Before the header was sanitised, each
payload became code: the compiled C exported the injected symbol, importing the NumPy module ran the
injected call, the Fortran compiled an injected procedure.  Now the C and the Fortran compile under
the strict flags with no injected symbol (``nm``), importing the NumPy module (in a fresh interpreter)
creates no sentinel file, and ``--json`` carries the same source.  A path with ``coding:unicode_escape``
(a Python encoding declaration under which an escape ``\\x0a`` would become a newline) is included."""
import json
import os
import shutil
import subprocess
import sys

import pytest
from support.codegen import C_FLAGS, CC, fortran_library

from dtcrit.cli import main

BODY = """integrator = "velocity-verlet"

[[particle]]
shape = "ellipsoid"
semi_axes = [3.0, 2.0, 1.0]
density = 1000.0

[contact]
model = "linear"
kn = 1.0e10
ks = 1.0e10
restitution = 0.3
"""
USER_SCHEME = """[integrator]
name = "my-scheme-{lang}"
state = ["x", "v"]
update = [{rule}, "x = x + h*v"]
"""
# per language: code behind a comment terminator or a newline, as a title and as a directory name
# (a directory, so that the file name in the "Scene" line stays plain and the payload appears once)
PAYLOAD = {
    "c": ("*/ int injected_title = 42; /*", " int injected_path = 1; /*"),  # the directory below "x*"
    "numpy": ('x\nopen("sentinel_title", "w").close()\n#', '\nopen("sentinel_path", "w").close()\n#'),
    "fortran": ("x\nsubroutine injected_title() bind(C)\nend subroutine injected_title\n!",
                "\nsubroutine injected_path() bind(C)\nend subroutine injected_path\n!"),
}
NM = shutil.which("nm")


def _scene(tmp_path, lang: str, case: str):
    """The scene file of ``case`` for ``lang``; its path."""
    title_payload, dir_payload = PAYLOAD[lang]
    title, directory, body = "plain", tmp_path / "scenes", BODY
    if case == "title":
        title = title_payload
    elif case == "path":
        directory = tmp_path / ("x*" if lang == "c" else "x") / dir_payload
    elif case == "coding":  # an escaped newline must stay text: no encoding declaration in the header
        directory, title = tmp_path / "coding:unicode_escape", PAYLOAD["numpy"][0]
    elif case == "rule":  # a user scheme's rule with a payload in a Python comment (ast drops it; a newline is refused)
        rule = "v = v + h*f(x, v)  # */ int injected_rule = 1; /* import os; os.system('touch sentinel_rule') ! &"
        body = USER_SCHEME.format(lang=lang, rule=json.dumps(rule)) + BODY.split("\n", 1)[1]
    try:
        directory.mkdir(parents=True)
    except OSError as exc:  # pragma: no cover - a filesystem without these characters
        pytest.skip(f"this filesystem refuses the directory name {directory.name!r}: {exc}")
    path = directory / "s.toml"
    path.write_text(f"title = {json.dumps(title)}\n{body}", encoding="utf-8")
    return path


def _symbols(lib) -> str:
    if NM is None:
        pytest.fail("nm (binutils) is not on PATH")
    return subprocess.run([NM, str(lib)], capture_output=True, text=True, check=True).stdout


def _emit(path, lang, out, capsys) -> str:
    assert main(["codegen", str(path), "--lang", lang, "--out", str(out)]) == 0
    assert main(["codegen", str(path), "--lang", lang, "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    text = out.read_text(encoding="ascii")
    assert doc["source"] == text
    assert all(ch == "\n" or 0x20 <= ord(ch) < 0x7F for ch in text)
    return text


CASES = [(lang, case) for lang in ("c", "numpy", "fortran") for case in ("title", "path", "rule")] + [("numpy", "coding")]


@pytest.mark.parametrize("lang,case", CASES)
def test_hostile_text_stays_in_the_header_comment(lang, case, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)  # a relative path: the "Regenerate with" line (the second) stays short, unwrapped
    path = _scene(tmp_path, lang, case).relative_to(tmp_path)
    build = tmp_path / "build"
    build.mkdir()
    suffix = {"c": ".c", "numpy": ".py", "fortran": ".f90"}[lang]
    text = _emit(path, lang, build / f"k{suffix}", capsys)
    if case == "rule":
        assert "injected" not in text and "sentinel" not in text  # a rule's text never reaches the output
    if lang == "c":
        header_end = text.index("\n */\n")
        assert text.find("*/") == header_end + 2  # the header closes once, where it should
        lib = build / "k.so"
        p = subprocess.run([CC, *C_FLAGS, "-O2", "-shared", "-fPIC", "-o", str(lib), str(build / "k.c"), "-lm"],
                           capture_output=True, text=True)
        assert p.returncode == 0, p.stderr
        symbols = _symbols(lib)
        assert "dtcrit_dt_crit" in symbols and "injected" not in symbols, symbols
    elif lang == "fortran":
        symbols = _symbols(fortran_library(text))  # skips without gfortran, fails under CI=true
        assert "dtcrit_dt_crit" in symbols and "injected" not in symbols, symbols
    else:
        code = ("import inspect, sys, k; f = k.dtcrit_dt_crit; n = len(inspect.signature(f).parameters); "
                "sys.stdout.write(repr(float(f(*[1.0] * n))))")
        env = {**os.environ, "PYTHONPATH": str(build), "PYTHONDONTWRITEBYTECODE": "1"}
        p = subprocess.run([sys.executable, "-c", code], cwd=build, capture_output=True, text=True, env=env)
        assert p.returncode == 0, p.stderr
        assert float(p.stdout) > 0
        assert sorted(f.name for f in build.iterdir()) == ["k.py"]  # no sentinel file


def test_a_rule_with_a_newline_is_refused_in_one_line(tmp_path, capsys):
    path = tmp_path / "s.toml"
    rule = json.dumps("v = v + h*f(x, v)\nimport os")
    path.write_text("title = 'plain'\n" + USER_SCHEME.format(lang="nl", rule=rule) + BODY.split("\n", 1)[1])
    assert main(["codegen", str(path), "--lang", "numpy"]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err.startswith(f"{path}:integrator.update[1]: ")
    assert len(captured.err.splitlines()) == 1


@pytest.mark.parametrize("name", ["a*/ int x; /*", "a\nimport os", 'a"""', "a\\"])
def test_a_user_scheme_name_that_could_leave_a_comment_or_docstring_is_refused(name, tmp_path, capsys):
    """The scheme's name is printed in comments and the NumPy docstring: only letters, digits, - _ . pass."""
    path = tmp_path / "s.toml"
    scheme = USER_SCHEME.replace('"my-scheme-{lang}"', json.dumps(name)).format(rule=json.dumps("v = v + h*f(x, v)"))
    path.write_text("title = 'plain'\n" + scheme + BODY.split("\n", 1)[1])
    assert main(["codegen", str(path), "--lang", "c"]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err.startswith(f"{path}:integrator.name: ")
    assert len(captured.err.splitlines()) == 1
