"""User-written integrators are checked against the ODE they discretise.

References: a 40-digit eigen-solve of the amplification matrix at two small steps (the principal
eigenvalue's error against e^{h lambda} falls as h^{p+1}), hand-derived dimensions, the built-in
schemes' own steps, and the command line's exit status, output and timing.
"""
from __future__ import annotations

import json
import time

import mpmath as mp
import pytest

from dtcrit.cli import main
from dtcrit.errors import InputError
from dtcrit.integrators.schemes import LinearForce
from dtcrit.integrators.user_rules import order_of, parse_integrator, register

BODY = ('[[particle]]\nshape = "sphere"\nradius = 0.001\ndensity = 2500.0\n'
        '[contact]\nmodel = "linear"\nkn = 1e5\nks = 2e4\ndamping_ratio = 0.1\n')
SOFT = BODY.replace("kn = 1e5\nks = 2e4", "kn = 1e-3\nks = 2e-4")
STIFF = ('[[particle]]\nshape = "ellipsoid"\nsemi_axes = [3.0, 2.0, 1.0]\ndensity = 1000.0\n'
         '[contact]\nmodel = "linear"\nkn = 1.0e10\nks = 1.0e10\n')


def scene(update, body=BODY, state=("x", "v")):
    rules = ", ".join(f'"{r}"' for r in update)
    name = "mine-" + str(sum(map(ord, rules)) % 99991)  # one name per rule set: names are registered per run
    return f'[integrator]\nname = "{name}"\nstate = {json.dumps(list(state))}\nupdate = [{rules}]\n' + body


SCHEMES = {  # (state, rules, order with damping, order undamped): textbook orders
    "symplectic": (("x", "v"), ["v = v + h*f(x, v)", "x = x + h*v"], 1, 2),
    "taylor": (("x", "v"), ["a = f(x, v)", "x = x + h*v + h*h/2*a", "v = v + h*a"], 1, 1),
    "midpoint": (("x", "v"), ["a = f(x, v)", "xm = x + h/2*v", "vm = v + h/2*a", "x = x + h*vm", "v = v + h*f(xm, vm)"], 2, 2),
    "ab2": (("x", "v", "ao"), ["a = f(x, v)", "w = v + 0.5*h*(3*a - ao)", "x = x + h*(v + w)/2", "v = w", "ao = a"], 2, 2),
    "rk4": (("x", "v"), ["k1 = f(x, v)", "x2 = x + h/2*v", "v2 = v + h/2*k1", "k2 = f(x2, v2)", "x3 = x + h/2*v2",
                         "v3 = v + h/2*k2", "k3 = f(x3, v3)", "x4 = x + h*v3", "v4 = v + h*k3", "k4 = f(x4, v4)",
                         "x = x + h/6*(v + 2*v2 + 2*v3 + v4)", "v = v + h/6*(k1 + 2*k2 + 2*k3 + k4)"], 4, 4),
}


def _principal_error(integ, h, K, C):
    """min over eigenvalues mu of G(h) of |mu - e^{h lambda_+}| (40 digits)."""
    d = len(integ.state)
    G = mp.matrix(d, d)
    for j in range(d):
        col = integ.step(tuple(mp.mpf(1 if i == j else 0) for i in range(d)), h, LinearForce(K, C))
        for i in range(d):
            G[i, j] = col[i]
    lam = (-C + mp.sqrt(mp.mpc(C * C - 4 * K))) / 2
    return min(abs(mu - mp.exp(h * lam)) for mu in mp.eig(G, left=False, right=False))


@pytest.mark.parametrize("key", SCHEMES)
def test_the_order_found_is_the_eigenvalue_error_slope(key):
    state, rules, damped, undamped = SCHEMES[key]
    integ = parse_integrator({"name": f"order-{key}", "state": list(state), "update": rules}, "integrator")
    assert order_of(integ) == (damped, undamped)
    with mp.workdps(40):
        for C, p in ((mp.mpf("0.7"), damped), (mp.mpf(0), undamped)):
            e1, e2 = (_principal_error(integ, mp.mpf(h), mp.mpf("1.3"), C) for h in ("1e-3", "5e-4"))
            assert abs(mp.log(e1 / e2, 2) - (p + 1)) < 0.05, (key, C, e1, e2)


# ---- refusals: one line naming the rule, exit 2, nothing written, in seconds

ISSUE_CASES = [
    (["v = v + f(x, v)", "x = x + v"], BODY, "integrator.update[1]", "joins a velocity and an acceleration"),
    (["v = v + h*f(x, v)", "x = x + v"], STIFF, "integrator.update[2]", "joins a position and a velocity"),
    (["v = v + h*h*f(x, v)", "x = x + h*v"], SOFT, "integrator.update[1]", "joins a velocity and a position"),
    (["v = v + h*h*f(x, v)", "x = x + h*v"], STIFF, "integrator.update[1]", "joins a velocity and a position"),
    (["v = v + h*f(x, v)*(h - 1)/(h - 1)", "x = x + h*v"], BODY, "integrator.update[1]", "joins a time (h) and a number"),
    (["x = x + h*v"], BODY, "integrator.update", "'v' is never assigned"),
    (["x = 0*x", "v = 0*v"], BODY, "integrator.update[1]", "not consistent with x'' = f(x, v)"),
    (["v = v + 2*h*f(x, v)", "x = x + h*v"], BODY, "integrator.update[1]", "it must give v + h f(x, v)"),
    (["v = v + h*f(x, v) + x/h", "x = x + h*v"], BODY, "integrator.update[1]", "a term in 1/h"),
]


@pytest.mark.parametrize("command", ["step", "codegen"])
@pytest.mark.parametrize("update,body,key,reason", ISSUE_CASES)
def test_inconsistent_schemes_are_refused_in_one_line(update, body, key, reason, command, tmp_path, capsys):
    path, out = tmp_path / "scene.toml", tmp_path / "dt.c"
    path.write_text(scene(update, body))
    argv = ["step", str(path)] if command == "step" else ["codegen", str(path), "--lang", "c", "--out", str(out)]
    start = time.perf_counter()
    rc = main(argv)
    elapsed = time.perf_counter() - start
    got, err = capsys.readouterr()
    assert rc == 2 and got == "" and not out.exists() and elapsed < 10
    assert err.count("\n") == 1 and err.startswith(f"{path}:{key}: ") and reason in err, err


def test_codegen_refuses_a_scheme_it_cannot_emit_in_one_line(tmp_path, capsys):
    path, out = tmp_path / "scene.toml", tmp_path / "dt.c"
    path.write_text(scene(SCHEMES["rk4"][1]))
    start = time.perf_counter()
    rc = main(["codegen", str(path), "--lang", "c", "--out", str(out)])
    got, err = capsys.readouterr()
    assert rc == 2 and got == "" and not out.exists() and time.perf_counter() - start < 10
    assert err.count("\n") == 1 and ":integrator: no code for the user-written scheme 'mine-" in err and "h^8" in err


def test_step_prints_the_order_and_json_carries_it(tmp_path, capsys):
    path = tmp_path / "scene.toml"
    path.write_text(scene(SCHEMES["ab2"][1], state=SCHEMES["ab2"][0]))
    assert main(["step", str(path)]) == 0
    assert "order of accuracy 2 damped, 2 undamped" in capsys.readouterr().out
    assert main(["step", str(path), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["order_of_accuracy"] == {"damped": 2, "undamped": 2}


@pytest.mark.parametrize("rule,dims", [("t = x/h", "a velocity"), ("t = f(x, v)", "an acceleration"),
                                       ("t = h*h*h*f(x, v)", "a position times a time")])
def test_dimensions_of_temporaries_are_inferred(rule, dims):
    with pytest.raises(InputError) as e:  # adding the temporary to x names both dimensions
        parse_integrator({"name": "d", "state": ["x", "v"], "update": [rule, "x = x + h*v + t"]}, "integrator")
    assert e.value.key == "integrator.update[2]" and dims in e.value.reason


def test_a_dimensionally_valid_temporary_is_accepted():
    integ = parse_integrator({"name": "d2", "state": ["x", "v"],
                              "update": ["t = h*h*f(x, v)", "v = v + t/h", "x = x + h*v"]}, "integrator")
    assert order_of(integ) == (1, 2)


# ---- the packing bound of a user scheme: the built-in's when it is the same update, else a true reason

DENSE = "coordination_max = 6\n"


def _json(tmp_path, capsys, text):
    path = tmp_path / "scene.toml"
    path.write_text(text)
    rc = main(["step", str(path), "--json"])
    out, err = capsys.readouterr()
    return rc, (json.loads(out) if rc == 0 else None), err


def test_a_user_symplectic_euler_gets_the_packing_bound(tmp_path, capsys):
    rc, user, _ = _json(tmp_path, capsys, DENSE + scene(SCHEMES["symplectic"][1]))
    rc2, builtin, _ = _json(tmp_path, capsys, DENSE + 'integrator = "symplectic-euler"\n' + BODY)
    assert rc == rc2 == 0 and user["dt_dense"] == pytest.approx(builtin["dt_dense"], rel=1e-12)


def test_an_unproven_user_scheme_gets_a_true_reason(tmp_path, capsys):
    rc, _, err = _json(tmp_path, capsys, DENSE + scene(SCHEMES["midpoint"][1]))
    assert rc == 2 and "unstable undamped" not in err and "not the same update as any of" in err


# ---- the runtime confirmation in physical units

def test_a_wrong_step_is_refused_not_printed(monkeypatch):
    from dtcrit.integrators import spectral_route
    from dtcrit.integrators.stability import critical_dt

    integ = parse_integrator({"name": "confirm-me", "state": ["x", "v"], "update": SCHEMES["symplectic"][1]}, "integrator")
    register(integ)
    good = critical_dt("confirm-me", 1e5, 0.1, 2e5).dt
    true_tau = spectral_route.tau_crit
    monkeypatch.setattr(spectral_route, "tau_crit", lambda i, z: 1.02 * true_tau(i, z))  # a boundary 2 % too large
    with pytest.raises(InputError) as e:
        critical_dt("confirm-me", 1e5, 0.1, 2e5)
    assert e.value.key == "integrator" and "not confirmed" in e.value.reason
    assert good > 0


def test_the_confirmation_is_cheap():
    from dtcrit.integrators.stability import critical_dt
    from dtcrit.integrators.user_confirm import confirm_step

    integ = parse_integrator({"name": "cheap", "state": ["x", "v", "ao"], "update": SCHEMES["ab2"][1]}, "integrator")
    register(integ)
    dt = critical_dt("cheap", 1e8, 3.0, 50.0).dt
    start = time.perf_counter()
    for _ in range(10):
        confirm_step("cheap", dt, 1e8 * 50.0, 3.0 * 50.0)
    assert (time.perf_counter() - start) / 10 < 0.25  # measured about 40 ms on one core


@pytest.mark.parametrize("rules,state,builtin", [
    (SCHEMES["symplectic"][1], ("x", "v"), "symplectic-euler"),
    (["vh = v + h/2*a", "vp = v + h*a", "x = x + h*vh", "a = f(x, vp)", "v = vh + h/2*a"], ("x", "v", "a"),
     "velocity-verlet-predicted"),
])
def test_a_dashpot_without_spring_gets_the_builtin_step(rules, state, builtin):
    from dtcrit.integrators.stability import mode_dt

    name = register(parse_integrator({"name": f"dashpot-{builtin}", "state": list(state), "update": rules}, "integrator"))
    for c, A in ((3.0, 2.0), (1e-4, 1e9), (1e6, 1e-3)):
        assert mode_dt(name, 0.0, c, A).dt == pytest.approx(mode_dt(builtin, 0.0, c, A).dt, rel=1e-14)


WALL_BLOCK = ('[[particle]]\nshape = "sphere"\nradius = 0.002\ndensity = 7800.0\n[contact]\nmodel = "linear"\n'
              'kn = 2.0e5\nks = 5.714e4\ndamping_ratio = 0.1\nkr = 1e-2\ncr = 1e-3\n[[wall]]\nname = "floor"\n'
              'kn = 2.0e5\nks = 2.0e5\nkr = 1e-2\ncr = 1e-7\ndamping_ratio = 0.3\n')


def test_a_coupled_shear_rolling_block_under_a_user_scheme(tmp_path, capsys):
    """Was a KeyError traceback; now the block's bisection, confirmed by stepping the rules on the block,
    against the built-in's exact root (lambda_max(2 h C + h^2 K) = 4)."""
    def block_dt(doc):
        wall = [p for p in doc["pairs"] if any(m["direction"] == "shear-rolling" for m in p["rotational_modes"])][0]
        return [m for m in wall["rotational_modes"] if m["direction"] == "shear-rolling"][0]["dt"]

    rc, user, err = _json(tmp_path, capsys, scene(SCHEMES["symplectic"][1], WALL_BLOCK))
    rc2, builtin, _ = _json(tmp_path, capsys, 'integrator = "symplectic-euler"\n' + WALL_BLOCK)
    assert rc == rc2 == 0, err
    assert block_dt(user) == pytest.approx(block_dt(builtin), rel=1e-9)
