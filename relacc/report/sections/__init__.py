"""Report sections, in page order (:data:`SECTIONS`, :mod:`.page`). Each module has ``ID``, ``TITLE`` and
``build(ctx) -> dict``."""

from relacc.report.sections.page import SECTIONS

__all__ = ["SECTIONS"]
