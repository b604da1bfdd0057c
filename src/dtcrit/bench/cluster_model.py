"""The memory and time model of a distributed SLEPc run, per rank (``python -m dtcrit.bench.cluster_model``).

``cluster_model(n, coordination, ranks)`` predicts each stage's peak resident memory on one rank and
its wall time for ``dtcrit packing --backend slepc`` (``dtcrit.packing.distributed.slepc_analysis``)
with ``N`` particles, ``C = z N / 2`` contacts and ``P`` ranks.  The stages are the ones the run's
JSON reports (``peak_rss_mib``, ``times``): input, contacts (search), assembly (the shell's operator
or the assembled matrix), solve and, on the shell route, bounds (``slepc_shell.shell_bounds``).

The constants of the matrix-free (shell) route's search, solve and bounds are fitted to runs of
``mpirun --bind-to none -n P .venv-mpi/bin/python -m dtcrit.bench.slepc_scaling N fcc`` (jittered
FCC, z = 12) at N = 1e5, 2e5, 5e5 and 10^6 and of ``slepc_scaling N random`` (z = 6) at 1e5 and 2e5,
P = 1 and 2, in the environment ``python3 dev.py mpi-env`` builds (with Numba: the shell's compiled
kernel, loaded from Numba's cache): peaks over each run's base, every fitted solve peak within 2 %.
The 4-rank runs and the ``tests/bench/test_cluster_model.py`` runs of ``dtcrit packing --random``
are not in the fit: they validate it (docs/howto/mpi.md).  The generated input's constants are
fitted to ``dtcrit packing --random N --cn 6`` runs; the text-dump, partitioned-read and
assembled-route constants are those measured in ``docs/howto/mpi.md`` (sections "Measured" and
"Partitioned input"); the ``.npz`` held memory (150 B per own particle with its halo) is an
estimate, not a measurement.  Time is of one core per rank (the two-rank runs on this 2-core
machine; one rank alone runs its compiled loops on every core it has, ``mpi_support.rank_threads``,
and solved 1.5x faster with two).  Plain arithmetic: no NumPy, no SciPy, no SymPy.
"""
from __future__ import annotations

import argparse
import json
import sys

MIB = 1024.0 ** 2
MATRICES = ("shell", "assembled")
INPUTS = ("text", "npz", "generated")
DEFAULT_PRODUCTS = 130  # disordered packings (measured 125-211 on the shell route at 5e4-2e5)

# Memory [bytes].  BASE: the interpreter with NumPy, SciPy, petsc4py, slepc4py and Numba loaded (the
# back-end imports the compiled kernel's module; measured 155 MiB before any work).
BASE = 155.0 * MIB
GENERATED_BASE = 162.4 * MIB  # --random: 162.4 MiB + 1.83 kB N (fitted, residuals within 4 MiB)
INPUT_PER_N = {"text": 900.0, "generated": 1830.0}  # replicated: text held with its lines; --random
HELD_PER_N = {"text": 900.0, "npz": 150.0}         # partitioned read, per own particle: estimates
SEARCH_BASE = 52.9 * MIB    # the search (k-d tree and Numba modules loaded, its fixed allocations)
SEARCH_PER_N = 284.0        # replicated positions (wrapped, renumbered, the halo's); per own one when partitioned
SEARCH_PER_C_LOCAL = 105.0  # the serial search's pairs and fields over the halo, and the block pattern
SHELL_BASE = BASE + 54.0 * MIB  # shell solve: BASE + the compiled kernels loaded from Numba's cache
SHELL_PER_N_LOCAL = 1245.0  # Krylov basis (ncv 12 + 1), work and ghosted vectors, the kernel's scale
SHELL_PER_C_LOCAL = 72.0    # the kernel's per-contact arrays (FCC z = 12 against random z = 6)
BOUNDS_BASE = 1.0 * MIB     # shell_bounds' extra over the solve: 1 MiB + 40 B per own particle (measured
BOUNDS_SLOPE = 40.0         # 0.6-39 MiB from 2.4e4 to 10^6 own particles: the particle pass's arrays
                            # mostly reuse the freed Krylov basis)
ASSEMBLED_PER_CN_LOCAL = 292.0  # one 6 x 6 SBAIJ block per contact and per particle (docs/howto/mpi.md)
ASSEMBLED_NCV = 32
# Time [s], one core per rank of the measuring machine.
TIME_INPUT_PER_N = {"text": 3.5e-6, "generated": 224e-6}   # replicated: every rank reads/generates all
TIME_HELD_PER_N = {"text": 25e-6, "npz": 5.5e-6}          # partitioned read and exchange, per own particle
TIME_SEARCH_PER_N = 0.76e-6        # Morton order and halo of all positions (of the own ones when partitioned)
TIME_SEARCH_PER_C_LOCAL = 1.02e-6
TIME_SHELL_BUILD_PER_C_LOCAL = 0.02e-6
TIME_ASSEMBLY_PER_C_LOCAL = 2.2e-6
TIME_PRODUCT_PER_CN_LOCAL = 30e-9    # shell: compiled product, scatters and Krylov-Schur (ncv 12), per (c + n)
TIME_PRODUCT_ASSEMBLED = (45e-9, 290e-9)  # per (C + N)/P and per N/P (ncv 32)
TIME_BOUNDS_PER_CN_LOCAL = 1.0e-6


def _check(name: str, value, low: float) -> None:
    from dtcrit.errors import InputError

    if isinstance(value, bool) or not isinstance(value, (int, float)) or not value > low:
        raise InputError(name, f"must be a number > {low:g}, got {value!r}")


def _memory(n: float, c: float, p: int, matrix: str, source: str, partitioned: bool) -> dict[str, float]:
    n_loc, c_loc = n / p, c / p
    held = n_loc if partitioned else n
    start = GENERATED_BASE if source == "generated" else BASE
    inp = start + (HELD_PER_N[source] * n_loc if partitioned else INPUT_PER_N[source] * n)
    mem = {"input": inp, "contacts": BASE + SEARCH_BASE + SEARCH_PER_N * held + SEARCH_PER_C_LOCAL * c_loc}
    if matrix == "shell":
        mem["solve"] = SHELL_BASE + SHELL_PER_N_LOCAL * n_loc + SHELL_PER_C_LOCAL * c_loc
        mem["bounds"] = mem["solve"] + BOUNDS_BASE + BOUNDS_SLOPE * n_loc
    else:
        mem["assembly"] = BASE + ASSEMBLED_PER_CN_LOCAL * (c_loc + n_loc)
        extra = 9 if p == 1 else 18
        mem["solve"] = mem["assembly"] + 48.0 * (ASSEMBLED_NCV + extra) * n_loc
    return mem


def _time(n: float, c: float, p: int, matrix: str, source: str, partitioned: bool,
          products: float) -> dict[str, float]:
    n_loc, c_loc = n / p, c / p
    t = {"input": TIME_HELD_PER_N[source] * n_loc if partitioned else TIME_INPUT_PER_N[source] * n,
         "contacts": TIME_SEARCH_PER_N * (n_loc if partitioned else n) + TIME_SEARCH_PER_C_LOCAL * c_loc}
    if matrix == "shell":
        t["assembly"] = TIME_SHELL_BUILD_PER_C_LOCAL * c_loc
        t["solve"] = products * TIME_PRODUCT_PER_CN_LOCAL * (c_loc + n_loc)
        t["bounds"] = TIME_BOUNDS_PER_CN_LOCAL * (c_loc + n_loc)
    else:
        t["assembly"] = TIME_ASSEMBLY_PER_C_LOCAL * c_loc
        t["solve"] = products * (TIME_PRODUCT_ASSEMBLED[0] * (c_loc + n_loc) + TIME_PRODUCT_ASSEMBLED[1] * n_loc)
    return t


def cluster_model(n: float, coordination: float, ranks: int, matrix: str = "shell", input: str = "text",
                  partitioned: bool = False, products: float = DEFAULT_PRODUCTS) -> dict:
    """Per-rank peak memory and wall time, by stage, of ``dtcrit packing --backend slepc``.

    Parameters
    ----------
    n : float
        Particles ``N`` (> 0).
    coordination : float
        Mean coordination ``z`` (> 0); contacts ``C = z N / 2``.
    ranks : int
        MPI ranks ``P`` (> 0).
    matrix : str
        ``"shell"`` (matrix-free, the default route) or ``"assembled"`` (``--slepc-matrix``).
    input : str
        ``"text"`` (a LAMMPS dump), ``"npz"`` (a ``dtcrit-spheres/1`` file, always read in
        pieces) or ``"generated"`` (``--random``, built whole on every rank).
    partitioned : bool
        ``--partitioned-read`` of a text dump: each rank holds only its slab and halo (implied by
        ``"npz"``).
    products : float
        Matrix-vector products of the eigen-solve (~130 for a disordered packing; more for
        lattice-like ones, docs/howto/mpi.md).

    Returns
    -------
    dict
        ``memory_mib`` and ``time_s`` (stage -> value, per rank), ``peak_mib`` and its ``peak_stage``,
        ``total_s``, ``contacts`` and the inputs.
    """
    from dtcrit.errors import InputError

    _check("N", n, 0)
    _check("cn", coordination, 0)
    _check("ranks", ranks, 0)
    _check("products", products, 0)
    if int(ranks) != ranks:
        raise InputError("ranks", f"must be a whole number, got {ranks!r}")
    if matrix not in MATRICES:
        raise InputError("matrix", f"unknown {matrix!r}; choose one of {', '.join(MATRICES)}")
    if input not in INPUTS:
        raise InputError("input", f"unknown {input!r}; choose one of {', '.join(INPUTS)}")
    if partitioned and input == "generated":
        raise InputError("partitioned", "a generated packing (--random) is built whole on every rank")
    partitioned = partitioned or input == "npz"
    c = coordination * n / 2.0
    mem = {k: v / MIB for k, v in _memory(n, c, int(ranks), matrix, input, partitioned).items()}
    t = _time(n, c, int(ranks), matrix, input, partitioned, products)
    stage = max(mem, key=mem.__getitem__)
    return {"n": n, "coordination": coordination, "ranks": int(ranks), "matrix": matrix, "input": input,
            "partitioned": partitioned, "products": products, "contacts": c, "memory_mib": mem,
            "time_s": t, "peak_mib": mem[stage], "peak_stage": stage, "total_s": sum(t.values())}


def format_model(model: dict) -> str:
    """The model as a text table.

    Parameters
    ----------
    model : dict
        A ``cluster_model`` result.

    Returns
    -------
    str
        One line per stage: peak MiB per rank and seconds.
    """
    head = (f"N = {model['n']:.4g}, z = {model['coordination']:g}, C = {model['contacts']:.4g}, "
            f"P = {model['ranks']}, matrix = {model['matrix']}, input = {model['input']}"
            f"{' (partitioned)' if model['partitioned'] else ''}, products = {model['products']:g}")
    lines = [head, f"{'stage':<10} {'MiB/rank':>12} {'seconds':>12}"]
    for k in model["time_s"]:
        mib = model["memory_mib"].get(k)
        lines.append(f"{k:<10} {'-' if mib is None else format(mib, '.0f'):>12} {model['time_s'][k]:>12.3g}")
    lines.append(f"{'peak':<10} {model['peak_mib']:>12.0f} {model['total_s']:>12.3g}  ({model['peak_stage']})")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    """``python -m dtcrit.bench.cluster_model N --cn Z --ranks P``: print the model.

    Parameters
    ----------
    argv : list of str or None
        The arguments (default ``sys.argv[1:]``).

    Returns
    -------
    int
        0, or 2 after a one-line error on bad input.
    """
    from dtcrit.errors import InputError

    ap = argparse.ArgumentParser(prog="python -m dtcrit.bench.cluster_model", description=__doc__.split("\n")[0])
    ap.add_argument("n", type=float, help="particles N")
    ap.add_argument("--cn", type=float, default=6.0, help="mean coordination z (default 6)")
    ap.add_argument("--ranks", type=float, default=1, help="MPI ranks P")
    ap.add_argument("--matrix", choices=MATRICES, default="shell")
    ap.add_argument("--input", choices=INPUTS, default="text")
    ap.add_argument("--partitioned", action="store_true", help="--partitioned-read of a text dump (implied by --input npz)")
    ap.add_argument("--products", type=float, default=DEFAULT_PRODUCTS)
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args(argv)
    try:
        model = cluster_model(args.n, args.cn, args.ranks, args.matrix, args.input, args.partitioned,
                              args.products)
    except InputError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    print(json.dumps(model, indent=2) if args.json else format_model(model))
    return 0


if __name__ == "__main__":
    sys.exit(main())
