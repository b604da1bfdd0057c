"""Set LAMMPS's ``timestep`` from dtcrit's rigorous bound every N steps (the LAMMPS Python module).

Runs in the Python that has the LAMMPS module (Debian: ``apt-get install python3-lammps
liblammps-dev``, then ``/usr/bin/python3`` has ``from lammps import lammps``), with the standard
library only: dtcrit is *not* imported there (it and its pinned dependencies live in their own
environment).  Before every chunk of ``every`` steps the hook

1. writes the atoms with ``write_dump all custom FILE id type x y z radius mass modify format float
   %.17g`` (17 digits: the overlaps are read back exactly);
2. with ``local=True`` (default) writes the engine's own contact list, a ``dump local`` of ``compute
   property/local patom1 patom2 cutoff radius`` (the pairs LAMMPS finds closer than R_i + R_j), during
   a ``run 0`` (a set-up, no step: the shear histories are not advanced);
3. runs the dtcrit command line on them in a subprocess,

       dtcrit audit FILE --pair-style 'STYLE ARGS' --json [--local FILE.local]

4. sets ``timestep safety * min(dt_safe, dt_crit)`` from the JSON it prints (``dt_safe``: a rigorous
   lower bound of the critical step, never above ``dt_crit``; the step is written with ``repr``, so
   LAMMPS's ``dt`` is that double exactly).

Use: run the input through the Python that has the module instead of ``lmp -in in.file``::

    /usr/bin/python3 run_hooked.py

with ``run_hooked.py``::

    import sys; sys.path.insert(0, "DIR")               # DIR: the directory holding this file
    from lammps import lammps
    from lammps_hook import DtcritLammpsHook
    lmp = lammps()
    lmp.file("in.setup")                                # the input up to (not including) its `run`
    hook = DtcritLammpsHook(lmp, "gran/hooke/history 1e4 NULL 0 NULL 0.5 0", every=1000)
    # safety 0.9; dtcrit found on PATH, or dtcrit="/path/to/dtcrit"
    # (or a command prefix: ["/venv/bin/python", "-m", "dtcrit"])
    hook.run(100000)                                    # instead of `run 100000`

``pair_style`` is the input's own ``pair_style`` line without the word ``pair_style`` (``gran/hooke``,
``gran/hooke/history``, ``gran/hertz/history``, ``granular ...``; ``dtcrit audit --help``).
``hook.run(n)`` runs ``n`` steps as ``run`` chunks of at most ``every`` steps, each ``start``/``stop``
at the ends of the whole ``n`` (so ramps such as ``fix deform`` or ``v_ramp`` span the ``n`` steps as
in one ``run n``), calling ``update`` before each chunk.  ``hook.update()`` audits and sets the step
once, now.  ``hook.apply_density_scaling(factors, dt)`` applies the per-body factors of ``dtcrit
plan`` once, before ``hook.run`` (each atom's mass, and so its inertia, and ``timestep dt``; needs an
atom map; ``density_scaling.py`` in this directory, which also writes the lines for an input file).  ``hook.history`` lists, per call: ``step``, ``dt_before``, ``dt_crit``, ``dt_safe``,
``dt`` (the step set), ``limiting`` (the particle ids the governing mode sits on), ``seconds`` (the
audit's wall time), or ``error`` or ``skipped``.  A snapshot without atoms, or (with ``local``) without
contacts, has nothing to audit and keeps its step.  If dtcrit fails (non-zero exit, no JSON, a
non-positive step) the hook raises ``RuntimeError`` with dtcrit's message, unless
``on_error="keep"``, which keeps the current step and records the failure.

``safety`` (default 0.9, in (0, 1]) multiplies the bound: ``dt_safe`` may equal ``dt_crit``, a step
*at* the boundary is only marginally stable, and a contact formed between two calls stiffens the
packing at once.  The audit costs a process start and an eigen-solve (about 1 s for 30 spheres);
``every`` trades that against how fast the packing changes.  What the audit sees: the atoms and their
pair contacts; ``fix wall/gran`` walls are not in a dump: give the input's own fix lines as
``extra_args=("--wall", "fix 2 all wall/gran ...")`` (one pair per wall, ``dtcrit audit --wall``) and
their contacts are audited too (with ``local``, a snapshot whose only contacts are with walls keeps its
step); frozen or driven atoms
are audited as free (a conservative choice for undamped packings: fixing degrees of freedom cannot
raise the largest eigenvalue, by eigenvalue interlacing).  Run serially: under ``mpirun`` every rank
would start dtcrit.

**The same with the ``lmp`` binary** (PYTHON package, no LAMMPS Python module needed):
``timestep_function`` gives a callable for a python-style variable; LAMMPS writes the dump itself and
``run N every M`` re-reads the step between chunks (LAMMPS refuses library commands issued from a
Python function during a ``run ... every``, so the step comes back as the variable's value)::

    variable dtcrit_now equal dt
    variable dtcrit_dt python dtcrit_dt
    python dtcrit_dt input 1 v_dtcrit_now return v_dtcrit_dt format ff here \"\"\"
    import sys; sys.path.insert(0, "DIR")
    from lammps_hook import timestep_function
    dtcrit_dt = timestep_function("gran/hooke/history 1e4 NULL 0 NULL 0.5 0", "dtcrit.dump",
                                  dtcrit="/path/to/dtcrit")
    \"\"\"
    write_dump all custom dtcrit.dump id type x y z radius mass modify format float %.17g
    timestep $(v_dtcrit_dt:%.17g)
    run 100000 every 1000 "write_dump all custom dtcrit.dump id type x y z radius mass modify format float %.17g" &
                          "timestep $(v_dtcrit_dt:%.17g)"

(LAMMPS keeps a python-style variable's value as text of 15 significant digits, so the function
returns the largest such number not above ``safety * min(dt_safe, dt_crit)``: the step LAMMPS sets is
then that number exactly, at most 1e-14 relative below the bound, never above it.  ``on_error="raise"``
makes the Python function, and so LAMMPS, fail with dtcrit's message; ``"keep"`` returns the current
step.)  This route audits the dump's own contacts (no ``--local``).
"""
from __future__ import annotations

import decimal
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

__all__ = ["DtcritLammpsHook", "DumpAudit", "timestep_function", "DUMP_COLUMNS"]

#: the per-atom columns dtcrit audit reads (atom_style sphere: ``mass`` is the per-atom rmass)
DUMP_COLUMNS = "id type x y z radius mass"


def _executable(dtcrit) -> list[str]:
    """The dtcrit command as a list: found on PATH, a path, or a command prefix."""
    if dtcrit is None:
        found = shutil.which("dtcrit")
        if found is None:
            raise ValueError("the dtcrit command was not found on PATH; pass dtcrit='/path/to/dtcrit'")
        return [found]
    if isinstance(dtcrit, (list, tuple)):
        return [str(a) for a in dtcrit]  # a command prefix, e.g. [python, "-m", "dtcrit"]
    return [os.fspath(dtcrit)]


class DumpAudit:
    """``dtcrit audit`` of a LAMMPS dump file and the step it allows (no LAMMPS object needed).

    ``step(dump, local=None, dt_before=None, step=None)`` runs the audit and returns
    ``safety * min(dt_safe, dt_crit)``; on failure it raises ``RuntimeError`` (``on_error="raise"``)
    or returns ``dt_before`` (``"keep"``).  Every call appends a record to ``history``.
    """

    def __init__(self, pair_style: str, safety: float = 0.9, dtcrit=None, extra_args=(), timeout: float = 600.0,
                 on_error: str = "raise"):
        if not isinstance(pair_style, str) or not pair_style.split():
            raise ValueError(f"pair_style must be the input's pair style text, got {pair_style!r}")
        if pair_style.split()[0] == "pair_style":
            pair_style = pair_style.split(None, 1)[1] if len(pair_style.split()) > 1 else ""
        if not (0.0 < float(safety) <= 1.0):
            raise ValueError(f"safety must lie in (0, 1], got {safety!r}")
        if on_error not in ("raise", "keep"):
            raise ValueError(f"on_error must be 'raise' or 'keep', got {on_error!r}")
        self.pair_style = " ".join(pair_style.split())
        self.safety = float(safety)
        self.dtcrit = _executable(dtcrit)
        self.extra_args = [str(a) for a in extra_args]
        self.timeout = float(timeout)
        self.on_error = on_error
        self.history: list[dict] = []

    def command(self, dump: str, local: str | None = None) -> list[str]:
        """The ``dtcrit audit`` command line for one snapshot.

        Parameters
        ----------
        dump : str
            The snapshot's dump file.
        local : str, optional
            The engine's own contact list (a ``dump local`` file), passed as ``--local``.

        Returns
        -------
        list of str
            The arguments, ``--json`` output asked for.
        """
        cmd = [*self.dtcrit, "audit", os.fspath(dump), "--pair-style", self.pair_style, "--json"]
        if local is not None:
            cmd += ["--local", os.fspath(local)]
        return cmd + self.extra_args

    def _fail(self, record: dict, message: str):
        record["error"] = message
        self.history.append(record)
        if self.on_error == "raise":
            where = f" at step {record['step']}" if record.get("step") is not None else ""
            raise RuntimeError(f"dtcrit hook{where}: {message}")
        return record.get("dt_before")

    def step(self, dump, local=None, dt_before: float | None = None, step: int | None = None) -> float | None:
        """The step dtcrit allows for the snapshot in ``dump`` (class docstring)."""
        record = {"step": step, "dt_before": dt_before}
        start = time.perf_counter()
        try:
            done = subprocess.run(self.command(dump, local), capture_output=True, text=True, timeout=self.timeout)
        except (OSError, subprocess.TimeoutExpired) as exc:
            return self._fail(record, f"could not run {' '.join(self.dtcrit)}: {exc}")
        record["seconds"] = time.perf_counter() - start
        if done.returncode != 0:
            return self._fail(record, (done.stderr or done.stdout).strip() or f"exit status {done.returncode}")
        try:
            out = json.loads(done.stdout)
            dt_crit, dt_safe = float(out["dt_crit"]), float(out["dt_safe"])
        except (ValueError, KeyError, TypeError) as exc:
            return self._fail(record, f"unreadable dtcrit output ({exc}): {done.stdout[:200]!r}")
        record.update(dt_crit=dt_crit, dt_safe=dt_safe)
        limiting = out.get("limiting")
        if isinstance(limiting, dict):
            record["limiting"] = limiting.get("ids")
        dt = self.safety * min(dt_safe, dt_crit)
        if not (0.0 < dt < float("inf")):
            return self._fail(record, f"no positive finite step (dt_crit={dt_crit!r}, dt_safe={dt_safe!r})")
        record["dt"] = dt
        self.history.append(record)
        return dt


def _floor_15_digits(x: float) -> float:
    """The largest number of 15 significant digits not above ``x`` (> 0), as a double: LAMMPS (29Sep2021)
    keeps a python-style variable's float as text of 15 significant digits (measured: a function returning
    1e-5/3 gives the variable 3.33333333333333e-06), which this survives unchanged (15 digits round-trip
    through a double); rounding to nearest could land above ``x``.
    """
    exact = decimal.Decimal(x)
    quantum = decimal.Decimal(1).scaleb(exact.adjusted() - 14)
    return float(exact.quantize(quantum, rounding=decimal.ROUND_FLOOR))


def timestep_function(pair_style: str, dump: str = "dtcrit.dump", **options):
    """For the ``lmp`` binary route (module docstring): a function ``f(dt_now=None) -> float``
    auditing the dump file LAMMPS has just written; ``f.audit`` is its ``DumpAudit`` (``history``).
    ``options``: ``safety``, ``dtcrit``, ``extra_args``, ``timeout``, ``on_error`` of ``DumpAudit``.
    """
    auditor = DumpAudit(pair_style, **options)

    def dtcrit_timestep(dt_now=None):
        dt = auditor.step(dump, dt_before=None if dt_now is None else float(dt_now))
        if dt is None:  # kept, but nothing to keep: a python-style variable must return a number
            raise RuntimeError(f"dtcrit hook: {auditor.history[-1].get('error')} (and no current step given)")
        if "error" in auditor.history[-1]:
            return dt
        auditor.history[-1]["dt"] = dt = _floor_15_digits(dt)
        return dt

    dtcrit_timestep.audit = auditor
    return dtcrit_timestep


def _density_scaling():
    try:
        from . import density_scaling  # imported as part of the dtcrit.engine_scripts package
    except ImportError:
        here = os.path.dirname(os.path.abspath(__file__))
        if here not in sys.path:
            sys.path.insert(0, here)
        import density_scaling
    return density_scaling


def _lammps_object(lmp):
    """The ``lammps.lammps`` instance (also accepts a ``PyLammps``, whose ``.lmp`` it is)."""
    if hasattr(lmp, "extract_global") and hasattr(lmp, "command"):
        return lmp
    inner = getattr(lmp, "lmp", None)
    if hasattr(inner, "extract_global") and hasattr(inner, "command"):
        return inner
    raise TypeError(f"expected a LAMMPS object (lammps.lammps or PyLammps), got {type(lmp).__name__}")


class DtcritLammpsHook:
    """LAMMPS's ``timestep`` from ``dtcrit audit`` every ``every`` steps (module docstring)."""

    def __init__(self, lmp, pair_style: str, every: int = 1000, safety: float = 0.9, dtcrit=None,
                 on_error: str = "raise", local: bool = True, directory=None, extra_args=(),
                 timeout: float = 600.0, label: str = "dtcrit"):
        if int(every) < 1:
            raise ValueError(f"every must be a positive number of steps, got {every!r}")
        if not label.replace("_", "").isalnum():
            raise ValueError(f"label must be letters, digits and underscores (a LAMMPS id), got {label!r}")
        self.lmp = _lammps_object(lmp)
        if int(self.lmp.extract_setting("world_size")) != 1:
            raise ValueError("the dtcrit hook runs serially (one MPI rank): every rank would start dtcrit")
        self.every = int(every)
        self.local = bool(local)
        self.label = label
        self.auditor = DumpAudit(pair_style, safety=safety, dtcrit=dtcrit, extra_args=extra_args,
                                 timeout=timeout, on_error=on_error)
        folder = os.fspath(directory) if directory is not None else tempfile.mkdtemp(prefix="dtcrit_hook_")
        os.makedirs(folder, exist_ok=True)
        self.dump_path = os.path.join(folder, "snapshot.dump")
        self.local_path = os.path.join(folder, "contacts.local")

    # the options of the audit, as attributes like the YADE hook's
    safety = property(lambda self: self.auditor.safety)
    dtcrit = property(lambda self: self.auditor.dtcrit)
    on_error = property(lambda self: self.auditor.on_error)
    history = property(lambda self: self.auditor.history)

    def command(self) -> list[str]:
        """The dtcrit command line ``update`` runs."""
        return self.auditor.command(self.dump_path, self.local_path if self.local else None)

    @staticmethod
    def _quoted(path: str) -> str:
        if '"' in path:
            raise ValueError(f"a path LAMMPS can read may not contain a double quote: {path!r}")
        return f'"{path}"'

    def _write_snapshot(self) -> int | None:
        """Write the dump (and the local contact list); the number of contacts, or None without --local."""
        lmp = self.lmp
        lmp.command(f"write_dump all custom {self._quoted(self.dump_path)} {DUMP_COLUMNS} "
                    "modify format float %.17g")
        if not self.local:
            return None
        cid, did = f"{self.label}_pairs", f"{self.label}_local"
        if os.path.exists(self.local_path):
            os.remove(self.local_path)
        lmp.command(f"compute {cid} all property/local patom1 patom2 cutoff radius")
        lmp.command(f"dump {did} all local 1 {self._quoted(self.local_path)} c_{cid}[1] c_{cid}[2]")
        try:
            lmp.command("run 0 post no")
        finally:
            lmp.command(f"undump {did}")
            lmp.command(f"uncompute {cid}")
        with open(self.local_path) as fh:
            lines = fh.read().splitlines()
        for k, line in enumerate(lines[:-1]):
            if line.startswith("ITEM: NUMBER OF ENTRIES"):
                return int(lines[k + 1].split()[0])
        raise RuntimeError(f"LAMMPS wrote no contact list to {self.local_path}")

    def update(self) -> float | None:
        """Audit the atoms now and set ``timestep``; returns the step set (None when nothing was set)."""
        lmp = self.lmp
        step, dt_before = int(lmp.extract_global("ntimestep")), float(lmp.extract_global("dt"))
        record = {"step": step, "dt_before": dt_before}
        if int(lmp.get_natoms()) == 0:
            self.history.append({**record, "skipped": "no atoms"})
            return None
        contacts = self._write_snapshot()
        if contacts == 0:
            self.history.append({**record, "skipped": "no contacts"})
            return None
        dt = self.auditor.step(self.dump_path, self.local_path if self.local else None, dt_before=dt_before,
                               step=step)
        if dt is None or "error" in self.history[-1]:
            return None  # on_error="keep": the step stays
        lmp.command(f"timestep {dt!r}")
        return dt

    def apply_density_scaling(self, factors, dt=None, safety: float = 1.0) -> float:
        """Multiply the atoms' masses (and so their inertias) by the planned factors and set ``timestep
        safety * dt`` (``density_scaling.apply_lammps``; once, before ``run``); returns the step.
        """
        return _density_scaling().apply_lammps(self.lmp, factors, dt, safety,
                                               directory=os.path.dirname(self.dump_path))

    def run(self, nsteps: int, run_options: str = "") -> None:
        """``run nsteps`` in chunks of at most ``every`` steps, ``update`` before each (module docstring).
        ``run_options``: more ``run`` keywords for every chunk (e.g. ``"post no"``).
        """
        nsteps = int(nsteps)
        if nsteps < 0:
            raise ValueError(f"nsteps must be >= 0, got {nsteps!r}")
        first = int(self.lmp.extract_global("ntimestep"))
        last = first + nsteps
        done = 0
        while done < nsteps:
            self.update()
            chunk = min(self.every, nsteps - done)
            self.lmp.command(f"run {chunk} start {first} stop {last} {run_options}".rstrip())
            done += chunk
