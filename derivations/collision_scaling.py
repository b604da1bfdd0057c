"""Record: each collision law reduced to its scaled form (units t_c and the elastic peak overlap).

Built with ``dtcrit.symbolic.collision_scaling`` (SymPy) and checked against the runtime's constants
(``dtcrit.collisions.scaled``) and the continuum reference (``dtcrit.collisions.reference``).
"""
from __future__ import annotations

import sympy as sp
from _shared.text import num

from dtcrit.collisions import reference_collision
from dtcrit.collisions.scaled import HERTZ_W0
from dtcrit.physics.collision_laws import DAMPING_MODELS
from dtcrit.symbolic import collision_scaling as cs

RECORD = "collision_scaling.md"


def _rows() -> list[str]:
    rows = ["| normal | damping | q | g | exponent of v in g |", "| --- | --- | --- | --- | --- |"]
    for normal in ("hooke", "hertz"):
        for damping in cs.MODEL_CLASS:
            if normal not in DAMPING_MODELS[damping].exponents:
                continue
            f = cs.scaled_form(normal, damping)
            rows.append(f"| {normal} | {damping} | {f['q']} | `{sp.sstr(f['g'])}` | {f['speed_exponent']} |")
    return rows


def build() -> str:
    """The record's Markdown text."""
    hooke, hertz = cs.scaled_form("hooke", "liggghts"), cs.scaled_form("hertz", "liggghts")
    w_hertz = float(hertz["w0"])
    const = cs.hertz_time_constant()
    clipped = [(e, reference_collision(normal="hertz", damping="liggghts", restitution=e, clip=True).restitution,
                reference_collision(normal="hertz", damping="yade-mindlin", restitution=e).restitution)
               for e in (0.9, 0.5, 0.1)]
    out = [
        "# The dimensionless impact",
        "",
        "Built by `derivations/collision_scaling.py` with `dtcrit.symbolic.collision_scaling`; regenerate with "
        "`python3 dev.py generate`.",
        "",
        "A normal law `m delta'' = -(k delta^p + c0 delta^q delta')` with `delta = D u`, `t = T s`, `D` the elastic "
        "peak overlap (`m v^2/2 = k D^(p+1)/(p+1)`) and `T = t_c = W D/v`, `W = 2 int_0^1 du/sqrt(1 - u^(p+1))`, becomes",
        "",
        "    u'' = -(kappa u^p + g u^q u'),   u(0) = 0,  u'(0) = w0 = W,   kappa = (p+1) W^2/2,   g = c0 D^q T/m.",
        "",
        f"* hooke (`p = 1`): `kappa = {sp.sstr(hooke['kappa'])}`, `w0 = {sp.sstr(hooke['w0'])}`.",
        f"* hertz (`p = 3/2`): `kappa = {sp.sstr(hertz['kappa'])}` = {num(float(hertz['kappa']), 12)}, "
        f"`w0 = {sp.sstr(hertz['w0'])}` = {num(w_hertz, 12)} (runtime `HERTZ_W0` = {num(HERTZ_W0, 12)}).",
        "",
        "Only the group `g` (a function of the restitution) and the clipping of the force at zero survive; "
        "`d` is the dimensionless prefactor of `sqrt(m k delta^(p-1))` (LAMMPS tsuji `sqrt(2) alpha(e)` in the current "
        "source, `alpha(e)` in 2021; coeff_restitution, LIGGGHTS/EDEM, YADE `en`, MercuryDPM: `sqrt(5) beta(e)` for hertz, "
        "`2 zeta(e)` for hooke), `damp` LAMMPS's viscoelastic or mass_velocity coefficient:",
        "",
        *_rows(),
        "",
        "Exponent 0: the restitution does not depend on the impact speed, so one table per integrator and model covers "
        "every material, size and speed.  `lammps-viscoelastic` (both laws) and hertz `lammps-mass-velocity` depend on it; "
        "dtcrit keys them by the continuum restitution they produce.  For oblique impacts (tangential Mindlin, Coulomb "
        "limit) the size ratio, friction coefficient and Poisson ratio would survive as well: not modelled here.",
        "",
        "## The Hertz contact time",
        "",
        f"`t_c = C (m*^2/(R* E*^2 v))^(1/5)` for `F = (4/3) E* sqrt(R*) delta^(3/2)`: `C = {sp.sstr(const)}` = "
        f"**{num(float(const), 8)}** (LIGGGHTS `check/timestep/gran` prints 2.87).  The constant 3.2145 of the issue "
        "does not come out of this law; it would need a different force constant.",
        "",
        "## Clipping changes the restitution",
        "",
        "With the Hertz-Mindlin dashpot the continuum impact reproduces the input `e` exactly only if the force may "
        "pull at the end; clipped at zero (LIGGGHTS `limitForce`; the contact then flies free) the realised "
        "restitution is higher.  YADE clips and maps `en` by Thornton et al. (2013) eqs. B6-B7, fitted to the "
        "clipped law, so it restitutes `en` to the fit's accuracy:",
        "",
        "| input e | realised e, 2 sqrt(5/6) beta clipped | realised e, YADE (Thornton, clipped) |",
        "| --- | --- | --- |",
        *[f"| {e} | {num(r, 6)} | {num(y, 6)} |" for e, r, y in clipped],
        "",
    ]
    return "\n".join(out)
