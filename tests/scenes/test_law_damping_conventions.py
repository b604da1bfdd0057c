"""Hertz scenes under a code's own damping law (``damping_convention = "lammps-tsuji"`` ...), checked independently.

For each convention the law is written here from the codes' documentation/source, at the scene's physical
units (2 mm glass beads, impact at ``--v-max``): the restitution of its continuum impact (``scipy`` ``solve_ivp``
of ``m* delta'' = -F(delta, delta')``) must equal ``dtcrit collide``'s ``restitution_continuum``; the dashpots at
the peak overlap (``cn_at_peak``, ``cs_at_peak``) and at the linearisation overlap of ``dtcrit step`` must equal
the hand formula there.

Laws (``F_el = K delta^(3/2)``, ``K = (4/3) E* sqrt(R*)``, force ``eta(delta) delta'`` on the approach):

* LAMMPS pair_granular doc, "damping": ``mass_velocity``: ``eta = eta_n0 m*``; ``viscoelastic``:
  ``eta = eta_n0 a m*``, ``a = sqrt(R* delta)``; ``tsuji``: ``eta = alpha(e) sqrt(m* F_el/delta)`` (the 29Sep2021
  release; ``sqrt(2) alpha`` since); ``coeff_restitution``: ``eta = sqrt(3/2) 2 sqrt(5/6) beta sqrt(m* F_el/delta)``;
  tangential ``eta_t = x_gammat eta_n``.
* YADE HertzMindlin.cpp: ``c_n = 2 beta_T(en) sqrt(m* (3/2) K sqrt(delta))``, Thornton's fit, total force clipped at 0;
  ``c_s = 2 beta_T sqrt(m* k_s)``, ``k_s = 8 G* sqrt(R* delta)``.
* MercuryDPM HertzianViscoelasticInteraction.cc: ``c = d sqrt(m* K sqrt(delta))``, ``d = sqrt(5) beta``; sliding 2/7.
"""
from __future__ import annotations

import json
import math

import pytest
from scipy.integrate import solve_ivp

from dtcrit.cli import main

R, RHO, E, NU, V_LIN, V_MAX = 1.0e-3, 2500.0, 63.0e9, 0.22, 1.0, 2.0
M = RHO * 4.0 / 3.0 * math.pi * R**3
MS, RS = M / 2.0, R / 2.0
ES = E / (2.0 * (1.0 - NU**2))
GS = E / (2.0 * (1.0 + NU)) / (2.0 * (2.0 - NU))
K = 4.0 / 3.0 * ES * math.sqrt(RS)
X_GAMMAT = 0.7


def _beta(e):
    return 0.0 if e >= 1.0 else -math.log(e) / math.sqrt(math.log(e) ** 2 + math.pi**2)


def _alpha(e):  # LAMMPS pair_granular doc, damping tsuji
    return 1.2728 - 4.2783 * e + 11.087 * e**2 - 22.348 * e**3 + 27.467 * e**4 - 18.022 * e**5 + 4.8218 * e**6


def _thornton(e):  # YADE Ip2_FrictMat_FrictMat_MindlinPhys, Thornton et al. 2013 B6-B7
    h = (-6.918798, -16.41105, 146.8049, -796.4559, 2928.711, -7206.864, 11494.29, -11342.18, 6276.757, -1489.915)
    alpha = e * sum(c * e**k for k, c in enumerate(h))
    return math.sqrt(1.0 / (1.0 - (1.0 + e) ** 2 * math.exp(alpha)) - 1.0)


# convention -> (scene damping lines, eta(delta), clipped, c_s/c_n or "yade")
CASES = {
    "lammps-tsuji": ("restitution = 0.5", lambda d: math.sqrt(2.0) * _alpha(0.5) * math.sqrt(MS * K * math.sqrt(d)), False),
    "lammps-tsuji-2021": ("restitution = 0.5", lambda d: _alpha(0.5) * math.sqrt(MS * K * math.sqrt(d)), False),
    "lammps-coeff-restitution": ("restitution = 0.3", lambda d: math.sqrt(1.5) * 2.0 * math.sqrt(5.0 / 6.0) * _beta(0.3)
                                 * math.sqrt(MS * K * math.sqrt(d)), False),
    "lammps-viscoelastic": ("damping_coefficient = 5.0e9", lambda d: 5.0e9 * math.sqrt(RS * d) * MS, False),
    "lammps-mass-velocity": ("damping_coefficient = 2.0e5", lambda d: 2.0e5 * MS, False),
    "yade-mindlin": ("restitution = 0.5", lambda d: 2.0 * _thornton(0.5) * math.sqrt(MS * 1.5 * K * math.sqrt(d)), True),
    "mercurydpm": ("restitution = 0.7", lambda d: math.sqrt(5.0) * _beta(0.7) * math.sqrt(MS * K * math.sqrt(d)), False),
}


def _scene(tmp_path, name: str, tangential: bool = True) -> str:
    lines, _, _ = CASES[name]
    extra = f"tangential_damping_factor = {X_GAMMAT}\n" if tangential and name.startswith("lammps") else ""
    text = (f'integrator = "velocity-verlet"\n[[particle]]\nshape = "sphere"\nradius = {R}\ndensity = {RHO}\n'
            f'youngs_modulus = {E}\npoisson_ratio = {NU}\n[contact]\nmodel = "hertz"\nvelocity = {V_LIN}\n'
            f'damping_convention = "{name}"\n{lines}\n{extra}')
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    return str(path)


def _continuum_restitution(eta, clip: bool, v: float) -> float:
    """``m* delta'' = -(K delta^(3/2) + eta(delta) delta')`` (clipped at 0), from first touch to separation."""
    def rhs(_t, y):
        d = max(y[0], 0.0)
        f = K * d**1.5 + eta(d) * y[1]
        return [y[1], -(max(f, 0.0) if clip else f) / MS]

    def out(_t, y):
        return y[0]
    setattr(out, "terminal", True)  # solve_ivp reads these attributes of an event function
    setattr(out, "direction", -1)
    t_c = 3.0 * (MS**2 / (RS * ES**2 * v)) ** 0.2
    sol = solve_ivp(rhs, (0.0, 20.0 * t_c), [0.0, v], method="DOP853", rtol=1e-12, atol=1e-20, events=out,
                    max_step=t_c / 200.0)
    return -float(sol.y_events[0][0][1]) / v


def _collide(capsys, path):
    assert main(["collide", path, "--v-max", str(V_MAX), "--json"]) == 0
    (pair,) = json.loads(capsys.readouterr().out)["pairs"]
    return pair


@pytest.mark.parametrize("name", list(CASES))
def test_collide_restitution_is_the_continuum_impact(tmp_path, capsys, name):
    """The continuum restitution at v_max is the law's, solved here; a coefficient law is keyed by it."""
    _, eta, clip = CASES[name]
    pair = _collide(capsys, _scene(tmp_path, name))
    assert pair["damping_convention"] == name
    assert pair["restitution_continuum"] == pytest.approx(_continuum_restitution(eta, clip, V_MAX), rel=2e-7)
    if name in ("lammps-viscoelastic", "lammps-mass-velocity"):  # keyed by the restitution they produce
        assert pair["restitution"] == pytest.approx(pair["restitution_continuum"], rel=1e-9)


def _peak(v):
    return (15.0 * MS * v * v / (16.0 * ES * math.sqrt(RS))) ** 0.4


def _shear_dashpot(name, cn, d):
    if name == "yade-mindlin":
        return 2.0 * _thornton(0.5) * math.sqrt(MS * 8.0 * GS * math.sqrt(RS * d))
    return (2.0 / 7.0 if name == "mercurydpm" else X_GAMMAT) * cn


@pytest.mark.parametrize("name", list(CASES))
def test_dashpots_at_the_peak_and_at_the_linearisation_overlap(tmp_path, capsys, name):
    """The dashpots of collide at the peak overlap at v_max, and step's at the overlap of the impact at velocity."""
    _, eta, _ = CASES[name]
    path = _scene(tmp_path, name)
    pair = _collide(capsys, path)
    d = _peak(V_MAX)
    assert pair["peak_overlap"] == pytest.approx(d, rel=1e-10)
    assert pair["cn_at_peak"] == pytest.approx(eta(d), rel=1e-9)
    assert pair["cs_at_peak"] == pytest.approx(_shear_dashpot(name, eta(d), d), rel=1e-9)
    assert main(["step", path, "--json"]) == 0
    (sp,) = json.loads(capsys.readouterr().out)["pairs"]
    d0 = _peak(V_LIN)
    assert sp["cn"] == pytest.approx(eta(d0), rel=1e-9)
    assert sp["cs"] == pytest.approx(_shear_dashpot(name, eta(d0), d0), rel=1e-9)


def _one_line_exit_2(capsys, argv, needle):
    assert main(argv) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err.count("\n") == 1 and needle in captured.err, captured.err


BAD = [
    ("unknown", 'damping_convention = "lammps-tsujii"\nrestitution = 0.5', "contact.damping_convention"),
    ("both", 'damping_convention = "lammps-viscoelastic"\nrestitution = 0.5\ndamping_coefficient = 1e5', "contact.restitution"),
    ("e-law-coefficient", 'damping_convention = "lammps-tsuji"\nrestitution = 0.5\ndamping_coefficient = 1e5',
     "contact.damping_coefficient"),
    ("missing", 'damping_convention = "lammps-mass-velocity"', "contact.damping_coefficient: missing"),
    ("ratio", 'damping_convention = "yade-mindlin"\ndamping_ratio = 0.1', "contact.damping_ratio"),
    ("stray-coefficient", 'restitution = 0.5\ndamping_coefficient = 1e5', "contact.damping_coefficient"),
    ("no-x-gammat", 'damping_convention = "lammps-tsuji"\nrestitution = 0.5', "contact.tangential_damping_factor: missing"),
    ("overdamped", 'damping_convention = "lammps-mass-velocity"\ndamping_coefficient = 1e9\ntangential_damping_factor = 0',
     "contact.damping_coefficient"),
]


@pytest.mark.parametrize("command, case, lines, needle",
                         [("collide", *b) for b in BAD] + [("step", *b) for b in BAD if b[0] != "overdamped"],
                         ids=[f"collide-{b[0]}" for b in BAD] + [f"step-{b[0]}" for b in BAD if b[0] != "overdamped"])
def test_bad_damping_input_is_one_line(tmp_path, capsys, command, case, lines, needle):
    """Refused in one line naming the key (an overdamped dashpot is refused by collide only: it does not rebound)."""
    path = tmp_path / "bad.toml"
    path.write_text(f'integrator = "velocity-verlet"\n[[particle]]\nshape = "sphere"\nradius = {R}\ndensity = {RHO}\n'
                    f'youngs_modulus = {E}\npoisson_ratio = {NU}\n[contact]\nmodel = "hertz"\nvelocity = {V_LIN}\n{lines}\n')
    _one_line_exit_2(capsys, [command, str(path)], needle)


def test_a_linear_wall_under_a_lammps_law_is_refused(tmp_path, capsys):
    """A linear wall in a scene whose Hertz convention is a LAMMPS law: not modelled, one line."""
    path = _scene(tmp_path, "lammps-tsuji")
    with open(path, "a") as fh:
        fh.write("[[wall]]\nkn = 1e5\nks = 1e4\n")
    _one_line_exit_2(capsys, ["collide", path], "wall[1].model")


def test_hertz_wall_under_a_law_convention(tmp_path, capsys):
    """A Hertz wall of the particle's material under tsuji (2021): ``m* = m``, ``R* = R``, its own restitution."""
    path = _scene(tmp_path, "lammps-tsuji-2021")
    with open(path, "a") as fh:
        fh.write('[[wall]]\nmodel = "hertz"\nrestitution = 0.3\n')
    assert main(["collide", path, "--v-max", str(V_MAX), "--json"]) == 0
    wall = {p["pair"]: p for p in json.loads(capsys.readouterr().out)["pairs"]}["1-wall1"]
    k_w = 4.0 / 3.0 * ES * math.sqrt(R)
    d = (15.0 * M * V_MAX**2 / (16.0 * ES * math.sqrt(R))) ** 0.4
    eta = _alpha(0.3) * math.sqrt(M * k_w * math.sqrt(d))
    assert wall["peak_overlap"] == pytest.approx(d, rel=1e-10)
    assert wall["cn_at_peak"] == pytest.approx(eta, rel=1e-9)
    assert wall["cs_at_peak"] == pytest.approx(X_GAMMAT * eta, rel=1e-9)

    def rhs(_t, y):
        x = max(y[0], 0.0)
        return [y[1], -(k_w * x**1.5 + _alpha(0.3) * math.sqrt(M * k_w * math.sqrt(x)) * y[1]) / M]

    def out(_t, y):
        return y[0]
    setattr(out, "terminal", True)
    setattr(out, "direction", -1)
    sol = solve_ivp(rhs, (0.0, 1e-3), [0.0, V_MAX], method="DOP853", rtol=1e-12, atol=1e-20, events=out,
                    max_step=1e-7)
    assert wall["restitution_continuum"] == pytest.approx(-sol.y_events[0][0][1] / V_MAX, rel=2e-7)
