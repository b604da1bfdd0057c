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
# # From quaternions to A_max: the contact kinematics of Peng et al. 2020, Sections 2–3
#
# Two rigid particles touch at a point.  A force $F$ on particle 2 (and $-F$ on particle 1) makes the
# contact point accelerate relative to both bodies:
#
# * translation: $\pm F/m_i$;
# * rotation: the moment $r_i \times F$ turns each body through Euler's equations (Eqs 11–12),
#   expressed in its principal frame with a rotation matrix built from a unit quaternion (Eq 7).
#
# dtcrit writes these equations once, for arbitrary particles, in SymPy
# (`dtcrit.symbolic.kinematics`), and derives everything else from them.

# %%
import numpy as np
import sympy as sp
import matplotlib.pyplot as plt

from dtcrit.symbolic import coefficient_forms as cforms
from dtcrit.symbolic import kinematics as K
from dtcrit.symbolic import quaternions as quat
from dtcrit.symbolic import tip_configurations as tips

qw, qx, qy, qz = sp.symbols("q_w q_x q_y q_z", real=True)
quat.quaternion_rotation_matrix((qw, qx, qy, qz))

# %% [markdown]
# This is the matrix of Eq. (7).  dtcrit reads a quaternion $q$ as a particle's orientation, body to
# world: $v_{world} = R(q)\,v_{body}$, in every function and JSON key that carries one.  The paper uses
# $M_L = R\,M_G$ (Eq. 5), a matrix from global to body components: that is $R(q)^T$, the matrix of
# the conjugate quaternion.  The convention checks (orthogonality, composition, inversion by the
# conjugate) all hold:

# %%
checks = quat.check_rotation_convention()
checks

# %%
assert all(checks.values())

# %% [markdown]
# ## Figure 2(A), derived, not typed
# Particle 1 is axis aligned with its arm to its $a_1$ tip; particle 2 is turned so that its long
# axis points along $-z$.  The coefficient of $F$ in $\ddot x_c$ comes out of the general equations.

# %%
conf = tips.FIG2["A"]
p1, p2 = conf.particles()
A = K.coefficient_matrix(p1, p2)
A

# %% [markdown]
# ## Two spheres: $A_{max} = 7/m$
# For two identical spheres in contact along an *arbitrary* normal $n$, with *arbitrary* unit
# quaternions, the general kinematics give $A = \frac{2}{m}\mathbb 1 + \frac{5}{m}(\mathbb 1 - n n^T)$,
# whose largest eigenvalue is $7/m$, exactly the paper's Eq. (26) for spheres; hence
# $\Delta t = \frac{2}{\sqrt 7}\sqrt{m/k}$ (Eq. 49) for the undamped central-difference family.

# %%
sph = cforms.sphere_pair_check()
print("residual A - closed form:", sph["residual"])
print("largest eigenvalue:", sph["lambda_max"], "  Eq. (26):", sph["a_max_eq26"])
assert sph["residual"] == sp.zeros(3, 3)
assert sp.simplify(sph["lambda_max"] - sph["a_max_eq26"]) == 0

import dtcrit
from dtcrit.bodies import Sphere
s = Sphere(0.01, density=2500.0)
alpha = dtcrit.critical_dt("velocity-verlet", 1e5, 0.0, dtcrit.a_bound(s)).dt * np.sqrt(1e5 / s.mass)
print(f"alpha = dt*sqrt(k/m) = {alpha:.15f}   2/sqrt(7) = {2/np.sqrt(7):.15f}")
assert abs(alpha - 2 / np.sqrt(7)) < 1e-14

# %% [markdown]
# ## The three configurations of Fig. 2, drawn
# Ellipsoids with $a = 3$, $b = 2$, $c = 1$ m.  Particle 2's body axes are the rows of its $R$;
# its centre sits at $x_c - r_2$.

# %%
def ellipsoid_mesh(center, R, axes, n=24):
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, n), np.linspace(0, np.pi, n))
    local = np.stack([axes[0] * np.cos(u) * np.sin(v), axes[1] * np.sin(u) * np.sin(v), axes[2] * np.cos(v)])
    glob = np.einsum("ji,jkl->ikl", R, local)  # R maps global -> local, so R^T maps local -> global
    return [glob[i] + center[i] for i in range(3)]

vals = {tips.P1.half_lengths[i]: v for i, v in enumerate((3.0, 2.0, 1.0))}
vals.update({tips.P2.half_lengths[i]: v for i, v in enumerate((3.0, 2.0, 1.0))})
fig = plt.figure(figsize=(12, 4))
for k, label in enumerate("ABC"):
    c = tips.FIG2[label]
    r1 = np.array(c.arm_global(1).subs(vals), dtype=float).ravel()
    r2 = np.array(c.arm_global(2).subs(vals), dtype=float).ravel()
    xc = r1
    ax = fig.add_subplot(1, 3, k + 1, projection="3d")
    for centre, R in ((np.zeros(3), np.array(c.R1, dtype=float)), (xc - r2, np.array(c.R2, dtype=float))):
        ax.plot_surface(*ellipsoid_mesh(centre, R, (3.0, 2.0, 1.0)), alpha=0.35)
    ax.scatter(*xc, color="k", s=30)
    ax.set_title(f"Fig. 2({label})"); ax.set_box_aspect((1, 1, 1))
plt.show()
