"""The ``exprclone`` command: :mod:`.main` parses and dispatches, one module per command does the work."""

from .main import build_parser, main

__all__ = ["build_parser", "main"]
