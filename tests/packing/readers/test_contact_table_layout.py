"""``--contacts`` tables as engines write them (comment and blank lines anywhere, the header among the
comments, columns in any order) and ``--engine yade`` with a dump plus a table (YADE's kinematics).

The YADE step is checked against the independent leapfrog threshold of ``tests/support/rigid_pair.py``
and against the audit of the same state as a YADE export.
"""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from dtcrit import audit_snapshot
from dtcrit.cli import main
from support.rigid_pair import leapfrog_threshold, pair_matrices

R1, R2, RHO = 1e-3, 1e-3, 2600.0
M1, M2 = (4.0 / 3.0 * math.pi * r**3 * RHO for r in (R1, R2))
DELTA = 3e-5
KN, KS, FN = 2e5, 6e4, 2e5 * 3e-5


def _dump(tmp_path):
    rows = [(1, 1, 0.05, 0.05, 0.05, R1, M1), (2, 1, 0.05 + R1 + R2 - DELTA, 0.05, 0.05, R2, M2)]
    lines = ["ITEM: TIMESTEP", "0", "ITEM: NUMBER OF ATOMS", "2", "ITEM: BOX BOUNDS ff ff ff"]
    lines += ["0.0 0.1"] * 3 + ["ITEM: ATOMS id type x y z radius mass"]
    lines += [" ".join(repr(v) if isinstance(v, float) else str(v) for v in row) for row in rows]
    path = tmp_path / "pair.dump"
    path.write_text("\n".join(lines) + "\n")
    return path


PLAIN = f"id1 id2 kn ks fn\n1 2 {KN!r} {KS!r} {FN!r}\n"
COMMENTED = (f"# contacts written by YADE, iteration 0\n# one row per real interaction: 16 words on this line, not "
             f"a header at all\n\n#  fn , ks , id2 , kn , id1\n\n# a comment between rows\n"
             f"{FN!r}, {KS!r}, 2, {KN!r}, 1\n\n")


def _table(tmp_path, text, name="contacts.txt"):
    path = tmp_path / name
    path.write_text(text)
    return path


@pytest.mark.parametrize("engine", ["lammps", "yade"])
def test_comments_blank_lines_and_column_order_do_not_change_the_step(engine, tmp_path):
    dump = _dump(tmp_path)
    plain = audit_snapshot(dump, engine=engine, contact_table=_table(tmp_path, PLAIN, "plain.txt")).dt_crit
    commented = audit_snapshot(dump, engine=engine, contact_table=_table(tmp_path, COMMENTED)).dt_crit
    assert commented == plain


def _inertia(m, r):
    return 0.4 * m * r * r * np.eye(3)


def test_yade_engine_on_a_dump_applies_yade_kinematics(tmp_path):
    """The free pair's step as YADE integrates it: slip with alpha and the full radius, torque at R - delta/2."""
    dump = _dump(tmp_path)
    got = audit_snapshot(dump, engine="yade", contact_table=_table(tmp_path, COMMENTED)).dt_crit
    x2 = [R1 + R2 - DELTA, 0.0, 0.0]
    k, c = pair_matrices([0.0, 0.0, 0.0], x2, R1, R2, kn=KN, ks=KS, fn=FN, ratcheting=True)
    expected = leapfrog_threshold(k, c, [M1, M2], [_inertia(M1, R1), _inertia(M2, R2)])
    assert got == pytest.approx(expected, rel=1e-6)
    lammps = audit_snapshot(dump, engine="lammps", contact_table=_table(tmp_path, COMMENTED)).dt_crit
    assert abs(lammps / got - 1) > 1e-4  # LAMMPS's full-radius arms differ


def test_yade_engine_dump_and_table_match_the_yade_export(tmp_path):
    dump = _dump(tmp_path)
    table = audit_snapshot(dump, engine="yade", contact_table=_table(tmp_path, COMMENTED)).dt_crit
    bodies = [{"id": k + 1, "pos": [0.05 + k * (R1 + R2 - DELTA), 0.05, 0.05], "radius": r, "mass": m,
               "inertia": [0.4 * m * r * r] * 3, "fixed": False} for k, (r, m) in enumerate(((R1, M1), (R2, M2)))]
    inter = [{"id1": 1, "id2": 2, "kn": KN, "ks": KS, "fn": FN, "penetration": DELTA}]
    export = tmp_path / "export.json"
    export.write_text(json.dumps({"schema": "dtcrit-yade-export/1", "bodies": bodies, "interactions": inter}))
    assert table == pytest.approx(audit_snapshot(export).dt_crit, rel=1e-12)


@pytest.mark.parametrize(("text", "expected"), [
    ("# only\n# comments\n", "contacts.txt:1: no header line names the columns id1 id2 kn ks"),
    ("id1 id2 kn ks kn\n1 2 1 1 1\n", "contacts.txt:1: the header names the column kn twice"),
    ("# YADE\nid1 id2 kn ks gamma_n\n1 2 1 1 1\n", "contacts.txt:2: the column gamma_n looks like a contact term"),
    ("# a comment\n\nid1 id2 kn\n1 2 1\n", "contacts.txt:3: the header must name the columns"),
    ("id1 id2 kn ks Cn\n1 2 1 1 1\n", "contacts.txt:1: the column Cn looks like a contact term"),  # any case
    ("id1 id2 kn ks\n1 2 1 1\n\n2 1 1 1\n", "contacts.txt:4: this pair is listed already on line 2"),
])
def test_bad_headers_are_one_line(text, expected, tmp_path, capsys):
    dump = _dump(tmp_path)
    rc = main(["audit", str(dump), "--engine", "yade", "--contacts", str(_table(tmp_path, text))])
    out, err = capsys.readouterr()
    assert rc == 2 and out == "" and len(err.splitlines()) == 1 and expected in err, err


def test_yade_engine_with_a_dump_needs_a_table(tmp_path, capsys):
    dump = _dump(tmp_path)
    for extra in (["--pair-style", "gran/hooke/history 1e4 NULL 0 NULL 0.5 0"], []):
        rc = main(["audit", str(dump), "--engine", "yade", *extra])
        out, err = capsys.readouterr()
        assert rc == 2 and "--contacts" in err and len(err.splitlines()) == 1, err
