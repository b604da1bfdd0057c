"""The immutable base of every particle shape: mass, volume, density, principal inertia, half-lengths,
largest arm, surface samples and the paper's assumption flags (fixed once in ``_finish``).
"""
from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np

from dtcrit.bodies.checks import AssumptionWarning, _assumption_issues, _count, _fmt, _mass_and_density, _vec3
from dtcrit.errors import InputError


class _Shape:
    """Common, immutable part of every shape (values fixed in ``_finish``)."""

    kind: str = ""
    __slots__ = ("_mass", "_volume", "_density", "_inertia", "_half_lengths", "_max_arm", "_issues", "_samples", "_frozen")

    def __setattr__(self, name: str, value: Any) -> None:
        if getattr(self, "_frozen", False):
            raise AttributeError(f"{type(self).__name__} is immutable")
        object.__setattr__(self, name, value)

    def __delattr__(self, name: str) -> None:
        raise AttributeError(f"{type(self).__name__} is immutable")

    def _finish(self, volume, density, mass, inertia_per_mass, half_lengths, max_arm, size_key) -> None:
        m, rho = _mass_and_density(float(volume), density, mass, size_key)
        inertia = _vec3(m * i for i in inertia_per_mass)
        if not all(math.isfinite(i) and i > 0.0 for i in inertia):
            raise InputError(size_key, f"principal moments {inertia} are outside double precision")
        self._volume = float(volume)
        self._mass = m
        self._density = rho
        self._inertia = inertia
        self._half_lengths = _vec3(half_lengths)
        self._max_arm = float(max_arm)
        self._issues = _assumption_issues(self._label(), self._half_lengths, inertia)
        self._samples: dict[int, tuple[np.ndarray, np.ndarray]] = {}  # n -> (points, normals), by surface_points
        self._frozen = True
        if self._issues:
            warnings.warn(
                "; ".join(self._issues) + " (Peng et al. 2020, Section 3, assumption 3)",
                AssumptionWarning,
                stacklevel=3,
            )

    def _label(self) -> str:  # pragma: no cover - overridden
        return type(self).__name__

    def __repr__(self) -> str:
        return f"{self._label()[:-1]}, mass={_fmt(self._mass)})"

    # ----- public read-only properties ------------------------------------------------------
    @property
    def mass(self) -> float:
        """Mass [kg]."""
        return self._mass

    @property
    def volume(self) -> float:
        """Volume [m^3]."""
        return self._volume

    @property
    def density(self) -> float:
        """Uniform density [kg/m^3]."""
        return self._density

    @property
    def inertia(self) -> tuple[float, float, float]:
        """Principal moments ``(I_xx, I_yy, I_zz)`` about the centre in the local frame [kg m^2]."""
        return self._inertia

    @property
    def half_lengths(self) -> tuple[float, float, float]:
        """Half-lengths ``(a, b, c)`` of the local axis-aligned bounding box [m]."""
        return self._half_lengths

    @property
    def max_arm(self) -> float:
        """Largest distance from the centre to the surface [m]."""
        return self._max_arm

    @property
    def equivalent_radius(self) -> float:
        """Radius of the sphere of equal volume, (3 V / (4 pi))^(1/3) [m]."""
        return float(np.cbrt(3.0 / (4.0 * math.pi)) * np.cbrt(self._volume))

    @property
    def vertices(self) -> np.ndarray | None:
        """Corners ``(N, 3)`` in the local frame for boxes and polyhedra, ``None`` otherwise."""
        return None

    @property
    def satisfies_paper_assumptions(self) -> bool:
        """Whether a >= b >= c and I_zz >= I_yy >= I_xx hold (Peng et al. 2020, Section 3, assumption 3)."""
        return not self._issues

    @property
    def assumption_issues(self) -> tuple[str, ...]:
        """What fails of Peng et al. (2020) Section 3 assumption 3, one sentence each (empty if none)."""
        return self._issues

    def surface_points(self, n: int) -> tuple[np.ndarray, np.ndarray]:
        """About ``n`` surface points roughly uniform in area and their outward unit normals.

        Returns ``(points, normals)``, two ``(N, 3)`` arrays in the local frame; deterministic
        (computed once per ``n`` and cached; each call returns fresh copies).  The sampling is
        described by each shape's ``_sample``.
        """
        n = _count(n)
        if n not in self._samples:
            if len(self._samples) >= 16:
                self._samples.pop(next(iter(self._samples)))
            self._samples[n] = self._sample(n)
        points, normals = self._samples[n]
        return points.copy(), normals.copy()

    def _sample(self, n: int) -> tuple[np.ndarray, np.ndarray]:  # pragma: no cover - overridden
        raise NotImplementedError

    def support(self, direction: Any) -> np.ndarray:
        """The surface point farthest along ``direction`` (local frame); ``(3,)`` or ``(N, 3)``."""
        raise NotImplementedError
