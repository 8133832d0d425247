"""The note's method for any kinematic tree: relacc's own model and evaluator.

* :mod:`~relacc.core.tree.model`: :class:`Tree`, :class:`Body`, :class:`Joint`, :class:`Point`;
* :mod:`~relacc.core.tree.coordinates`: the three cases' coordinates and speeds per joint, their
  checks, the maps between cases, random states;
* :mod:`~relacc.core.tree.walk`: each body's partial velocities from its parent's (plain numpy);
* :mod:`~relacc.core.tree.kinematics`: :func:`tree_kinematics`.

Engine-free like the rest of the core: :meth:`Tree.from_file` reads MJCF and URDF by relacc's own reading
(:mod:`relacc.reading`, imported at the call), never through an engine's compiler.
"""

from relacc.core.tree.coordinates import convert, random_states, reference_q
from relacc.core.tree.kinematics import PointKinematics, TreeKinematics, tree_kinematics
from relacc.core.tree.model import Body, Joint, Point, Tree

__all__ = ["Body", "Joint", "Point", "PointKinematics", "Tree", "TreeKinematics", "convert",
           "random_states", "reference_q", "tree_kinematics"]
