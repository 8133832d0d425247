"""Pinocchio's reading of a model file, and its joints matched to the reference's.

Imports only ``pinocchio``. Pinocchio reads an MJCF by ``buildModelFromMJCF`` (a body with several joints becomes
one ``JointModelComposite`` named ``Composite_<first joint>``) or a URDF by ``buildModelFromXML`` (its text without
visual and collision elements, :mod:`relacc.engines.urdf`; with a free-flyer root when the reference's root is
free). :func:`split_composites` rebuilds a model with every composite replaced by its sub-joints: Pinocchio 4.1.0's
Jacobian time variation of a composite is wrong in its slide columns (it treats every column as fixed in the
composite's output frame, which a ball rotates; stack-of-tasks/pinocchio#2519 reports the like), while its
positions, velocities, Jacobians and classical accelerations are right.
"""

from __future__ import annotations

import re
from pathlib import Path

import pinocchio as pin

from relacc.engines.base import NQ, NV, Match, by_order
from relacc.engines.mjcf import with_defaults_merged, without_keyframes
from relacc.engines.urdf import dynamics_text
from relacc.errors import ModelError


def kind(joint) -> str | None:
    """The common type of a (sub-)joint model, or None for one relacc does not map."""
    name = joint.shortname()
    if name == "JointModelFreeFlyer":
        return "free"
    if name == "JointModelSpherical":
        return "ball"
    if name.startswith(("JointModelR", "JointModelRevolute")):
        return "hinge"
    if name.startswith(("JointModelP", "JointModelPrismatic")):
        return "slide"
    return None


FLOATING = re.compile(r"""<joint\b[^>]*\btype\s*=\s*["']floating["']""")
"""A URDF joint of type ``floating``, which Pinocchio's URDF parser reads as a free flyer itself."""


def parse(path, urdf=None, root_free: bool = False) -> tuple["pin.Model", list[str]]:
    """Pinocchio's model of ``path`` (MJCF), or of ``urdf`` by its URDF parser, and the lines the parser printed
    (its warnings, on stdout or stderr: captured, never mixed into relacc's output).

    Raises:
        ModelError: the parser's message.
    """
    from relacc.isolate import captured_output

    text = dynamics_text(urdf)[0] if urdf is not None else None  # its kinematics and inertials only
    try:
        with captured_output(stdout=True) as printed:  # urdfdom prints its errors to stderr: they go in the message
            if text is not None:  # a URDF whose root is free by its own floating joint needs no second one
                floating = FLOATING.search(re.sub(r"<!--.*?-->", "", text, flags=re.S))  # not a commented-out one
                model = pin.buildModelFromXML(text, pin.JointModelFreeFlyer()) if root_free and not floating else \
                    pin.buildModelFromXML(text)
            else:
                model = _from_mjcf(path, printed)
        return model, printed
    except Exception as exc:  # Pinocchio raises ValueError/RuntimeError with its parser's message
        said = " ".join(" ".join(printed).split())
        why = _bodies_included(path) if urdf is None and "No such node (body)" in str(exc) else ""
        raise ModelError(f"{urdf or path}: Pinocchio cannot read it: {' '.join(str(exc).split())}"
                         + (f" ({said})" if said else "") + why) from None


def _bodies_included(path) -> str:
    """Why Pinocchio's MJCF parser found no body in a file whose ``<worldbody>`` has none of its own but includes
    others (a scene that includes its robot: Unitree's ``scene.xml``), or "" where that is not so."""
    import xml.etree.ElementTree as ET

    try:
        root = ET.parse(path).getroot()
    except (ET.ParseError, OSError):
        return ""
    worlds = root.findall("worldbody")
    if any(w.find("body") is not None for w in worlds) or root.find(".//include") is None:
        return ""
    names = [i.get("file", "") for i in root.iter("include")]
    return (f": its MJCF parser expands no <include>, and this file's bodies are all in the files it includes "
            f"({', '.join(names)}); the included file itself is what Pinocchio reads")


KEYFRAME_REFUSED = "Keyframe size does not match model size"
"""Pinocchio's MJCF parser's message for a ``<keyframe>`` whose size is not that of its own reading of the file."""


def _from_mjcf(path, printed: list) -> "pin.Model":
    """Pinocchio's reading of the MJCF at ``path``; where its parser refuses what is no part of the dynamics, its
    reading of the file made acceptable (each of :data:`REMEDIES` that applies, in turn), parsed from a temporary
    directory, the notes saying so added to ``printed``."""
    import tempfile

    source, notes = Path(path), []
    with tempfile.TemporaryDirectory(prefix="relacc-pinocchio-") as tmp:
        for step in range(len(REMEDIES) + 1):
            try:
                model = pin.buildModelFromMJCF(str(source))
            except Exception as exc:  # noqa: BLE001 - Pinocchio's ValueError/RuntimeError/IndexError: raised unless
                remedy = next((r for refused, r in REMEDIES if refused in str(exc)), None)  # a remedy mends it
                mended = remedy(source) if remedy is not None else None
                if mended is None or step == len(REMEDIES):
                    raise
                source = Path(tmp) / str(step) / Path(path).name
                source.parent.mkdir()
                source.write_text(mended[0])
                notes.append(mended[1])
            else:
                printed.extend(notes)
                return model
    raise AssertionError("unreachable")  # pragma: no cover - the last step returns or raises


REMEDIES = ((KEYFRAME_REFUSED, without_keyframes), ("unordered_map::at", with_defaults_merged))
"""``(Pinocchio's message, remedy)``: what its MJCF parser refuses that is no part of the dynamics, and the function
giving ``(text, note)`` of the file without it (or None where it does not apply): the file's keyframes
(:func:`relacc.engines.mjcf.without_keyframes`), classes in a second top-level ``<default>``
(:func:`relacc.engines.mjcf.with_defaults_merged`)."""


def split_composites(model: "pin.Model") -> "pin.Model":
    """The same model with every ``JointModelComposite`` replaced by its sub-joints.

    Sub-joints keep their order (so ``q`` and ``v`` keep their layout) and their placements (the composite's own
    placement times the first's, then each after the one before, as ``JointModelComposite.jointPlacements`` holds
    them); the body inertia goes to the last sub-joint, massless bodies sit in between. Sub-joint ``k`` is named
    ``<composite>[k]``. Frames are re-attached to the last sub-joint with their placements unchanged.
    """
    new = pin.Model()
    new.name = model.name
    new.gravity = model.gravity
    joint_map = {0: 0}
    for jid in range(1, model.njoints):
        jm = model.joints[jid]
        parent = joint_map[model.parents[jid]]
        placement = model.jointPlacements[jid]
        armature = model.armature[model.idx_vs[jid]:model.idx_vs[jid] + model.nvs[jid]].copy()
        if jm.shortname() == "JointModelComposite":
            comp = jm.extract()
            subs, places = list(comp.joints), list(comp.jointPlacements)
            for k, sub in enumerate(subs):  # places[k]: sub-joint k's placement after sub-joint k - 1
                parent = new.addJoint(parent, sub, placement * places[0] if k == 0 else places[k],
                                      f"{model.names[jid]}[{k}]")
                if k < len(subs) - 1:
                    new.appendBodyToJoint(parent, pin.Inertia.Zero(), pin.SE3.Identity())
            new_id = parent
        else:
            new_id = new.addJoint(parent, jm, placement, model.names[jid])
        new.appendBodyToJoint(new_id, model.inertias[jid], pin.SE3.Identity())
        armatures = new.armature.copy()  # the composite's speeds keep their layout: its armature, in order
        armatures[new.nv - len(armature):new.nv] = armature
        new.armature = armatures
        joint_map[jid] = new_id
    for frame in list(model.frames)[1:]:
        new.addFrame(pin.Frame(frame.name, joint_map[frame.parentJoint], frame.parentFrame, frame.placement,
                               frame.type, frame.inertia), False)
    return new


def subjoints(model) -> dict:
    """``{(name, k): (joint model, q start, v start)}``: every joint and every composite's sub-joint ``k``."""
    out = {}
    for j in range(1, model.njoints):
        jm = model.joints[j]
        if jm.shortname() == "JointModelComposite":
            iq, iv = jm.idx_q, jm.idx_v
            for k, sub in enumerate(jm.extract().joints):
                out[(model.names[j], k)] = (sub, iq, iv)
                iq, iv = iq + sub.nq, iv + sub.nv
        else:
            name, _, k = model.names[j].partition("[")  # split composites: "Composite_<first>[k]"
            out[(name, int(k[:-1]) if k else 0)] = (jm, jm.idx_q, jm.idx_v)
    return out


def moving(model) -> dict:
    """``{body name: joint index}``: the body each Pinocchio joint moves (the first body frame on it)."""
    out = {}
    for f in model.frames:
        if f.type == pin.FrameType.BODY and f.parentJoint > 0 and f.parentJoint not in out.values():
            out[f.name] = f.parentJoint
    return out


def match(model, reference, from_urdf: bool) -> list[Match]:
    """Each reference joint Pinocchio has, of the same type: by name (a composite's sub-joints by their place in
    it), else by structure: the joint that moves the same body, at the same place among that body's joints
    (unnamed joints, which MuJoCo leaves nameless and Pinocchio's parsers name ``base_free`` or ``<body>Joint_0``;
    a URDF's free-flyer root)."""
    subs = subjoints(model)
    by_body = moving(model)
    on_body: dict[int, list[int]] = {}
    for k, (b, _) in enumerate(reference.joints):
        on_body.setdefault(b, []).append(k)
    out, taken = [], set()
    for k, ((b, joint), qa, da) in enumerate(zip(reference.joints, reference.qadr(2), reference.dofadr)):
        siblings = [reference.joints[i][1].name for i in on_body[b]]
        place = on_body[b].index(k)
        key = (joint.name, 0) if joint.name else None
        if key not in subs and len(siblings) > 1 and siblings[0]:
            key = (f"Composite_{siblings[0]}", place)
        if key not in subs and reference.bodies[b].name in by_body:  # by structure: the body it moves
            key = (model.names[by_body[reference.bodies[b].name]], place)
        if key not in subs and from_urdf and k == 0 and joint.type == "free":
            key = (model.names[1], 0)
        if key not in subs or key in taken:
            continue
        taken.add(key)
        jm, iq, iv = subs[key]
        if kind(jm) != joint.type:
            continue  # reported by the audit as a type difference
        nq, nv = NQ[joint.type], NV[joint.type]
        out.append(Match(joint.type, (k,), tuple(range(qa, qa + nq)), tuple(range(da, da + nv)),
                         tuple(range(iq, iq + jm.nq)), tuple(range(iv, iv + nv))))
    ordered = sorted(subs.values(), key=lambda x: x[2])  # Pinocchio's joints in its order
    return by_order(reference, out, [(iv, kind(jm), tuple(range(iq, iq + jm.nq)), tuple(range(iv, iv + jm.nv)))
                                     for jm, iq, iv in ordered])
