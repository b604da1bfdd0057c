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
# # Impact: exit velocity against ω·Δt and the entry phase
#
# The linear stability bound assumes a contact that lasts forever.  A real DEM contact opens and
# closes within a few steps, and the question the CFL note asks is different: after one impact,
# does the particle leave **faster** than it came in?  If so, the integrator created energy.
#
# The answer depends on where, within a step, the contact begins (the *entry phase*), so we sweep
# it.  Units: time $1/\omega$ with $\omega = \sqrt{k/m}$, speed $v_0$.

# %%
INTEGRATOR = "leapfrog"      # try "velocity-verlet", "forward-euler"
ZETA = 0.05                  # damping ratio of the contact

# %%
import numpy as np
import matplotlib.pyplot as plt

import dtcrit
from dtcrit.impact import entry_phases, exact_impact, phase_stats, simulate_impacts, undamped_exit_ratios

exact = exact_impact(ZETA)
print(f"exact impact: duration {exact.duration:.4f}/omega, exit/entry speed {exact.exit_ratio:.6f}")

# %% [markdown]
# ## Sweep over the step and the entry phase

# %%
taus = np.linspace(0.02, 2.2, 110)
phases = entry_phases(64)
run = simulate_impacts(INTEGRATOR, taus, phases, ZETA)
stats = phase_stats(run)
lo = np.array([s.min for s in stats]); hi = np.array([s.max for s in stats]); mean = np.array([s.mean for s in stats])
bound = dtcrit.critical_dt(INTEGRATOR, 1.0, 2 * ZETA, 1.0).dt

fig, ax = plt.subplots(figsize=(7, 4))
ax.fill_between(taus, lo, hi, alpha=0.3, label="min..max over entry phases")
ax.plot(taus, mean, label="mean over phases")
ax.axhline(exact.exit_ratio, color="k", ls=":", label="exact")
ax.axhline(1.0, color="r", lw=0.8, label="$v_{exit} = v_{entry}$ (above: energy created)")
ax.axvline(bound, color="g", ls="--", label="linear stability bound")
ax.set_xlabel(r"$\omega\,\Delta t$"); ax.set_ylabel(r"$v_{exit}/v_{entry}$"); ax.set_ylim(0, 3)
ax.legend(fontsize=8)
plt.show()

# %% [markdown]
# ## What the sweep shows
# * Small steps reproduce the exact exit speed.
# * Inside the linear stability range, light damping does **not** prevent energy creation for some
#   entry phases: the linear bound does not guarantee $v_{exit} \le v_{entry}$.

# %%
small = taus < 0.1
assert np.allclose(mean[small], exact.exit_ratio, rtol=0.02)
inside = (taus < bound) & (hi > 1.0)
print(f"steps inside the linear bound where some phase leaves faster than it came: {inside.sum()} of {(taus < bound).sum()}")
if INTEGRATOR == "leapfrog" and ZETA == 0.05:
    assert inside.any()

# %% [markdown]
# ## The undamped closed form
# For the central-difference family the undamped exit ratio has a closed form in the entry and exit
# phases; it equals 1 for *every* phase at the isolated steps $\tau_N = 2\sin(\pi/2N)$ (Feng 2005's
# "few values"), and otherwise lies between $\sqrt{1-\tau^2/4}$ and its reciprocal.

# %%
tau_N = [2 * np.sin(np.pi / (2 * N)) for N in (2, 3, 4)]
closed = undamped_exit_ratios("leapfrog", np.array(tau_N), phases)
sim = simulate_impacts("leapfrog", np.array(tau_N), phases, 0.0).ratios
print("max |ratio - 1| at tau_N:", np.max(np.abs(sim - 1)))
assert np.allclose(sim, 1.0, atol=1e-12) and np.allclose(closed, sim, atol=1e-12)
