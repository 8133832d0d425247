"""``relacc check --model robot.xml``: relacc's tree of any MJCF or URDF against every engine, in all three cases.

relacc reads the file itself (:mod:`relacc.reading`; :class:`relacc.validation.robots.tree.TreeRobot`) and is the
reference here: each engine (MuJoCo, Pinocchio and Drake through their parsers and speed maps, as
``relacc compare`` loads them) is compared with relacc's evaluation in case 1, 2 and 3 on the same seeded
states (the reference configuration and random ones), quantity by quantity: the mass matrix, bias and gravity
forces, forward dynamics, and each link's centre of mass, its Jacobian, ``J_dot v`` and classical acceleration.
Tolerances are :func:`relacc.core.tolerances.robot_tolerance`. Why an engine differs (its reading of the
file, its algorithms) is ``relacc compare``'s job; this check says where.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

from relacc.engines import judges
from relacc.errors import ModelError
from relacc.validation.robots.agreement import away_from_lock, compare_dynamics, lock_note, padded, states_at
from relacc.validation.robots.tree import TreeRobot


@dataclass(frozen=True)
class TreeCheck:
    """The result of :func:`check_tree`: ``rows`` (a :class:`relacc.validation.compare.Comparison` per case x engine x
    quantity), the engines that could not load the file (``{name: message}``)."""

    model: str
    n_states: int
    seed: int
    rows: list = field(default_factory=list)
    not_loaded: dict = field(default_factory=dict)
    not_evaluated: tuple = ()
    """One line per kind of element of the file the check leaves out (:attr:`relacc.reading.Reading.unevaluated`),
    and the states at which case 3 is not defined (:func:`relacc.validation.robots.agreement.away_from_lock`)."""

    @property
    def passed(self) -> bool:
        return bool(self.rows) and all(r.passed for r in self.rows)

    def as_json(self) -> dict:
        return {"model": self.model, "states": self.n_states, "seed": self.seed, "passed": self.passed,
                "not_loaded": self.not_loaded, "not_evaluated": list(self.not_evaluated),
                "comparisons": [_row(r) for r in self.rows]}


def check_tree(model, *, engines=None, cases=(1, 2, 3), n_states: int = 20, seed: int = 0, progress=None) -> TreeCheck:
    """relacc's tree of ``model`` against each engine in each case (see the module docstring).

    Args:
        engines: among :data:`relacc.engines.ENGINES` (default: :func:`relacc.engines.judges`).

    Raises:
        ModelError: relacc cannot read the file, or nothing in it moves.
    """
    from relacc.reading import read_moving
    from relacc.validation.robots import load_robot

    reading = read_moving(model, "there is nothing to check")
    from relacc.limits import require_comparable

    require_comparable(reading.tree, n_states, "checking")
    names = list(judges(reading.format)) if engines is None else list(engines)
    robots, not_loaded = [], {}
    for name in names:
        try:
            robots.append(load_robot(name, model, reading.tree))
        except ModelError as exc:
            not_loaded[name] = str(exc)
    states = TreeRobot(reading, 2).states(n_states, seed)
    rows, left_out = [], []
    for case in cases:
        tree = TreeRobot(reading, case, backend="auto")  # the compiled kernels a user's call runs
        keep = away_from_lock(reading.tree, states, case)
        if not keep.all():
            left_out.append(lock_note(keep))
            if not keep.any():
                continue
        for robot in robots:
            if progress:
                progress(f"case {case}: {robot.engine}")
            for r in compare_dynamics(tree, robot, states_at(states, keep)).values():
                rows.append(replace(padded(r, keep), case=int(case)))
    return TreeCheck(str(model), n_states, seed, rows, not_loaded, tuple(reading.unevaluated) + tuple(left_out))


def _row(r) -> dict:
    """One comparison's JSON: case, engine, quantity, the worst error (null where undefined), tolerance, state."""
    return {"case": r.case, "engine": r.engine, "quantity": r.quantity, **{k: v for k, v in r.as_row().items()
                                                                          if k in ("max_error", "tolerance", "state")},
            "passed": r.passed}
