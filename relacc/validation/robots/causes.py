"""Why an engine's reading differs from relacc's: typed causes, and the known readings in relacc's own terms.

A :class:`Cause` is a kind, a sentence and, where relacc knows it, the place in the file (``file:line``) the
difference comes from. Kinds:

* ``explained``: a reproduced engine behaviour (the catalogue) makes the difference disappear;
* ``finding``: the file's own fault (a body that is not physical, :mod:`relacc.reading.physical`), which each engine
  reads its own way;
* ``taken``: relacc took that element from the engine (a mesh's mass properties from MuJoCo): it cannot judge it;
* ``urdf``: the URDF given for Pinocchio and the MJCF describe the element differently;
* ``singular``: a mass matrix singular over the shared speeds leaves the forward dynamics undefined;
* ``not explained``: nothing known reproduces it; the place says where to look.

:data:`READINGS` holds known engine behaviours as changes to relacc's own reading (:class:`relacc.reading.Reading`),
so that they apply whichever engine reads the file, MuJoCo included: each a
:class:`relacc.engines.base.KnownBehaviour` (``applies(reading)``, ``change(reading) -> Reading``); the audit
applies those that apply and takes ``text`` as the cause of the differences that disappear. Most are relacc's own
reader reading the file the engine's way (:data:`relacc.reading.mjcf.VARIANTS`): they need no engine, MuJoCo
included, to read the file.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from relacc.core.tree.model import Tree
from relacc.engines.base import KnownBehaviour

KINDS = ("explained", "finding", "taken", "urdf", "singular", "not explained")


@dataclass(frozen=True)
class Cause:
    """Why a difference is there: ``kind`` (one of :data:`KINDS`), ``text``, ``place`` (``file:line`` or empty)."""

    kind: str
    text: str
    place: str = ""

    def __str__(self) -> str:
        return self.text + (f" (see {self.place})" if self.place else "")

    @property
    def explained(self) -> bool:
        return self.kind != "not explained"


def with_bodies(reading, change):
    """``reading`` with each body replaced by ``change(body)`` (None keeps it)."""
    bodies = tuple(change(b) or b for b in reading.tree.bodies)
    t = reading.tree
    return replace(reading, tree=Tree(t.name, bodies, gravity=t.gravity, points=t.points, source=t.source))


def _massless_with_inertia(reading) -> bool:
    return any(b.mass == 0 and np.any(b.inertia != 0) for b in reading.tree.bodies)


def _drop_massless_inertia(reading):
    return with_bodies(reading, lambda b: replace(b, inertia=np.zeros((3, 3))) if b.mass == 0 else None)


WATER = 1000.0
"""kg/m^3: the density of the solid sphere Drake's URDF parser puts in place of an inertia it cannot take."""


def water_sphere(mass: float) -> np.ndarray:
    """``(3, 3)`` kg m^2: the inertia about its centre of a solid sphere of water of ``mass`` kg, ``0.4 m r^2`` with
    ``r = (3 m / (4 pi 1000))^(1/3)``: what Drake's URDF parser gives a link whose inertia is not physical (measured on
    Drake 1.51: the 25 such bodies of a public URDF dataset to 1.2e-15, and a massless link given 1 kg)."""
    r = (3.0 * mass / (4.0 * np.pi * WATER)) ** (1.0 / 3.0)
    return 0.4 * mass * r * r * np.eye(3)


def _massless_get_a_kilogram(reading):
    return with_bodies(reading, lambda b: replace(b, mass=1.0, inertia=water_sphere(1.0))
                       if b.mass == 0 and np.any(b.inertia != 0) else None)


def _unphysical_inertia(reading) -> bool:
    return reading.format == "urdf" and any(not b.physical and b.mass > 0 for b in reading.tree.bodies)


def _water_spheres(reading):
    return with_bodies(reading, lambda b: replace(b, inertia=water_sphere(b.mass))
                       if not b.physical and b.mass > 0 else None)


def _urdf_inertial_turned(reading) -> bool:
    """A URDF whose inertials are turned (``rpy``): what MuJoCo up to 3.13 misreads (google-deepmind/mujoco#3559;
    measured on the releases 3.3.1 to 4.0.0: wrong up to 3.13.0, right from 3.14.0)."""
    return reading.format == "urdf" and bool(reading.turned_inertials)


def _unturned_inertials(reading):
    """Each turned inertial as if its ``rpy`` were zero: the inertia as written, in the link's axes."""
    return with_bodies(
        reading,
        lambda b: replace(b, inertia=reading.turned_inertials[b.name]) if b.name in reading.turned_inertials else None,
    )


def _reread(*variant):
    """The change that reads the file again the engine's way (:data:`relacc.reading.mjcf.VARIANTS`), on top of the
    variants the reading already follows."""

    def change(reading):
        from relacc.reading import read

        return read(reading.source, variant=reading.variant | frozenset(variant))

    return change


def _mjcf(reading) -> bool:
    return reading.format == "mjcf"


def _springdamper_ignored(engine: str) -> KnownBehaviour:
    """``engine``'s MJCF parser keeping the written stiffness and damping of a joint with ``springdamper`` (Pinocchio's
    and Drake's, measured on pin 4.1 and Drake 1.51)."""
    return KnownBehaviour(
        "springdamper",
        f"{engine}'s MJCF parser ignores a joint's springdamper, from which MuJoCo's compiler sets the stiffness and "
        "damping (it keeps those written)",
        lambda r: _mjcf(r) and bool(r.facts.get("springdamper")),
        _reread("springdamper_ignored"),
    )


READINGS = {
    "mujoco": (
        KnownBehaviour(
            "massless_inertia",
            "the file gives a body no mass but an inertia (a finding); MuJoCo's compiler drops the "
            "inertia of a massless body",
            _massless_with_inertia,
            _drop_massless_inertia,
        ),
        KnownBehaviour(
            "obj_first_object",
            "MuJoCo reads only the first object (o or g) of an OBJ mesh file of several (google-deepmind/mujoco#911): "
            "its legacy, exact and shell inertias are that object's",
            lambda r: _mjcf(r) and bool(r.facts.get("multi_object_meshes")),
            _reread("mesh_obj_first_object"),
        ),
        KnownBehaviour(
            "urdf_inertial_rotation",
            "MuJoCo's URDF reader up to 3.13 drops the rotation of an <inertial>'s <origin "
            "rpy> (google-deepmind/mujoco#3559, fixed in 3.14): it takes the inertia as if written in the link's axes",
            _urdf_inertial_turned,
            _unturned_inertials,
        ),
    ),
    "pinocchio": (
        KnownBehaviour(
            "first_body",
            "Pinocchio's MJCF parser reads only the first <body> written directly in the main file's "
            "<worldbody> (it expands no <include>); the others are dropped",
            lambda r: _mjcf(r) and r.facts["world_children"] > 1,
            _reread("first_body_only"),
        ),
        KnownBehaviour(
            "fixed_root",
            "Pinocchio's MJCF parser drops the pos and orientation of a first <body> that has no joint (it "
            "puts that body at the world frame)",
            lambda r: _mjcf(r) and r.facts["placed_jointless_first"],
            _reread("first_body_unplaced"),
        ),
        KnownBehaviour(
            "settotalmass",
            "Pinocchio ignores <compiler settotalmass>, which makes MuJoCo scale every mass",
            lambda r: _mjcf(r) and r.facts["settotalmass"],
            _reread("settotalmass_ignored"),
        ),
        KnownBehaviour(
            "default_mass",
            "Pinocchio's MJCF parser ignores a geom's mass inherited from a <default> class (it honours "
            "one written on the geom) and takes the geom's density times its volume",
            lambda r: _mjcf(r) and r.facts["default_geom_masses"] > 0,
            _reread("default_geom_mass_ignored"),
        ),
        KnownBehaviour(
            "visual_geoms",
            "Pinocchio's MJCF parser takes geoms with contype=0 and conaffinity=0 as visual and leaves "
            "them out of the inertia; MuJoCo counts every geom in inertiagrouprange",
            lambda r: _mjcf(r) and r.facts["visual_geoms"] > 0,
            _reread("visual_geoms_ignored"),
        ),
        KnownBehaviour(
            "mesh_inertia",
            "Pinocchio's MJCF parser gives a mesh geom 1 kg and a unit inertia at the geom's frame (it "
            "reads neither the mesh's volume nor the geom's mass)",
            lambda r: _mjcf(r) and r.facts["mesh_bodies"],
            _reread("mesh_unit_inertia"),
        ),
        KnownBehaviour(
            "unnamed_bodies",
            "Pinocchio's MJCF parser names an unnamed <body> after its parent (<parent>Bis), so of "
            "several unnamed children of one body only the first is read; the others and their subtrees are dropped",
            lambda r: _mjcf(r) and r.facts.get("unnamed_dropped", 0) > 0,
            _reread("unnamed_siblings_dropped"),
        ),
        KnownBehaviour(
            "default_joint_pos",
            "Pinocchio's MJCF parser ignores a joint's pos inherited from a <default> (it honours one written on "
            "the joint) and puts the joint at its body's origin",
            lambda r: _mjcf(r) and r.facts.get("default_joint_pos", 0) > 0,
            _reread("default_joint_pos_ignored"),
        ),
        KnownBehaviour(
            "default_geom_pose",
            "Pinocchio's MJCF parser ignores a geom's pos and orientation inherited from a <default> (it honours "
            "those written on the geom) and puts the geom at its body's frame",
            lambda r: _mjcf(r) and r.facts.get("default_geom_pose", 0) > 0,
            _reread("default_geom_pose_ignored"),
        ),
        _springdamper_ignored("Pinocchio"),
        KnownBehaviour(
            "ball_free_damping",
            "Pinocchio's MJCF parser drops the damping of a ball or free joint (it keeps a hinge's and a slide's)",
            lambda r: _mjcf(r) and (r.facts.get("damped_free", 0) + r.facts.get("damped_balls", 0)) > 0,
            _reread("free_damping_dropped", "ball_damping_dropped"),
        ),
        KnownBehaviour(
            "gravity",
            'Pinocchio\'s MJCF parser ignores <option gravity> and <flag gravity="disable"/> and keeps (0, 0, -9.81)',
            lambda r: _mjcf(r) and list(r.tree.gravity) != [0.0, 0.0, -9.81],
            _reread("gravity_default"),
        ),
    ),
    "drake": (
        KnownBehaviour(
            "stacked_joints",
            "Drake's MJCF parser reads the position and axis of every joint but the last of a body "
            "with several joints in the parent body's frame instead of the body's",
            lambda r: _mjcf(r) and r.facts["stacked"] > 0,
            _reread("stacked_joints_in_parent"),
        ),
        KnownBehaviour(
            "armature",
            "Drake's MJCF parser keeps a joint's armature only as the reflected inertia of an actuator it "
            "reads on that joint (<motor> or <position>); joints without one lose it",
            lambda r: _mjcf(r) and r.facts["unactuated_armature"] > 0,
            _reread("armature_without_actuator"),
        ),
        KnownBehaviour(
            "free_damping",
            "Drake's MJCF parser drops a free joint's damping (it warns that damping is not supported for free bodies)",
            lambda r: _mjcf(r) and r.facts["damped_free"] > 0,
            _reread("free_damping_dropped"),
        ),
        KnownBehaviour(
            "default_chain",
            "Drake's MJCF parser inherits a <default> class's <joint> or <geom> attributes only "
            "through classes that have that element themselves: a class without one gives its joints or geoms nothing "
            "of its ancestors' (damping, armature, mass, size...)",
            lambda r: _mjcf(r) and r.facts.get("broken_defaults", 0) > 0,
            _reread("default_chain_broken"),
        ),
        KnownBehaviour(
            "settotalmass",
            "Drake ignores <compiler settotalmass> (it warns so), which makes MuJoCo scale every mass",
            lambda r: _mjcf(r) and r.facts["settotalmass"],
            _reread("settotalmass_ignored"),
        ),
        _springdamper_ignored("Drake"),
        KnownBehaviour(
            "mesh_exact",
            "Drake computes a mesh geom's volume, mass centre and inertia exactly (tetrahedra from the mesh's origin), "
            "whatever the mesh's inertia mode, and from its convex hull where that is not a rigid body's (an open "
            "mesh, which it warns of): MuJoCo's default, legacy, sums every face's pyramid from the face centroid as "
            "positive, which overcounts a mesh that is not convex",
            lambda r: _mjcf(r) and r.facts.get("legacy_meshes", 0) > 0,
            _reread("mesh_inertia_exact"),
        ),
        KnownBehaviour(
            "gravity_flag",
            'Drake\'s MJCF parser ignores <flag gravity="disable"/> and keeps <option gravity>',
            lambda r: _mjcf(r) and r.facts["gravity_disabled"],
            _reread("gravity_flag_ignored"),
        ),
        KnownBehaviour(
            "massless_kilogram",
            "the file gives a body no mass but an inertia (a finding); Drake's URDF parser gives "
            "such a link a mass of 1 kg and the inertia of a solid sphere of water of that mass",
            lambda r: r.format == "urdf" and _massless_with_inertia(r),
            _massless_get_a_kilogram,
        ),
        KnownBehaviour(
            "unphysical_water_sphere",
            "the file gives a body an inertia that is not physical (a finding); Drake's URDF parser replaces it with "
            "that of a solid sphere of water of the body's mass (0.4 m r^2, r = (3 m / (4 pi 1000 kg/m^3))^(1/3))",
            _unphysical_inertia,
            _water_spheres,
        ),
    ),
}
"""Known engine behaviours as changes to relacc's reading (module docstring), per engine."""
