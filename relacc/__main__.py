"""``python -m relacc``: the command line."""

import sys

from relacc.cli import main

sys.exit(main())
