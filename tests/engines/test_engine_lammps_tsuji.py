"""Debian's LAMMPS (29Sep2021) ``damping tsuji`` is the law without the sqrt(2) of the current source.

Two equal spheres collide head-on in the real ``lmp`` (pair_style granular, hertz/material, no tangential
force) at about 15000 steps per collision, starting at contact; the realised restitution is compared
with dtcrit's continuum reference of ``lammps-tsuji-2021`` (and shown far from ``lammps-tsuji``).
"""
from __future__ import annotations

import re
import subprocess

import pytest

from dtcrit.collisions import contact_time, reference_collision
from support.engines import require_engine

RADIUS, RHO, YOUNG, NU, V = 1e-3, 2500.0, 7e9, 0.25, 0.5

SCRIPT = """units si
atom_style sphere
atom_modify map array
boundary f f f
comm_modify vel yes
region box block -0.01 0.01 -0.01 0.01 -0.01 0.01
create_box 1 box
create_atoms 1 single -{r} 0 0
create_atoms 1 single {r} 0 0
set atom * diameter {d} density {rho}
pair_style granular
pair_coeff * * hertz/material {E} {e} {nu} tangential linear_nohistory 0 0 damping tsuji
velocity all set 0 0 0
set atom 1 vx {v}
set atom 2 vx -{v}
fix 1 all nve/sphere
timestep {dt}
variable v1 equal vx[1]
run {steps}
print "RESULT ${{v1}}"
"""


@pytest.mark.parametrize("e", [0.9, 0.5, 0.2])
def test_debian_tsuji_is_the_2021_law(e, tmp_path):
    lmp = require_engine("lammps")
    m_eff = RHO * 4.0 / 3.0 * 3.141592653589793 * RADIUS**3 / 2.0
    t_c = contact_time("hertz", m_eff=m_eff, E_eff=YOUNG / (2 * (1 - NU**2)), R_eff=RADIUS / 2, v_impact=2 * V)
    dt = t_c / 15000
    script = SCRIPT.format(r=RADIUS, d=2 * RADIUS, rho=RHO, E=YOUNG, e=e, nu=NU, v=V, dt=dt, steps=30000)
    (tmp_path / "in.tsuji").write_text(script)
    out = subprocess.run([lmp, "-in", "in.tsuji", "-log", "none"], cwd=tmp_path, capture_output=True, text=True,
                         timeout=60, check=True).stdout
    realised = -float(re.search(r"RESULT (\S+)", out).group(1)) / V
    ref_2021 = reference_collision(normal="hertz", damping="lammps-tsuji-2021", restitution=e).restitution
    ref_now = reference_collision(normal="hertz", damping="lammps-tsuji", restitution=e).restitution
    assert realised == pytest.approx(ref_2021, rel=1e-3)
    assert abs(realised - ref_now) > 0.02
