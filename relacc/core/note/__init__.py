"""The note's mathematics, one module per case, every formula labelled with its equation id.

* :mod:`relacc.core.note.common` -- configuration symbols shared by the cases.
* :mod:`relacc.core.note.case1` -- fixed-frame angular velocity components (eq1, eq3-eq9).
* :mod:`relacc.core.note.case2` -- body-frame components (eq2, eq10, eq11, case2-a/b/c).
* :mod:`relacc.core.note.case3` -- 1-2-3 angle rates (case3-partials, eq12, case3-rates).
* :mod:`relacc.core.note.equations` -- the registry of ids, printed and corrected forms.

Nothing here imports an engine.
"""

__all__: list[str] = []
"""The package hands on no names: import its modules."""
