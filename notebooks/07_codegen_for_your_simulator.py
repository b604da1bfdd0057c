# ---
# jupyter:
#   jupytext:
#     formats: py:percent
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # Generating code for your own simulator
#
# `dtcrit codegen SCENE --lang c` emits a self-contained C function that returns the critical
# step of one contact, specialised to the scene: undamped scenes carry no damping terms, identical
# particles one set of arguments, spheres their two exact contact modes, $A_n = 2/m$ (normal) and $A_s = 7/m$ (sliding with rolling).  Here we emit it, compile it with the
# system C compiler, call it, and use the step in a small velocity-Verlet loop of a damped
# two-sphere contact: stable at 0.99 of the step, blowing up at 1.01.

# %%
import ctypes
import shutil
import subprocess
import tempfile
from pathlib import Path

import numpy as np
import matplotlib.pyplot as plt

from dtcrit.codegen import emit_for_scene
from dtcrit.scenes.scene import parse_scene

SCENE = """
title = "two steel spheres, damped linear contact"
integrator = "velocity-verlet"

[[particle]]
shape = "sphere"
radius = 0.005
density = 7800.0

[contact]
model = "linear"
kn = 2.0e6
ks = 1.5e6
damping_ratio = 0.2
"""
scene = parse_scene(SCENE, "steel_spheres.toml")
source = emit_for_scene(scene, "c")
print(source)

# %% [markdown]
# ## Compile and call it

# %%
cc = shutil.which("cc") or shutil.which("gcc")
assert cc, "a C compiler is needed for this notebook"
work = Path(tempfile.mkdtemp())
(work / "dt.c").write_text(source)
subprocess.run([cc, "-O2", "-shared", "-fPIC", "-o", str(work / "libdt.so"), str(work / "dt.c"), "-lm"], check=True)
lib = ctypes.CDLL(str(work / "libdt.so"))
fn = lib.dtcrit_dt_crit
fn.restype = ctypes.c_double
n_args = source.split("dtcrit_dt_crit(")[1].split(")")[0].count("double")
fn.argtypes = [ctypes.c_double] * n_args

m = scene.particles[0].shape.mass
kn, ks = 2.0e6, 1.5e6
zeta = 0.2
A_n, A_s = 2.0 / m, 7.0 / m        # the two modes of two equal spheres (arm = radius)
cn = 2 * zeta * np.sqrt(kn / A_n)  # damping coefficients for zeta = 0.2 of each contact mode
cs = 2 * zeta * np.sqrt(ks / A_s)
print("arguments:", source.split("dtcrit_dt_crit(")[1].split(")")[0])
dt = fn(m, kn, ks, cn, cs)
print(f"critical step from the compiled C: {dt:.6e} s")

# %% [markdown]
# ## A velocity-Verlet loop on each contact mode
# $\ddot x = -k A\,x - c A\,\dot x$ (Peng et al. 2020, Eq. 30) for the normal mode $(k_n, c_n, A_n)$ and
# the tangential one $(k_s, c_s, A_s)$, the damping force from the half-step velocity, as LAMMPS,
# LIGGGHTS and PFC evaluate it.  The stiffer mode (here the tangential: $k_s A_s > k_n A_n$) governs.

# %%
def run(step, k, c, A, n=4000):
    x, v = 1e-6, 0.0
    a = -k * A * x - c * A * v
    amp = []
    for _ in range(n):
        v_half = v + 0.5 * step * a
        x = x + step * v_half
        a = -k * A * x - c * A * v_half
        v = v_half + 0.5 * step * a
        amp.append(abs(x))
    return np.array(amp)

normal = (kn, cn, A_n)
shear = (ks, cs, A_s)
below = [run(0.99 * dt, *mode) for mode in (normal, shear)]
above = run(1.01 * dt, *shear)
plt.semilogy(below[1], label="tangential mode, 0.99 dt_crit")
plt.semilogy(above, label="tangential mode, 1.01 dt_crit")
plt.semilogy(below[0], label="normal mode, 0.99 dt_crit", alpha=0.6)
plt.xlabel("step"); plt.ylabel("|x|"); plt.legend()
plt.show()
assert all(b[-1] < b[0] for b in below) and above[-1] > 1e3 * above[0]
print(f"tangential mode, 0.99 dt: |x| {below[1][0]:.1e} -> {below[1][-1]:.1e};  1.01 dt: |x| {above[0]:.1e} -> {above[-1]:.1e}")
