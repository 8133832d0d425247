"""The errors relacc raises on purpose.

Every error relacc raises deliberately is a :class:`RelaccError`. Each message
says what was wrong and what is accepted, so that the command line can print
it as one line and exit non-zero.
"""

from __future__ import annotations


class RelaccError(Exception):
    """Base of every error relacc raises on purpose."""


class InputError(RelaccError, ValueError):
    """A numeric input has the wrong shape, type or value (NaN, inf, norm)."""


class CaseError(InputError):
    """An unknown choice of generalized speeds (accepted: 1, 2, 3)."""


class VariantError(InputError):
    """An unknown formula variant or equation id."""


class SingularityError(InputError):
    """An inverse map asked for at or too near its singularity (1-2-3 gimbal lock)."""


class FixtureError(RelaccError):
    """A model or scene file is missing or malformed (path and field named)."""


class ModelError(FixtureError):
    """A robot model cannot be loaded or compared (the file, and the element when the parser names one)."""


class NotARobot(ModelError):
    """A description with no robot to compare in it: no ``<link>`` (a xacro file of macros), a xacro fragment whose
    joints name links another file defines, or nothing that moves. ``relacc compare --models-only`` (what a pre-commit
    hook runs) skips such a file with a word; elsewhere it is the ModelError it is."""


class EngineError(RelaccError):
    """An engine cannot be used as asked (unknown engine, unsupported case)."""


class OutputError(RelaccError):
    """An output file or directory cannot be written (the path and the reason named)."""


class IntegrationError(RelaccError):
    """A simulation diverged: its state became non-finite (reduce the step or change the coordinates)."""


class AccuracyWarning(UserWarning):
    """An answer relacc gives with fewer correct digits than usual, saying where and about how many are left (for
    example case-3 rates near the 1-2-3 gimbal lock). Not an error: the answer is as accurate as the problem's
    conditioning allows; ``warnings.simplefilter("error", relacc.AccuracyWarning)`` makes it one."""
