"""The differences in Drake's algorithms relacc knows: none (how Drake's parsers *read* a file differently, relacc's
reader reproduces itself: :data:`relacc.validation.robots.causes.READINGS`)."""

ENGINE_READINGS = ()
"""No known difference in Drake's algorithms."""
