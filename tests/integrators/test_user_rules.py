"""Integrators a user writes (``dtcrit.integrators.user_rules``): exact agreement with the built-in
schemes, random whitelisted rule sets against a direct reimplementation, refusals in one line."""
import math
import random

import mpmath as mp
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from dtcrit.errors import InputError
from dtcrit.integrators.schemes import LinearForce
from dtcrit.integrators.spectral_route import tau_crit
from dtcrit.integrators.stability import critical_dt
from dtcrit.integrators.user_rules import parse_integrator, register
from dtcrit.symbolic.boundary import tau_crit_mp
from dtcrit.symbolic.closed_forms import formula_text
from dtcrit.symbolic.integrators import amplification_matrix, characteristic_polynomial


def table(update, state=("x", "v"), name="user-scheme"):
    return {"name": name, "state": list(state), "update": list(update)}


LEAPFROG = table(["v = v + h*f(x, v)", "x = x + h*v"], name="user-leapfrog")


def test_user_leapfrog_gives_exactly_the_builtin_boundary():
    u = parse_integrator(LEAPFROG, "integrator")
    assert amplification_matrix(u) == amplification_matrix("leapfrog")
    assert characteristic_polynomial(u) == characteristic_polynomial("leapfrog")
    assert formula_text(u) == formula_text("leapfrog")
    for z in (0, "1/100", "1/3", 2, 50):
        assert tau_crit_mp(u, z)[0] == tau_crit_mp("leapfrog", z)[0]
    register(u)
    for c in (0.0, 1e3, 3e5, 1e7):  # the runtime's spectral route against the emitted closed form
        got, ref = critical_dt("user-leapfrog", 1e10, c, 7.0).dt, critical_dt("leapfrog", 1e10, c, 7.0).dt
        assert got == pytest.approx(ref, rel=1e-15)


def test_user_adams_bashforth_with_temporaries_matches_the_builtin():
    u = parse_integrator(table(["a = f(x, v)", "w = v + 0.5*h*(3*a - ao)", "x = x + h*(v + w)/2", "v = w", "ao = a"],
                               state=("x", "v", "ao"), name="user-ab2"), "integrator")
    assert characteristic_polynomial(u) == characteristic_polynomial("adams-bashforth-2")
    with mp.workdps(50):
        for z in ("1/10", 1):
            assert tau_crit_mp(u, z)[0] == tau_crit_mp("adams-bashforth-2", z)[0]
    assert abs(tau_crit(u, 0.1) - float(tau_crit_mp("adams-bashforth-2", "1/10")[0])) < 1e-15


# ---- random whitelisted rule sets against a direct reimplementation

def rule_sets(draw):
    state = ["x", "v", "q"][: draw(st.integers(2, 3))]
    known = list(state)
    rules, refs = [], []
    for i in range(draw(st.integers(1, 5))):
        terms, parts = [], []
        for _ in range(draw(st.integers(1, 3))):
            coef = draw(st.sampled_from(["1", "2", "0.5", "3/4", "1.25", "-1"]))
            power = draw(st.integers(0, 2))
            if draw(st.booleans()):
                a, b = draw(st.sampled_from(known)), draw(st.sampled_from(known))
                atom, fn = f"f({a}, {b})", (lambda env, f, a=a, b=b: f(env[a], env[b]))
            else:
                var = draw(st.sampled_from(known))
                atom, fn = var, (lambda env, f, var=var: env[var])
            hp = "*h" * power
            terms.append(f"({coef}){hp}*{atom}")
            c = eval(coef.replace("/", "/"))  # the test's own arithmetic on its own literals
            parts.append((c, power, fn))
        target = draw(st.sampled_from(state + ["t1", "t2"]))
        rules.append(f"{target} = " + " + ".join(terms))
        refs.append((target, parts))
        if target not in known:
            known.append(target)
    return state, rules, refs


@settings(max_examples=150, derandomize=True)
@given(st.data(), st.floats(-3, 1), st.floats(0, 3))
def test_random_rules_step_like_a_direct_reimplementation(data, log_h, zeta):
    state, rules, refs = rule_sets(data.draw)
    assume(any(t in state for t, _ in refs))
    integ = parse_integrator(table(rules, state=state), "integrator", check=False)  # the reader only
    h = 10.0**log_h
    f = LinearForce(1.3, 2 * zeta)
    rng = random.Random(len(rules))
    s = tuple(rng.uniform(-1, 1) for _ in state)
    env = dict(zip(state, s))
    for target, parts in refs:
        env[target] = sum(c * h**p * fn(env, f) for c, p, fn in parts)
    expected = [env[n] for n in state]
    got = integ.step(s, h, f)
    for g, e in zip(got, expected):
        assert math.isclose(g, e, rel_tol=1e-12, abs_tol=1e-12 * (1 + max(map(abs, expected))))


# ---- refusals: one line, naming the rule and the reason

HOSTILE = [
    (["__import__('os').system('touch /tmp/pwned')"], "integrator.update[1]", "assignment"),
    (["v = __import__('os').system('echo')"], "integrator.update[1]", "only function"),
    (["v = v + h*f(x, v)", "x = x*v"], "integrator.update[2]", "not linear"),
    (["v = f(x, v)*v"], "integrator.update[1]", "not linear"),
    (["v = v/x"], "integrator.update[1]", "not linear"),
    (["v = v + h"], "integrator.update[1]", "affine"),
    (["v = h"], "integrator.update[1]", "does not depend on the state"),
    (["v = v + h*f(x, w)", "w = v"], "integrator.update[1]", "not yet defined"),
    (["v = v + h*w", "w = v"], "integrator.update[1]", "before it is assigned"),
    (["v = v + h*y"], "integrator.update[1]", "unknown name"),
    (["v = v**2"], "integrator.update[1]", "not allowed"),
    (["v = x.real"], "integrator.update[1]", "not allowed"),
    (["v = [x][0]"], "integrator.update[1]", "not allowed"),
    (["v = (lambda: x)()"], "integrator.update[1]", "only function"),
    (["v = 'x'"], "integrator.update[1]", "only numbers"),
    (["v = x if x else v"], "integrator.update[1]", "not allowed"),
    (["v == x"], "integrator.update[1]", "assignment"),
    (["v = v; x = x"], "integrator.update[1]", "exactly one"),
    (["v = v +"], "integrator.update[1]", "syntax"),
    (["v = x/(h - h)"], "integrator.update[1]", "division by zero"),
    (["v = f(x, v, v)"], "integrator.update[1]", "two positional"),
    (["v = f(x, v=v)"], "integrator.update[1]", "two positional"),
    (["v = f(x + v, v)"], "integrator.update[1]", "arguments of f"),
    (["h = v"], "integrator.update[1]", "assigned name"),
    (["v = 1e999*x"], "integrator.update[1]", "finite"),
    (["v = True*x"], "integrator.update[1]", "only numbers"),
    (["x, v = v, x"], "integrator.update[1]", "one name"),
    ([3], "integrator.update[1]", "must be a string"),
]


@pytest.mark.parametrize("update,key,reason", HOSTILE)
def test_refused_in_one_line(update, key, reason, tmp_path):
    with pytest.raises(InputError) as e:
        parse_integrator(table(update), "integrator")
    assert e.value.key == key and reason in e.value.reason and "\n" not in str(e.value)


@pytest.mark.parametrize("tbl,key", [
    ({"state": ["x", "v"], "update": ["v = v"]}, "integrator.name"),
    ({"name": "a", "update": ["v = v"]}, "integrator.state"),
    ({"name": "a", "state": ["x", "v"]}, "integrator.update"),
    ({"name": "a", "state": ["x", "v"], "update": ["v = v"], "extra": 1}, "integrator.extra"),
    ({"name": "leapfrog", "state": ["x", "v"], "update": ["v = v"]}, "integrator.name"),
    ({"name": "a", "state": ["x", "x"], "update": ["v = v"]}, "integrator.state"),
    ({"name": "a", "state": ["h", "v"], "update": ["v = v"]}, "integrator.state[1]"),
    ({"name": "a", "state": [], "update": ["v = v"]}, "integrator.state"),
    ({"name": "a", "state": ["x", "v"], "update": []}, "integrator.update"),
    ({"name": "a", "state": ["x", "v"], "update": ["t = v"]}, "integrator.update"),
    ("leapfrog", "integrator"),
])
def test_missing_and_malformed_keys(tbl, key):
    with pytest.raises(InputError) as e:
        parse_integrator(tbl, "integrator")
    assert e.value.key == key and "\n" not in str(e.value)


def test_nothing_runs(tmp_path):
    marker = tmp_path / "ran"
    for text in (f"v = __import__('pathlib').Path('{marker}').touch()", f"x = open('{marker}', 'w')"):
        with pytest.raises(InputError):
            parse_integrator(table([text]), "integrator")
    assert not marker.exists()


@settings(max_examples=300, derandomize=True)
@given(st.lists(st.text(alphabet=st.sampled_from(list("xvhf()+-*/=., 0123456789_aq[]'\"")), max_size=40),
                min_size=1, max_size=4))
def test_fuzzed_rules_give_an_integrator_or_an_input_error(update):
    try:
        integ = parse_integrator(table(update), "integrator")
    except InputError as e:
        assert "\n" not in str(e)
        return
    integ.step((1.0, 0.5), 0.1, LinearForce(1.0, 0.2))
