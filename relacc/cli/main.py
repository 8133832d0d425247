"""``relacc``'s entry point: parse, dispatch, and turn every relacc error into one line and exit 2."""

from __future__ import annotations

import sys


def main(argv=None) -> int:
    """Run ``relacc`` with ``argv`` (default ``sys.argv[1:]``); returns the exit code (see ``--help``)."""
    from relacc.cli.parser import build_parser

    try:
        args = build_parser().parse_args(argv)
    except SystemExit as exc:  # --help, --version (0) and usage errors (2, one line already printed)
        return exc.code if isinstance(exc.code, int) else 2
    from relacc.cli import commands
    from relacc.errors import RelaccError

    try:
        return getattr(commands, f"cmd_{args.command}")(args)
    except RelaccError as exc:
        print(f"relacc {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"relacc {args.command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
