"""Apply planned per-body mass and inertia factors in YADE or LAMMPS, with the step at or below the plan's.

Runs inside the engines' own Python (standard library only, like ``yade_hook`` and ``lammps_hook``,
which call it from their ``apply_density_scaling``); any Python can use it to write LAMMPS inputs.
The factors come from ``dtcrit plan ... --json`` (``density_scaling``: one factor per body, ordered
as the snapshot's bodies) or from ``dtcrit.plan.plan_density_scaling`` (``zip(ids, plan.factors)``);
``read_factors`` turns either form into ``{id: factor}``, ``read_plan`` gives the plan file's factors
and ``target_dt`` together.

A factor ``f`` multiplies a body's mass *and* its moments of inertia (density scaling: the shape and
the contacts are unchanged, so every eigenvalue of ``M^-1 K`` that the body carries drops by up to
``f``).  The step is then set to ``safety * dt`` (``safety`` in (0, 1], default 1): the planned step
``dt`` is one the scaled packing is proved stable at, so the step never exceeds it.

**YADE** (``apply_yade``, or ``DtcritHook.apply_density_scaling``): ``b.state.mass *= f`` and
``b.state.inertia *= f`` for each listed body, then ``O.dt = safety * dt``.  NewtonIntegrator
computes ``linAccel = F / mass + gravity`` and ``angAccel = T / inertia`` (NewtonIntegrator.cpp,
``computeAccel``, ``computeAngAccel``), so the contact forces act on ``f`` times the inertia while
gravity still accelerates at ``g`` (the weight grows with the mass).  YADE's own
``NewtonIntegrator.densityScaling`` instead multiplies the whole acceleration, gravity included, by
``state.densityScaling`` (mass factor ``1 / densityScaling``: the weight stays the real one, bodies
fall ``f`` times more slowly); it is set only by ``GlobalStiffnessTimeStepper`` (with
``densityScaling=True`` it overwrites every body's value; without one a manual
``state.densityScaling`` has no effect -- measured in YADE 2023.02a), which is why the factors are
written into the masses.  Call it once: the masses stay scaled, and a later ``yade_export`` (and
so the ``DtcritHook`` audit) sees the scaled packing.  Clump members are refused (scale the clump).

**LAMMPS** (``atom_style sphere``: ``rmass`` per atom; ``fix nve/sphere`` takes the moment of inertia
as ``0.4 rmass radius^2`` every step, so scaling the mass scales the inertia with it).
``lammps_factor_file`` writes an ``atomfile`` (``# comment``, the count, then ``id factor`` lines) and
``lammps_commands`` the input lines that apply it::

    variable dtcrit_factor atomfile "factors.txt"
    variable dtcrit_mass atom mass*(v_dtcrit_factor+(v_dtcrit_factor==0))
    set group all mass v_dtcrit_mass
    timestep 2.5e-06

``python3 density_scaling.py plan.json scaled.in`` (``write_lammps_include``) writes these lines to
``scaled.in`` and the factors to ``scaled.in.factors``, for ``include scaled.in`` after ``read_data``
(atoms the file does not list read factor 0 and keep their mass; ``atomfile`` variables need an atom
map, ``atom_modify map array`` or ``hash``, before ``read_data``).  The two variables stay defined:
``variable ... delete`` of both made LAMMPS 29Sep2021 crash on exit (measured), so a second
application needs another ``label``.  ``apply_lammps`` does both
through the LAMMPS Python module (``DtcritLammpsHook.apply_density_scaling``).  Run it once, after
``read_data`` and before ``run``.  Nothing from the caller ends up outside a double-quoted argument
(the file path, refused when it holds a double quote or a line break) or a number written by
``repr``.
"""
from __future__ import annotations

import math
import os
import tempfile

__all__ = ["read_factors", "read_plan", "apply_yade", "lammps_factor_file", "lammps_commands", "apply_lammps",
           "write_lammps_include"]


def _factor(value, where: str) -> float:
    try:
        f = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{where}: a mass factor must be a number, got {value!r}") from None
    if not (math.isfinite(f) and f > 0.0):
        raise ValueError(f"{where}: a mass factor must be finite and positive, got {value!r}")
    return f


def _body_id(value, where: str) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise ValueError(f"{where}: a body id must be an integer, got {value!r}")
    try:
        as_int = int(value)
    except ValueError:
        raise ValueError(f"{where}: a body id must be an integer, got {value!r}") from None
    if isinstance(value, float) and value != as_int:
        raise ValueError(f"{where}: a body id must be an integer, got {value!r}")
    return as_int


def _pairs(source) -> list:
    """(id, factor) pairs of the accepted forms (``read_factors``)."""
    if isinstance(source, dict):
        scaling = source.get("density_scaling", source)
        if isinstance(scaling, dict) and "factors" in scaling:
            factors = scaling["factors"]
            if isinstance(factors, dict):
                return list(factors.items())
            ids = scaling.get("ids")
            if ids is None and factors and isinstance(factors[0], dict):
                return [(row.get("id"), row.get("factor")) for row in factors]
            if ids is None or len(ids) != len(factors):
                raise ValueError("density_scaling.factors: a list of factors needs 'ids' of the same length")
            return list(zip(ids, factors))
        return list(source.items())
    return list(source)


def read_factors(source) -> dict:
    """Per-body mass factors as ``{id: factor}``.

    Parameters
    ----------
    source : str, os.PathLike, dict or iterable
        A ``dtcrit plan --json`` file (path) or its parsed document, whose ``density_scaling`` holds
        ``factors`` as ``{id: factor}``, as rows ``{"id": ..., "factor": ...}`` or as a list beside a
        list ``ids``; a plain mapping ``{id: factor}``; or ``(id, factor)`` pairs.

    Returns
    -------
    dict
        Integer body id -> factor (finite, positive).

    Raises
    ------
    ValueError
        A factor that is not a finite positive number, an id that is not an integer, an id listed twice.
    """
    if isinstance(source, (str, os.PathLike)):
        import json

        with open(source) as fh:
            source = json.load(fh)
    out: dict = {}
    for k, (bid, value) in enumerate(_pairs(source)):
        key = _body_id(bid, f"factor {k}")
        if key in out:
            raise ValueError(f"factor {k}: body {key} is listed twice")
        out[key] = _factor(value, f"body {key}")
    return out


def read_plan(source) -> tuple:
    """The factors and the target step of a ``dtcrit plan --json`` document.

    Parameters
    ----------
    source : str, os.PathLike or dict
        The JSON file (path) or its parsed document (``target_dt`` [s] and ``density_scaling``).

    Returns
    -------
    tuple
        ``({id: factor}, target_dt)``, ready for ``apply_yade``, ``apply_lammps`` or a hook's
        ``apply_density_scaling``.

    Raises
    ------
    ValueError
        No ``density_scaling`` or no finite positive ``target_dt`` in the document (``read_factors``'s
        refusals besides).
    """
    if isinstance(source, (str, os.PathLike)):
        import json

        with open(source) as fh:
            source = json.load(fh)
    if not isinstance(source, dict) or not isinstance(source.get("density_scaling"), dict):
        raise ValueError("not a dtcrit plan document: no 'density_scaling' object")
    return read_factors(source), _step(source.get("target_dt"), 1.0)


def _step(dt, safety) -> float:
    safety = float(safety)
    if not (0.0 < safety <= 1.0):
        raise ValueError(f"safety must lie in (0, 1], got {safety!r}")
    try:
        step = safety * float(dt)
    except (TypeError, ValueError):
        raise ValueError(f"the planned step must be a number, got {dt!r}") from None
    if not (math.isfinite(step) and step > 0.0):
        raise ValueError(f"the planned step must be finite and positive, got {dt!r}")
    return step


def apply_yade(factors, dt=None, safety: float = 1.0) -> dict:
    """Scale the listed YADE bodies' mass and inertia, and set ``O.dt`` (module docstring).

    Parameters
    ----------
    factors : dict or source of ``read_factors``
        Body id -> mass factor.
    dt : float, optional
        The planned step; ``O.dt`` becomes ``safety * dt``.  None keeps ``O.dt``.
    safety : float
        In (0, 1]; default 1 (the plan's step is proved stable for the scaled packing).

    Returns
    -------
    dict
        ``bodies`` (how many were scaled), ``mass`` (their total mass before) and ``added_mass`` (what
        the scaling added) [kg], ``dt`` (``O.dt`` after).
    """
    from yade import wrapper

    omega = wrapper.Omega()
    table = read_factors(factors)
    step = None if dt is None else _step(dt, safety)
    bodies = []
    for bid, f in table.items():
        b = omega.bodies[bid] if 0 <= bid < len(omega.bodies) else None
        if b is None:
            raise ValueError(f"body {bid}: no such body in O.bodies")
        if b.isClumpMember:
            raise ValueError(f"body {bid} is a clump member: give the clump's id")
        bodies.append((b, f))
    mass = added = 0.0
    for b, f in bodies:
        mass += b.state.mass
        added += (f - 1.0) * b.state.mass
        b.state.mass = f * b.state.mass
        b.state.inertia = f * b.state.inertia
    if step is not None:
        omega.dt = step
    return {"bodies": len(bodies), "mass": mass, "added_mass": added, "dt": omega.dt}


def lammps_factor_file(factors) -> str:
    """Text of a LAMMPS ``atomfile`` of the factors (``# comment``, count, ``id factor`` lines).

    Parameters
    ----------
    factors : dict or source of ``read_factors``
        Atom id -> mass factor.

    Returns
    -------
    str
        The file's text (LAMMPS ``variable ... atomfile`` format; factors written by ``repr``).
    """
    table = read_factors(factors)
    rows = [f"{bid:d} {f!r}" for bid, f in sorted(table.items())]
    return "\n".join(["# dtcrit density scaling: atom id, mass factor", str(len(rows)), *rows]) + "\n"


def _quoted(path) -> str:
    text = os.fspath(path)
    if any(c in text for c in '"\n\r\0'):
        raise ValueError(f"a path LAMMPS can read may not contain a double quote or a line break: {text!r}")
    return f'"{text}"'


def lammps_commands(factor_file, dt=None, safety: float = 1.0, label: str = "dtcrit") -> list:
    """LAMMPS input lines that multiply each atom's mass by its factor and set the step.

    Parameters
    ----------
    factor_file : str or os.PathLike
        The ``atomfile`` written from ``lammps_factor_file`` (as LAMMPS will see the path).
    dt : float, optional
        The planned step: ``timestep safety * dt`` ends the lines.  None leaves the step alone.
    safety : float
        In (0, 1]; default 1.
    label : str
        Prefix of the two temporary variables (letters, digits, underscores).

    Returns
    -------
    list of str
        The commands, in order (module docstring).
    """
    if not label or not label.replace("_", "").isalnum() or not label.isascii():
        raise ValueError(f"label must be letters, digits and underscores, got {label!r}")
    fac, mass = f"{label}_factor", f"{label}_mass"
    lines = [f"variable {fac} atomfile {_quoted(factor_file)}",
             f"variable {mass} atom mass*(v_{fac}+(v_{fac}==0))",
             f"set group all mass v_{mass}"]
    if dt is not None:
        lines.append(f"timestep {_step(dt, safety)!r}")
    return lines


def write_lammps_include(plan, include, safety: float = 1.0) -> list:
    """Write a LAMMPS ``include`` file (and its ``atomfile`` beside it) from a ``dtcrit plan --json`` file.

    Parameters
    ----------
    plan : str, os.PathLike or dict
        The plan document (``read_plan``).
    include : str or os.PathLike
        The input file to write; the factors go to ``<include>.factors`` beside it, named in the file by
        its base name (run LAMMPS from that folder).
    safety : float
        In (0, 1]; ``timestep safety * target_dt``.

    Returns
    -------
    list of str
        The commands written.
    """
    factors, dt = read_plan(plan)
    include = os.fspath(include)
    atomfile = include + ".factors"
    lines = lammps_commands(os.path.basename(atomfile), dt, safety)
    with open(atomfile, "w") as fh:
        fh.write(lammps_factor_file(factors))
    with open(include, "w") as fh:
        fh.write("# dtcrit density scaling: each atom's mass (and so its inertia) times its factor, then the step\n")
        fh.write("\n".join(lines) + "\n")
    return lines


_APPLIED = [0]  # applications in this process: each gets its own variable names


def apply_lammps(lmp, factors, dt=None, safety: float = 1.0, directory=None) -> float:
    """Apply the factors and the step through the LAMMPS Python module (module docstring).

    Parameters
    ----------
    lmp : lammps.lammps
        The running LAMMPS instance (its input has read the atoms, with an atom map).
    factors : dict or source of ``read_factors``
        Atom id -> mass factor.
    dt : float, optional
        The planned step (``timestep safety * dt``); None keeps the current one.
    safety : float
        In (0, 1]; default 1.
    directory : str, optional
        Where the ``atomfile`` is written (a new temporary directory by default).

    Returns
    -------
    float
        LAMMPS's step after the call (``extract_global("dt")``).
    """
    folder = os.fspath(directory) if directory is not None else tempfile.mkdtemp(prefix="dtcrit_scaling_")
    _APPLIED[0] += 1
    path = os.path.join(folder, f"mass_factors_{_APPLIED[0]}.txt")
    with open(path, "w") as fh:
        fh.write(lammps_factor_file(factors))
    for line in lammps_commands(path, dt, safety, label=f"dtcrit{_APPLIED[0]}"):
        lmp.command(line)
    return float(lmp.extract_global("dt"))


if __name__ == "__main__":  # python3 density_scaling.py PLAN.json SCALED.in
    import sys

    if len(sys.argv) != 3:
        sys.exit("usage: python3 density_scaling.py PLAN.json SCALED.in  (then `include SCALED.in` after read_data)")
    write_lammps_include(sys.argv[1], sys.argv[2])
