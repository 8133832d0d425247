"""PyBullet's two :class:`relacc.engines.traits.Traits`, one per loading (imports nothing of PyBullet):

* ``pybullet``: ``loadURDF`` as users call it, without flags, which replaces each link's inertia by one Bullet
  computes from the link's collision shapes (:mod:`.readings` reproduces it);
* ``pybullet_file``: ``loadURDF(..., flags=URDF_USE_INERTIA_FROM_FILE)``, as PyBullet's quickstart guide recommends
  for a URDF with good inertias: the file's inertias, held to relacc's reading like any engine.
"""

from dataclasses import replace

from relacc.engines.traits import Traits

TRAITS = Traits(
    name="pybullet", label="PyBullet", order=4, package="pybullet", pip="pybullet", color="#9467bd", marker="v",
    marker_size=6, integrators=("euler",), own_steppers=True, formats=("urdf",), home="pybullet", file_inertias=False,
    speeds="a URDF's fixed base: revolute, continuous and prismatic joints, one angle or displacement and its rate "
           "each, as case 2; PyBullet's joint order (its movable joints' uIndex) mapped to relacc's by name",
    chain_routes={})
"""PyBullet as users load a URDF: ``loadURDF(path, useFixedBase=True)``."""

TRAITS_FILE = replace(TRAITS, name="pybullet_file", label="PyBullet (URDF_USE_INERTIA_FROM_FILE)", order=5,
                      color="#8c564b", marker="^", file_inertias=True, options={"inertia_from_file": True},
                      readings="FILE_READINGS_FROM_FILE")
"""PyBullet with the flag its documentation recommends: ``loadURDF(path, useFixedBase=True,
flags=URDF_USE_INERTIA_FROM_FILE)``."""

CARDS = (TRAITS, TRAITS_FILE)
