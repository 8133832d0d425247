"""Reproduce the Pinocchio composite-joint finding on relacc's own fixture.

Pinocchio's MJCF loader merges B2's three slides and ball into one
JointModelComposite. Its frame Jacobian time variation (LOCAL_WORLD_ALIGNED)
then disagrees with the time derivative of the frame Jacobian in the slide
columns, and J a + Jdot v disagrees with getFrameClassicalAcceleration. On the
model with the composite split (relacc's adapter) both agree to rounding.

Run:  python scripts/pinocchio_composite_jdot.py
"""

import numpy as np
import pinocchio as pin

from relacc.engines.pinocchio_.adapter import LWA, split_composites
from relacc.fixtures import load


def measure(model, seed=0, h=1e-6):
    data = model.createData()
    f = model.getFrameId("G2")
    rng = np.random.default_rng(seed)
    q = pin.randomConfiguration(model, -np.ones(model.nq), np.ones(model.nq))
    v, a = rng.normal(size=(2, model.nv))

    def jacobian(qq):
        pin.computeJointJacobians(model, data, qq)
        pin.updateFramePlacements(model, data)
        return pin.getFrameJacobian(model, data, f, LWA)[:3].copy()

    fd = (jacobian(pin.integrate(model, q, h * v)) - jacobian(pin.integrate(model, q, -h * v))) / (2 * h)
    pin.forwardKinematics(model, data, q, v, a)
    pin.updateFramePlacements(model, data)
    acc = pin.getFrameClassicalAcceleration(model, data, f, LWA).linear.copy()
    pin.computeJointJacobians(model, data)
    pin.computeJointJacobiansTimeVariation(model, data, q, v)
    J = pin.getFrameJacobian(model, data, f, LWA)[:3]
    Jd = pin.getFrameJacobianTimeVariation(model, data, f, LWA)[:3]
    return np.abs(Jd - fd).max(axis=0), np.abs(J @ a + Jd @ v - acc).max()


if __name__ == "__main__":
    loaded = pin.buildModelFromMJCF(str(load().path("two_body.xml")))
    print(f"pinocchio {pin.__version__}; joints: {[j.shortname() for j in loaded.joints][1:]}")
    for label, model in (("as loaded (composite)", loaded), ("composite split", split_composites(loaded))):
        cols, acc = measure(model)
        print(f"{label:22s} |Jdot - dJ/dt| per column (central difference, h=1e-6): {np.round(cols, 6)}")
        print(f"{'':22s} |J a + Jdot v - classical acceleration| = {acc:.2e} m/s^2")
