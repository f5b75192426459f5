"""``exprclone expressions``: the built-in expressions' names, one a line (:mod:`exprclone.expressions`)."""

from __future__ import annotations

import argparse


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    sub.add_parser("expressions", help="list the built-in expressions, for --expression")


def run(args: argparse.Namespace) -> None:
    from ..expressions import names

    print("\n".join(names()))
