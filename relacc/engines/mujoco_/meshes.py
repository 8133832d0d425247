"""The mass properties of one mesh geom by MuJoCo: what relacc's own reading of an MJCF asks MuJoCo for and says so
(:mod:`relacc.reading.mjcf`, ``taken``).

relacc computes primitives' mass properties itself; a mesh's depend on MuJoCo's processing of it (its ``inertia``
mode, the convex hull, the recentring of the mesh on its own centre of mass), so relacc compiles a model of that
geom alone, in a free body, with the compiler options the file gives, and reads the body's mass, mass centre and
inertia: the geom's, in the frame it is placed in. The body is static (MuJoCo computes a static body's mass properties
as a moving one's, and allows it no mass: a geom of zero mass is one).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import mujoco
import numpy as np

from relacc.core.rotations import matrix_from_quaternion
from relacc.errors import ModelError

GEOM_KEYS = ("type", "mesh", "pos", "quat", "axisangle", "euler", "xyaxes", "zaxis", "mass", "density",
             "shellinertia", "size", "fromto", "fitscale")
"""The attributes of a geom that its mass properties depend on."""


def mesh_inertia(mesh) -> tuple[float, np.ndarray, np.ndarray]:
    """``(mass kg, centre (3,) m, inertia about it (3, 3) kg m^2)`` of a :class:`relacc.reading.mjcf.MeshGeom`, in
    the frame the geom is placed in.

    Raises:
        ModelError: MuJoCo cannot compile the geom alone (its message, naming the file's element).
    """
    root = ET.Element("mujoco")
    compiler = ET.SubElement(root, "compiler", angle="degree" if mesh.degree else "radian")
    directory = Path(mesh.file).parent
    compiler.set("meshdir", str((directory / mesh.meshdir).resolve()) if mesh.meshdir else str(directory.resolve()))
    if mesh.mesh is not None:
        asset = ET.SubElement(root, "asset")
        attrib = {k: v for k, v in mesh.mesh.attrib.items() if k != "class"}
        attrib.setdefault("name", mesh.attributes.get("mesh", "mesh"))
        ET.SubElement(asset, "mesh", attrib)
    body = ET.SubElement(ET.SubElement(root, "worldbody"), "body", name="geom")
    ET.SubElement(body, "geom", {k: v for k, v in mesh.attributes.items() if k in GEOM_KEYS})
    try:
        model = mujoco.MjModel.from_xml_string(ET.tostring(root, encoding="unicode"))
    except Exception as exc:  # mujoco raises ValueError with its compiler's message
        raise ModelError(f"{mesh.geom.place}: MuJoCo cannot compute this mesh geom's mass properties: "
                         f"{' '.join(str(exc).split())}") from None
    R = matrix_from_quaternion(model.body_iquat[1])
    return float(model.body_mass[1]), model.body_ipos[1].copy(), R @ np.diag(model.body_inertia[1]) @ R.T
