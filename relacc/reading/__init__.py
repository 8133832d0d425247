"""relacc's own reading of a robot description: a fourth, independent opinion of what the file describes.

Layer rule: imports the core, the errors and the standard library (and scipy) only, never an engine: a reading that
went through an engine would be that engine's reading, and could not judge it. :func:`read` takes an MJCF (``.xml``,
:mod:`relacc.reading.mjcf`) or a URDF (``.urdf``, :mod:`relacc.reading.urdf`) and gives a
:class:`relacc.reading.model.Reading`: relacc's :class:`relacc.Tree` of the file with the place of every element, and
what relacc could not compute itself, does not evaluate, or finds physically impossible
(:mod:`relacc.reading.physical`).
docs/reading.md tables what is read, element by element, with the specification's words.
"""

from relacc.reading.model import Finding, Reading
from relacc.reading.read import read, read_moving, read_tree

__all__ = ["Finding", "Reading", "read", "read_moving", "read_tree"]
