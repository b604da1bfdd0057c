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
# # Damping and the integrator: which bound belongs to which scheme
#
# "The" critical time step does not exist without naming the integrator, and with viscous damping
# the details matter: *which velocity* the damping force sees.  Here we put side by side
#
# * the exact bound of every integrator in dtcrit (derived from its update rule),
# * the CFL note's formula $\Delta t \le \frac{2}{\omega}(\sqrt{\zeta^2+1} - \zeta)$,
# * Belytschko's criterion (Peng et al. 2020, Eq. 34), Silbert's collision time (Eq. 36) and the
#   paper's Eq. (46).

# %%
import numpy as np
import matplotlib.pyplot as plt
import mpmath as mp

import dtcrit
from dtcrit._generated import critical_steps as gen

zetas = np.concatenate([[0.0], np.logspace(-3, 2, 400)])
curves = {name: np.array([dtcrit.critical_dt(name, 1.0, 2 * z, 1.0).dt for z in zetas]) for name in dtcrit.INTEGRATORS}
cfl_note = 2 * (np.sqrt(zetas**2 + 1) - zetas)
with np.errstate(invalid="ignore"):
    belytschko = gen.belytschko_eq34(1.0, 2 * zetas, 1.0)
eq46 = np.array([dtcrit.paper_eq46(1.0, 2 * z, 1.0) for z in zetas])

fig, ax = plt.subplots(figsize=(7.5, 4.5))
for name, y in curves.items():
    ax.plot(zetas[1:], y[1:], label=name)
ax.plot(zetas[1:], cfl_note[1:], "k:", lw=3, label="CFL note")
ax.plot(zetas[1:], belytschko[1:], "c--", label="Belytschko Eq. (34)")
ax.plot(zetas[1:], eq46[1:], "r--", label="paper Eq. (46)")
ax.set_xscale("log"); ax.set_yscale("log")
ax.set_xlabel(r"damping ratio $\zeta$"); ax.set_ylabel(r"$\omega\,\Delta t_{crit}$")
ax.legend(fontsize=7, ncol=2)
plt.show()

# %% [markdown]
# ## Which integrators does the CFL note's formula belong to?
# It coincides with three schemes: lagged-velocity leapfrog, symplectic Euler and velocity Verlet
# with the half-step velocity in the damping force (what LAMMPS, LIGGGHTS and PFC do).  They share
# one reduced characteristic polynomial.
#
# A numerical aside: written as $2(\sqrt{\zeta^2+1} - \zeta)$ the formula subtracts two nearly
# equal numbers when $\zeta$ is large and loses digits; dtcrit evaluates the equivalent
# $2/(\zeta + \sqrt{\zeta^2+1})$ (with `hypot`), which keeps full precision.

# %%
moderate = zetas <= 1
owners = [n for n, y in curves.items() if np.allclose(y[moderate], cfl_note[moderate], rtol=1e-13, atol=0)]
print("CFL note's bound is exact for:", owners)
assert sorted(owners) == ["leapfrog", "symplectic-euler", "velocity-verlet"]
stable_form = 2 / (zetas + np.hypot(zetas, 1.0))
worst = np.max(np.abs(cfl_note / stable_form - 1))
print(f"digits lost by the subtractive form up to zeta = 100: relative error {worst:.1e}")
# against a 50-digit reference: dtcrit's step is within 4 ulp of the exact value for every zeta
with mp.workdps(50):
    exact = np.array([float(2 / (mp.mpf(z) + mp.sqrt(mp.mpf(z) ** 2 + 1))) for z in zetas])
ulps = np.abs(curves["leapfrog"] - exact) / np.spacing(exact)
print(f"dtcrit's leapfrog bound against 50-digit mpmath: at most {ulps.max():.1f} ulp")
assert ulps.max() <= 4

# %% [markdown]
# ## Belytschko and Eq. (46) are not bounds once there is damping
# Belytschko's $2/\omega_d$ (Eq. 34) *grows* with damping and stops existing at critical damping;
# Eq. (46) also grows with damping.  Every real integrator's bound shrinks (except centred damping,
# which keeps $\omega\Delta t = 2$).  So both overestimate the safe step for every damped case.

# %%
damped = zetas > 0
for name, y in curves.items():
    assert np.all(eq46[damped] > y[damped]), name
under = damped & (zetas < 1)
for name, y in curves.items():
    assert np.all(belytschko[under] >= y[under] * (1 - 1e-12)), name
print("Eq. (46) and Belytschko exceed every integrator's exact bound whenever zeta > 0")

# %% [markdown]
# ## Silbert's collision time (Eq. 36)
# For two identical spheres of mass $m$ ($A = 7/m$ for the two-sphere contact, $\beta = c/\sqrt{mk}$)
# Silbert's time $\pi/\sqrt{2k/m - c^2/(4m^2)}$ is a *collision duration*, not a stability bound:
# codes take a fraction of it (1/50 in MercuryDPM and MFiX).  Compare with the exact bound:

# %%
m, k = 1.0, 1.0
betas = np.linspace(0, 1.5, 7)
for b in betas:
    c = b * np.sqrt(m * k)
    exact = dtcrit.critical_dt("velocity-verlet", k, c, 7 / m).dt
    silbert = gen.silbert_eq36(k, c, m)
    print(f"beta={b:4.2f}  exact VV bound={exact:7.4f}  Silbert={silbert:7.4f}  Silbert/50={silbert/50:7.4f}  ratio={silbert/exact:5.2f}")
    assert silbert / 50 < exact  # the /50 rule of thumb is safe here, by a wide margin
