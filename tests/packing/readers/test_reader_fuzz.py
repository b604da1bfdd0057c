"""Every file reader answers or refuses in one line, never a traceback, never a hang.

Mutations of valid files -- the LAMMPS/LIGGGHTS dump of ``examples/packings``, a LAMMPS local dump
and a contact table beside a small dump, the bodies file ``examples/packings/ellipsoids.json``, a
YADE export of spheres and one with a clump -- go through the command line in-process
(``dtcrit.cli.main``): truncations, NaN/inf/negative/zero/huge/tiny numbers, wrong types, missing
keys, huge counts, empty files, binary garbage.  Each run must return 0, or 2 with exactly one line
on standard error of the form ``dtcrit: FILE:LINE: reason``, ``dtcrit: FILE: key: reason`` or
``dtcrit: --flag: reason``, within ``LIMIT`` seconds.  A few cases also run as a subprocess.
"""
from __future__ import annotations

import copy
import json
import math
import re
import subprocess
import sys
import time
import warnings

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from dtcrit.cli import main
from support.paths import REPO_ROOT as ROOT

DUMP = ROOT / "examples" / "packings" / "random_lognormal_60.dump"
BODIES = ROOT / "examples" / "packings" / "ellipsoids.json"
LIMIT = 10.0
R, RHO = 1e-3, 2650.0
MASS = 4.0 / 3.0 * math.pi * R**3 * RHO
XS = (0.0, 1.998e-3, 3.996e-3, 5.994e-3)
PAIR_STYLE = "gran/hooke/history 1e5 NULL 0 NULL 0.5 0"

CHAIN_DUMP = ("ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n4\nITEM: BOX BOUNDS ff ff ff\n-0.002 0.008\n-0.002 0.002\n"
              "-0.002 0.002\nITEM: ATOMS id type x y z radius mass\n"
              + "".join(f"{k + 1} 1 {x!r} 0 0 {R!r} {MASS!r}\n" for k, x in enumerate(XS)))
LOCAL = ("ITEM: TIMESTEP\n0\nITEM: NUMBER OF ENTRIES\n3\nITEM: BOX BOUNDS ff ff ff\n-0.002 0.008\n-0.002 0.002\n"
         "-0.002 0.002\nITEM: ENTRIES c_pairs[1] c_pairs[2]\n1 2\n2 3\n3 4\n")
TABLE = "# id1 id2 kn ks cn cs fn\n1 2 1e5 8e4 0.1 0.05 0.2\n2 3 1e5 8e4 0.1 0.05 0.2\n3 4 1e5 8e4 0.1 0.05 0.2\n"


def _yade_sphere(bid, x, **kw):
    return {"id": bid, "pos": [x, 0.0, 0.0], "radius": R, "mass": MASS, "inertia": [0.4 * MASS * R * R] * 3,
            "clump_id": None, "is_clump": False, "fixed": False, "ori": [1, 0, 0, 0], **kw}


def _yade_inter(a, b, **kw):
    return {"id1": a, "id2": b, "kn": 1e5, "ks": 3e4, "kr": None, "ktw": None, "cn": None, "cs": None, "fn": 2.0,
            "penetration": 2e-6, "shift2": [0.0, 0.0, 0.0], **kw}


def _yade_export(bodies, interactions):
    return {"schema": "dtcrit-yade-export/1", "yade_version": "2023.02a", "dt": 1e-7, "iter": 3,
            "newton_damping": 0.0, "periodic": False, "cell_hsize": None, "avoid_granular_ratcheting": True,
            "bodies": bodies, "interactions": interactions}


YADE_SPHERES = _yade_export([_yade_sphere(k, x) for k, x in enumerate(XS)],
                            [_yade_inter(0, 1), _yade_inter(1, 2, kr=1e-3, ktw=1e-3, cn=0.1, cs=0.05), _yade_inter(2, 3)])
YADE_CLUMP = _yade_export(
    [_yade_sphere(0, -0.75 * R, clump_id=2), _yade_sphere(1, 0.75 * R, clump_id=2),
     {"id": 2, "pos": [0.0, 0.0, 0.0], "radius": None, "mass": 2 * MASS, "inertia": [1e-11, 2e-11, 3e-11],
      "clump_id": None, "is_clump": True, "fixed": False, "ori": [0.9, 0.0, 0.0, 0.43588989435406735]},
     _yade_sphere(3, 2.74 * R)], [_yade_inter(0, 1), _yade_inter(1, 3)])

ONE_LINE = re.compile(r'dtcrit: (?:(?P<file>[^:\n]+)(?::\d+|: ?(?:[\w\[\].-]|"[^"\n]*")+)|--[\w-]+|packing): \S[^\n]*\n')
"""``FILE:LINE: reason``, ``FILE: key: reason`` (``key`` a path such as ``bodies[2].shape.radius``)
or ``--flag: reason``; a key that is no bare word is quoted, as TOML writes it.  ``packing: reason``
is ``dtcrit packing``'s verdict on a packing read whole (no two particles touch, no stiffness)."""


def _check(argv, capsys, files):
    """Run ``dtcrit ARGV`` in-process: 0, or 2 with one line naming a FILE of ``files`` or a --flag."""
    start = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:  # a warning would be one more line on stderr
        warnings.simplefilter("always")
        try:
            code = main(argv)
        except SystemExit as exc:  # argparse
            code = exc.code
    elapsed = time.perf_counter() - start
    out, err = capsys.readouterr()
    assert not caught, [str(w.message) for w in caught]
    assert elapsed < LIMIT, (argv, elapsed)
    assert code in (0, 2), (code, err)
    if code == 0:
        assert err == "", err
        return
    match = ONE_LINE.fullmatch(err)
    assert match, err
    assert match["file"] is None or match["file"] in {str(f) for f in files}, err
    for leak in ("np.float64", "Traceback", "array must not contain", "Error:", "<class", "object at 0x"):
        assert leak not in err, err


# ---------------------------------------------------------------------------- text mutations

NASTY_NUMBERS = ("nan", "-nan", "inf", "-inf", "-1", "0", "-0", "1e308", "1e-320", "1e400", "-1e308", "abc", "0x10",
                 "1,5", "99999999999999999999999", "", "1e-300", "2.5e-310")
GARBAGE = (b"\x00", b"\xff\xfe", b"\x89PNG\r\n\x1a\n", b"\xc3\x28", "\u00e9".encode("utf-8"), b"\r", b"\x1b[31m",
           b"ITEM: TIMESTEP\n", b"ITEM: ATOMS id x\n")


@st.composite
def text_mutation(draw, text: str) -> bytes:
    """A mutated copy of ``text``: one to three edits of lines, tokens or bytes."""
    lines = text.splitlines(keepends=True)
    for _ in range(draw(st.integers(1, 3))):
        kind = draw(st.sampled_from(["token", "token", "token", "drop", "repeat", "truncate", "garbage", "count",
                                     "empty", "swap"]))
        n = draw(st.integers(0, max(len(lines) - 1, 0)))
        if not lines or kind == "empty":
            lines = [draw(st.sampled_from(["", "\n", " \n\n", "\ufeff"]))]
            continue
        if kind == "token":
            parts = lines[n].split(" ")
            k = draw(st.integers(0, len(parts) - 1))
            parts[k] = draw(st.sampled_from(NASTY_NUMBERS)) + ("\n" if parts[k].endswith("\n") else "")
            lines[n] = " ".join(parts)
        elif kind == "drop":
            del lines[n]
        elif kind == "repeat":
            lines.insert(n, lines[n])
        elif kind == "swap":
            m = draw(st.integers(0, len(lines) - 1))
            lines[n], lines[m] = lines[m], lines[n]
        elif kind == "truncate":
            joined = "".join(lines)
            lines = [joined[: draw(st.integers(0, len(joined)))]]
        elif kind == "count":
            lines[n] = draw(st.sampled_from(["99999999999999\n", "-5\n", "0\n", "1e9\n", "4294967297\n"]))
        else:
            raw = "".join(lines).encode()
            at = draw(st.integers(0, len(raw)))
            return raw[:at] + draw(st.sampled_from(GARBAGE)) + raw[at:]
    return "".join(lines).encode("utf-8", "surrogatepass")


FUZZ = settings(deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])


@FUZZ
@given(data=text_mutation(DUMP.read_text()))
def test_dump_mutations_are_answered_or_refused_in_one_line(data, tmp_path, capsys):
    path = tmp_path / "m.dump"
    path.write_bytes(data)
    _check(["packing", str(path), "--kn", "1e5", "--certify", "no"], capsys, [path])


@FUZZ
@given(dump=text_mutation(CHAIN_DUMP), local=text_mutation(LOCAL), which=st.sampled_from(["dump", "local"]))
def test_local_dump_mutations_are_answered_or_refused_in_one_line(dump, local, which, tmp_path, capsys):
    a, b = tmp_path / "chain.dump", tmp_path / "pairs.local"
    a.write_bytes(dump if which == "dump" else CHAIN_DUMP.encode())
    b.write_bytes(local if which == "local" else LOCAL.encode())
    _check(["audit", str(a), "--pair-style", PAIR_STYLE, "--local", str(b)], capsys, [a, b])


@FUZZ
@given(table=text_mutation(TABLE), comma=st.booleans())
def test_contact_table_mutations_are_answered_or_refused_in_one_line(table, comma, tmp_path, capsys):
    a, b = tmp_path / "chain.dump", tmp_path / "contacts.txt"
    a.write_text(CHAIN_DUMP)
    b.write_bytes(table.replace(b" ", b",") if comma else table)
    _check(["audit", str(a), "--contacts", str(b)], capsys, [a, b])


# ---------------------------------------------------------------------------- JSON mutations

NASTY_VALUES = (None, True, False, "x", "", "1.0", -1, 0, -0.0, 1e308, -1e308, 1e-320, 10**400, 2**63, float("nan"),
                float("inf"), float("-inf"), [], {}, [1, 2], [None, None, None], [0.0, 0.0, 0.0, 0.0], [[[[[]]]]],
                {"a": 1}, 1.5, 3)


def _paths(doc, prefix=()):
    """Every path into ``doc`` (dict keys and list indices)."""
    yield prefix
    if isinstance(doc, dict):
        for k, v in doc.items():
            yield from _paths(v, prefix + (k,))
    elif isinstance(doc, list):
        for k, v in enumerate(doc):
            yield from _paths(v, prefix + (k,))


@st.composite
def json_mutation(draw, doc: dict) -> bytes:
    """A mutated copy of ``doc`` as JSON bytes (NaN and Infinity as Python writes them): values
    replaced or deleted, lists emptied or grown, then possibly truncated or given garbage."""
    doc = json.loads(json.dumps(doc))
    paths = [p for p in _paths(doc) if p]
    for _ in range(draw(st.integers(1, 3))):
        path = draw(st.sampled_from(paths))
        parent = doc
        try:
            for key in path[:-1]:
                parent = parent[key]
            kind = draw(st.sampled_from(["value", "value", "value", "delete", "grow"]))
            if kind == "value":
                parent[path[-1]] = copy.deepcopy(draw(st.sampled_from(NASTY_VALUES)))  # never the shared object
            elif kind == "delete":
                del parent[path[-1]]
            elif isinstance(parent, list):
                parent.extend(copy.deepcopy(parent[path[-1]]) for _ in range(draw(st.integers(1, 3))))
        except (KeyError, IndexError, TypeError):
            continue  # an earlier edit removed or replaced the parent
    raw = json.dumps(doc).encode()
    tail = draw(st.sampled_from(["none", "none", "none", "truncate", "garbage"]))
    if tail == "truncate":
        return raw[: draw(st.integers(0, len(raw)))]
    if tail == "garbage":
        at = draw(st.integers(0, len(raw)))
        return raw[:at] + draw(st.sampled_from(GARBAGE)) + raw[at:]
    return raw


@FUZZ
@given(data=json_mutation(json.loads(BODIES.read_text())))
def test_bodies_file_mutations_are_answered_or_refused_in_one_line(data, tmp_path, capsys):
    path = tmp_path / "bodies.json"
    path.write_bytes(b"{" + data[1:] if data[:1] == b"{" else b"{" + data)  # stays a bodies file (first char {)
    _check(["packing", str(path), "--kn", "1e5", "--ks", "8e4", "--certify", "no"], capsys, [path])


@FUZZ
@given(data=json_mutation(YADE_SPHERES))
def test_yade_export_mutations_are_answered_or_refused_in_one_line(data, tmp_path, capsys):
    path = tmp_path / "export.json"
    path.write_bytes(data)
    _check(["audit", str(path)], capsys, [path])


@FUZZ
@given(data=json_mutation(YADE_CLUMP))
def test_yade_clump_mutations_are_answered_or_refused_in_one_line(data, tmp_path, capsys):
    path = tmp_path / "clumps.json"
    path.write_bytes(data)
    _check(["audit", str(path)], capsys, [path])


# ---------------------------------------------------------------------------- valid inputs stay valid

@pytest.mark.parametrize("argv", [
    lambda d: ["packing", str(DUMP), "--kn", "1e5", "--certify", "no"],
    lambda d: ["audit", str(d / "chain.dump"), "--pair-style", PAIR_STYLE, "--local", str(d / "pairs.local")],
    lambda d: ["audit", str(d / "chain.dump"), "--contacts", str(d / "contacts.txt")],
    lambda d: ["packing", str(BODIES), "--kn", "1e5", "--certify", "no"],
    lambda d: ["audit", str(d / "spheres.json")],
    lambda d: ["audit", str(d / "clump.json")],
])
def test_the_unmutated_files_are_answered(argv, tmp_path, capsys):
    """The fuzz above starts from files that are answered (so a refusal is the mutation's doing)."""
    (tmp_path / "chain.dump").write_text(CHAIN_DUMP)
    (tmp_path / "pairs.local").write_text(LOCAL)
    (tmp_path / "contacts.txt").write_text(TABLE)
    (tmp_path / "spheres.json").write_text(json.dumps(YADE_SPHERES))
    (tmp_path / "clump.json").write_text(json.dumps(YADE_CLUMP))
    assert main(argv(tmp_path)) == 0
    assert capsys.readouterr().err == ""


# ---------------------------------------------------------------------------- as a subprocess

@pytest.mark.parametrize("name, content, argv_tail", [
    ("empty.dump", b"", ["--kn", "1"]),
    ("garbage.dump", bytes(range(256)) * 64, ["--kn", "1"]),
    ("huge_count.dump", CHAIN_DUMP.replace("ATOMS\n4\n", "ATOMS\n999999999999\n").encode(), ["--kn", "1"]),
    ("nan.json", json.dumps(json.loads(BODIES.read_text()) | {"box": None}).replace("0.0015", "NaN", 1).encode(),
     ["--kn", "1"]),
    ("deep.json", b"{" + b'"bodies": ' + b"[" * 100000 + b"]" * 100000 + b"}", ["--kn", "1"]),
])
def test_subprocess_refusals_are_one_line_with_status_2(name, content, argv_tail, tmp_path):
    path = tmp_path / name
    path.write_bytes(content)
    start = time.perf_counter()
    run = subprocess.run([sys.executable, "-m", "dtcrit", "packing", str(path), *argv_tail], capture_output=True,
                         text=True, timeout=60, cwd=tmp_path)
    assert time.perf_counter() - start < LIMIT + 5.0  # interpreter start-up on a shared machine
    assert run.returncode == 2 and run.stdout == ""
    match = ONE_LINE.fullmatch(run.stderr)
    assert match and match["file"] == str(path), run.stderr


# ---------------------------------------------------------------------------- messages that leaked library text

def _yade_edit(change):
    doc = json.loads(json.dumps(YADE_SPHERES))
    change(doc)
    return doc


@pytest.mark.parametrize("change, message", [
    (lambda d: d["bodies"][0]["inertia"].__setitem__(1, 0.0), "bodies[0].inertia[1]: must be positive, found 0"),
    (lambda d: d["bodies"][0]["inertia"].__setitem__(1, 1e-320),
     f"bodies[0].inertia: a principal moment of inertia [kg m^2] {1e-320:g} is below the 1e-100 a packing's masses and "
     "moments may reach (every spring is divided by them in double precision)"),
    (lambda d: d["interactions"][1].__setitem__("kr", 1e300),
     "interactions[1]: its springs and dashpots on these masses and moments of inertia give omega^2 beyond "
     "double precision, above the 1e+200 1/s^2 the eigen-solve carries in double precision (a step below 2e-100 s)"),
    (lambda d: d["interactions"][0].__setitem__("id1", [0]), "interactions[0].id1: expected an integer id, found [0]"),
    (lambda d: d["bodies"][1].__setitem__("id", 0), "bodies[1].id: id 0 is already used by bodies[0]"),
    (lambda d: d.__setitem__("dt", "x"), "dt: expected a finite number, found 'x'"),
    (lambda d: d["bodies"][2].__setitem__("pos", [1e101, 0.0, 0.0]),
     "bodies[2].pos: a coordinate 1e+101 m is beyond the 1e+100 m a packing's lengths may reach (they are squared "
     "and multiplied in double precision)"),
])
def test_yade_export_messages_name_the_key_and_the_reason(change, message, tmp_path, capsys):
    """Before: ``np.float64(0.0)``, ``array must not contain infs or NaNs``, ``TypeError: unhashable type``,
    ``ids: expected 4 distinct particle ids``, ``TypeError: must be real number, not str``."""
    path = tmp_path / "export.json"
    path.write_text(json.dumps(_yade_edit(change)))
    assert main(["audit", str(path)]) == 2
    assert capsys.readouterr().err == f"dtcrit: {path}: {message}\n"


def test_contact_table_spring_that_overflows_is_refused_by_its_line(tmp_path, capsys):
    a, b = tmp_path / "chain.dump", tmp_path / "contacts.txt"
    a.write_text(CHAIN_DUMP)
    b.write_text(TABLE.replace("2 3 1e5", "2 3 1e300"))
    assert main(["audit", str(a), "--contacts", str(b)]) == 2
    err = capsys.readouterr().err
    inertia = 0.4 * MASS * R * R  # arms at most the radius R on both spheres: 1e300 (2/m + 2 R^2/I)
    assert err.startswith(f"dtcrit: {b}:3: its springs and dashpots on these masses and moments of inertia give "
                          f"omega^2 ~ {1e300 * (2 / MASS + 2 * R * R / inertia):.3g} 1/s^2, above the 1e+200 1/s^2")
