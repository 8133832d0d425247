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

from dataclasses import dataclass
from enum import StrEnum

from relacc.engines import ENGINES, file_readings


class CauseKind(StrEnum):
    """What kind of reason a :class:`Cause` gives (module docstring), in order from best explained to not explained;
    each member's value is its text in the JSON (``cause_kind``)."""

    EXPLAINED = "explained"
    FINDING = "finding"
    TAKEN = "taken"
    URDF = "urdf"
    SINGULAR = "singular"
    NOT_EXPLAINED = "not explained"


KINDS = tuple(CauseKind)
"""Every :class:`CauseKind`, in order."""


@dataclass(frozen=True)
class Cause:
    """Why a difference is there: ``kind`` (a :class:`CauseKind`; ``""`` for a row that needs none), ``text``,
    ``place`` (``file:line`` or empty)."""

    kind: CauseKind | str
    text: str
    place: str = ""

    def __str__(self) -> str:
        return self.text + (f" (see {self.place})" if self.place else "")

    @property
    def explained(self) -> bool:
        return self.kind != CauseKind.NOT_EXPLAINED


READINGS = {name: file_readings(name) for name in ENGINES}
"""Known engine behaviours as changes to relacc's reading (module docstring), per engine: each engine package's
``FILE_READINGS`` (:func:`relacc.engines.known`)."""
