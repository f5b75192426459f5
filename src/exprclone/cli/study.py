"""``exprclone study``: the paper's user study (Table 1) on your photos: make a study, serve it to participants, read the results."""

from __future__ import annotations

import argparse
import sys

from ..errors import ExprCloneError
from ..io.progress import Bar
from ..options import Options, names
from .batch import add_workers, backend_of
from .evaluate import add_lists
from .inputs import add_options, options_of
from .serve import UVICORN, add_address, add_bounds, check_bounds, listen, server_packages

#: the clone's options of a study, for every set (each set is cloned by every method; a set's own lambda may change it).
STUDY = tuple(n for n in names(Options) if n not in ("method", "global_landmarks", "eigenfaces"))


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    s = sub.add_parser("study", help="the paper's user study (Table 1): make a study, serve it to participants, read the results")
    commands = s.add_subparsers(dest="study_command", required=True)
    m = commands.add_parser("make", help="clone each set of a manifest by every method into a study folder, the methods hidden")
    m.add_argument("manifest", help="CSV: source_neutral,source_expression,target_neutral[,set,lambda] (paths relative to it)")
    m.add_argument("-o", "--out", required=True, metavar="DIR", help="the study folder to write")
    add_lists(m, Options, ("method",), "the methods to compare", every=("method",))
    m.add_argument(
        "--max-size", metavar="PIXELS", type=int, help="make the photos at most this long on their longest side (default: as they are)"
    )
    add_options(m, Options, STUDY)
    add_workers(m)
    m.add_argument("--overwrite", action="store_true", help="replace a study already in DIR, its ratings too")
    v = commands.add_parser("serve", help="serve a study's page to participants, saving their ratings in the study folder")
    v.add_argument("folder", metavar="DIR", help="a study folder (exprclone study make)")
    add_address(v)
    v.add_argument("--max-participants", type=int, default=1000, help="participants the study takes at most (default: 1000)")
    v.add_argument("--new-per-address", type=int, default=5, help="participants one client address may start in an hour (default: 5)")
    add_bounds(v, tuple(UVICORN))
    r = commands.add_parser("results", help="the paper's Table 1: each method's mean score per set and overall, with a 95%% interval")
    r.add_argument("folder", metavar="DIR", help="a study folder with ratings")
    r.add_argument("--csv", metavar="FILE", help="also write one row per set and method: set,method,n,mean,ci95")


def run(args: argparse.Namespace) -> None:
    {"make": make, "serve": serve, "results": results}[args.study_command](args)


def make(args: argparse.Namespace) -> None:
    from ..study.make import make as make_study  # (numpy and the rest: loaded when the command runs, not for --help)

    options = options_of(args, Options, STUDY)
    backend = backend_of(args)
    make_study(
        args.manifest,
        args.out,
        args.methods,
        options,
        backend,
        max_size=args.max_size,
        overwrite=args.overwrite,
        progress=lambda total, what: Bar(sys.stderr, total, what),
    )
    print(f"exprclone: study written to {args.out}; serve it with: exprclone study serve {args.out}")


def serve(args: argparse.Namespace) -> None:
    server_packages()
    from ..study.app import create_app  # (FastAPI, numpy and the rest: loaded when serving, not for --help)

    for flag, value in (("--max-participants", args.max_participants), ("--new-per-address", args.new_per_address)):
        if value < 1:
            raise ExprCloneError(flag, f"expected at least 1, got {value}")
    check_bounds(args, tuple(UVICORN))
    app = create_app(args.folder, args.max_participants, args.new_per_address)
    listen(app, args, f"serving the study {args.folder} on http://{args.host}:{args.port}/ (Ctrl-C to stop)")


def results(args: argparse.Namespace) -> None:
    from ..io.images import atomic_write, check_output_path  # (numpy and the rest: loaded when the command runs, not for --help)
    from ..study.results import csv_text, formatted
    from ..study.results import results as table

    if args.csv:
        check_output_path(args.csv, extensions=(".csv",))
    found = table(args.folder)
    if args.csv:
        text = csv_text(found.cells)
        atomic_write(args.csv, lambda f: f.write(text.encode()))
    print(formatted(found))
