"""Fuzz of user-written integrators: every printed step is confirmed independently, or refused in one line.

Random rule sets are drawn from the allow-list (numbers, + - *, h, 1/h, state variables, temporaries,
f(a, b)), with and without h, some shaped like real schemes with perturbed coefficients.  For each, at
a stiffness K, damping ratio zeta and inverse mass spanning many decades, dtcrit either refuses in one
line (InputError) or prints a step dt.  The reference is this test's own arithmetic: it applies the
drawn rules (kept as Python closures, not parsed from the text) to the unit states at 30 digits in
physical units (h in seconds, K = k A in 1/s^2, C = c A in 1/s) and eigen-solves the amplification
matrix with mpmath: stable (rho <= 1 + 1e-15) at 0.99 dt and unstable (rho > 1) at 1.01 dt.
"""
from __future__ import annotations

import math

import mpmath as mp
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from dtcrit.errors import InputError
from dtcrit.integrators.stability import critical_dt
from dtcrit.integrators.user_rules import parse_integrator, register

DIM = {"x": 0, "v": -1, "q": -2}
COEFS = ["1", "1", "1", "2", "0.5", "3/2", "-1", "1/6"]


def _term(draw, target_dim, known, dims, shaped):
    """One term ``(text, (coef, power, fn))`` of a rule assigning a quantity of dimension ``target_dim``."""
    coef = draw(st.sampled_from(COEFS))
    velocity_like = {a: [b for b in known if dims[b] == dims[a] - 1] for a in known}
    if draw(st.booleans()) and (not shaped or any(velocity_like.values())):
        a = draw(st.sampled_from([a for a in known if velocity_like[a]] if shaped else known))
        b = draw(st.sampled_from(velocity_like[a] if shaped else known))
        atom, fn, dim = f"f({a}, {b})", (lambda env, K, C, a=a, b=b: -K * env[a] - C * env[b]), dims[a] - 2
    else:
        var = draw(st.sampled_from(known))
        atom, fn, dim = var, (lambda env, K, C, var=var: env[var]), dims[var]
    power = target_dim - dim if shaped else draw(st.integers(-1, 3))
    hp = "*h" * power if power >= 0 else "/h" * -power
    return f"({coef}){hp}*{atom}", (_coef(coef), power, fn)


def _coef(text: str):
    num, _, den = text.partition("/")
    return mp.mpf(num) / (mp.mpf(den) if den else 1)


@st.composite
def schemes(draw):
    """(state, rule texts, closures) of a random scheme; ``shaped`` ones are dimensionally consistent."""
    state = ["x", "v", "q"][: draw(st.integers(2, 3))]
    shaped = draw(st.booleans())
    known, dims = list(state), dict(DIM)
    texts, refs = [], []
    if draw(st.sampled_from([True, True, True, False])):  # a real scheme's skeleton, perturbed
        skeleton = [("v", "f(x, v)"), ("x", "v")] if draw(st.booleans()) else [("x", "v"), ("v", "f(x, v)")]
        for target, atom in skeleton:
            coef = draw(st.sampled_from(["1"] * 6 + COEFS))
            power = 1 if shaped or draw(st.booleans()) else draw(st.integers(0, 2))
            fn = ((lambda env, K, C: -K * env["x"] - C * env["v"]) if atom.startswith("f")
                  else (lambda env, K, C: env["v"]))
            texts.append(f"{target} = {target} + ({coef}){'*h' * power}*{atom}")
            refs.append((target, [(mp.mpf(1), 0, lambda env, K, C, t=target: env[t]), (_coef(coef), power, fn)]))
        if "q" in state:  # a history variable: the last force (paper-eq40 style), read by a later rule or not
            texts.append("q = f(x, v)")
            refs.append(("q", [(mp.mpf(1), 0, lambda env, K, C: -K * env["x"] - C * env["v"])]))
    for _ in range(draw(st.sampled_from([0, 0, 1, 2])) if texts else 1):
        target = draw(st.sampled_from(state + ["t1", "t2"]))
        tdim = dims.get(target, draw(st.sampled_from([0, -1, -2])))
        parts = [_term(draw, tdim, known, dims, shaped) for _ in range(draw(st.integers(1, 3)))]
        texts.append(f"{target} = " + " + ".join(t for t, _ in parts))
        refs.append((target, [r for _, r in parts]))
        if target not in known:
            known.append(target)
            dims[target] = tdim
    return state, texts, refs


def _rho(state, refs, h, K, C):
    """Spectral radius of the drawn rules' amplification matrix at the physical step h (30 digits)."""
    d = len(state)
    G = mp.matrix(d, d)
    for j in range(d):
        env = {n: mp.mpf(1 if i == j else 0) for i, n in enumerate(state)}
        for target, parts in refs:
            env[target] = sum(c * h**p * fn(env, K, C) for c, p, fn in parts)
        for i, n in enumerate(state):
            G[i, j] = env[n]
    return max(abs(e) for e in mp.eig(G, left=False, right=False))


COUNTS = {"refused": 0, "step": 0, "zero": 0}


@settings(max_examples=300, derandomize=True, deadline=None, suppress_health_check=list(HealthCheck))
@given(schemes(), st.floats(-6, 14), st.sampled_from([0.0, 1e-4, 0.03, 0.5, 1.0, 7.0, 300.0]), st.floats(-3, 6))
def test_every_printed_step_is_confirmed_by_an_independent_eigen_solve(scheme, log_k, zeta, log_a):
    state, texts, refs = scheme
    assume(any(t in state for t, _ in refs))
    k, A = 10.0**log_k, 10.0**log_a
    c = 2 * zeta * math.sqrt(k / A)
    name = f"fuzz-{abs(hash(tuple(texts))) % 10**12}"
    try:
        integ = parse_integrator({"name": name, "state": state, "update": texts}, "integrator")
        register(integ)
        dt = critical_dt(name, k, c, A).dt
    except InputError as e:
        assert "\n" not in str(e) and e.key.startswith(("integrator", "k"))
        COUNTS["refused"] += 1
        return
    assert math.isfinite(dt) and dt >= 0, dt
    if dt == 0:
        COUNTS["zero"] += 1
        return
    COUNTS["step"] += 1
    with mp.workdps(30):
        K, C = mp.mpf(k) * mp.mpf(A), mp.mpf(c) * mp.mpf(A)
        assert _rho(state, refs, mp.mpf(0.99) * dt, K, C) <= 1 + mp.mpf(10) ** -15, (texts, dt)
        assert _rho(state, refs, mp.mpf(1.01) * dt, K, C) > 1, (texts, dt)


def test_the_fuzz_reaches_printed_steps():
    """The fuzz above must exercise both outcomes (run after it in file order)."""
    if COUNTS["step"] + COUNTS["refused"] == 0:  # run alone: nothing to check
        test_every_printed_step_is_confirmed_by_an_independent_eigen_solve()
    assert COUNTS["step"] >= 10 and COUNTS["refused"] >= 10, COUNTS
