"""``exprclone expressions``: the built-in expressions, one a line: its name, then what it is (:mod:`exprclone.expressions`)."""

from __future__ import annotations

import argparse


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    sub.add_parser("expressions", help="list the built-in expressions, for --expression: each one's name and what it is")


def run(args: argparse.Namespace) -> None:
    from ..expressions import load, names  # (numpy and the rest: loaded when the command runs, not for --help)

    width = max(len(name) for name in names())
    print("\n".join(f"{name:<{width}}  {load(name).description}" for name in names()))
