"""``python -m relacc``: the command line."""

from relacc.cli import entry

entry()
