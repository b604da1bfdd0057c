"""Dimensional consistency of user-written update rules (runtime; no SymPy).

Every quantity of a rule is a length times a power of time: the position has time exponent 0,
the velocity -1, the step ``h`` +1 (a number 0), and the force ``f(a, b) = -K a - C b`` needs
``e(b) = e(a) - 1`` and returns ``e(a) - 2`` (``K`` is 1/s^2, ``C`` 1/s; Peng et al. 2020, Eq. (30)).
The exponents of history variables and temporaries are inferred (a weighted union-find);
``+`` and ``-`` need equal exponents, and each state variable must come back with its own.

Why it is required: the step is analysed in scaled units (omega = 1, tau = omega h, zeta); a rule
with exponents ``e_i`` obeys ``G_phys(h, K, C) = D^-1 G(omega h, 1, 2 zeta) D`` with
``D = diag(omega^e_i)``, so the scaled and physical amplification matrices have the same spectrum
exactly when the rules are dimensionally consistent.  A rule that drops or doubles ``h``
(``v = v + f(x, v)``, ``x = x + v``) would otherwise get a step unrelated to the scheme it runs.
It also makes every state-free subexpression a monomial ``c h^a``, so no denominator can vanish at
a positive step.
"""
from __future__ import annotations

from dtcrit.errors import InputError

_ABS = "<abs>"  # the root of known exponents (e = 0 is a position, or a number for constants)


class _Units:
    """Weighted union-find: ``find(n) = (root, off)`` with ``e(n) = e(root) + off``."""

    def __init__(self):
        self.parent: dict[str, tuple[str, int]] = {}

    def find(self, n: str) -> tuple[str, int]:
        if n == _ABS or n not in self.parent:
            return n, 0
        p, off = self.parent[n]
        root, off2 = self.find(p)
        self.parent[n] = (root, off + off2)
        return root, off + off2

    def unify(self, a: tuple[str, int], b: tuple[str, int]) -> bool:
        """Make ``e(a) == e(b)`` (each ``(node, offset)``); False when they are fixed and differ."""
        (ra, oa), (rb, ob) = self.find(a[0]), self.find(b[0])
        oa, ob = oa + a[1], ob + b[1]
        if ra == rb:
            return oa == ob
        if ra == _ABS:
            ra, oa, rb, ob = rb, ob, ra, oa
        self.parent[ra] = (rb, ob - oa)
        return True

    def value(self, a: tuple[str, int]) -> tuple[str, int]:
        r, o = self.find(a[0])
        return r, o + a[1]


def describe(e: tuple[str, int], const: bool = False) -> str:
    """Words for a time exponent: 'a position', 'a velocity', 'h^2', ...

    Parameters
    ----------
    e : tuple of (str, int)
        ``(root, k)``: the quantity (the absolute time root or a history variable) and its time exponent.
    const : bool
        True for a state-free expression (a number or a power of ``h``).

    Returns
    -------
    str
        The words.
    """
    root, k = e
    if root != _ABS:
        return "a history quantity" if k == 0 else f"a history quantity times time^{k}"
    if const:
        return "a number" if k == 0 else ("a time (h)" if k == 1 else f"time^{k} (h^{k})")
    names = {0: "a position", -1: "a velocity", -2: "an acceleration", 1: "a position times a time"}
    return names.get(k, f"a position times time^{k}")


class _Refusal(Exception):
    pass


def _exp(e, units: _Units, version: dict[str, str]):
    """(exponent, is_const) of a checked tree (``dtcrit.integrators.user_rules``)."""
    tag = e[0]
    if tag == "num":
        return (_ABS, 0), True
    if tag == "h":
        return (_ABS, 1), True
    if tag == "var":
        return units.value((version[e[1]], 0)), False
    if tag == "f":
        a, b = units.value((version[e[1]], 0)), units.value((version[e[2]], 0))
        if not units.unify(b, (a[0], a[1] - 1)):
            raise _Refusal(f"f({e[1]}, {e[2]}) needs a velocity-like second argument (the first one's dimension "
                           f"divided by a time): '{e[2]}' is {describe(b)} and '{e[1]}' is {describe(a)}")
        return units.value((a[0], a[1] - 2)), False
    if tag == "neg":
        return _exp(e[1], units, version)
    (a, ca), (b, cb) = _exp(e[1], units, version), _exp(e[2], units, version)
    if tag in "+-":
        if not units.unify(a, b):
            raise _Refusal(f"'{tag}' joins {describe(units.value(a), ca)} and {describe(units.value(b), cb)}: "
                           "the rule is not dimensionally consistent (h is a time; is an h missing or extra?)")
        return units.value(a), ca
    if tag == "*":
        if ca and cb:
            return (_ABS, a[1] + b[1]), True
        lin, con = (b, a) if ca else (a, b)
        return units.value((lin[0], lin[1] + con[1])), False
    return units.value((a[0], a[1] - b[1])), ca  # '/': the parser allows a state-free denominator only


def check_dimensions(state: tuple[str, ...], rules, keys) -> None:
    """Refuse (InputError naming ``keys[i]``) the first rule that is not dimensionally consistent.

    ``rules`` are ``(target, tree)`` pairs; the first state variable is a position (time exponent 0)
    and the second, if any, a velocity (-1).

    Parameters
    ----------
    state : tuple of str
        The scheme's state variables.
    rules : sequence of tuple
        The parsed rules, ``(target, tree)`` pairs in order.
    keys : sequence of str
        The input key of each rule, named in the error.
    """
    units = _Units()
    version = {n: f"{n}@0" for n in state}
    units.unify((version[state[0]], 0), (_ABS, 0))
    if len(state) > 1:
        units.unify((version[state[1]], 0), (_ABS, -1))
    last = {}
    for i, ((target, tree), key) in enumerate(zip(rules, keys), 1):
        try:
            e, _ = _exp(tree, units, version)
        except _Refusal as exc:
            raise InputError(key, str(exc)) from None
        node = f"{target}@{i}"
        units.unify((node, 0), e)
        version[target] = node
        last[target] = key
    for n in state:
        if version[n] != f"{n}@0" and not units.unify((version[n], 0), (f"{n}@0", 0)):
            new, old = units.value((version[n], 0)), units.value((f"{n}@0", 0))
            raise InputError(last[n], f"'{n}' is {describe(old)} but is assigned {describe(new)}: the rule is not "
                             "dimensionally consistent (h is a time; is an h missing or extra?)")
