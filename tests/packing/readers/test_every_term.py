"""Every field the YADE exporter writes and every pair-style keyword the parsers know is either modelled
(the step changes as an independent computation says) or refused in one line naming it, exit 2.

The exporter's fields are read from its own source (the dictionaries ``snapshot``, ``_body`` and
``_interaction`` return), so a field added there without a decision in
``dtcrit.packing.readers.yade_terms`` fails here.  The independent step is the leapfrog threshold of
two rigid bodies with YADE's kinematics (``tests/support/rigid_pair.py``).
"""
from __future__ import annotations

import ast
import copy
import json
import math

import numpy as np
import pytest

from dtcrit import audit_snapshot
from dtcrit.cli import main
from dtcrit.errors import InputError
from dtcrit.numerics.rotations import unit_body_to_world_matrix
from dtcrit.packing.conventions import granular_style as gs
from dtcrit.packing.conventions.pair_styles import GRAN_TERMS, parse_pair_style
from dtcrit.packing.readers import yade_terms as yt
from support.paths import SRC
from support.rigid_pair import leapfrog_threshold, pair_matrices

EXPORTER = SRC / "dtcrit" / "engine_scripts" / "yade_export.py"
R, RHO = 1e-3, 2600.0
MASS = 4.0 / 3.0 * math.pi * R**3 * RHO
INERTIA = 0.4 * MASS * R**2
DELTA = 2e-5


def _returned_keys(function: str) -> set[str]:
    tree = ast.parse(EXPORTER.read_text())
    node = next(n for n in ast.walk(tree) if isinstance(n, ast.FunctionDef) and n.name == function)
    found = [r.value for r in ast.walk(node) if isinstance(r, ast.Return) and isinstance(r.value, ast.Dict)]
    return {k.value for d in found for k in d.keys if isinstance(k, ast.Constant)}


@pytest.mark.parametrize(("function", "table"), [("snapshot", yt.TOP), ("_body", yt.BODY),
                                                 ("_interaction", yt.INTERACTION)])
def test_every_exported_field_has_a_decision(function, table):
    assert _returned_keys(function) == set(table)


def _export(**top) -> dict:
    """A free sphere (id 0) on a fixed one (id 1) along x, one FrictPhys contact, no ratcheting."""
    bodies = [{"id": 0, "pos": [0.0, 0.0, 0.0], "radius": R, "mass": MASS, "inertia": [INERTIA] * 3,
               "clump_id": None, "is_clump": False, "fixed": False, "ori": [1.0, 0.0, 0.0, 0.0],
               "blocked_dofs": "", "is_damped": True},
              {"id": 1, "pos": [2 * R - DELTA, 0.0, 0.0], "radius": R, "mass": MASS, "inertia": [INERTIA] * 3,
               "clump_id": None, "is_clump": False, "fixed": True, "ori": [1.0, 0.0, 0.0, 0.0],
               "blocked_dofs": "xyzXYZ", "is_damped": True}]
    inter = {"id1": 0, "id2": 1, "kn": 1e5, "ks": 3e4, "kr": None, "ktw": None, "cn": None, "cs": None,
             "normal": [1.0, 0.0, 0.0], "point": [R - DELTA / 2, 0.0, 0.0], "penetration": DELTA,
             "radius1": R, "radius2": R, "bonded": False, "shift2": [0.0, 0.0, 0.0], "geom": "ScGeom",
             "phys": "FrictPhys", "fn": 1e5 * DELTA}
    doc = {"schema": "dtcrit-yade-export/1", "yade_version": "2023.02a", "dt": 1e-7, "iter": 10,
           "newton_damping": None, "periodic": False, "cell_hsize": None, "cell_vel_grad": None,
           "cell_next_vel_grad": None, "density_scaling": False, "exact_aspherical_rot": True,
           "laws": [{"class": "Law2_ScGeom_FrictPhys_CundallStrack", "sphericalBodies": True}],
           "avoid_granular_ratcheting": False, "bodies": bodies, "interactions": [inter]}
    doc.update(top)
    return doc


def _independent(doc: dict) -> float:
    """The leapfrog threshold of the export's two bodies (``tests/support/rigid_pair.py``)."""
    spheres = {b["id"]: b for b in doc["bodies"] if not b["is_clump"]}
    rigid = {b["id"]: b for b in doc["bodies"] if b["is_clump"]}
    it = doc["interactions"][0]
    s1, s2 = spheres[it["id1"]], spheres[it["id2"]]
    b1, b2 = (rigid.get(s["clump_id"], s) for s in (s1, s2))
    x2 = np.add(s2["pos"], it["shift2"])
    fn = it["fn"] if it["fn"] is not None else it["kn"] * it["penetration"]
    k, c = pair_matrices(s1["pos"], x2, s1["radius"], s2["radius"], kn=it["kn"], ks=it["ks"], kr=it["kr"] or 0.0,
                         ktw=it["ktw"] or 0.0, cn=it["cn"] or 0.0, cs=it["cs"] or 0.0, fn=fn,
                         ratcheting=doc["avoid_granular_ratcheting"] is not False)
    inertias = []
    for b in (b1, b2):
        w, x, y, z = np.asarray(b["ori"], float) / np.linalg.norm(b["ori"])
        rot = unit_body_to_world_matrix(np.array([w, x, y, z]))
        inertias.append(rot @ np.diag(b["inertia"]) @ rot.T)
    free = (not b1["fixed"], not b2["fixed"])
    return leapfrog_threshold(k, c, [b1["mass"], b2["mass"]], inertias, free)


def _dtcrit(doc: dict, tmp_path) -> float:
    path = tmp_path / "export.json"
    path.write_text(json.dumps(doc))
    return audit_snapshot(path).dt_crit


def _body(doc, k, **values):
    doc["bodies"][k].update(values)
    return doc


def _inter(doc, **values):
    doc["interactions"][0].update(values)
    return doc


def _one_clump(doc):
    """Body 0 made the only member of clump 7, centred on it, heavier and anisotropic, rotated."""
    half = math.sqrt(0.5)
    doc["bodies"].append({"id": 7, "pos": [0.0, 0.0, 0.0], "radius": None, "mass": 2 * MASS,
                          "inertia": [INERTIA, 2 * INERTIA, 3 * INERTIA], "clump_id": None, "is_clump": True,
                          "fixed": False, "ori": [half, 0.0, 0.0, half], "blocked_dofs": "", "is_damped": True})
    doc["bodies"][0]["clump_id"] = 7
    doc["interactions"][0]["fn"] = 0.0  # contacts of clumps carry no pre-load (yade_clumps)
    return doc


def _across_the_cell(doc):
    """The contact across the boundary of a periodic cell of side 0.5 m: body 1 one cell to the left."""
    doc.update(periodic=True, cell_hsize=[[0.5, 0, 0], [0, 0.5, 0], [0, 0, 0.5]], cell_vel_grad=[[0.0] * 3] * 3,
               cell_next_vel_grad=[[0.0] * 3] * 3)
    doc["bodies"][0]["pos"] = [0.25, 0.25, 0.25]
    doc["bodies"][1]["pos"] = [0.25 + 2 * R - DELTA - 0.5, 0.25, 0.25]
    doc["interactions"][0]["shift2"] = [0.5, 0.0, 0.0]


#: a change of each modelled field, applied to the base export (its step is then computed independently)
MODELLED = {
    "top": {
        "avoid_granular_ratcheting": lambda d: d.update(avoid_granular_ratcheting=True),
        "periodic": lambda d: _across_the_cell(d),
    },
    "body": {
        "pos": lambda d: _body(d, 0, pos=[-DELTA / 2, 0.0, 0.0]),
        "radius": lambda d: _body(d, 0, radius=1.2 * R),
        "mass": lambda d: _body(d, 0, mass=0.3 * MASS),
        "inertia": lambda d: _body(d, 0, inertia=[0.1 * INERTIA] * 3),
        "fixed": lambda d: (_body(d, 1, fixed=False, blocked_dofs=""), _inter(d, fn=0.0)),
        "clump_id": _one_clump,
        "is_clump": _one_clump,
        "ori": _one_clump,
    },
    "interaction": {
        "kn": lambda d: _inter(d, kn=7e5, fn=7e5 * DELTA),
        "ks": lambda d: _inter(d, ks=2e5),
        "kr": lambda d: _inter(d, kr=3e4 * R * R),
        "ktw": lambda d: _inter(d, ktw=2e5 * R * R),
        "cn": lambda d: _inter(d, cn=0.5 * math.sqrt(1e5 * MASS)),
        "cs": lambda d: _inter(d, cs=0.5 * math.sqrt(3e4 * MASS)),
        "fn": lambda d: _inter(d, fn=40.0),
        "penetration": lambda d: _inter(d, fn=None, penetration=4e-4),
        "shift2": lambda d: _across_the_cell(d),
        "id1": lambda d: _inter(d, id1=1, id2=0),
        "id2": lambda d: _inter(d, id1=1, id2=0),
    },
}

#: a change of each derived or recorded field: the step must not move
UNCHANGED = {
    "top": {"yade_version": "2099.01", "dt": 3e-5, "iter": 99, "wall_no_ratch": False},  # no wall here
    "body": {"id": None, "shape": None, "axis": None, "sense": None, "vertices": None},  # walls: test_audit_walls
    "interaction": {"normal": [0.0, 1.0, 0.0], "point": [5.0, 5.0, 5.0], "radius1": 9.0, "radius2": 9.0,
                    "bonded": True},
}


@pytest.mark.parametrize(("level", "key"), [(lv, k) for lv, keys in MODELLED.items() for k in keys])
def test_modelled_field_changes_the_step_as_yade_does(level, key, tmp_path):
    doc = _export()
    base = _dtcrit(copy.deepcopy(doc), tmp_path)
    MODELLED[level][key](doc)
    expected = _independent(doc)
    assert _dtcrit(doc, tmp_path) == pytest.approx(expected, rel=2e-6)
    if key not in ("id1", "id2", "shift2", "periodic"):  # these move the contact, not its step
        assert abs(expected / base - 1) > 1e-3, f"{key}: the change should move the step"


@pytest.mark.parametrize(("level", "key"), [(lv, k) for lv, keys in UNCHANGED.items() for k in keys])
def test_derived_and_recorded_fields_leave_the_step(level, key, tmp_path):
    doc = _export()
    base = _dtcrit(copy.deepcopy(doc), tmp_path)
    value = UNCHANGED[level][key]
    if level == "top":
        doc[key] = value
    elif level == "body":  # renumber the free body
        doc["bodies"][0]["id"] = 42
        doc["interactions"][0]["id1"] = 42
    else:
        doc["interactions"][0][key] = value
    assert _dtcrit(doc, tmp_path) == pytest.approx(base, rel=1e-12)


def test_every_field_is_covered_by_a_test():
    covered = {"top": set(MODELLED["top"]) | set(UNCHANGED["top"]) | set(REFUSED["top"]),
               "body": set(MODELLED["body"]) | set(UNCHANGED["body"]) | set(REFUSED["body"]),
               "interaction": set(MODELLED["interaction"]) | set(UNCHANGED["interaction"]) | set(REFUSED["interaction"])}
    # structural keys: the format's name, the lists, the cell (owned by the sheared-cell reader), local damping
    covered["top"] |= {"schema", "bodies", "interactions", "cell_hsize", "newton_damping"}
    assert covered == {"top": set(yt.TOP), "body": set(yt.BODY), "interaction": set(yt.INTERACTION)}
    for table in (yt.TOP, yt.BODY, yt.INTERACTION):
        for key, (kind, _) in table.items():
            assert (kind == yt.REFUSED) == (key in REFUSED["top"] | REFUSED["body"] | REFUSED["interaction"]), key


#: for each refused field, a value that changes YADE's dynamics and the word the one-line refusal names
REFUSED = {
    "top": {
        "cell_vel_grad": (lambda d: d.update(cell_vel_grad=[[0, 1.0, 0], [0, 0, 0], [0, 0, 0]]), "cell_vel_grad"),
        "cell_next_vel_grad": (lambda d: d.update(cell_next_vel_grad=[[1.0, 0, 0], [0, 0, 0], [0, 0, 0]]),
                               "cell_vel_grad"),
        "density_scaling": (lambda d: d.update(density_scaling=True), "density_scaling"),
        "exact_aspherical_rot": (lambda d: (d.update(exact_aspherical_rot=False),
                                            _body(d, 0, inertia=[INERTIA, 2 * INERTIA, INERTIA])),
                                 "exact_aspherical_rot"),
        "laws": (lambda d: d["laws"].append({"class": "Law2_ScGeom_MindlinPhys_Mindlin"}),
                 "Law2_ScGeom_MindlinPhys_Mindlin"),
    },
    "body": {
        "blocked_dofs": (lambda d: _body(d, 0, blocked_dofs="xZ"), "blocked_dofs"),
        "is_damped": (lambda d: (d.update(newton_damping=0.2), _body(d, 0, is_damped=False)), "is_damped"),
    },
    "interaction": {
        "phys": (lambda d: _inter(d, phys="ViscElPhys"), "ViscElPhys"),
        "geom": (lambda d: _inter(d, geom="L3Geom"), "L3Geom"),
    },
}

MORE_REFUSALS = [
    (lambda d: d["laws"].append({"class": "Law2_ScGeom6D_CohFrictPhys_CohesionMoment", "shear_creep": True}),
     "shear_creep"),
    (lambda d: d["laws"].append({"class": "Law2_ScGeom6D_CohFrictPhys_CohesionMoment", "twist_creep": True}),
     "twist_creep"),
    (lambda d: _inter(d, phys="MindlinPhys"), "MindlinPhys"),
    (lambda d: _inter(d, shift2=[0.5, 0.0, 0.0]), "shift2"),  # an image shift without a periodic cell
]


def _refused(doc, tmp_path, capsys) -> str:
    path = tmp_path / "export.json"
    path.write_text(json.dumps(doc))
    rc = main(["audit", str(path)])
    out, err = capsys.readouterr()
    assert rc == 2 and out == "" and len(err.splitlines()) == 1, err
    return err


@pytest.mark.parametrize("case", [v for keys in REFUSED.values() for v in keys.values()] + MORE_REFUSALS)
def test_refused_field_is_one_line_naming_it(case, tmp_path, capsys):
    change, word = case
    doc = _export()
    change(doc)
    assert word in _refused(doc, tmp_path, capsys)


def test_refused_fields_at_their_default_are_accepted(tmp_path):
    """The same fields at YADE's defaults (and local damping, modelled elsewhere) pass; so does a cell
    moving at 0.01/s, 2e-7 per critical step."""
    doc = _export(newton_damping=0.2, cell_vel_grad=[[0.01, 0, 0], [0, 0, 0], [0, 0, 0]], laws=[{"class": "Law2_ScGeom6D_CohFrictPhys_CohesionMoment",
                                             "shear_creep": False, "twist_creep": False}])
    _body(doc, 1, blocked_dofs="xZ")  # a fixed body's blocked DOFs do not matter
    _inter(doc, phys="CohFrictPhys", geom="ScGeom6D")
    path = tmp_path / "export.json"
    path.write_text(json.dumps(doc))
    audit_snapshot(path)  # no InputError


# ---- LAMMPS pair styles ------------------------------------------------------------------------------


def _granular_keywords() -> set[str]:
    """The keywords ``parse_granular`` branches on (``key == "..."``), read from its source."""
    tree = ast.parse((SRC / "dtcrit" / "packing" / "conventions" / "granular_style.py").read_text())
    node = next(n for n in ast.walk(tree) if isinstance(n, ast.FunctionDef) and n.name == "parse_granular")
    return {c.comparators[0].value for c in ast.walk(node) if isinstance(c, ast.Compare)
            and isinstance(c.left, ast.Name) and c.left.id == "key" and isinstance(c.comparators[0], ast.Constant)}


def test_every_granular_keyword_has_a_decision():
    decided = {key.split()[0] for key in gs.GRANULAR_TERMS}
    assert _granular_keywords() | {"normal"} == decided
    for table, word in ((gs.NORMAL_ARGS, "normal"), (gs.TANGENTIAL_ARGS, "tangential"), (gs.DAMPING, "damping")):
        assert {f"{word} {name}" for name in table} <= set(gs.GRANULAR_TERMS)


GRANULAR_LINES = {
    "normal hooke": "granular hooke 1e4 0.5 tangential linear_history 1e4 1 0.5",
    "normal hertz": "granular hertz 1e9 0.5 tangential linear_history 1e4 1 0.5",
    "normal hertz/material": "granular hertz/material 1e8 0.5 0.3 tangential mindlin NULL 1 0.5",
    "normal dmt": "granular dmt 1e8 0.5 0.3 0.1 tangential mindlin NULL 1 0.5",
    "normal jkr": "granular jkr 1e8 0.5 0.3 0.1 tangential mindlin NULL 1 0.5",
    "damping coeff_restitution": "granular hooke 1e4 0.5 tangential linear_history 1e4 1 0.5 damping coeff_restitution",
    "tangential mindlin/force": "granular hertz/material 1e8 0.5 0.3 tangential mindlin/force NULL 1 0.5",
    "tangential mindlin_rescale/force": "granular hertz/material 1e8 0.5 0.3 tangential mindlin_rescale/force NULL 1 0.5",
    "heat area": "granular hooke 1e4 0.5 tangential linear_history 1e4 1 0.5 heat area 1.0",
    "heat radius": "granular hooke 1e4 0.5 tangential linear_history 1e4 1 0.5 heat radius 1.0",
    "limit_damping": "granular hooke 1e4 0.5 tangential linear_history 1e4 1 0.5 limit_damping",
}


def _granular_line(key: str) -> str:
    if key in GRANULAR_LINES:
        return GRANULAR_LINES[key]
    word, name = key.split()
    base = "granular hertz/material 1e8 0.5 0.3 tangential mindlin NULL 1 0.5"
    if word == "tangential":
        return f"granular hertz/material 1e8 0.5 0.3 tangential {name}{' 1e4' if name != 'linear_nohistory' else ''} 1 0.5"
    tail = {"damping": name, "rolling": f"{name} 1e3 10 0.1" if name == "sds" else name,
            "twisting": f"{name} 1e3 10 0.1" if name == "sds" else name, "heat": name}[word]
    return f"{base} {word} {tail}"


@pytest.mark.parametrize("key", sorted(gs.GRANULAR_TERMS))
def test_granular_keyword_is_modelled_or_refused_naming_it(key):
    line = _granular_line(key)
    if gs.GRANULAR_TERMS[key].startswith("refused"):
        with pytest.raises(InputError) as info:
            parse_pair_style(line)
        assert key.split()[-1] in str(info.value)
    else:
        style = parse_pair_style(line)
        assert style.describe().endswith(line.split(" ", 1)[1])


def test_limit_damping_without_a_dashpot_is_a_no_op():
    line = "granular hooke 1e4 0 tangential linear_history 1e4 1 0.5"
    assert parse_pair_style(line + " limit_damping") == parse_pair_style(line).__class__(
        **{**parse_pair_style(line).__dict__, "text": " ".join((line + " limit_damping").split()[1:])})
    gran = "gran/hooke/history 1e4 NULL 0 NULL 0.5 0"
    assert parse_pair_style(gran + " limit_damping").kn == parse_pair_style(gran).kn


def _gran_terms(style: str):
    """The terms of ``style`` on one pair of spheres (masses 1 and 3, radii 1e-3 and 2e-3, overlap 1e-5)."""
    from dtcrit.packing.conventions.engines import overlaps_of_pairs
    from dtcrit.packing.model import Packing

    packing = Packing(np.array([[0.0, 0, 0], [3e-3 - 1e-5, 0, 0]]), np.array([1.0, 3.0]), np.ones((2, 3)),
                      np.array([1e-3, 2e-3]))
    contacts = overlaps_of_pairs(packing, np.array([0]), np.array([1]))
    return parse_pair_style(style).terms(packing, contacts)


#: for each gran/* argument, a style changing it and the terms LAMMPS's pair_gran docs give (m_eff 3/4)
GRAN_CASES = {
    "Kn": ("gran/hooke/history 2e4 NULL 0 NULL 0.5 0", {"kn": 2e4, "ks": 2.0 / 7.0 * 2e4}),
    "Kt": ("gran/hooke/history 2e4 5e3 0 NULL 0.5 0", {"ks": 5e3}),
    "gamma_n": ("gran/hooke/history 2e4 5e3 10 NULL 0.5 1", {"cn": 0.75 * 10, "cs": 0.75 * 5}),
    "gamma_t": ("gran/hooke/history 2e4 5e3 10 4 0.5 1", {"cs": 0.75 * 4}),
    "xmu": ("gran/hooke/history 2e4 5e3 10 4 0 1", {"ks": 0.0, "cs": 0.0}),
    "dampflag": ("gran/hooke/history 2e4 5e3 10 4 0.5 0", {"cs": 0.0}),
}


@pytest.mark.parametrize("key", sorted(GRAN_TERMS))
def test_gran_argument_is_modelled_or_refused_naming_it(key):
    if GRAN_TERMS[key].startswith("refused"):
        with pytest.raises(InputError) as info:
            parse_pair_style("gran/hooke/history 2e4 NULL 10 NULL 0.5 1 limit_damping")
        assert key in str(info.value)
        return
    style, expected = GRAN_CASES[key]
    terms = _gran_terms(style)
    for name, value in expected.items():
        assert float(getattr(terms, name)[0]) == pytest.approx(value, rel=1e-12), (key, name)


# ---- the docs' list ------------------------------------------------------------------------------------


def refusals_block() -> str:
    """The docs' list of refused inputs (``docs/explanation/audit_conventions.md``), generated from the decision tables."""
    lines = ["YADE exports (`src/dtcrit/packing/readers/yade_terms.py`):", ""]
    lines += [f"* `{key}`: {text}" for key, text in (line.split(": ", 1) for line in yt.refusal_lines())]
    lines += ["", "LAMMPS `pair_style gran/*` (`src/dtcrit/packing/conventions/pair_styles.py`):", ""]
    lines += [f"* `{key}`: {text}" for key, text in GRAN_TERMS.items() if text.startswith("refused")]
    lines += ["", "LAMMPS `pair_style granular` (`src/dtcrit/packing/conventions/granular_style.py`):", ""]
    lines += [f"* `{key}`: {text}" for key, text in gs.GRANULAR_TERMS.items() if text.startswith("refused")]
    return "\n".join(lines)


def test_the_docs_list_every_refusal():
    text = (SRC.parent / "docs" / "explanation" / "audit_conventions.md").read_text()
    block = text.split("<!-- refusals:start -->\n", 1)[1].split("\n<!-- refusals:end -->", 1)[0]
    assert block == refusals_block(), "regenerate the docs' block with refusals_block():\n" + refusals_block()
