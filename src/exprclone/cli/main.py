"""The ``exprclone`` command: its parser, and errors turned into one line and an exit status.

Errors a user can cause come out as one line on stderr (``exprclone: error: subject:
problem``) and exit status 2; warnings as one line each. No output file is written
unless the whole job succeeded. Each command lives in a module of its own, which
imports nothing heavy until it runs.
"""

from __future__ import annotations

import argparse
import difflib
import re
import sys
import warnings
from collections.abc import Sequence
from typing import Any, NoReturn, TextIO

from .. import __version__
from ..errors import ExprCloneError
from . import batch, clone, compare, demo, edit, evaluate, expressions, faces, serve, study, video
from .inputs import Interrupted

EXIT_USAGE = 2
#: exit status after Ctrl-C (128 + SIGINT), as shells report it.
EXIT_INTERRUPTED = 130
#: each command's module: ``add_parser(subparsers)`` and ``run(args)``.
COMMANDS = {
    "clone": clone,
    "edit": edit,
    "faces": faces,
    "compare": compare,
    "video": video,
    "batch": batch,
    "serve": serve,
    "demo": demo,
    "evaluate": evaluate,
    "study": study,
    "expressions": expressions,
}


class Parser(argparse.ArgumentParser):
    """argparse's parser, its errors one line long: the problem, the closest option to a mistyped one, and the help of
    the command used (``exprclone clone --help``), not a usage of every argument."""

    words: list[str] = []

    def parse_args(self, args: Sequence[str] | None = None, namespace: Any = None) -> Any:  # type: ignore[override]
        Parser.words = list(sys.argv[1:] if args is None else args)
        return super().parse_args(args, namespace)

    def error(self, message: str) -> NoReturn:
        command = self._command()
        options = [o for action in command._actions for o in action.option_strings]
        typed = [w.split("=")[0] for w in Parser.words if w.startswith("--") and w != "--" and w.split("=")[0] not in options]
        if typed and "required" in message:  # a mistyped option is why the one it meant is missing: say that first
            message = f"unrecognized arguments: {' '.join(typed)}"
        if "unrecognized" in message:
            close = [m for w in typed for m in difflib.get_close_matches(w, options, n=1, cutoff=0.6)]
        else:  # an invalid choice: the closest of those the message lists
            bad, choices = re.findall(r"invalid choice: '([^']*)'", message), re.findall(r"'([^']*)'", message.partition("choose from")[2])
            close = difflib.get_close_matches(bad[0], choices, n=1, cutoff=0.6) if bad else []
        hint = f" (did you mean {close[0]}?)" if close else ""
        self.exit(EXIT_USAGE, f"exprclone: error: {message}{hint}; see {command.prog} --help\n")

    def _command(self) -> argparse.ArgumentParser:
        """The parser of the command the words name (a command's, or a study's subcommand's), else this one."""
        parser: argparse.ArgumentParser = self
        for word in Parser.words:
            chosen = next(
                (a.choices[word] for a in parser._actions if isinstance(a, argparse._SubParsersAction) and word in a.choices), None
            )
            if chosen is not None:
                parser = chosen
        return parser


def build_parser() -> argparse.ArgumentParser:
    parser = Parser(prog="exprclone", description="Facial expression cloning with elastic and muscle models (E+MD).")
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
    except Interrupted:
        return EXIT_INTERRUPTED
    except KeyboardInterrupt:  # the output, written under a temporary name, is already gone
        print("\nexprclone: interrupted; no output written", file=sys.stderr)
        return EXIT_INTERRUPTED
    return 0
