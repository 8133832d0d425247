"""``python -m relacc``: the command line.

``python -m`` puts the working directory first on ``sys.path``; the console script ``relacc`` does not. It is taken
off again here, so that a file of the working directory named like a library relacc imports (``mujoco.py`` beside a
graded module) is never imported in its place: relacc behaves the same in any working directory, however started.
"""

import os
import sys

if sys.path and sys.path[0] in ("", os.getcwd()):
    del sys.path[0]

from relacc.cli import entry  # noqa: E402 - after the path is the console script's

entry()
