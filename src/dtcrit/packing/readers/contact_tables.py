"""Contact lists from files: ``--contacts TABLE`` (any engine) and ``--local DUMP`` (LAMMPS's own).

**Contact table.**  A text table, whitespace- or comma-separated.  Blank lines and comment lines
(``#``) may stand anywhere; the header is the first line naming the required columns, with or
without a leading ``#`` (a ``#`` line before it that does not name them is a comment), or else the
first line that is not a comment.  Columns in any order, each named once.  Required: ``id1 id2 kn ks``
(springs in N/m); optional: ``cn cs`` (dashpots, N s/m), ``kr ktw`` (rolling and twisting springs,
N m/rad), ``cr ctw`` (rolling and twisting dashpots, N m s/rad), ``fn`` (the compressive normal force
in N, for the pre-load's geometric stiffness).  Other columns (positions, normals, ...) carry no
term and are not read; a column named like a term (``kt``, ``gamma_n``, ... :data:`SYNONYMS`) is
refused, naming it, rather than dropped.  Ids are those of the atom dump.  :func:`table_contacts` gives the contacts an
engine's kinematics (``--engine yade``: YADE's, ``dtcrit.packing.conventions.engines.with_arms``).

**LAMMPS local dump** of the engine's own contact list, e.g.::

    compute pairs all property/local patom1 patom2 cutoff radius
    dump cl all local 1000 contacts.local c_pairs[1] c_pairs[2]

The two id columns are the ones whose header names contain ``patom1``/``patom2`` (or ``id1``/``id2``),
else the first two columns.  The last snapshot is used.  Pairs that do not overlap in the atom dump
carry no force in LAMMPS and are dropped.

Every malformed line raises ``InputError`` keyed ``FILE:LINE``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from dtcrit.errors import InputError
from dtcrit.inputs.files import located_in, text_lines
from dtcrit.packing.model import Packing
from dtcrit.packing.periodic_cell import nearest_image
from dtcrit.packing.readers.limits import check_rates, contact_rates

REQUIRED = ("id1", "id2", "kn", "ks")
OPTIONAL = ("cn", "cs", "kr", "ktw", "cr", "ctw", "fn")
#: other names engines give these terms: refused (naming the column) rather than read as "no term"
SYNONYMS = {"k_n": "kn", "k_s": "ks", "kt": "ks", "k_t": "ks", "c_n": "cn", "c_s": "cs", "ct": "cs", "c_t": "cs",
            "gamman": "cn", "gamma_n": "cn", "gammat": "cs", "gamma_t": "cs", "k_r": "kr", "k_tw": "ktw",
            "c_r": "cr", "c_tw": "ctw", "f_n": "fn", "normalforce": "fn"}


@dataclass(frozen=True)
class ContactTable:
    """The contacts of a ``--contacts`` table.

    Parameters
    ----------
    i, j : numpy.ndarray
        The pairs as particle indices of the packing.
    values : dict of str to numpy.ndarray
        The per-contact columns given, by name (``kn``, ``ks`` [N/m]; ``cn``, ``cs`` [N s/m];
        ``kr``, ``ktw`` [N m/rad]; ``fn`` [N]).
    """

    i: np.ndarray
    j: np.ndarray
    values: dict[str, np.ndarray]


def _in_range(path: Path, packing: Packing, ij: np.ndarray, values: dict, lines: list[int]) -> None:
    """Refuse a row whose springs and dashpots overflow the mass-scaled matrices (``reader_limits``;
    arms at most the radii).
    """
    zero = np.zeros(len(ij))
    arm_i = np.zeros((len(ij), 3))
    arm_j = np.zeros((len(ij), 3))
    arm_i[:, 0], arm_j[:, 0] = packing.radii[ij[:, 0]], packing.radii[ij[:, 1]]
    with np.errstate(over="ignore"):  # an overflowing F/r is refused below
        preload = values.get("fn", zero) / (packing.radii[ij[:, 0]] + packing.radii[ij[:, 1]])
    rate = contact_rates(packing.masses, packing.inertia, ij[:, 0], ij[:, 1], arm_i, arm_j,
                         np.maximum(np.maximum(values["kn"], values["ks"]), preload),  # pre-load: F/r
                         np.maximum(values.get("kr", zero), values.get("ktw", zero)),
                         np.maximum(values.get("cn", zero), values.get("cs", zero)))
    check_rates(rate, lambda c: f"{path}:{lines[c]}")


def _apart(path: Path, packing: Packing, ij: np.ndarray, lines: list[int]) -> None:
    """Refuse a listed pair whose centres coincide in the atom dump (nearest periodic image; |sep| = 0 in
    double precision): no normal.
    """
    sep = packing.positions[ij[:, 1]] - packing.positions[ij[:, 0]]
    box = packing.box
    if box is not None:
        sep = sep + box.shift(nearest_image(box, sep))
    with np.errstate(under="ignore"):
        same = ~(np.linalg.norm(sep, axis=1) > 0)  # as the contact normal sep/|sep| needs it
    if same.any():
        k = int(np.argmax(same))
        a, b = (packing.particle_id(v) for v in ij[k])
        raise InputError(f"{path}:{lines[k]}", f"particles {a} and {b} have coincident centres in the atom dump "
                                               "(closer than double precision resolves): no contact normal")


def _split(line: str) -> list[str]:
    return line.replace(",", " ").split()


def _index_map(packing: Packing):
    ids = packing.ids if packing.ids is not None else np.arange(1, packing.n + 1)
    return {int(v): k for k, v in enumerate(ids)}


def _pair_indices(where: str, a: float, b: float, lookup) -> tuple[int, int]:
    out = []
    for value in (a, b):
        if not math.isfinite(value) or value != math.floor(value) or int(value) not in lookup:
            raise InputError(where, f"particle id {value:g} is not in the atom dump")
        out.append(lookup[int(value)])
    if out[0] == out[1]:
        raise InputError(where, f"a particle cannot touch itself (id {a:g})")
    return out[0], out[1]


def read_contact_table(path, packing: Packing) -> ContactTable:
    """Read a ``--contacts`` table of per-contact springs and dashpots (module docstring).

    Parameters
    ----------
    path : str or pathlib.Path
        The table.
    packing : Packing
        The atom dump's packing, whose ids the table's ``id1``/``id2`` name.

    Returns
    -------
    ContactTable
        The pairs as particle indices and the columns given; errors are located at their line
        (``InputError.location``: source and line).
    """
    with located_in(path):
        return _read_contact_table(Path(path), packing)


def _header(path: Path, lines: list[str]) -> tuple[int, list[str]]:
    """The header's line index and column names (module docstring)."""
    first = None
    for n, line in enumerate(lines):
        text = line.strip()
        if not text:
            continue
        names = _split(text.lstrip("#"))
        if all(c in names for c in REQUIRED) or not text.startswith("#"):
            first = n
            break
    if first is None:
        raise InputError(f"{path}:1", "the contact table is empty" if not any(ln.strip() for ln in lines) else
                         f"no header line names the columns {' '.join(REQUIRED)} (only comments)")
    header = _split(lines[first].strip().lstrip("#"))
    missing = [c for c in REQUIRED if c not in header]
    if missing:
        raise InputError(f"{path}:{first + 1}", f"the header must name the columns {' '.join(REQUIRED)} "
                                                f"(missing {' '.join(missing)})")
    known = REQUIRED + OPTIONAL
    other = [c for c in header if (c.lower() in SYNONYMS or c.lower() in known) and c not in known]
    if other:  # a term under another name or case (Cn, KT): refused, never dropped
        name = SYNONYMS.get(other[0].lower(), other[0].lower())
        raise InputError(f"{path}:{first + 1}", f"the column {other[0]} looks like a contact term, which this table "
                                                f"would not read: name it {name} (N/m, N s/m, "
                                                "N m/rad, N m s/rad, N) or drop it")
    twice = sorted({c for c in header if header.count(c) > 1})
    if twice:
        raise InputError(f"{path}:{first + 1}", f"the header names the column {twice[0]} twice")
    return first, header


def _read_contact_table(path: Path, packing: Packing) -> ContactTable:
    lines = text_lines(path)
    k, header = _header(path, lines)
    used = [c for c in REQUIRED + OPTIONAL if c in header]
    col = {c: header.index(c) for c in used}
    lookup = _index_map(packing)
    pairs, rows, numbers = [], [], []
    for n in range(k + 1, len(lines)):
        parts = _split(lines[n])
        if not parts or parts[0].startswith("#"):
            continue  # blank and comment lines may stand anywhere
        where = f"{path}:{n + 1}"
        if len(parts) != len(header):
            raise InputError(where, f"expected {len(header)} columns ({' '.join(header)}), found {len(parts)}")
        try:
            vals = {c: float(parts[col[c]]) + 0.0 for c in used}  # -0.0 is 0
        except ValueError:
            raise InputError(where, "a value is not a number") from None
        for c, v in vals.items():
            if not math.isfinite(v) or (c not in ("id1", "id2") and v < 0):
                raise InputError(where, f"{c} must be a finite number >= 0, found {parts[col[c]]}")
        pairs.append(_pair_indices(where, vals["id1"], vals["id2"], lookup))
        rows.append([vals[c] for c in used[2:]])
        numbers.append(n + 1)
    if not pairs:
        raise InputError(f"{path}:{k + 1}", "the contact table has a header but no contacts")
    seen: dict[tuple[int, int], int] = {}
    for (i, j), line in zip(pairs, numbers):  # a contact listed twice would count its springs twice
        key = (min(i, j), max(i, j))
        if key in seen:
            raise InputError(f"{path}:{line}", f"this pair is listed already on line {seen[key]}: each contact "
                                               "goes on one line")
        seen[key] = line
    ij = np.array(pairs, dtype=np.int64)
    _apart(path, packing, ij, numbers)
    data = np.array(rows, dtype=float).reshape(len(pairs), len(used) - 2)
    _in_range(path, packing, ij, {c: data[:, m] for m, c in enumerate(used[2:])}, numbers)
    return ContactTable(ij[:, 0], ij[:, 1], {c: data[:, m] for m, c in enumerate(used[2:])})


def table_contacts(packing: Packing, table: ContactTable, arm: str):
    """The contacts of a read table with an engine's kinematics, springs, dashpots and pre-load.

    The stiffness is set before the arms, since YADE's kinematics (``arm="yade"``) scale ``ks`` by
    ``alpha = (R_1 + R_2)/(R_1 + R_2 - delta)`` (``dtcrit.packing.conventions.engines.with_arms``); without
    an ``fn`` column the pre-load is ``kn`` times the overlap (the linear law).

    Parameters
    ----------
    packing : Packing
        The atom dump's packing.
    table : ContactTable
        The table (:func:`read_contact_table`).
    arm : str
        The engine's arm convention (``EngineConvention.arm``: ``radius``, ``yade``, ...).

    Returns
    -------
    Contacts
        One contact per row with the engine's arms and every term the table gives.
    """
    from dtcrit.packing.conventions.engines import overlaps_of_pairs, with_arms

    v = table.values
    contacts = overlaps_of_pairs(packing, table.i, table.j)
    contacts = contacts.with_stiffness(v["kn"], v["ks"], v.get("kr"), v.get("ktw"))
    contacts = with_arms(packing, contacts, arm)
    contacts = contacts.with_damping(v.get("cn", 0.0), v.get("cs", 0.0), v.get("cr"), v.get("ctw"))
    return contacts.with_normal_force(v.get("fn", v["kn"] * contacts.overlap))


def _id_columns(names: list[str]) -> tuple[int, int]:
    for a, b in (("patom1", "patom2"), ("id1", "id2")):
        hit_a = [m for m, name in enumerate(names) if a in name]
        hit_b = [m for m, name in enumerate(names) if b in name]
        if hit_a and hit_b:
            return hit_a[0], hit_b[0]
    return 0, 1


def read_local_dump(path, packing: Packing) -> tuple[np.ndarray, np.ndarray]:
    """Read the contact pairs of the last snapshot of a LAMMPS ``dump local`` (module docstring).

    Parameters
    ----------
    path : str or pathlib.Path
        The local dump.
    packing : Packing
        The atom dump's packing, whose ids the entries name.

    Returns
    -------
    tuple of numpy.ndarray
        ``(i, j)``: the pairs as particle indices, ``i < j``, each pair once.
    """
    with located_in(path):
        return _read_local_dump(Path(path), packing)


def _read_local_dump(path: Path, packing: Packing) -> tuple[np.ndarray, np.ndarray]:
    lines = text_lines(path)
    starts = [n for n, ln in enumerate(lines) if ln.startswith("ITEM: NUMBER OF ENTRIES")]
    if not starts:
        raise InputError(f"{path}:1", "not a LAMMPS local dump (no 'ITEM: NUMBER OF ENTRIES')")
    s = starts[-1]
    try:
        count = int(lines[s + 1])
    except (IndexError, ValueError):
        raise InputError(f"{path}:{s + 2}", "expected the number of entries") from None
    head = next((n for n in range(s + 2, min(s + 8, len(lines))) if lines[n].startswith("ITEM: ENTRIES")), None)
    if head is None:
        raise InputError(f"{path}:{s + 3}", "expected 'ITEM: ENTRIES ...' after the box bounds")
    names = lines[head].split()[2:]
    if len(names) < 2:
        raise InputError(f"{path}:{head + 1}", "the entries need at least two columns (the two atom ids)")
    c1, c2 = _id_columns(names)
    lookup = _index_map(packing)
    if count < 0:
        raise InputError(f"{path}:{s + 2}", f"the number of entries must be >= 0, found {count}")
    pairs = []
    for n in range(head + 1, head + 1 + count):
        where = f"{path}:{n + 1}"
        if n >= len(lines):
            raise InputError(where, f"the file ends after {n - head - 1} of {count} entries (truncated)")
        parts = lines[n].split()
        if len(parts) != len(names):
            raise InputError(where, f"expected {len(names)} values, found {len(parts)}")
        try:
            a, b = float(parts[c1]), float(parts[c2])
        except ValueError:
            raise InputError(where, "an atom id is not a number") from None
        pairs.append(_pair_indices(where, a, b, lookup))
    if not pairs:
        raise InputError(f"{path}:{s + 2}", "the local dump lists no contacts")
    ij = np.array(pairs, dtype=np.int64)
    _apart(path, packing, ij, list(range(head + 2, head + 2 + count)))
    ij.sort(axis=1)
    ij = np.unique(ij, axis=0)  # newton off lists a pair across processors twice
    return ij[:, 0], ij[:, 1]
