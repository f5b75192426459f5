"""``exprclone evaluate``: every method on many London pairs, scored against the real smiles (:mod:`exprclone.evaluation`)."""

from __future__ import annotations

import argparse
import os
import sys

from ..errors import ExprCloneError


def add_parser(sub) -> None:
    e = sub.add_parser("evaluate", help="score every method against real smiles on many pairs")
    e.add_argument(
        "--data",
        default=os.path.join(os.environ["EXPRCLONE_DATA"], "london") if "EXPRCLONE_DATA" in os.environ else None,
        help="folder with neutral_front/ID_03.jpg and smiling_front/ID_08.jpg, such as the London Set"
        " (default: $EXPRCLONE_DATA/london, else the three people shipped as samples)",
    )
    e.add_argument("--pairs", type=int, default=50, help="ordered pairs of different people, drawn with --seed (0: all; default 50)")
    e.add_argument("--seed", type=int, default=0)
    e.add_argument("--methods", default="all", help="comma-separated methods, or all (default)")
    e.add_argument("--out", default="report", help="report folder (default: report/)")
    e.add_argument("--jobs", type=int, default=1, help="processes to use (default 1)")


def run(args: argparse.Namespace) -> None:
    from pathlib import Path

    from .. import data as samples
    from ..evaluation.london import Dataset
    from ..evaluation.report import run as score
    from ..evaluation.report import summarise, table, write_report
    from ..methods import METHODS, lookup
    from ..progress import Bar

    with_methods = METHODS if args.methods == "all" else tuple(m.strip() for m in args.methods.split(","))
    try:
        methods = tuple(m.name for m in lookup(with_methods))
    except ExprCloneError as e:
        raise ExprCloneError("--methods", e.problem) from None
    data = Dataset.open(args.data or samples.london())
    pairs = data.pairs(args.pairs, args.seed)
    rows, landmarks = score(data, pairs, methods, jobs=max(1, args.jobs), progress=lambda total, what: Bar(sys.stderr, total, what))
    command = "exprclone evaluate " + " ".join(sys.argv[2:]) if sys.argv[1:2] == ["evaluate"] else "exprclone evaluate"
    write_report(Path(args.out), data, rows, landmarks, methods, command)
    print(table(summarise(rows)))
    print(f"strong smiles only:\n{table(summarise(rows, strong_only=True))}")
    print(f"report: {Path(args.out) / 'summary.md'}")
