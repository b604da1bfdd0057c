"""Set YADE's ``O.dt`` from dtcrit's rigorous bound every N steps (a PyRunner).

Runs inside YADE (standard library and ``yade`` only).  dtcrit is *not* imported into YADE's Python
(Debian's, with NumPy 1.24; dtcrit and its pinned dependencies live in their own environment): every
``every`` steps the hook exports the
scene with ``yade_export.export`` (this directory) and runs the dtcrit command line on it,

    dtcrit audit EXPORT.json --engine yade --json

in a subprocess, then sets ``O.dt = safety * min(dt_safe, dt_crit)`` from the JSON it prints
(``dt_safe``: a rigorous lower bound of the critical step, never above ``dt_crit``).  Use::

    import sys; sys.path.insert(0, "DIR")           # DIR: the directory holding this file
    from yade_hook import DtcritHook
    hook = DtcritHook(every=1000)                   # safety 0.9; dtcrit found on PATH, or dtcrit="/path/to/dtcrit"
                                                    # (or a command prefix: ["/venv/bin/python", "-m", "dtcrit"])
    O.engines = O.engines + [hook.runner()]         # after NewtonIntegrator: the next step uses the new dt
    O.run(100000, True)

``hook.update()`` does the same once, now.  ``hook.apply_density_scaling(factors, dt)`` applies the
per-body factors of ``dtcrit plan`` once, before the run (mass and inertia of each body, ``O.dt =
dt``; ``density_scaling.py`` in this directory); the audits that follow see the scaled masses.  A scene without real interactions has nothing to audit
and keeps its step.  If dtcrit fails (non-zero exit, no JSON, a non-positive step) the hook stops the
simulation (``O.pause()``) and raises ``RuntimeError`` with dtcrit's message, unless
``on_error="keep"``, which keeps the current step and records the failure.  ``hook.history`` lists,
per call: ``iter``, ``dt_crit``, ``dt_safe``, ``local_damping`` (the audit's object, or None),
``dt`` (the step set) and ``seconds`` (the audit's wall time), or ``error``.

Local (Cundall) damping: the export carries ``NewtonIntegrator.damping`` (``newton_damping``), which
the audit reads with YADE's law, so ``dt_crit`` and ``dt_safe`` are already the damped ones,
``2/(omega_max sqrt(1 + damping))`` and the rigorous bound times ``1/sqrt(1 + damping)``: the hook's
step stays below YADE's threshold with damping as without.  Viscous dashpots (``cn``, ``cs``) together
with ``damping`` > 0, and clumps with ``damping`` > 0, are not modelled: the audit refuses them and the
hook stops (or keeps its step with ``on_error="keep"``).

``safety`` (default 0.9, in (0, 1]) multiplies the bound: ``dt_safe`` may equal ``dt_crit`` (for an
isolated pair the rigorous bound is exact), and a step *at* the boundary is only marginally stable
(leapfrog's critical mode then grows linearly); a contact formed between two calls also stiffens the
packing at once.  The audit costs a process start and an eigen-solve (about 2 s); ``every`` trades
that against how fast the packing changes.
"""
from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

__all__ = ["DtcritHook", "dtcrit_runner"]


def _export_function():
    try:
        from .yade_export import export  # imported as part of the dtcrit.engine_scripts package
        return export
    except ImportError:
        pass
    here = os.path.dirname(os.path.abspath(__file__))
    if here not in sys.path:
        sys.path.insert(0, here)
    from yade_export import export
    return export


def _density_scaling():
    try:
        from . import density_scaling  # imported as part of the dtcrit.engine_scripts package
    except ImportError:
        here = os.path.dirname(os.path.abspath(__file__))
        if here not in sys.path:
            sys.path.insert(0, here)
        import density_scaling
    return density_scaling


def _omega():
    from yade import wrapper

    return wrapper.Omega()


class DtcritHook:
    """``O.dt`` from ``dtcrit audit`` every ``every`` steps (module docstring)."""

    def __init__(self, every: int = 1000, safety: float = 0.9, dtcrit: str | None = None, export_path=None,
                 extra_args=(), timeout: float = 600.0, on_error: str = "raise", label: str = "dtcritHook"):
        if int(every) < 1:
            raise ValueError(f"every must be a positive number of steps, got {every!r}")
        if not (0.0 < float(safety) <= 1.0):
            raise ValueError(f"safety must lie in (0, 1], got {safety!r}")
        if on_error not in ("raise", "keep"):
            raise ValueError(f"on_error must be 'raise' or 'keep', got {on_error!r}")
        if dtcrit is None:
            found = shutil.which("dtcrit")
            if found is None:
                raise ValueError("the dtcrit command was not found on PATH; pass dtcrit='/path/to/dtcrit'")
            exe = [found]
        elif isinstance(dtcrit, (list, tuple)):
            exe = [str(a) for a in dtcrit]  # a command prefix, e.g. [python, "-m", "dtcrit"]
        else:
            exe = [os.fspath(dtcrit)]
        self.every = int(every)
        self.safety = float(safety)
        self.dtcrit = exe
        self.export_path = os.fspath(export_path) if export_path is not None else os.path.join(
            tempfile.mkdtemp(prefix="dtcrit_hook_"), "scene.json")
        self.extra_args = [str(a) for a in extra_args]
        self.timeout = float(timeout)
        self.on_error = on_error
        self.label = str(label)
        self.history: list[dict] = []
        self._export = _export_function()

    def command(self) -> list[str]:
        return [*self.dtcrit, "audit", self.export_path, "--engine", "yade", "--json", *self.extra_args]

    def _fail(self, O, record: dict, message: str) -> None:
        record["error"] = message
        self.history.append(record)
        if self.on_error == "raise":
            O.pause()
            raise RuntimeError(f"dtcrit hook at iteration {record['iter']}: {message}")

    def update(self) -> float | None:
        """Audit the scene now and set ``O.dt``; returns the step set (None when nothing was set)."""
        O = _omega()
        record = {"iter": int(O.iter)}
        if not any(i.isReal for i in O.interactions):
            record["skipped"] = "no real interactions"
            self.history.append(record)
            return None
        self._export(self.export_path)
        start = time.perf_counter()
        try:
            done = subprocess.run(self.command(), capture_output=True, text=True, timeout=self.timeout)
        except (OSError, subprocess.TimeoutExpired) as exc:
            self._fail(O, record, f"could not run {' '.join(self.dtcrit)}: {exc}")
            return None
        record["seconds"] = time.perf_counter() - start
        if done.returncode != 0:
            self._fail(O, record, (done.stderr or done.stdout).strip() or f"exit status {done.returncode}")
            return None
        try:
            out = json.loads(done.stdout)
            dt_crit, dt_safe = float(out["dt_crit"]), float(out["dt_safe"])
        except (ValueError, KeyError, TypeError) as exc:
            self._fail(O, record, f"unreadable dtcrit output ({exc}): {done.stdout[:200]!r}")
            return None
        record.update(dt_crit=dt_crit, dt_safe=dt_safe, local_damping=out.get("local_damping"))
        dt = self.safety * min(dt_safe, dt_crit)
        if not (dt > 0.0 and dt < float("inf")):
            self._fail(O, record, f"no positive finite step (dt_crit={dt_crit!r}, dt_safe={dt_safe!r})")
            return None
        O.dt = dt
        record["dt"] = dt
        self.history.append(record)
        return dt

    def apply_density_scaling(self, factors, dt=None, safety: float = 1.0) -> dict:
        """Multiply the bodies' masses and inertias by the planned factors and set ``O.dt = safety * dt``
        (``density_scaling.apply_yade``; once, before the run: later audits see the scaled masses)."""
        return _density_scaling().apply_yade(factors, dt, safety)

    def runner(self):
        """A PyRunner calling ``update`` every ``every`` steps (registered in ``__main__`` by label)."""
        import __main__
        from yade import wrapper

        name = f"_dtcrit_hook_{self.label}"
        setattr(__main__, name, self.update)
        return wrapper.PyRunner(command=f"{name}()", iterPeriod=self.every, label=self.label)


def dtcrit_runner(every: int = 1000, safety: float = 0.9, dtcrit: str | None = None, **kw):
    """``DtcritHook(every, safety, dtcrit, **kw).runner()``: the PyRunner alone."""
    return DtcritHook(every=every, safety=safety, dtcrit=dtcrit, **kw).runner()
