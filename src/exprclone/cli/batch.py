"""``exprclone batch``: many clones in one run, on all cores or on a Dask cluster (:mod:`exprclone.batch`)."""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import ExprCloneError
from ..io.progress import Bar
from ..options import Options, names
from .inputs import Interrupted, add_expression, add_options, load_expression, options_of

if TYPE_CHECKING:
    import numpy as np

    from ..batch.job import Dask, Local
    from ..batch.manifest import Row

#: exit status when some rows failed (the others were done).
EXIT_SOME_FAILED = 1
#: the clone's options of a job, for every row (a manifest's row may change its own, :mod:`exprclone.batch.manifest`):
#: all but the files of one clone.
JOB = tuple(n for n in names(Options) if n not in ("global_landmarks", "eigenfaces"))


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    b = sub.add_parser("batch", help="many clones in one run: a manifest, or one expression on a folder of portraits")
    b.add_argument("manifest", nargs="?", help="CSV: source_neutral,source_expression,target_neutral,output[,method,lambda,...]")
    b.add_argument("--source-neutral", metavar="IMAGE", help="with --targets: the source's neutral photo")
    b.add_argument("--source-expression", metavar="IMAGE", help="with --targets: the source's photo with the expression")
    add_expression(b, "instead of --source-neutral and --source-expression, with --targets")
    b.add_argument("--targets", metavar="DIR_OR_GLOB", help="every portrait in a folder or glob gets the expression: OUT/<name>.png")
    b.add_argument("--out", metavar="DIR", help="where outputs go (default: the manifest's folder; needed with --targets)")
    add_options(b, Options, JOB)  # every row's, but what a row's own columns change
    add_workers(b)
    b.add_argument("--cache", metavar="DIR", help="keep the photos' landmarks here between runs (by the photos' content)")
    b.add_argument("--overwrite", action="store_true", help="redo rows whose output exists (default: skip them)")
    b.add_argument(
        "--report",
        metavar="REPORT.csv",
        help="one row per manifest row: status, error, lambda_k, seconds, warnings (default: OUT/report.csv)",
    )


def add_workers(p: argparse.ArgumentParser) -> None:
    """Where a job's clones run: ``--jobs`` local processes, or a Dask cluster (``--scheduler``)."""
    p.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="worker processes (default: the number of cores)")
    p.add_argument("--scheduler", metavar="ADDRESS", help="run on this Dask cluster (tcp://HOST:8786) instead of local processes")


def backend_of(args: argparse.Namespace) -> Local | Dask:
    """The backend that :func:`add_workers`'s options ask for (:class:`exprclone.batch.job.Local` or ``Dask``)."""
    from ..batch import job  # (numpy and the rest: loaded when the command runs, not for --help)

    if args.jobs < 1:
        raise ExprCloneError("--jobs", f"expected at least 1, got {args.jobs}")
    return job.Dask(args.scheduler) if args.scheduler else job.Local(args.jobs)


def rows_of(args: argparse.Namespace) -> tuple[list[Row], dict[str, np.ndarray]]:
    """The job's rows, from the manifest or from --targets, and the landmarks known of their photos (a built-in
    expression's); ExprCloneError for arguments that cannot be used."""
    from ..batch.manifest import read_manifest, rows_for_targets  # (numpy and the rest: loaded when the command runs, not for --help)

    if args.manifest and args.targets:
        raise ExprCloneError("batch", "give a manifest or --targets, not both")
    if args.expression is not None:
        if not args.targets or args.source_neutral or args.source_expression:
            raise ExprCloneError("--expression", "goes with --targets, instead of --source-neutral and --source-expression")
        expression = load_expression(args.expression)
        if not args.out:
            raise ExprCloneError("--targets", "needs --out")
        known = dict(zip(expression.files, (expression.neutral.points, expression.expression.points)))
        return rows_for_targets(*expression.files, args.targets, args.out), known
    if args.targets:
        if not (args.source_neutral and args.source_expression and args.out):
            raise ExprCloneError("--targets", "needs --source-neutral and --source-expression (or --expression), and --out")
        return rows_for_targets(args.source_neutral, args.source_expression, args.targets, args.out), {}
    if not args.manifest:
        raise ExprCloneError("batch", "give a manifest CSV, or --targets with --source-neutral, --source-expression and --out")
    return read_manifest(args.manifest, args.out), {}


def run(args: argparse.Namespace) -> None:

    from ..batch import job  # (numpy and the rest: loaded when the command runs, not for --help)
    from ..batch.rows import Outcome

    backend = backend_of(args)
    rows, known = rows_of(args)
    folder = Path(args.out or Path(args.manifest).resolve().parent)
    report = args.report or str(folder / "report.csv")
    options = options_of(args, Options, JOB)
    cache = None if args.cache is None else Path(args.cache)
    outcomes: dict[int, Outcome] = {}
    try:
        bar = lambda n, what: Bar(sys.stderr, n, what)  # noqa: E731
        job.run(rows, options, backend, outcomes, overwrite=args.overwrite, cache=cache, progress=bar, known=known)
    except ExprCloneError:  # the job could not go on (a worker died, the cluster went): keep the report of what finished
        job.write_report(report, rows, outcomes)
        raise
    except KeyboardInterrupt:
        job.write_report(report, rows, outcomes)
        print(
            f"\nexprclone: interrupted; the {len(outcomes)} rows finished are whole, the report is {report}; run again to resume",
            file=sys.stderr,
        )
        raise Interrupted from None
    job.write_report(report, rows, outcomes)
    counts = {status: sum(o.status == status for o in outcomes.values()) for status in ("done", "skipped", "failed")}
    done = f"{counts['done']} done, {counts['skipped']} skipped (output already there), {counts['failed']} failed"
    warned = sum(bool(o.warnings) for o in outcomes.values())
    if warned:  # as clone says them on stderr, but once for the job: the report has each row's
        print(f"exprclone: warning: {warned} rows' source photos look wrong (swapped, or two people): see the report", file=sys.stderr)
    print(f"{len(rows)} rows: {done}; report: {report}")
    if counts["failed"]:
        raise SystemExit(EXIT_SOME_FAILED)
