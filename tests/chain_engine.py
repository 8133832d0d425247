"""The note's chain through an engine, mapped back to the note's speeds: the inverse of
:meth:`relacc.engines.chain.ChainEngine.engine_input` and the engine's equations of motion in a case's speeds, which
only the tests use (moved here from ``ChainEngine``, issue 51: the engine interface carries what relacc's checks
use)."""

import numpy as np

from relacc.core.cases import Case, as_case, check_q, check_u
from relacc.core.conventions import Route
from relacc.core.note.common import mv
from relacc.core.rotations import angles_123_from_matrix, matrix_from_quaternion
from relacc.core.speeds import check_invertible


def note_coordinates(engine, route: str, case: int, q_e: np.ndarray) -> np.ndarray:
    """Engine positions ``(n, nq_e)`` back to the case's ``q`` (1-2-3 angles for case 3 on the quaternion route,
    through :func:`relacc.core.rotations.angles_123_from_matrix`)."""
    adapter = engine.routes[route]
    q, _ = adapter.from_engine(q_e, np.zeros((len(q_e), adapter.nv_e)))
    if route == Route.EULER or as_case(case) is not Case.ANGLE_RATES:
        return q
    return np.concatenate([q[:, 0:3], angles_123_from_matrix(matrix_from_quaternion(q[:, 3:7])), q[:, 7:10],
                           angles_123_from_matrix(matrix_from_quaternion(q[:, 10:14]))], 1)


def note_state(engine, route: str, case: int, x):
    """Inverse of ``engine.engine_input``: ``(q, u, udot)`` of the case; ``u = [E]^-1 v_e``,
    ``udot = [E]^-1 (a_e - [E_dot] u)``.

    Raises:
        SingularityError: case 3 within ``MAX_CONDITION`` of gimbal lock.
    """
    c = as_case(case)
    q = note_coordinates(engine, route, c, x.q)
    check_invertible(c, q)
    u = np.linalg.solve(x.E, x.v[..., None])[..., 0]
    udot = None if x.a is None else np.linalg.solve(x.E, (x.a - mv(x.E_dot, u))[..., None])[..., 0]
    return q, u, udot


def equations_of_motion(engine, case: int, q: np.ndarray, u: np.ndarray, effects):
    """The engine's ``(M, f)`` mapped to a case's speeds: ``E^T M_e E`` and ``E^T (f_e - M_e E_dot u)``."""
    c = as_case(case)
    q, u = check_q(c, q), check_u(f"u for case {int(c)}", u)
    x = engine.engine_input(Route.QUATERNION, c, np.atleast_2d(q), np.atleast_2d(u), None)
    Me, fe = engine.adapter.equations(np.ascontiguousarray(x.q), np.ascontiguousarray(x.v), effects.for_tree())
    M = np.swapaxes(x.E, -1, -2) @ Me @ x.E
    f = np.einsum("nji,nj->ni", x.E, fe - np.einsum("nij,njk,nk->ni", Me, x.E_dot, np.atleast_2d(u)))
    return M.reshape(q.shape[:-1] + (12, 12)), f.reshape(q.shape[:-1] + (12,))
