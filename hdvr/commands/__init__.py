"""CLI subcommands. Each module here defines ``register(subparsers)`` and is discovered by :mod:`hdvr.cli`.

A command module is a thin layer: it parses arguments, calls the library, and prints results.
"""
