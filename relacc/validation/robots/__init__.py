"""``relacc compare``: does each engine see the robot the file describes, and do their dynamics agree?

relacc reads the file itself (:mod:`relacc.reading`) and holds every engine, MuJoCo included, to that reading
(:mod:`relacc.validation.robots.comparison`): the audit (:mod:`~relacc.validation.robots.audit`) with causes
(:mod:`~relacc.validation.robots.causes`), the dynamics (:mod:`~relacc.validation.robots.agreement`) and the referee
(:mod:`~relacc.validation.robots.referee`). This package hands those names on; the modules hold the logic.
"""

from relacc.validation.referee import Verdict
from relacc.validation.robots.audit import Item
from relacc.validation.robots.comparison import (
    REFERENCE,
    URDF_CAUSE,
    EngineReport,
    RobotComparison,
    compare,
    load_robot,
)

__all__ = ["REFERENCE", "URDF_CAUSE", "EngineReport", "Item", "RobotComparison", "Verdict", "compare", "load_robot"]
