"""The ``hdvr`` command line: a thin layer over the library.

Subcommands live in :mod:`hdvr.commands` (one module per command, each with ``register(subparsers)``) and are
discovered here, so adding a stage adds a module, not an edit to this file. Errors in user input
(:class:`hdvr.errors.HDVRError`) print as one line ``hdvr: error: ...`` with exit status 2.
"""

from __future__ import annotations

import argparse
import importlib
import os
import pkgutil
import sys

# Headless rendering: MuJoCo must pick its GL backend before it is imported anywhere.
os.environ.setdefault("MUJOCO_GL", "egl")

from hdvr import __version__  # noqa: E402
from hdvr.errors import HDVRError  # noqa: E402


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="hdvr",
        description="Hierarchical dance video recognition: video -> tracks -> 2D poses -> 3D fit -> "
                    "movements -> genre, on a MuJoCo digital dancer.")
    parser.add_argument("--version", action="version", version=f"hdvr {__version__}")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND")
    import hdvr.commands as commands

    for info in sorted(pkgutil.iter_modules(commands.__path__), key=lambda m: m.name):
        module = importlib.import_module(f"hdvr.commands.{info.name}")
        module.register(subparsers)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 0
    try:
        result = args.func(args)
    except HDVRError as exc:
        print(f"hdvr: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("hdvr: interrupted (finished outputs were kept)", file=sys.stderr)
        return 130
    return int(result or 0)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
