"""The differences in Drake's algorithms relacc knows: none (how Drake's parsers *read* a file differently, relacc's
reader reproduces itself: :data:`relacc.validation.robots.causes.READINGS`)."""

from __future__ import annotations

from relacc.engines.base import KnownBehaviour
from relacc.engines.known import (
    element_skipped,
    inertiagrouprange_ignored,
    massless_get_a_kilogram,
    massless_with_inertia,
    mjcf,
    reread,
    settotalmass_ignored,
    springdamper_ignored,
    unphysical_inertia,
    water_spheres,
)

ENGINE_READINGS = ()
"""No known difference in Drake's algorithms."""

FILE_READINGS = (
    KnownBehaviour(
        "stacked_joints",
        "Drake's MJCF parser reads the position and axis of every joint but the last of a body "
        "with several joints in the parent body's frame instead of the body's",
        lambda r: mjcf(r) and r.facts["stacked"] > 0,
        reread("stacked_joints_in_parent"),
    ),
    KnownBehaviour(
        "armature",
        "Drake's MJCF parser keeps a joint's armature only as the reflected inertia of an actuator it "
        "reads on that joint (<motor> or <position>); joints without one lose it",
        lambda r: mjcf(r) and r.facts["unactuated_armature"] > 0,
        reread("armature_without_actuator"),
    ),
    KnownBehaviour(
        "free_damping",
        "Drake's MJCF parser drops a free joint's damping (it warns that damping is not supported for free bodies)",
        lambda r: mjcf(r) and r.facts["damped_free"] > 0,
        reread("free_damping_dropped"),
    ),
    KnownBehaviour(
        "default_chain",
        "Drake's MJCF parser inherits a <default> class's <joint> or <geom> attributes only "
        "through classes that have that element themselves: a class without one gives its joints or geoms nothing "
        "of its ancestors' (damping, armature, mass, size...)",
        lambda r: mjcf(r) and r.facts.get("broken_defaults", 0) > 0,
        reread("default_chain_broken"),
    ),
    settotalmass_ignored("Drake", " (it warns so)"),
    springdamper_ignored("Drake"),
    inertiagrouprange_ignored("Drake"),
    KnownBehaviour(
        "mesh_exact",
        "Drake computes a mesh geom's volume, mass centre and inertia exactly (tetrahedra from the mesh's origin), "
        "whatever the mesh's inertia mode, and from its convex hull where that is not a rigid body's (an open "
        "mesh, which it warns of): MuJoCo's default, legacy, sums every face's pyramid from the face centroid as "
        "positive, which overcounts a mesh that is not convex",
        lambda r: mjcf(r) and r.facts.get("legacy_meshes", 0) > 0,
        reread("mesh_inertia_exact"),
    ),
    KnownBehaviour(
        "gravity_flag",
        'Drake\'s MJCF parser ignores <flag gravity="disable"/> and keeps <option gravity>',
        lambda r: mjcf(r) and r.facts["gravity_disabled"],
        reread("gravity_flag_ignored"),
    ),
    KnownBehaviour(
        "massless_kilogram",
        "the file gives a body no mass but an inertia (a finding); Drake's URDF parser gives "
        "such a link a mass of 1 kg and the inertia of a solid sphere of water of that mass",
        lambda r: r.format == "urdf" and massless_with_inertia(r),
        massless_get_a_kilogram,
    ),
    KnownBehaviour(
        "unphysical_water_sphere",
        "the file gives a body an inertia that is not physical (a finding); Drake's URDF parser replaces it with "
        "that of a solid sphere of water of the body's mass (0.4 m r^2, r = (3 m / (4 pi 1000 kg/m^3))^(1/3))",
        unphysical_inertia,
        water_spheres,
    ),
    element_skipped("Drake", "replicate", "replicates", "and everything in it: its copies absent, without a word"),
    element_skipped("Drake", "attach", "attaches", "the attached bodies absent; it warns that the tag is unsupported"),
)
"""How drake's parsers read a file differently, as changes to relacc's reading (:mod:`relacc.engines.known`):
the audit applies those that apply, whichever engine reads the file."""
