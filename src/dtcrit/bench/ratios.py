"""Section 4 of ``dtcrit bench``: the closed forms against the eigen route and the NumPy kernels against
two floors, all timed in the same run (figures only; nothing here is ever a pass/fail on time).
"""
from __future__ import annotations

import math
import time
from typing import Any

import numpy as np
from tqdm import tqdm

from dtcrit.bench.routes import floor_kernel


def ratios(config, batch, timing_raw) -> dict:
    """Section 4's speed ratios, all measured in this run, interleaved, best of each.

    * ``speedup_vs_eig_by_integrator``: eigvals + bisection time per scene over the NumPy closed form's
      (``critical_dt_array``); ``speedup_vs_eig_c_by_integrator`` the same over the emitted C step's;
    * ``kernel_vs_floor_by_integrator``: the NumPy kernels (generated through ``critical_dt_array``, and
      the fused form) over two floors on the same arrays: the *arithmetic floor* 2/sqrt(k A) (the
      cheapest closed form: a product, a square root and a division per scene) and the *memory floor*,
      one NumPy pass reading k and A and writing one array (``np.multiply(k, A, out=...)``).

    Parameters
    ----------
    config : BenchConfig
        The bench's sizes and repeats.
    batch : Batch
        The random scenes timed.
    timing_raw : dict
        Per-route timings already measured.

    Returns
    -------
    dict
        The ratios, per integrator and overall.
    """
    from dtcrit.bench.fused import FUSED, critical_dt_fused
    from dtcrit.integrators.stability import critical_dt_array

    out: dict[str, Any] = {"speedup_vs_eig_by_integrator": {}, "speedup_vs_eig_c_by_integrator": {},
                           "kernel_vs_floor_by_integrator": {}}
    k, c, A = batch.k, batch.c, batch.A
    buf = np.empty_like(k)
    for name in tqdm(config.integrators, desc="bench: floor ratios", disable=None):
        floor = mem = gen = fused = math.inf
        for _ in range(max(3, config.repeats)):  # interleaved, best of each
            t0 = time.perf_counter()
            floor_kernel(k, A)
            t1 = time.perf_counter()
            np.multiply(k, A, out=buf)
            t2 = time.perf_counter()
            critical_dt_array(name, k, c, A)
            t3 = time.perf_counter()
            if name in FUSED:
                critical_dt_fused(name, k, c, A)
            t4 = time.perf_counter()
            floor, mem, gen = min(floor, t1 - t0), min(mem, t2 - t1), min(gen, t3 - t2)
            if name in FUSED:
                fused = min(fused, t4 - t3)
        entry = {"floor_seconds": floor, "memory_floor_seconds": mem, "generated_seconds": gen,
                 "generated_ratio": gen / floor, "generated_ratio_memory": gen / mem}
        if name in FUSED:
            entry["fused_seconds"] = fused
            entry["fused_ratio"] = fused / floor
            entry["fused_ratio_memory"] = fused / mem
        entry["best_ratio"] = min(entry["generated_ratio"], entry.get("fused_ratio", math.inf))
        entry["best_ratio_memory"] = min(entry["generated_ratio_memory"], entry.get("fused_ratio_memory", math.inf))
        out["kernel_vs_floor_by_integrator"][name] = entry
        eig = timing_raw.get(("eigvals+bisection", name))
        if eig is not None:
            out["speedup_vs_eig_by_integrator"][name] = eig / (gen / len(batch))
            c_time = timing_raw.get(("closed-form-c", name))
            if c_time:
                out["speedup_vs_eig_c_by_integrator"][name] = eig / c_time
    sp = out["speedup_vs_eig_by_integrator"]
    kv = out["kernel_vs_floor_by_integrator"]
    radical = [n for n in kv if n in FUSED]
    out["speedup_vs_eig"] = min(sp.values()) if sp else None
    out["speedup_vs_eig_c"] = min(out["speedup_vs_eig_c_by_integrator"].values()) if out["speedup_vs_eig_c_by_integrator"] else None
    out["kernel_vs_floor"] = max(kv[n]["best_ratio"] for n in radical) if radical else None
    out["kernel_vs_memory_floor"] = max(kv[n]["best_ratio_memory"] for n in radical) if radical else None
    out["kernel_vs_floor_generated"] = max(kv[n]["generated_ratio"] for n in radical) if radical else None
    out["kernel_vs_floor_cubic"] = kv["paper-eq40"]["best_ratio"] if "paper-eq40" in kv else None
    out["n_scenes"] = len(batch)
    return out
