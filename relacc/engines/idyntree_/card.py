"""iDynTree's :class:`relacc.engines.traits.Traits` (imports nothing of iDynTree)."""

from relacc.engines.traits import Traits

TRAITS = Traits(
    name="idyntree", label="iDynTree", order=6, package="idyntree", pip="idyntree", color="#ff7f0e", marker="s",
    marker_size=5, integrators=(), formats=("urdf",),
    speeds="a URDF's fixed base (iDynTree's floating base held at the world, zero twist): revolute, continuous and "
           "prismatic joints, one angle or displacement and its rate each, as case 2, in iDynTree's DOF order mapped "
           "to relacc's by name; frame velocities in its MIXED representation ([p_dot, omega], world components)",
    chain_routes={})
