"""Validation: the harness that holds the core to the engines.

Layer rule: imports the core, kernels, dynamics, reading, the engines and the
fixtures; never the report or the CLI. The error model it applies is :mod:`relacc.core.tolerances`
and :mod:`relacc.core.scales`.

* :mod:`~relacc.validation.check`: case x engine x route x quantity cross-validation (``relacc check``).
* :mod:`~relacc.validation.errata`: each equation id of the note, printed against corrected.
* :mod:`~relacc.validation.diff`, :mod:`~relacc.validation.diff_dynamics`: two descriptions of one robot
  (``relacc diff``).
* :mod:`~relacc.validation.hardcases`, :mod:`~relacc.validation.hardsearch`: the hard-case
  catalogue with its accuracy models, and a Hypothesis search for the worst state.
"""

__all__: list[str] = []
"""The package hands on no names: import its modules."""
