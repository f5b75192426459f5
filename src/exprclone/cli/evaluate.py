"""``exprclone evaluate``: every method on many London pairs, scored against the real smiles (:mod:`exprclone.evaluation`)."""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

from .. import data as samples
from ..io.progress import Bar
from ..options import Options, key, spec
from .inputs import add_options, options_of, value_type


def listed(cls: type, name: str) -> Callable[[str], tuple[Any, ...]]:
    """An argparse type: comma-separated values of the option ``name`` of ``cls``, each read and checked by its spec
    (:func:`~exprclone.cli.inputs.value_type`), without repeats; ``all``, for an option of named choices, is every one."""
    read, choices = value_type(cls, name), spec(cls, name).choices

    def parse_list(text: str) -> tuple[Any, ...]:
        if choices and text.strip() == "all":
            return choices
        return tuple(dict.fromkeys(read(v.strip()) for v in text.split(",")))

    return parse_list


def add_lists(p: argparse.ArgumentParser, cls: type, chosen: tuple[str, ...], said: str, every: tuple[str, ...] = ()) -> None:
    """Options of ``cls`` given as comma-separated lists, each its key made plural (``--global-warps``, ``--retargets``)
    and its values read as the option's (:func:`listed`); by default the option's default alone, or every choice for
    those of ``every``. ``said`` ends each one's help: what the list is for."""
    default = cls()
    for name in chosen:
        option = spec(cls, name)
        start = option.choices if name in every and option.choices else (getattr(default, name),)
        shown = "all" if name in every else ",".join(f"{v:g}" if isinstance(v, float) else str(v).lower() for v in start)
        choices = f" ({', '.join(option.choices)}, or all)" if option.choices else " (true, false)" if option.kind is bool else ""
        p.add_argument(
            f"--{key(cls, name).replace('_', '-')}s",
            dest=f"{name}s",
            type=listed(cls, name),
            default=start,
            metavar="LIST",
            help=f"comma-separated values{choices} of: {option.help}; {said} (default: {shown})",
        )


#: the options whose lists make an evaluation's variants (:func:`exprclone.evaluation.runner.variants`).
VARIANTS = ("global_warp", "image_warp", "strength", "retarget")


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    e = sub.add_parser("evaluate", help="score every method against real smiles on many pairs")
    e.add_argument(
        "--data",
        default=os.path.join(os.environ["EXPRCLONE_DATA"], "london") if "EXPRCLONE_DATA" in os.environ else None,
        help="folder of people's photos: neutral/NAME.jpg and expression/NAME.jpg (one name a person, any image type),"
        " or the London Set's neutral_front/ID_03.jpg and smiling_front/ID_08.jpg"
        " (default: $EXPRCLONE_DATA/london, else the three people shipped as samples)",
    )
    e.add_argument("--pairs", type=int, default=50, help="ordered pairs of different people, drawn with --seed (0: all; default 50)")
    e.add_argument("--seed", type=int, default=0)
    e.add_argument(
        "--held-out",
        type=int,
        default=0,
        metavar="K",
        help="deal the people into K folds, draw the pairs within them, and clone each fold's pairs with what is learnt"
        " from people (the expression's shape, for --retargets true) learnt without that fold's people: no clone judged on"
        " people it learnt from (default 0: the models shipped, learnt from the London Set)",
    )
    add_lists(e, Options, ("method",), "the methods scored", every=("method",))
    e.add_argument("--out", default="report", help="report folder (default: report/)")
    e.add_argument(
        "--full",
        action="store_true",
        help="print the full tables (every score of every method, the broad smiles, the variants pair by pair), as"
        " summary.md has them, instead of the summary of which method is best on what",
    )
    e.add_argument("--jobs", type=int, default=1, help="processes to use (default 1)")
    add_options(e, Options, ("landmarker",))  # the clones'; the scores' are always dlib's, so that both compare
    flags = ", ".join(f"--{key(Options, n).replace('_', '-')}s" for n in VARIANTS)
    add_lists(e, Options, VARIANTS, f"every combination of {flags} is a variant, scored beside the others")
    e.add_argument(
        "--expression",
        type=lambda text: tuple(v.strip() for v in text.split(",")),
        default=(),
        metavar="LIST",
        help="also clone these built-in expressions (names, or .json files: tools/build_expressions.py) onto every person"
        " not made into them, scored beside the pairs' individual sources on the same targets; expressions of one name"
        " made without different people (--folds) score each person with the first made without them",
    )


def run(args: argparse.Namespace) -> None:

    from ..evaluation.digest import digest  # (numpy and the rest: loaded when the command runs, not for --help)
    from ..evaluation.expression import held_out
    from ..evaluation.expression import section as expression_section
    from ..evaluation.london import Dataset
    from ..evaluation.report import alike, write_report
    from ..evaluation.runner import run as score
    from ..evaluation.runner import variants
    from ..expressions import load

    methods = args.methods
    data = Dataset.open(args.data or samples.london())
    folds = data.folds(args.held_out, args.seed) if args.held_out > 1 else None
    pairs = data.pairs(args.pairs, args.seed, folds)
    chosen = variants(args.global_warps, args.image_warps, args.strengths, args.retargets)
    bar = lambda total, what: Bar(sys.stderr, total, what)  # noqa: E731
    held = held_out([load(name) for name in args.expression], data) if args.expression else []
    landmarker = str(options_of(args, Options, ("landmarker",)).landmarker)
    rows, landmarks = score(data, pairs, methods, jobs=max(1, args.jobs), progress=bar, variants=chosen, landmarker=landmarker, folds=folds)
    sections: list[str] = []
    if held:
        jobs = max(1, args.jobs)
        found, sections = expression_section(Path(args.out), data, held, rows, landmarks, methods, chosen, jobs, bar, landmarker)
        rows += found
    command = "exprclone evaluate " + " ".join(sys.argv[2:]) if sys.argv[1:2] == ["evaluate"] else "exprclone evaluate"
    out = Path(args.out)
    full = write_report(out, data, rows, landmarks, methods, command, chosen, tuple(sections), len(folds or ()))
    if args.full:
        print(full + (f"\n{sections[2]}" if sections else "") + f"\nreport: {out / 'summary.md'}")
        return
    pair_rows = [r for r in rows if r["source"] in data.photos]  # (not a built-in expression's)
    print(digest(pair_rows, data.root, out, alike(pair_rows), len(folds or ())))
    if sections:
        print(f"The built-in expressions against the individual sources: {out / 'summary.md'}, its section {sections[0][3:]!r}.")
