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
# # Shapes and aspect ratio: Eq. (26) against the verified bound
#
# For two contacting rigid bodies the contact point accelerates as $\ddot x_c = A\,F + \Omega$
# (Peng et al. 2020, Eq. 25), with a full symmetric $3\times3$ coefficient matrix
# $A = (1/m_1 + 1/m_2)\,\mathbb{1} + \sum_i [r_i]_\times^T W_i [r_i]_\times$.
# The critical step needs the largest eigenvalue of $A$ over every admissible contact.
#
# * The paper's **Eq. (26)** takes $A_{max} = a_1^2/I_{xx,1} + a_2^2/I_{xx,2} + 1/m_1 + 1/m_2$.
# * dtcrit's **`a_bound`** is the supremum of each particle's arm term over its whole body
#   (a convex function of the arm, so for a polyhedron it is attained at a vertex), added up.
#
# Change the shapes below and re-run.

# %%
import numpy as np
import matplotlib.pyplot as plt

import dtcrit
from dtcrit.bodies import Box, Ellipsoid, Sphere, Superquadric

shapes = {
    "sphere r=1": Sphere(1.0, density=1000.0),
    "ellipsoid 3x2x1": Ellipsoid(3.0, 2.0, 1.0, density=1000.0),
    "superquadric 3x2x1, eps=0.5": Superquadric(3.0, 2.0, 1.0, 0.5, 0.5, density=1000.0),
    "cube (box 1x1x1)": Box(1.0, 1.0, 1.0, density=1000.0),
    "box 3x2x1": Box(3.0, 2.0, 1.0, density=1000.0),
}
rows = []
for name, p in shapes.items():
    rows.append((name, p.mass, dtcrit.a_max(p), dtcrit.a_bound(p)))
    print(f"{name:30s} m={p.mass:10.4g} kg   A_max(Eq 26)*m={dtcrit.a_max(p)*p.mass:7.4f}   a_bound*m={dtcrit.a_bound(p)*p.mass:7.4f}")

# %% [markdown]
# Two identical spheres give exactly $7/m$ both ways.  For ellipsoids Eq. (26) is conservative
# (the arm to the tip, along $x$, cannot produce a moment about $x$, so the tip term is
# $a^2/I_{yy}$, not $a^2/I_{xx}$).  For boxes the corner is farther than the half-length, and
# Eq. (26) is **not** an upper bound.

# %%
sphere = shapes["sphere r=1"]
assert abs(dtcrit.a_max(sphere) * sphere.mass - 7) < 1e-12 and abs(dtcrit.a_bound(sphere) * sphere.mass - 7) < 1e-12
ell = shapes["ellipsoid 3x2x1"]
assert dtcrit.a_bound(ell) < dtcrit.a_max(ell)
for name in ("cube (box 1x1x1)", "box 3x2x1"):
    assert dtcrit.a_bound(shapes[name]) > dtcrit.a_max(shapes[name]), name
print("Eq. (26) is exceeded for boxes, conservative for ellipsoids")

# %% [markdown]
# ## A random search over contact arms and orientations
# For random arms to surface points and random orientations, the largest eigenvalue of the full
# coefficient matrix never exceeds `a_bound` -- and for the cube it exceeds Eq. (26).

# %%
rng = np.random.default_rng(0)

def random_rotation(rng):
    """A uniformly random proper rotation matrix (QR of a Gaussian matrix)."""
    Q, R = np.linalg.qr(rng.normal(size=(3, 3)))
    Q = Q * np.sign(np.diag(R))
    return Q if np.linalg.det(Q) > 0 else -Q

def search(p, n=3000):
    pts, _ = p.surface_points(400)
    if p.vertices is not None:
        pts = np.vstack([pts, p.vertices])
    best = 0.0
    for _ in range(n):
        R1, R2 = random_rotation(rng), random_rotation(rng)
        r1 = pts[rng.integers(len(pts))]
        r2 = pts[rng.integers(len(pts))]
        # orientations body to world (dtcrit's convention for every rotation and quaternion):
        # the surface points, in body components, map to world arms with R
        A = dtcrit.coefficient_matrix(p, p, R1 @ r1, R2 @ r2, body_to_world=(R1, R2))
        best = max(best, np.linalg.eigvalsh(A)[-1])
    return best

for name in ("ellipsoid 3x2x1", "cube (box 1x1x1)"):
    p = shapes[name]
    found = search(p)
    print(f"{name:20s} searched max*m = {found*p.mass:.4f}   a_bound*m = {dtcrit.a_bound(p)*p.mass:.4f}   A_max*m = {dtcrit.a_max(p)*p.mass:.4f}")
    assert found <= dtcrit.a_bound(p) * (1 + 1e-9)
assert search(shapes["cube (box 1x1x1)"], 2000) > dtcrit.a_max(shapes["cube (box 1x1x1)"])

# %% [markdown]
# ## Aspect ratio at fixed volume (the paper's Fig. 6)
# Ellipsoids of volume $8\pi$ m³, $k_n = k_s = 10^{10}$ N/m, $\rho = 1000$, undamped, velocity
# Verlet.  The translation-dominant step falls as the particle departs from a sphere, so an
# "equivalent sphere" step is not conservative.  How much it falls depends on the bound: with
# Eq. (26)'s $A_{max}$ (the paper's Eq. (48)) it falls steeply, with the verified `a_bound` far
# less (83 % against 24 % from the sphere to $e_1 = e_2 = 5$ on the full Fig. 6 grid): most of the
# paper's strong decrease is the looseness of Eq. (26).

# %%
from dtcrit.figures.fig6_aspect_ratio import ellipsoid_axes

e1s = np.linspace(1, 5, 9)
dts_paper, dts_verified = [], []
for e1 in e1s:
    a, b, c = ellipsoid_axes(e1, 1.0)
    p = Ellipsoid(a, b, c, density=1000.0)
    dts_paper.append(dtcrit.critical_dt("velocity-verlet", 1e10, 0.0, dtcrit.a_max(p)).dt)
    dts_verified.append(dtcrit.critical_dt("velocity-verlet", 1e10, 0.0, dtcrit.a_bound(p)).dt)
plt.plot(e1s, dts_paper, "o-", label="with Eq. (26) A_max")
plt.plot(e1s, dts_verified, "s-", label="with verified a_bound")
plt.xlabel("e1 = a/b (e2 = 1)"); plt.ylabel("critical dt [s]"); plt.legend()
plt.show()
assert np.all(np.diff(dts_verified) < 0) and np.all(np.diff(dts_paper) < 0)
fall_paper, fall_verified = 1 - dts_paper[-1] / dts_paper[0], 1 - dts_verified[-1] / dts_verified[0]
print(f"from e1 = 1 to 5 (e2 = 1) the step falls {100 * fall_paper:.1f} % with A_max, {100 * fall_verified:.1f} % with a_bound")
assert fall_paper > 2 * fall_verified
