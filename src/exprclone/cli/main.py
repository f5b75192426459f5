"""The ``exprclone`` command: its parser, and errors turned into one line and an exit status.

Errors a user can cause come out as one line on stderr (``exprclone: error: subject:
problem``) and exit status 2; warnings as one line each. No output file is written
unless the whole job succeeded. Each command lives in a module of its own, which
imports nothing heavy until it runs.
"""

from __future__ import annotations

import argparse
import sys
import warnings
from typing import TextIO

from .. import __version__
from ..errors import ExprCloneError
from . import batch, clone, compare, demo, evaluate, expressions, serve, study, video

EXIT_USAGE = 2
#: exit status after Ctrl-C (128 + SIGINT), as shells report it.
EXIT_INTERRUPTED = 130
#: each command's module: ``add_parser(subparsers)`` and ``run(args)``.
COMMANDS = {
    "clone": clone,
    "compare": compare,
    "video": video,
    "batch": batch,
    "serve": serve,
    "demo": demo,
    "evaluate": evaluate,
    "study": study,
    "expressions": expressions,
}


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="exprclone", description="Facial expression cloning with elastic and muscle models (E+MD).")
    parser.add_argument("--version", action="version", version=f"exprclone {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    for command in COMMANDS.values():
        command.add_parser(sub)
    return parser


def show_warning(
    message: Warning | str, category: type[Warning], filename: str, lineno: int, file: TextIO | None = None, line: str | None = None
) -> None:
    """Warnings as one line each on stderr, no source location."""
    print(f"exprclone: warning: {message}", file=sys.stderr)


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    warnings.showwarning = show_warning
    try:
        COMMANDS[args.command].run(args)
    except ExprCloneError as e:
        print(f"exprclone: error: {e}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:  # the output, written under a temporary name, is already gone
        print("\nexprclone: interrupted; no output written", file=sys.stderr)
        return EXIT_INTERRUPTED
    return 0
