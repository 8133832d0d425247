"""Report sections, in page order (:data:`SECTIONS`, :mod:`.page`). Each module has ``ID``, ``TITLE`` and
``build(ctx) -> dict``, and may declare ``READS``, the context's fields its ``build`` reads: the report then draws it
while it waits for its second process, as soon as those are known (:func:`relacc.report.build.build_context`)."""

from relacc.report.sections.page import SECTIONS

__all__ = ["SECTIONS"]
