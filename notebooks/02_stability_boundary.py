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
# # Amplification matrices and the true stability boundary
#
# An explicit integrator maps the state of a contact, e.g. $(x_n, v_n)$, to the next state by a
# fixed linear rule when the contact law is linear, $\ddot x = -kA\,x - cA\,\dot x$
# (Peng et al. 2020, Eq. 30).  That linear map is the **amplification matrix** $G$:
# $s_{n+1} = G\,s_n$.  The scheme is stable when every eigenvalue of $G$ — complex ones included —
# lies inside the unit circle, i.e. when the spectral radius $\rho(G) \le 1$.
#
# dtcrit never types $G$ in: each integrator is written once as its update rule, and SymPy
# differentiates the rule.  Change the integrator or the damping below and re-run.

# %%
INTEGRATOR = "velocity-verlet"   # try "leapfrog-centred", "forward-euler", "paper-eq40"
ZETA_MAX = 3.0                   # damping ratios shown on the map

# %%
import numpy as np
import matplotlib.pyplot as plt
import sympy as sp

import dtcrit
from dtcrit.integrators.amplification import spectral_radius
from dtcrit.symbolic.integrators import amplification_matrix, characteristic_polynomial
from dtcrit.symbolic.jury import jury_conditions

G = amplification_matrix(INTEGRATOR, dimensionless=True)
G

# %% [markdown]
# In scaled variables $\tau = \omega\,\Delta t$ and $\zeta = cA/(2\omega)$ with $\omega = \sqrt{kA}$,
# the characteristic polynomial depends on $(\tau, \zeta)$ only.  Zero eigenvalues (from a stored
# acceleration) are removed: they never matter for stability.

# %%
P = characteristic_polynomial(INTEGRATOR)
P.as_expr()

# %% [markdown]
# The Schur–Cohn / Jury conditions say, without solving for the roots, when all of them are inside
# the unit circle.  Each expression below must be positive.

# %%
for label, expr in jury_conditions(P):
    print(f"{label:55s}  {sp.factor(expr)}")

# %% [markdown]
# ## The spectral-radius map
#
# Colour: $\log_{10}\rho(G)$ computed by a direct eigen-solve at every point.  Black: dtcrit's
# closed-form boundary.  Red dashed: the paper's Eq. (46), the point where a *real* eigenvalue of
# the Eq. (40) scheme reaches $-1$.

# %%
taus = np.linspace(0.005, 4.5, 300)
zetas = np.linspace(0.0, ZETA_MAX, 200)
T, Z = np.meshgrid(taus, zetas)
rho = spectral_radius(INTEGRATOR, T, Z)

tau_crit = np.array([dtcrit.critical_dt(INTEGRATOR, 1.0, 2 * z, 1.0).dt for z in zetas])
tau_eq46 = np.array([dtcrit.paper_eq46(1.0, 2 * z, 1.0) for z in zetas])

fig, ax = plt.subplots(figsize=(7, 4.5))
im = ax.pcolormesh(T, Z, np.log10(np.maximum(rho, 1e-3)), cmap="RdBu_r", vmin=-0.5, vmax=0.5, shading="auto")
ax.plot(tau_crit, zetas, "k", lw=2, label=f"dtcrit: exact boundary ({INTEGRATOR})")
ax.plot(tau_eq46, zetas, "r--", lw=2, label="paper Eq. (46)")
ax.set_xlabel(r"$\omega\,\Delta t$")
ax.set_ylabel(r"$\zeta$")
ax.set_xlim(taus[0], taus[-1])
fig.colorbar(im, label=r"$\log_{10}\rho(G)$")
ax.legend(loc="upper right")
plt.show()

# %% [markdown]
# ## The claims, checked
# Just inside the black curve the spectral radius is at most 1; just outside it exceeds 1.  Eq. (46)
# lies in the unstable (red) region for every damped case.

# %%
for z, t in zip(zetas[1::20], tau_crit[1::20]):
    if t == 0:
        assert spectral_radius(INTEGRATOR, 0.01, z) > 1
        continue
    assert spectral_radius(INTEGRATOR, 0.999 * t, z) <= 1 + 1e-9, (z, t)
    assert spectral_radius(INTEGRATOR, 1.001 * t, z) > 1, (z, t)
for z, t46 in zip(zetas[1::20], tau_eq46[1::20]):
    assert spectral_radius(INTEGRATOR, t46, z) > 1
print("boundary confirmed by direct eigen-solves; Eq. (46) is unstable for every damped case shown")
