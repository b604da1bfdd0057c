"""Consistency and order of accuracy of a user-written scheme, in exact rational arithmetic (no SymPy).

The rules applied to the linear test ODE ``x' = v, v' = f(x, v) = -K x - C v`` (Peng et al. 2020,
Eq. (30); generator ``L = [[0, 1], [-K, -C]]``, eigenvalues ``lambda`` with ``lambda^2 + C lambda + K = 0``)
give ``z_{n+1} = G(h) z_n``.  Once the rules are dimensionally consistent
(``dtcrit.integrators.user_dimensions``) every state-free subexpression is a monomial ``c h^a``, so the
entries of ``G`` are Laurent polynomials in ``h`` with rational coefficients at rational ``K, C``;
they are computed exactly (``Fraction``).

Criterion (one-step form of Dahlquist's theory for the linear test problem):

* no negative power of ``h`` (``G`` has a limit ``G0`` as ``h -> 0``);
* two state variables ``(x, v)``: ``G(h) = I + h L + O(h^2)`` row by row, so the rule that breaks it
  is named;
* with history variables: ``G0`` has the eigenvalue 1 exactly twice and semisimple
  (``rank(G0 - I) = d - 2``), the principal eigenvalues of ``G(h)`` then are ``e^{h lambda} + O(h^{p+1})``;
* the order ``p`` is read from ``P(e^{h lambda}, h) = O(h^{p+2})`` with ``P(mu, h) = det(mu I - G(h))``
  (``P`` has the principal factor ``(mu - mu_+)(mu - mu_-)``, ``mu_+ - mu_- ~ h (lambda_+ - lambda_-)``,
  and a factor that is a unit at ``mu = 1``); ``p >= 1`` is consistency.

``P`` is formed by Berkowitz's division-free algorithm.  Each coefficient of ``h^m`` in
``P(e^{h lambda_+}, h)`` is, by dimensional homogeneity, a homogeneous polynomial of degree ``m`` in
``(lambda_+, lambda_-)``; it is tested at the roots ``(-t, -1)`` for ``len(RATIOS)`` distinct ratios
``t`` (both roots each), which proves it zero for ``m < len(RATIOS)``.  The undamped order uses
``K = 1, C = 0, lambda = i``.
"""
from __future__ import annotations

from fractions import Fraction
from math import factorial

from dtcrit.errors import InputError

RATIOS = tuple(Fraction(a, b) for a, b in ((2, 1), (3, 1), (5, 1), (1, 2), (7, 3), (11, 4), (1, 3), (13, 5),
                                            (17, 7), (4, 1), (19, 3), (23, 6), (3, 10)))
MAX_M = len(RATIOS) - 1  # P(e^{h lambda}) is examined up to h^MAX_M: orders up to MAX_M - 2
MAX_ORDER = MAX_M - 2


# ---- Laurent polynomials in h: {exponent: Fraction} ------------------------------------------

def _add(a: dict, b: dict, sign: int = 1) -> dict:
    out = dict(a)
    for k, c in b.items():
        out[k] = out.get(k, 0) + sign * c
    return {k: c for k, c in out.items() if c != 0}


def _mul(a: dict, b: dict) -> dict:
    out: dict = {}
    for i, x in a.items():
        for j, y in b.items():
            out[i + j] = out.get(i + j, 0) + x * y
    return {k: c for k, c in out.items() if c != 0}


def _div(a: dict, b: dict) -> dict:
    if len(b) != 1:  # dimensional consistency makes every state-free denominator a monomial c h^k
        raise ValueError("denominator is not a monomial in h")
    (k, c), = b.items()
    return {i - k: x / c for i, x in a.items()}


def _value(e, env: dict, K: Fraction, C: Fraction):
    """The tree ``e`` as a linear form ``{state index: Laurent poly}`` (const trees: ``{None: poly}``)."""
    tag = e[0]
    if tag == "num":
        return {None: {0: Fraction(e[1])}} if e[1] != 0 else {None: {}}
    if tag == "h":
        return {None: {1: Fraction(1)}}
    if tag == "var":
        return env[e[1]]
    if tag == "f":
        a, b = env[e[1]], env[e[2]]
        out = {j: {k: -K * c for k, c in p.items()} for j, p in a.items()}
        for j, p in b.items():
            out[j] = _add(out.get(j, {}), {k: -C * c for k, c in p.items()})
        return out
    if tag == "neg":
        return {j: {k: -c for k, c in p.items()} for j, p in _value(e[1], env, K, C).items()}
    a, b = _value(e[1], env, K, C), _value(e[2], env, K, C)
    if tag in "+-":
        out = dict(a)
        for j, p in b.items():
            out[j] = _add(out.get(j, {}), p, 1 if tag == "+" else -1)
        return out
    if tag == "*":
        if None in a and None in b:
            return {None: _mul(a[None], b[None])}
        con, lin = (a, b) if None in a else (b, a)
        return {j: _mul(p, con[None]) for j, p in lin.items()}
    return {j: _div(p, b[None]) for j, p in a.items()}


def amplification_exact(state, rules, K, C) -> tuple[list[list[dict]], list[int]]:
    """``G[i][j]`` as a Laurent polynomial in ``h`` (exact) at rational ``K, C``, and per rule the
    lowest power of ``h`` its value carries (to name a rule with a term in 1/h).

    Parameters
    ----------
    state : tuple of str
        The scheme's state variables (position first, then velocity, then history variables).
    rules : sequence of tuple
        The parsed rules, ``(target, tree)`` pairs in order.
    K : fractions.Fraction
        Stiffness per unit mass of the test ODE ``x'' = -K x - C x'``.
    C : fractions.Fraction
        Damping per unit mass of the test ODE.

    Returns
    -------
    tuple
        ``(G, lowest)``: ``G[i][j]`` a dict ``{power of h: Fraction}``, and the lowest power of ``h`` per rule.
    """
    d = len(state)
    env = {n: {j: {0: Fraction(1)}} for j, n in enumerate(state)}
    lowest = []
    for target, tree in rules:
        val = {j: p for j, p in _value(tree, env, K, C).items() if j is not None and p}
        env[target] = val
        lowest.append(min((k for p in val.values() for k in p), default=0))
    G = [[env[state[i]].get(j, {}) for j in range(d)] for i in range(d)]
    return G, lowest


def _charpoly(G: list[list[dict]]) -> list[dict]:
    """Coefficients ``[1, c1, ..., cd]`` of ``det(mu I - G) = mu^d + c1 mu^{d-1} + ...`` (Berkowitz)."""
    C = [{0: Fraction(1)}, {k: -c for k, c in G[0][0].items()}]
    for r in range(1, len(G)):
        R, S, a = G[r][:r], [G[i][r] for i in range(r)], G[r][r]
        vec = [{0: Fraction(1)}, {k: -c for k, c in a.items()}]
        w = S
        for _ in range(r):
            s: dict = {}
            for x, y in zip(R, w):
                s = _add(s, _mul(x, y))
            vec.append({k: -c for k, c in s.items()})
            w = [_sum_row(G[i][:r], w) for i in range(r)]
        C = [_sum(_mul(vec[i - j], C[j]) for j in range(0, min(i, r) + 1)) for i in range(r + 2)]
    return C


def _sum_row(row, w):
    return _sum(_mul(x, y) for x, y in zip(row, w))


def _sum(items) -> dict:
    out: dict = {}
    for p in items:
        out = _add(out, p)
    return out


def _residual_lowest(P: list[dict], lam: tuple[Fraction, Fraction]) -> int:
    """Lowest power m <= MAX_M of h with a non-zero coefficient in ``P(e^{h lam}, h)`` (MAX_M + 1: none).

    ``lam = (re, im)``; ``P`` as from ``_charpoly``: the coefficient of ``mu^{d-i}`` is ``P[i]``.
    """
    d = len(P) - 1
    total = [[Fraction(0), Fraction(0)] for _ in range(MAX_M + 1)]
    for i, p in enumerate(P):
        k = d - i
        z = (k * lam[0], k * lam[1])  # e^{h k lam} = sum (h z)^n / n!
        power = (Fraction(1), Fraction(0))
        for n in range(MAX_M + 1):
            for a, c in p.items():
                if 0 <= a and a + n <= MAX_M:
                    total[a + n][0] += c * power[0] / factorial(n)
                    total[a + n][1] += c * power[1] / factorial(n)
            power = (power[0] * z[0] - power[1] * z[1], power[0] * z[1] + power[1] * z[0])
    return next((m for m, (re, im) in enumerate(total) if re or im), MAX_M + 1)


def _rank(M: list[list[Fraction]]) -> int:
    M = [row[:] for row in M]
    rank, cols = 0, len(M[0]) if M else 0
    for c in range(cols):
        piv = next((r for r in range(rank, len(M)) if M[r][c] != 0), None)
        if piv is None:
            continue
        M[rank], M[piv] = M[piv], M[rank]
        for r in range(len(M)):
            if r != rank and M[r][c] != 0:
                q = M[r][c] / M[rank][c]
                M[r] = [x - q * y for x, y in zip(M[r], M[rank])]
        rank += 1
    return rank


def _form(row: list, names, h_power: int) -> str:
    terms = []
    for n, p in zip(names, row):
        c = p.get(h_power, 0)
        if c:
            terms.append(f"{'-' if c < 0 else '+'} {'' if abs(c) == 1 else str(abs(c)) + ' '}{n}")
    text = " ".join(terms).lstrip("+ ") if terms else "0"
    return text if not text.startswith("- ") else "-" + text[2:]


def order_of_accuracy(state, rules, keys, where: str) -> tuple[int, int]:
    """(order with damping, order undamped) of a dimensionally consistent scheme, or InputError
    naming the rule (``keys[i]``) or ``where.update`` when the scheme is not consistent with
    ``x'' = f(x, v)``.  Orders above ``MAX_ORDER`` are reported as ``MAX_ORDER``.

    Parameters
    ----------
    state : tuple of str
        The scheme's state variables (position first, then velocity, then history variables).
    rules : sequence of tuple
        The parsed rules, ``(target, tree)`` pairs in order.
    keys : sequence of str
        The input key of each rule, named in the error.
    where : str
        The input key of the scheme's table.

    Returns
    -------
    tuple of (int, int)
        The order of accuracy with damping and without.
    """
    d = len(state)
    if d < 2:
        raise InputError(f"{where}.state", "needs a position and a velocity (x'' = f(x, v) is second order)")
    samples = [(t, Fraction(1)) for t in RATIOS]  # roots (-t, -1): K = t, C = 1 + t
    orders = []
    for lam_p, lam_m in samples:
        K, C = lam_p * lam_m, lam_p + lam_m
        G, lowest = amplification_exact(state, rules, K, C)
        if any(k < 0 for row in G for p in row for k in p):
            i = next(i for i, k in enumerate(lowest) if k < 0)
            raise InputError(keys[i], "the value has a term in 1/h: the update does not tend to the old state as "
                             "h -> 0, so it does not discretise x'' = f(x, v)")
        if d == 2:
            _check_rows(state, rules, keys, where, G, K, C)
        else:
            _check_history(G, where)
        P = _charpoly(G)
        orders.append(min(_residual_lowest(P, (-lam_p, Fraction(0))), _residual_lowest(P, (-lam_m, Fraction(0)))) - 2)
    p = min(orders)
    if p < 1:
        raise InputError(f"{where}.update", "not consistent with x'' = f(x, v): the principal eigenvalues of the "
                         "amplification matrix are not e^{h lambda} + O(h^2) (lambda^2 + C lambda + K = 0)")
    G, _ = amplification_exact(state, rules, Fraction(1), Fraction(0))
    q = _residual_lowest(_charpoly(G), (Fraction(0), Fraction(1))) - 2
    return min(p, MAX_ORDER), min(max(q, p), MAX_ORDER)


def h_degree(state, rules) -> int:
    """Highest power of h in the characteristic polynomial det(mu I - G(h)) (at the first sample point).

    Parameters
    ----------
    state : tuple of str
        The scheme's state variables (position first, then velocity, then history variables).
    rules : sequence of tuple
        The parsed rules, ``(target, tree)`` pairs in order.

    Returns
    -------
    int
        The degree in ``h``.
    """
    G, _ = amplification_exact(state, rules, RATIOS[0], RATIOS[0] + 1)
    return max((k for p in _charpoly(G) for k in p), default=0)


def _check_rows(state, rules, keys, where, G, K, C) -> None:
    """Two-variable schemes: ``G = I + h L + O(h^2)``; name the last rule assigning the bad row."""
    want = [[{0: Fraction(1)}, {1: Fraction(1)}], [{1: -K}, {0: Fraction(1), 1: -C}]]
    for i, n in enumerate(state):
        got = [{k: c for k, c in p.items() if k <= 1} for p in G[i]]
        if got != want[i]:
            assigning = [key for (t, _), key in zip(rules, keys) if t == n]
            key = assigning[-1] if assigning else f"{where}.update"
            need = f"{state[0]} + h {state[1]}" if i == 0 else f"{state[1]} + h f({state[0]}, {state[1]})"
            zero, one = _form(G[i], state, 0), _form(G[i], state, 1)
            raise InputError(key, f"not consistent with x'' = f(x, v): to first order the step gives {n} -> {zero}"
                             + (f" + h ({one})" if one != "0" else "") + f" at f = -{K} {state[0]} - {C} {state[1]}; it must give {need}"
                             + ("" if assigning else f" ('{n}' is never assigned)"))


def _check_history(G, where) -> None:
    d = len(G)
    G0 = [[G[i][j].get(0, Fraction(0)) for j in range(d)] for i in range(d)]
    shifted = [[G0[i][j] - (1 if i == j else 0) for j in range(d)] for i in range(d)]
    P0 = [p.get(0, Fraction(0)) for p in _charpoly([[{0: x} if x else {} for x in row] for row in G0])]
    value = [sum(P0[i] * _falling(d - i, r) for i in range(d + 1)) for r in range(3)]  # P0^(r)(1)
    if value[0] or value[1] or not value[2] or _rank(shifted) != d - 2:
        raise InputError(f"{where}.update", "not consistent with x'' = f(x, v): as h -> 0 the amplification matrix "
                         "must keep the position and velocity (eigenvalue 1 exactly twice, semisimple) and damp the "
                         "history (found otherwise)")


def _falling(n: int, r: int) -> int:
    out = 1
    for i in range(r):
        out *= n - i
    return out
