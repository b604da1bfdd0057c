"""Integrators a user writes in a scene: an ``[integrator]`` table parsed into an ``Integrator``.

```toml
[integrator]
name = "my-scheme"
state = ["x", "v"]                                # position first, then velocity, then any history
update = ["v = v + h*f(x, v)", "x = x + h*v"]     # in order; later rules see updated values
```

Each rule is ``target = expression``, read with Python's ``ast`` parser and then checked node by node
against an allow-list; nothing is ever evaluated as Python, and no SymPy parser sees the text.
Allowed: numbers (decimal literals are taken exactly, ``0.5`` is 1/2), ``+ - * /``, unary ``-`` and
``+``, parentheses, the step ``h``, the state variables, temporaries assigned by earlier rules, and
calls ``f(a, b)`` of the linear contact force ``f(x, v) = -K x - C v`` (Peng et al. 2020, Eq. (30))
whose two arguments are state variables or temporaries.  The step function is built by walking the
checked tree, so the ``Integrator`` works with every layer: the symbolic one (amplification matrix,
characteristic polynomial, exact boundary), the runtime (``dtcrit.integrators.spectral_route``) and
codegen (after ``register``).

Checked after parsing (``parse_integrator(check=True)``): dimensional consistency
(``dtcrit.integrators.user_dimensions``: h is a time, x a position, v a velocity), consistency with
``x'' = f(x, v)`` and the order of accuracy (``dtcrit.integrators.user_consistency``, exact rational
arithmetic); every step the runtime prints for the scheme is confirmed by stepping the rules in physical
units (``dtcrit.integrators.user_confirm``).

Refused, with one line naming the rule (``integrator.update[2]``) and the reason: a rule that is not
linear in the state (``x*v``, ``f(x, v)*v``, a state variable in a denominator) or not homogeneous (a
term without the state, ``v + h``), an implicit rule (a name read before the rule that assigns it,
``f`` of a not-yet-defined argument), an unknown name, any other syntax (calls of other functions,
attributes, subscripts, ``**``, comparisons, lambdas, strings ...), missing or malformed keys, and a
scheme that fails the checks above.
"""
from __future__ import annotations

import ast
import math
import re
from fractions import Fraction

from dtcrit.errors import InputError
from dtcrit.integrators.schemes import INTEGRATORS, USER_INTEGRATORS, Integrator, MatrixForce

KEYS = ("name", "state", "update")
RESERVED = ("h", "f")
MAX_STATE, MAX_RULES, MAX_RULE_CHARS, MAX_DIGITS = 6, 32, 400, 30
_IDENT = re.compile(r"[A-Za-z][A-Za-z0-9_]{0,31}\Z")
_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.-]{0,63}\Z")
_OPS = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/"}

# A checked expression is a tuple tree: ("num", Fraction) | ("h",) | ("var", name) |
# ("f", name, name) | ("neg", e) | (op, e1, e2) with op in "+-*/".  ``kind`` is "const" (numbers and
# h only) or "lin" (linear and homogeneous in the state).


class _Refusal(Exception):
    pass


def _check_ident(value, key: str, what: str) -> str:
    if not isinstance(value, str) or not _IDENT.match(value) or value in RESERVED:
        raise InputError(key, f"{what} must be a name of letters, digits and '_' starting with a letter, "
                              f"at most 32 characters, not 'h' or 'f' (got {value!r:.60})")
    return value


def _number(node: ast.Constant) -> Fraction:
    v = node.value
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise _Refusal(f"only numbers are allowed as constants (got {type(v).__name__})")
    if isinstance(v, float) and not math.isfinite(v):
        raise _Refusal("a number must be finite")
    q = Fraction(repr(v)) if isinstance(v, float) else Fraction(v)
    if len(str(q.numerator)) > MAX_DIGITS or len(str(q.denominator)) > MAX_DIGITS:
        raise _Refusal(f"a number has more than {MAX_DIGITS} digits")
    return q


def _const_value(e, h: float):
    """Value of a state-free tree at a sample step (to find a denominator that is identically 0)."""
    tag = e[0]
    if tag == "num":
        return float(e[1])
    if tag == "h":
        return h
    if tag == "neg":
        return -_const_value(e[1], h)
    a, b = _const_value(e[1], h), _const_value(e[2], h)
    return math.nan if tag == "/" and b == 0 else _plain(tag, a, b)


def _expr(node, known: set[str], later: dict[str, int]):
    """(tree, kind) of an allowed expression node, or _Refusal with the reason."""
    if isinstance(node, ast.Constant):
        return ("num", _number(node)), "const"
    if isinstance(node, ast.Name):
        if node.id == "h":
            return ("h",), "const"
        if node.id == "f":
            raise _Refusal("'f' is the force: call it as f(x, v)")
        if node.id in known:
            return ("var", node.id), "lin"
        if node.id in later:
            raise _Refusal(f"'{node.id}' is read before it is assigned (update[{later[node.id]}] assigns it): "
                           "an implicit rule needs solving, write the explicit update")
        raise _Refusal(f"unknown name '{node.id}' (allowed: h, f, the state variables and earlier temporaries)")
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
        e, kind = _expr(node.operand, known, later)
        return (("neg", e) if isinstance(node.op, ast.USub) else e), kind
    if isinstance(node, ast.BinOp) and type(node.op) in _OPS:
        op = _OPS[type(node.op)]
        a, ka = _expr(node.left, known, later)
        b, kb = _expr(node.right, known, later)
        if op in "+-":
            if ka != kb:
                raise _Refusal(f"'{op}' joins a term with the state and a term without it: the rule is affine, "
                               "not linear (no constant forces)")
            return (op, a, b), ka
        if op == "*":
            if ka == kb == "lin":
                raise _Refusal("a product of two state-dependent terms is not linear")
            return (op, a, b), ("lin" if "lin" in (ka, kb) else "const")
        if kb == "lin":
            raise _Refusal("dividing by a state-dependent term is not linear")
        if all(_const_value(b, t) == 0 for t in (0.37, 1.3, 5.0)):
            raise _Refusal("division by zero")
        return (op, a, b), ka
    if isinstance(node, ast.BinOp):
        raise _Refusal(f"operator '{type(node.op).__name__}' is not allowed (allowed: + - * /)")
    if isinstance(node, ast.Call):
        if not (isinstance(node.func, ast.Name) and node.func.id == "f"):
            raise _Refusal("the only function is the force f(x, v)")
        if node.keywords or len(node.args) != 2:
            raise _Refusal("f takes two positional arguments, f(position, velocity)")
        names = []
        for arg in node.args:
            if not isinstance(arg, ast.Name) or arg.id in RESERVED:
                raise _Refusal("the arguments of f must be state variables or temporaries")
            if arg.id not in known:
                raise _Refusal(f"f has the argument '{arg.id}', which is not yet defined: an implicit rule "
                               "needs solving, write the explicit update")
            names.append(arg.id)
        return ("f", *names), "lin"
    raise _Refusal(f"'{type(node).__name__}' is not allowed in a rule (numbers, + - * /, h, f(x, v) and names only)")


def _parse_rule(text, key: str, known: set[str], later: dict[str, int]):
    if not isinstance(text, str):
        raise InputError(key, f"must be a string 'name = expression' (got {type(text).__name__})")
    if len(text) > MAX_RULE_CHARS:
        raise InputError(key, f"a rule is at most {MAX_RULE_CHARS} characters (got {len(text)})")
    try:
        tree = ast.parse(text.strip(), mode="exec")
    except (SyntaxError, ValueError, MemoryError, RecursionError) as exc:
        col = getattr(exc, "offset", None)
        raise InputError(key, "not a rule 'name = expression'" + (f" (syntax error at column {col})" if col else "")) from None
    if len(tree.body) != 1 or not isinstance(tree.body[0], ast.Assign):
        raise InputError(key, "must be exactly one assignment 'name = expression'")
    stmt = tree.body[0]
    if len(stmt.targets) != 1 or not isinstance(stmt.targets[0], ast.Name):
        raise InputError(key, "the left side must be one name")
    target = _check_ident(stmt.targets[0].id, key, "the assigned name")
    try:
        expr, kind = _expr(stmt.value, known, later)
    except _Refusal as exc:
        raise InputError(key, str(exc)) from None
    except RecursionError:
        raise InputError(key, "the expression is nested too deeply") from None
    if kind != "lin":
        raise InputError(key, "the right side does not depend on the state: the rule is not linear in the state")
    return target, expr


def _combine(op: str, a, b):
    """The value ``a op b`` where either may be an exact Fraction (kept exact against SymPy, float against arrays)."""
    fa, fb = isinstance(a, Fraction), isinstance(b, Fraction)
    if fa and fb or not (fa or fb):
        return _plain(op, a, b)
    if fb:
        p, q = b.numerator, b.denominator
        if op == "*":
            return a * p if q == 1 else a * p / q
        if op == "/":
            return a * q / p if p != 1 else a * q
        return (a * q + p) / q if op == "+" else (a * q - p) / q
    if fa:
        p, q = a.numerator, a.denominator
        if op == "*":
            return b * p if q == 1 else b * p / q
        if op == "/":
            return p / (b * q) if q != 1 else p / b
        return (b * q + p) / q if op == "+" else (p - b * q) / q
    raise AssertionError("unreachable")


def _plain(op: str, a, b):
    if op == "+":
        return a + b
    if op == "-":
        return a - b
    return a * b if op == "*" else a / b


def _evaluate(e, env: dict, h, f):
    tag = e[0]
    if tag == "num":
        return e[1]
    if tag == "h":
        return h
    if tag == "var":
        return env[e[1]]
    if tag == "f":
        return f(env[e[1]], env[e[2]])
    if tag == "neg":
        v = _evaluate(e[1], env, h, f)
        return -v
    return _combine(tag, _evaluate(e[1], env, h, f), _evaluate(e[2], env, h, f))


def _make_step(state: tuple[str, ...], rules: tuple):
    def step(s, h, f):
        env = dict(zip(state, s))
        for target, expr in rules:
            env[target] = _evaluate(expr, env, h, f)
        return tuple(env[n] for n in state)

    return step


ORDERS: dict[tuple[str | None, str | None], tuple[int, int]] = {}
"""(order with damping, order undamped) of each checked user scheme, by (name, summary)."""


H_DEGREES: dict[tuple[str | None, str | None], int] = {}
"""Highest power of h in the characteristic polynomial of each checked user scheme, by (name, summary)."""


def order_of(integ) -> tuple[int, int] | None:
    """The order of accuracy found for a checked user scheme (``None``: a built-in or unchecked one).

    Parameters
    ----------
    integ : Integrator or object
        A scheme (anything else gives None).

    Returns
    -------
    tuple of (int, int) or None
        (order with damping, order undamped).
    """
    return ORDERS.get((getattr(integ, "name", None), getattr(integ, "summary", None)))


def h_degree_of(integ) -> int | None:
    """Highest power of h in the characteristic polynomial of a checked user scheme (``None``: not checked).

    Parameters
    ----------
    integ : Integrator or object
        A scheme (anything else gives None).

    Returns
    -------
    int or None
        The degree in ``h``.
    """
    return H_DEGREES.get((getattr(integ, "name", None), getattr(integ, "summary", None)))


def parse_integrator(table: dict, where: str = "integrator", check: bool = True) -> Integrator:
    """The ``Integrator`` of a scene's ``[integrator]`` table; ``where`` prefixes the error keys.

    Parameters
    ----------
    table : dict
        The table ``{name, state, update}`` (``update`` a list of rules ``"target = expression"``).
    where : str
        Input key of the table, prefixed to the keys named in errors.
    check : bool
        Refuse, naming the rule, a scheme that is not dimensionally consistent
        (``dtcrit.integrators.user_dimensions``) or not consistent with ``x'' = f(x, v)``
        (``dtcrit.integrators.user_consistency``), and keep the order of accuracy found
        (:func:`order_of`); False only parses (tests of the rule reader use it).

    Returns
    -------
    Integrator
        The parsed scheme, not yet registered (:func:`register`).
    """
    if not isinstance(table, dict):
        raise InputError(where, "must be a scheme name or a table {name, state, update}")
    for key in table:
        if key not in KEYS:
            raise InputError(f"{where}.{key}", f"unknown key; valid keys here: {', '.join(KEYS)}")
    for key in KEYS:
        if key not in table:
            raise InputError(f"{where}.{key}", "missing (an [integrator] table needs name, state and update)")
    name = table["name"]
    if not isinstance(name, str) or not _NAME.match(name):
        raise InputError(f"{where}.name", "must be 1-64 letters, digits, '-', '_' or '.' starting with a letter or digit")
    if name in INTEGRATORS:
        raise InputError(f"{where}.name", f"'{name}' is a built-in scheme; give yours another name")
    state = table["state"]
    if not isinstance(state, list) or not 1 <= len(state) <= MAX_STATE:
        raise InputError(f"{where}.state", f"must be a list of 1 to {MAX_STATE} variable names (position first, then velocity)")
    state = tuple(_check_ident(v, f"{where}.state[{i}]", "a state variable") for i, v in enumerate(state, 1))
    if len(set(state)) != len(state):
        raise InputError(f"{where}.state", "the state variables must be distinct")
    update = table["update"]
    if not isinstance(update, list) or not 1 <= len(update) <= MAX_RULES:
        raise InputError(f"{where}.update", f"must be a list of 1 to {MAX_RULES} rules 'name = expression'")
    first_assign: dict[str, int] = {}
    for i, text in enumerate(update, 1):  # which names later rules assign (to explain an early read)
        m = re.match(r"\s*([A-Za-z][A-Za-z0-9_]*)\s*=(?!=)", text) if isinstance(text, str) else None
        if m and m.group(1) not in state:
            first_assign.setdefault(m.group(1), i)
    known = set(state)
    rules = []
    for i, text in enumerate(update, 1):
        later = {n: j for n, j in first_assign.items() if j >= i and n not in known}
        target, expr = _parse_rule(text, f"{where}.update[{i}]", known, later)
        rules.append((target, expr))
        known.add(target)
    assigned = {t for t, _ in rules}
    if not assigned & set(state):
        raise InputError(f"{where}.update", "no rule assigns a state variable: the scheme does not advance")
    velocities = sorted({e[2] for _, e in _walk_calls(rules)})
    summary = "user-written: " + "; ".join(" ".join(str(t).split()) for t in update)
    damping = ", ".join(velocities) + " (the velocity argument of f)" if velocities else "none (f is not called)"
    integ = Integrator(name, state, _make_step(state, tuple(rules)), summary, damping, "user-written")
    if check:
        from dtcrit.integrators.user_consistency import h_degree, order_of_accuracy
        from dtcrit.integrators.user_dimensions import check_dimensions

        keys = [f"{where}.update[{i}]" for i in range(1, len(rules) + 1)]
        check_dimensions(state, rules, keys)
        ORDERS[(name, summary)] = order_of_accuracy(state, rules, keys, where)
        H_DEGREES[(name, summary)] = h_degree(state, rules)
    return integ


def _walk_calls(rules):
    def walk(e):
        if e[0] == "f":
            yield e
        elif e[0] in ("neg",):
            yield from walk(e[1])
        elif e[0] in _OPS.values():
            yield from walk(e[1])
            yield from walk(e[2])

    for target, e in rules:
        for call in walk(e):
            yield target, call


def register(integ: Integrator, where: str = "integrator") -> str:
    """Make a parsed scheme known by its name to the runtime and codegen.

    The same name with the same rules may be registered again (a scene read twice); the same name
    with different rules in one run is refused (the derivations are cached by name).

    Parameters
    ----------
    integ : Integrator
        The parsed scheme (:func:`parse_integrator`).
    where : str
        Input key of its table, named in the error.

    Returns
    -------
    str
        The scheme's name.
    """
    old = USER_INTEGRATORS.get(integ.name)
    if old is not None and (old.state, old.summary) != (integ.state, integ.summary):
        raise InputError(f"{where}.name", f"a different scheme named '{integ.name}' is already defined in this run")
    if old is None:
        USER_INTEGRATORS[integ.name] = integ
    return integ.name


def same_update_as(integ, candidates) -> str | None:
    """The first built-in scheme in ``candidates`` whose update is the same map as ``integ``'s for a whole
    packing (state vectors, non-commuting matrices K and C, any h), or None.

    Tested at three seeded random points (vectors of 4, symmetric K and C, h in [0.1, 1]) to 1e-9:
    both maps are polynomials in (h, K, C), so a difference vanishes at random points with
    probability 0 (Schwartz-Zippel).

    Parameters
    ----------
    integ : Integrator
        The scheme to compare.
    candidates : iterable of str
        Built-in scheme keys to try, in order.

    Returns
    -------
    str or None
        The first matching key.
    """
    import numpy as np

    rng = np.random.default_rng(20240601)
    points = []
    for _ in range(3):
        a, b = rng.standard_normal((4, 4)), rng.standard_normal((4, 4))
        state = tuple(rng.standard_normal(4) for _ in integ.state)
        points.append((state, float(rng.uniform(0.1, 1.0)), MatrixForce(a @ a.T, b @ b.T)))
    for name in candidates:
        other = INTEGRATORS.get(name)
        if other is None or len(other.state) != len(integ.state):
            continue
        try:
            same = all(np.allclose(np.asarray(integ.step(s, h, f)), np.asarray(other.step(s, h, f)), rtol=1e-9, atol=1e-9)
                       for s, h, f in points)
        except (TypeError, ValueError):  # a scheme that needs the scalar f.dv (the centred damping)
            same = False
        if same:
            return name
    return None
