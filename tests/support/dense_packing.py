"""Small sphere packings for the audit's mode tests: a dump, a contact table, and their dense ``K`` and
``M`` assembled here by hand, independently of ``dtcrit.packing.operators``.

Kinematics (Otsubo et al. 2017, Section 3; global rotation axes for spheres): the contact point of
``i`` moves by ``u_i + theta_i x a_i``, so the relative displacement is
``delta = [-1, [a_i]_x] q_i + [1, -[a_j]_x] q_j`` and the relative rotation ``rho = theta_j - theta_i``.
Each spring term is ``G^T T G`` with ``T = k n n^T`` (normal, twisting) or ``k (1 - n n^T)``
(tangential, rolling).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


def cross_matrix(a) -> np.ndarray:
    """``[a]_x`` with ``[a]_x b = a x b``."""
    x, y, z = a
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


@dataclass
class DensePacking:
    """Spheres (id, x, radius, mass) and contacts (i, j, kn, ks, kr, ktw) with the arms the audit uses."""

    ids: list
    positions: np.ndarray
    radii: np.ndarray
    masses: np.ndarray
    contacts: list  # (index i, index j, kn, ks, kr, ktw)

    def dump_text(self, box=(-0.1, 0.1)) -> str:
        """A LAMMPS text dump of the spheres (non-periodic box)."""
        lines = ["ITEM: TIMESTEP", "0", "ITEM: NUMBER OF ATOMS", str(len(self.ids)), "ITEM: BOX BOUNDS ff ff ff"]
        lines += [f"{box[0]!r} {box[1]!r}"] * 3
        lines.append("ITEM: ATOMS id type x y z radius mass")
        for pid, x, r, m in zip(self.ids, self.positions, self.radii, self.masses):
            lines.append(" ".join([str(pid), "1"] + [repr(float(v)) for v in (*x, r, m)]))
        return "\n".join(lines) + "\n"

    def table_text(self) -> str:
        """The contact table ``id1 id2 kn ks kr ktw fn`` (no pre-load: ``fn = 0``)."""
        rows = ["id1 id2 kn ks kr ktw fn"]
        rows += [" ".join([str(self.ids[i]), str(self.ids[j])] + [repr(float(v)) for v in k]) + " 0.0"
                 for i, j, *k in self.contacts]
        return "\n".join(rows) + "\n"

    def mass(self) -> np.ndarray:
        """``M = diag(m, m, m, 2/5 m R^2 x 3)``, dense."""
        inertia = 0.4 * self.masses * self.radii**2
        return np.diag(np.column_stack([np.repeat(self.masses[:, None], 3, 1), np.repeat(inertia[:, None], 3, 1)]).ravel())

    def stiffness_terms(self) -> dict[str, np.ndarray]:
        """Dense ``K`` of each spring kind, full-radius arms ``a_i = R_i n``, ``a_j = -R_j n`` (LAMMPS)."""
        n6 = 6 * len(self.ids)
        out = {k: np.zeros((n6, n6)) for k in ("normal", "tangential", "rolling", "twisting")}
        for i, j, kn, ks, kr, ktw in self.contacts:
            d = self.positions[j] - self.positions[i]
            n = d / np.linalg.norm(d)
            nn = np.outer(n, n)
            slip = np.zeros((3, n6))
            slip[:, 6 * i:6 * i + 3] = -np.eye(3)
            slip[:, 6 * i + 3:6 * i + 6] = cross_matrix(self.radii[i] * n)
            slip[:, 6 * j:6 * j + 3] = np.eye(3)
            slip[:, 6 * j + 3:6 * j + 6] = -cross_matrix(-self.radii[j] * n)
            turn = np.zeros((3, n6))
            turn[:, 6 * i + 3:6 * i + 6] = -np.eye(3)
            turn[:, 6 * j + 3:6 * j + 6] = np.eye(3)
            out["normal"] += slip.T @ (kn * nn) @ slip
            out["tangential"] += slip.T @ (ks * (np.eye(3) - nn)) @ slip
            out["twisting"] += turn.T @ (ktw * nn) @ turn
            out["rolling"] += turn.T @ (kr * (np.eye(3) - nn)) @ turn
        return out
