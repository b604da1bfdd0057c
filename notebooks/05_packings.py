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
# # Packings: the global eigen-analysis against the two-particle bound and the rules of thumb
#
# A particle with many contacts vibrates faster than a particle with one.  Otsubo, O'Sullivan &
# Shire (2017) take the largest eigenfrequency of the whole packing, $K\varphi = \omega^2 M\varphi$
# with 6 degrees of freedom per sphere, and $\Delta t_{crit} = 2/\omega_{max}$ (central difference).
# dtcrit assembles $M$ and $K$ as sparse matrices and sets the exact step beside the cheap
# estimates.

# %%
import numpy as np
import matplotlib.pyplot as plt

from dtcrit.packing import LinearLaw, analyse, lattice, random_packing

law = LinearLaw(1.0e5, 1.0e5)   # kn, ks [N/m]
rep = analyse(lattice("fcc", 2, radius=0.01, density=2500.0), law)
print(f"FCC: omega_max = {rep.omega_max:.4g} rad/s, dt_crit = {rep.dt_crit:.4g} s, alpha = {rep.alpha:.4f}, CN = {rep.cn_max}")
for row in rep.estimate_table():
    print(f"  {row['name']:28s} dt = {row['dt']:.4g} s   x{row['ratio']:.3f}   {'safe' if row['safe'] else 'UNSAFE'}")

# %% [markdown]
# The two-particle bound (a single contact, Peng et al. Eq. 49) is *not* safe in a packing: the
# step of one isolated contact is an upper bound on the packing's step.

# %%
two = [r for r in rep.estimate_table() if "pair" in r["name"] or "two" in r["name"]]
print(two)
assert all(r["ratio"] >= 1 - 1e-9 for r in two)

# %% [markdown]
# ## $\alpha$ against the coordination number
# Random monodisperse packings of 200 spheres at several mean coordination numbers.

# %%
rows = []
for cn in (4.5, 6.0, 8.0, 10.0):
    p = random_packing(200, cn=cn, radius=0.01, density=2500.0, seed=1)
    r = analyse(p, law)
    rows.append((r.cn_mean, r.cn_max, r.alpha))
    print(f"target CN {cn:4.1f}: mean CN {r.cn_mean:5.2f}, CN_max {r.cn_max:2d}, alpha = {r.alpha:.4f}")
rows = np.array(rows)
plt.plot(rows[:, 1], rows[:, 2], "o")
plt.xlabel("CN_max"); plt.ylabel(r"$\alpha = \Delta t_{crit}/\sqrt{m_{min}/K_{max}}$")
plt.show()
assert rows[-1, 2] < rows[0, 2]  # denser packings need a smaller step
