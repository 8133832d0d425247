"""``pybullet`` imported once for the package, and its clients freed, each without what Bullet prints on standard
output meanwhile (its build time at import; its allocation count when a client that read an empty mesh is freed),
which would land in a ``--json`` document."""

from __future__ import annotations

from relacc.isolate import captured_output

with captured_output(stdout=True):  # "pybullet build time: ..." on standard output, a word about the build only
    import pybullet as pb


def disconnect(client: int) -> None:
    """``pb.disconnect(client)`` with what Bullet's C++ prints on standard output meanwhile dropped: freeing a client
    that loaded a URDF through its in-memory file reader can print "Error: InMemoryFile::~InMemoryFileIO (numAllocs
    35 numFrees 36" (Bullet's allocation count, about Bullet and not the model: Trossen's ``stationary_ai.urdf``),
    which at the end of ``relacc compare --json`` landed before the JSON document in a file or a pipe."""
    with captured_output(stdout=True):
        pb.disconnect(client)


__all__ = ["disconnect", "pb"]
