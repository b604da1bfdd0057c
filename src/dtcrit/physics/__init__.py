"""The contact physics both stacks share, written once as NumPy functions of scalars or arrays.

``dtcrit.scenes`` evaluates them with one value per pair of particle types, ``dtcrit.packing`` with
one array entry per contact.  Modules:

* ``contact_laws`` -- effective radius, mass and moduli; Hooke, Hertz and Hertz-Mindlin stiffness;
* ``rotational_springs`` -- the codes' rolling and twisting springs (LAMMPS ``sds``, ``marshall``,
  LIGGGHTS EPSD, YADE);
* ``damping_conventions`` -- restitution <-> damping ratio and each engine's dashpot convention;
* ``rules_of_thumb`` -- the step estimates DEM codes use (Rayleigh time, Hertz duration, collision
  time, YADE's GlobalStiffnessTimeStepper);
* ``local_damping`` -- local (Cundall) damping: the laws (``yade``, ``pfc``), the coefficient's range
  and the step factor ``1/sqrt(1 + alpha)``, with what is proved for each law;
* ``estimate`` -- one estimate type rated against ``dt_crit`` with one tolerance;
* ``json_numbers`` -- non-finite numbers as JSON ``null``;
* ``walls`` -- a sphere on a fixed wall as each engine codes it (LAMMPS ``fix wall/gran``'s effective
  radius and material constants, YADE's wall and facet arms, the Hertz wall's tangent stiffness).
* ``collision_laws`` -- the codes' normal collision laws (hooke, hertz; each damping model, clipping).
* ``collision_rules`` -- the codes' rules for the step of a collision (LIGGGHTS Hertz fraction, EDEM
  Rayleigh fractions, t_c/50, Burns et al. 2019).

No SymPy is imported here.
"""
