"""The ``relacc`` command line: one parser (:mod:`~relacc.cli.parser`), one function per subcommand
(:mod:`~relacc.cli.commands`).

Layer rule: the top layer; it may import anything, but only inside the
subcommand that needs it, so that ``relacc --help`` loads nothing heavy.
Every :class:`relacc.RelaccError` becomes one line on stderr and exit 2.
"""

from relacc.cli.main import entry, main

__all__ = ["entry", "main"]
