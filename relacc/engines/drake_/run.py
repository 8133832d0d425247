"""Drake stepping: its ``Simulator`` with one of its own integrators, and a ``LeafSystem`` that applies exactly a
scene's effects (gravity through the plant's gravity field, set to the effects' or the model's own; springs,
dampers and loads as applied generalized forces at the context's time; no such system where the effects have none,
so a run under gravity alone never calls back into Python). Imports only ``pydrake``.
"""

from __future__ import annotations

import numpy as np
from pydrake.systems.analysis import ResetIntegratorFromFlags, Simulator
from pydrake.systems.framework import BasicVector, DiagramBuilder, LeafSystem

from relacc.dynamics.steps import Stepper
from relacc.engines.drake_.card import DRAKE_SCHEMES
from relacc.engines.drake_.plant import quiet
from relacc.errors import EngineError, IntegrationError

SAME_SCHEME = {"euler": "semi_explicit_euler"}
"""A scene integrator Drake has under another name: semi-implicit Euler (``v`` first, then ``q`` with the new ``v``)."""


DIVERGED = "the integration diverged (Drake's {scheme}): its state is no longer finite; reduce the step"


class _Effects(LeafSystem):
    """Applies the generalized forces of exactly the given effects (gravity excepted: the plant's field)."""

    def __init__(self, adapter, effects):
        super().__init__()
        self.adapter, self.effects = adapter, effects
        self.nq, self.nv = adapter.nq_e, adapter.nv_e
        self.state = self.DeclareVectorInputPort("state", BasicVector(self.nq + self.nv))
        self.DeclareVectorOutputPort("tau", BasicVector(self.nv), self._calc)

        self.failure, self.diverged = None, False
        """What went wrong in the last callback (Drake cannot carry a Python exception through its C++ integrator:
        pydrake turns one into an exit), raised by :func:`stepper` once ``AdvanceTo`` returns."""

    def _calc(self, context, output):
        x = np.asarray(self.state.Eval(context))
        tau = np.full(self.nv, np.nan)
        self.diverged = self.diverged or not np.all(np.isfinite(x))
        if not self.diverged:  # a diverged state has no forces: NaN, and the run is stopped after the step
            try:
                tau = self.adapter.generalized_forces(x[None, :self.nq], x[None, self.nq:], self.effects,
                                                      context.get_time())[0]
            except (np.linalg.LinAlgError, RuntimeError, ArithmeticError) as exc:
                self.failure = exc
        output.SetFromVector(tau)


def stepper(adapter, effects, dt, integrator, accuracy=None) -> Stepper:
    """Drake's ``Simulator`` with one of ``DRAKE_SCHEMES``, fixed-step (``accuracy`` None) or error-controlled.

    Error-controlled runs keep ``dt`` as their largest step, so every record falls on a step. ``euler`` is Drake's
    ``semi_explicit_euler`` (the same scheme); Drake has no RK4. Time runs on from one call to the next, from 0.
    """
    scheme = SAME_SCHEME.get(integrator, integrator)
    if scheme not in DRAKE_SCHEMES:
        raise EngineError(f"Drake has no {integrator!r} integrator; accepted: euler, {', '.join(DRAKE_SCHEMES)} "
                          "(a scene names Drake's in [simulate.drake] integrator)")
    builder = DiagramBuilder()
    plant = builder.AddSystem(adapter.rebuilt())
    g = adapter.gravity0 if effects is None or effects.gravity is None else effects.gravity
    plant.mutable_gravity_field().set_gravity_vector(np.asarray(g, dtype=float))
    forces = None
    if effects is not None and (effects.joints or effects.bodies):  # else nothing to apply: no call into Python
        forces = builder.AddSystem(_Effects(adapter, effects))
        builder.Connect(plant.get_state_output_port(), forces.get_input_port(0))
        builder.Connect(forces.get_output_port(0), plant.get_applied_generalized_force_input_port())
    diagram = builder.Build()
    simulator = Simulator(diagram)
    ResetIntegratorFromFlags(simulator, scheme, dt)
    integ = simulator.get_mutable_integrator()
    if accuracy is None:
        integ.set_fixed_step_mode(True)
    else:
        integ.set_fixed_step_mode(False)
        integ.set_target_accuracy(float(accuracy))
    context = simulator.get_mutable_context()
    pctx = plant.GetMyMutableContextFromRoot(context)
    quiet(plant, pctx)
    steps = [0]

    def advance(x, w, k):
        plant.SetPositions(pctx, x)
        plant.SetVelocities(pctx, w)
        steps[0] += k
        try:
            simulator.AdvanceTo(steps[0] * dt)
        except RuntimeError as exc:  # Drake stops a run whose state has become meaningless (NaN, a step too long)
            if forces is not None and forces.diverged:
                raise IntegrationError(DIVERGED.format(scheme=scheme)) from None
            raise IntegrationError(f"Drake's {scheme} stopped: {str(exc).splitlines()[0]}") from None
        if forces is not None and forces.failure is not None:
            raise IntegrationError(f"Drake's {scheme} stopped: the scene's forces could not be evaluated at its "
                                   f"state ({type(forces.failure).__name__}: {forces.failure})") from None
        x, w = plant.GetPositions(pctx).copy(), plant.GetVelocities(pctx).copy()
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(w))):
            raise IntegrationError(DIVERGED.format(scheme=scheme))
        return x, w

    simulator.Initialize()
    return Stepper(advance)
