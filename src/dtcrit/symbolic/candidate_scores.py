"""Reconstruction of the Figure 2 configurations of Peng et al. (2020): every candidate against the printed entries.

Each candidate of :func:`dtcrit.symbolic.tip_configurations.candidate_configurations` is scored by how
many legible entries of Eqs. (22)-(24) and (50)-(52) (``dtcrit.symbolic.printed_entries``) the general
kinematics reproduces with it.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Any, Callable

import sympy as sp

from dtcrit.symbolic.kinematics import RigidParticle, relative_accelerations, to_global
from dtcrit.symbolic.printed_entries import ENTRY_INDEX, PANELS, parse_reading, printed_entries, printed_symbols
from dtcrit.symbolic.tip_configurations import P1, P2, candidate_configurations


@dataclass(frozen=True)
class CandidateScore:
    """How many legible printed entries one candidate reproduces, per part, and the matches.

    Parameters
    ----------
    panel : str
        The Figure 2 panel.
    index : int
        The candidate's index in :func:`dtcrit.symbolic.tip_configurations.candidate_configurations`.
    w_is_local : bool
        Omega symbols read as local (body) components.
    arm_length : bool
        Printed a2 read as the length of particle 2's arm (its half-length along the arm) rather than
        literally as its largest half-length.
    matches : dict
        Entry name -> index of the reading it reproduces (-1: differs, None: illegible).
    """

    panel: str
    index: int
    w_is_local: bool
    arm_length: bool
    matches: dict

    @property
    def total(self) -> int:
        """Number of legible entries reproduced, over all parts."""
        return sum(1 for v in self.matches.values() if v is not None and v >= 0)

    def part(self, prefix: str) -> int:
        """Number of entries of one part reproduced.

        Parameters
        ----------
        prefix : str
            Start of the part's entry names (``"A_"``, ``"Omega_"``, ``"wdot_"``).

        Returns
        -------
        int
            The count.
        """
        return sum(1 for k, v in self.matches.items() if k.startswith(prefix) and v is not None and v >= 0)


@lru_cache(maxsize=None)
def _general_pair_function(w_is_local: bool):
    """NumPy function of (particle symbols..., R1 (9), R2 (9), local arm 1 (3), local arm 2 (3))
    returning the 9 entries of A, the 3 of Omega and the 3 of wdot_c, from the general kinematics.
    """
    import numpy as np  # noqa: F401  (lambdify target)

    Rs = [sp.Matrix(3, 3, sp.symbols(f"R{j}_0:9")) for j in (1, 2)]
    arms = [sp.Matrix(sp.symbols(f"s{j}_0:3")) for j in (1, 2)]
    ps = [RigidParticle(s.m, s.inertia, R, to_global(R, arm), s.w, w_is_local) for s, R, arm in zip((P1, P2), Rs, arms)]
    # xdd_c is affine in F: column k of A is xdd_c(F = e_k) - xdd_c(F = 0)
    xdd0, wdot0 = relative_accelerations(ps[0], ps[1], (0, 0, 0))
    cols = [relative_accelerations(ps[0], ps[1], tuple(sp.eye(3)[:, k]))[0] - xdd0 for k in range(3)]
    exprs = list(sp.Matrix.hstack(*cols)) + list(xdd0) + list(wdot0)
    names = sorted(printed_symbols().items())
    args = [s for _, s in names] + list(Rs[0]) + list(Rs[1]) + list(arms[0]) + list(arms[1])
    return [n for n, _ in names], sp.lambdify(args, exprs, modules="numpy")


@lru_cache(maxsize=None)
def score_candidates(points: int = 2, seed: int = 20200) -> tuple[CandidateScore, ...]:
    """Score every candidate of :func:`candidate_configurations` against every panel's printed
    entries, for both readings of the omega symbols and both readings of printed ``a2``.

    The general kinematics is evaluated in floating point at ``points`` random parameter sets
    (all values in [0.5, 3]); an entry matches a reading when they agree to 1e-10 relative at
    all points.  Candidates chosen this way are re-checked exactly with SymPy in the records.
    """
    import numpy as np

    cands = candidate_configurations()
    N = len(cands)
    rng = np.random.default_rng(seed)
    R1 = np.array([[float(x) for x in c.R1] for c in cands]).T
    R2 = np.array([[float(x) for x in c.R2] for c in cands]).T
    length_name = {0: "a2", 1: "b2", 2: "c2"}
    out = []
    values = {}
    for lw in (False, True):
        names, fn = _general_pair_function(lw)
        for k in range(points):
            pt = {n: float(v) for n, v in zip(names, rng.uniform(0.5, 3.0, len(names)))}
            s1, s2 = np.zeros((3, N)), np.zeros((3, N))
            for n, c in enumerate(cands):
                s1[c.arm1[0], n] = c.arm1[1] * pt["abc"[c.arm1[0]] + "1"]
                s2[c.arm2[0], n] = c.arm2[1] * pt["abc"[c.arm2[0]] + "2"]
            res = fn(*([np.full(N, pt[n]) for n in names] + list(R1) + list(R2) + list(s1) + list(s2)))
            values[(lw, k)] = (pt, [np.broadcast_to(np.asarray(r, float), (N,)) for r in res])
    position = {"A": lambda i: 4 * i, "Omega": lambda i: 9 + i, "wdot_c": lambda i: 12 + i}
    symbols = printed_symbols()
    order = sorted(symbols, key=lambda n: str(symbols[n]))
    arm2_length = np.array([length_name[c.arm2[0]] for c in cands])
    printed_values: dict[tuple, np.ndarray] = {}
    printed_functions: dict[str, Callable[..., Any]] = {}

    def printed(text: str, lw: bool, k: int, arm_len: bool) -> np.ndarray:
        key = (text, lw, k, arm_len)
        if key not in printed_values:
            if text not in printed_functions:
                printed_functions[text] = sp.lambdify([symbols[n] for n in order], parse_reading(text), modules="numpy")
            fn = printed_functions[text]
            pt = values[(lw, k)][0]
            args = {n: np.full(N, pt[n]) for n in order}
            if arm_len:
                args["a2"] = np.array([pt[name] for name in arm2_length])
            printed_values[key] = np.broadcast_to(np.asarray(fn(*[args[n] for n in order]), float), (N,))
        return printed_values[key]

    for panel, eqs in PANELS.items():
        entries = [e for eq in eqs for e in printed_entries(eq)]
        for lw in (False, True):
            for arm_len in (False, True):
                table = {}
                for e in entries:
                    if not e.legible:
                        table[e.entry] = np.full(N, -2)
                        continue
                    part, i = ENTRY_INDEX[e.entry]
                    got = np.full(N, -1)
                    for r in reversed(range(len(e.readings))):
                        ok = np.ones(N, dtype=bool)
                        for k in range(points):
                            res = values[(lw, k)][1]
                            ok &= np.isclose(res[position[part](i)], printed(e.readings[r], lw, k, arm_len),
                                             rtol=1e-10, atol=1e-12)
                        got[ok] = r
                    table[e.entry] = got
                for n in range(N):
                    matches = {k: (None if v[n] == -2 else int(v[n])) for k, v in table.items()}
                    out.append(CandidateScore(panel, n, lw, arm_len, matches))
    return tuple(out)


def best_candidates(panel: str) -> list[CandidateScore]:
    """The highest-scoring candidates of a panel (ties kept, in a fixed order): most reproduced
    legible entries; ties broken by preferring the literal reading of a2, then admissible
    contacts (opposite normals at the two tips).

    Parameters
    ----------
    panel : str
        The Figure 2 panel.

    Returns
    -------
    list of CandidateScore
        The best candidates.
    """
    cands = candidate_configurations()
    scores = [s for s in score_candidates() if s.panel == panel]
    top = max(s.total for s in scores)
    best = [s for s in scores if s.total == top]
    best = [s for s in best if not s.arm_length] or best
    return [s for s in best if cands[s.index].normals_opposite()] or best
