"""The JSON summary of ``dtcrit figures --json``: the verdicts of every figure in numbers.

Keys (each present when its figure was run):

* ``fig3``: for two spheres, ``A*m`` of Eq. (26) and of the verified bound, and dt*sqrt(k/m) at
  beta = 0 and 1 for the printed Eq. (60) and each integrator's verified bound;
* ``fig4`` / ``fig5``: the trend with damping N of the printed Eq. (46) and of each scene integrator's
  verified bound, the ratio a_bound/A_max, and the values at the first sweep point;
* ``aspect_ratio`` (Fig. 6): ``min_ratio``, ``max_ratio`` (largest finite), ``fraction_over_1e4``
  over the grid of rotation-dominant / translation-dominant steps (Eq. (57) / Eq. (48)), the grid
  points where the ratio is unbounded (a sphere: B_max = 0), ``translation_fall_sphere_to_5_5`` (the
  fraction by which the translation-dominant step falls from e1 = e2 = 1 to e1 = e2 = 5), the same
  with the verified bound (``verified``, same grid), and ``four_orders_region`` (distance from
  e1 = e2 = 1 within which the printed ratio exceeds 1e4; with a_bound <= A_max the verified ratio
  is smaller still);
* ``appendix_a``: ``orthogonal``, ``max_found``, ``max_config``, ``orthogonal_is_max`` (|xdd_c| for
  F = (1, 1, 1)), the eigenvalue maxima, and the superquadric and box searches.  Each configuration
  carries particle 2's orientation as ``quaternion_2_body_to_world_wxyz`` (body to world, the
  convention of ``dtcrit.bodies.contact.coefficient_matrix``: passed there as
  ``body_to_world=(None, q)``, it reproduces the configuration's ``matrix`` and ``accel``).

:func:`document` puts the envelope of every dtcrit JSON document in front (``dtcrit.json_meta``:
``schema`` = ``dtcrit-figures/1``, ``dtcrit_version``, ``units``, ``derivation_hashes``); its schema is
``dtcrit/schemas/dtcrit-figures-1.json``.  Values are plain floats; nothing infinite or NaN is
emitted (strict JSON).
"""
from __future__ import annotations


import numpy as np

from dtcrit.physics.json_numbers import json_safe

__all__ = ["JSON_SCHEMA", "JSON_UNITS", "document", "summary", "fig3_summary", "pair_summary", "aspect_ratio_summary"]

JSON_SCHEMA = "dtcrit-figures/1"
_PAIR_UNITS = {
    "first_point.k_n": "N/m", "first_point.density": "kg/m^3", "a_max_eq26": "1/kg", "a_bound": "1/kg",
    "a_bound_over_a_max": "1", "N": "1", "eq46_printed": "s", "verified_a_max.*": "s", "verified_a_bound.*": "s",
}
_CONFIG_UNITS = {
    "accel": "m/s^2", "lambda_max": "1/kg", "normal_1": "1", "contact_point": "m", "r1": "m", "r2": "m",
    "centre_2": "m", "quaternion_2_body_to_world_wxyz": "1", "long_axis_2": "1", "angle_between_long_axes_deg": "deg",
    "matrix": "1/kg",
}
_SHAPE_UNITS = {
    "mass": "kg", "max_arm": "m", "a_max_eq26": "1/kg", "a_bound": "1/kg", "max_accel": "m/s^2",
    "max_accel_grid": "m/s^2", "accel_bound_eq26": "m/s^2", "max_lambda": "1/kg", "max_lambda_grid": "1/kg",
    "lambda_over_eq26": "1", "lambda_over_a_bound": "1", "penetration_of_maximisers": "m", "contacts_evaluated": "1",
}
JSON_UNITS: dict[str, str] = {
    # Fig. 3 is dimensionless throughout: A*m, beta = c/sqrt(m k), dt*sqrt(k/m)
    "fig3.*": "1",
    **{f"{fig}.{k}": u for fig in ("fig4", "fig5") for k, u in _PAIR_UNITS.items()},
    # Fig. 6: step ratios, fractions, counts, (e1, e2) points and distances in the (e1, e2) plane
    "aspect_ratio.*": "1",
    **{f"appendix_a.{k}": u for k, u in {
        "orthogonal": "m/s^2", "orthogonal_lambda": "1/kg", "orthogonal_penetration_depth": "m", "max_found": "m/s^2",
        "margin": "1", "max_lambda_found": "1/kg", "lambda_margin_over_orthogonal": "1", "a_max_eq26": "1/kg",
        "a_bound": "1/kg", "accel_bound_eq26": "m/s^2", "scenarios.*.roll_deg": "deg"}.items()},
    **{f"appendix_a.*.{k}": u for k, u in _CONFIG_UNITS.items()},
    **{f"appendix_a.shapes.*.{k}": u for k, u in _SHAPE_UNITS.items()},
}
"""Unit of every number of a figures document: keys are dotted paths into it, ``*`` standing for any run of
keys (an integrator, a shape, a configuration); a list has the unit of its key; ``1`` is dimensionless.
Appendix A is at unit density with F = (1, 1, 1) N."""


def document(summary_: dict) -> dict:
    """The ``--json`` document: the envelope (``dtcrit.json_meta.envelope``), then the figures' summary.

    Parameters
    ----------
    summary_ : dict
        The figures' summary.

    Returns
    -------
    dict
        The JSON document.
    """
    from dtcrit.json_meta import envelope

    return {**envelope(JSON_SCHEMA, JSON_UNITS), **summary_}


def _clean(obj):
    """Round-trip-safe JSON values (``dtcrit.physics.json_numbers.json_safe``), keys as strings."""
    if isinstance(obj, dict):
        return {str(k): _clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_clean(v) for v in obj]
    return json_safe(obj)


def fig3_summary() -> dict:
    """Figure 3's key numbers at beta = 0..3: A m of Eq. (26) and of the verified bound, Eq. (60), the
    verified steps and the groups of identical curves.

    Returns
    -------
    dict
        JSON-ready summary.
    """
    from dtcrit.figures.fig3_damping import fig3_data

    d = fig3_data(n=4)  # beta = 0, 1, 2, 3
    return {
        "a_max_eq26_times_m": d.a_max_times_m,
        "a_bound_times_m": d.a_bound_times_m,
        "beta": d.beta.tolist(),
        "eq60_printed": d.printed["eq60"].tolist(),
        "verified": {k: v.tolist() for k, v in d.verified.items()},
        "identical_groups": [list(g) for g in d.groups],
    }


def pair_summary(data) -> dict:
    """Figures 4 and 5's key numbers: the steps at the first sweep point and their trends along N.

    Parameters
    ----------
    data : dtcrit.figures.ellipsoid_pair.PairSteps
        The curves.

    Returns
    -------
    dict
        JSON-ready summary.
    """
    from dtcrit.figures.ellipsoid_pair import SCENE_INTEGRATORS, describe_trend

    j = 0
    return {
        "first_point": {"k_n": float(data.stiffness[j]), "density": float(data.density[j])},
        "a_max_eq26": float(data.a_max[j]),
        "a_bound": float(data.a_bound[j]),
        "a_bound_over_a_max": float(data.a_bound[j] / data.a_max[j]),
        "N": list(data.n_values),
        "eq46_printed": data.printed_eq46[:, j].tolist(),
        "eq46_trend_with_N": describe_trend(data.printed_eq46[:, j]),
        "verified_a_max": {n: data.verified_a_max[n][:, j].tolist() for n in SCENE_INTEGRATORS},
        "verified_a_bound": {n: data.verified_a_bound[n][:, j].tolist() for n in SCENE_INTEGRATORS},
        "verified_trend_with_N": {n: describe_trend(data.verified_a_max[n][:, j]) for n in SCENE_INTEGRATORS},
    }


def aspect_ratio_summary(fine: bool = False, region: bool = True) -> dict:
    """Figure 6's key numbers: ratio statistics, the fall from the sphere and the four-orders region.

    Parameters
    ----------
    fine : bool
        Use the fine grid.
    region : bool
        Also measure the region where the ratio exceeds 1e4.

    Returns
    -------
    dict
        JSON-ready summary.
    """
    from dtcrit.figures.fig6_aspect_ratio import fig6_data, four_orders_region, ratio_at

    d = fig6_data(161 if fine else 41)
    out = {}
    for key, verified in (("printed", False), ("verified", True)):
        st = d.ratio_stats(verified)
        r = d.ratio_verified if verified else d.ratio_printed
        inf_pts = [[float(d.e1[i]), float(d.e2[j])] for i, j in zip(*np.nonzero(~np.isfinite(r)))]
        out[key] = {
            "min_ratio": st["min_ratio"],
            "max_ratio": st["max_finite_ratio"],
            "fraction_over_1e4": st["fraction_over_1e4"],
            "points_over_1e4": st["points_over_1e4"],
            "points": st["points"],
            "unbounded_at": inf_pts,
            "translation_fall_sphere_to_5_5": d.fall_from_sphere(verified),
        }
    res = dict(out["printed"])
    res.update({
        "grid": f"{d.e1.size} x {d.e2.size}, e1, e2 in [1, 5]",
        "ratio_at_a3_b2_c1": ratio_at(1.5, 2.0),
        "ratio_at_a3_b2_c1_verified": ratio_at(1.5, 2.0, verified=True),
        "verified": dict(out["verified"], grid=f"{d.e1.size} x {d.e2.size}",
                         # equal at e1 = 1 (a = b), where they agree to the last bit or two
                         a_bound_below_a_max=bool(np.all(d.a_bound <= d.a_max * (1.0 + 1e-12))),
                         a_bound_over_a_max_range=[float(np.min(d.a_bound / d.a_max)),
                                                   float(np.max(d.a_bound / d.a_max))]),
    })
    if region:
        res["four_orders_region"] = four_orders_region()
    return res


def summary(names, fine: bool = False, appendix: dict | None = None) -> dict:
    """Summary for the figures in ``names`` (``appendix``: a finished appendix_a_study to reuse).

    Parameters
    ----------
    names : iterable of str
        Canonical figure names.
    fine : bool
        Use the fine grids.
    appendix : dict, optional
        A finished ``appendix_a_study`` to reuse.

    Returns
    -------
    dict
        One entry per figure.
    """
    out: dict = {}
    if "fig3" in names:
        out["fig3"] = fig3_summary()
    if "fig4" in names:
        from dtcrit.figures.fig4_stiffness import fig4_data

        out["fig4"] = pair_summary(fig4_data(2))
    if "fig5" in names:
        from dtcrit.figures.fig5_density import fig5_data

        out["fig5"] = pair_summary(fig5_data(2))
    if "fig6" in names:
        out["aspect_ratio"] = aspect_ratio_summary(fine)
    if "appendix_a" in names:
        if appendix is None:
            from dtcrit.figures.appendix_a import appendix_a_study

            appendix = appendix_a_study(fine=fine)
        out["appendix_a"] = appendix["summary"]
    return _clean(out)
