"""``exprclone evaluate``: every method on many London pairs, scored against the real smiles (:mod:`exprclone.evaluation`)."""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Callable
from typing import Any

from ..errors import ExprCloneError
from ..options import GLOBAL_WARPS, IMAGE_WARPS, Options
from .inputs import add_options, options_of, value_type


def listed(parse: Callable[[str], Any] | tuple[str, ...], name: str) -> Callable[[str], tuple[Any, ...]]:
    """An argparse type: comma-separated values, each parsed by ``parse`` (a function, or the tuple of allowed words)."""

    def parse_list(text: str) -> tuple[Any, ...]:
        values = tuple(v.strip() for v in text.split(","))
        if isinstance(parse, tuple):
            bad = [v for v in values if v not in parse]
            if bad:
                raise argparse.ArgumentTypeError(f"unknown {name} {bad[0]!r}; choose from: {', '.join(parse)}")
            return tuple(dict.fromkeys(values))
        return tuple(dict.fromkeys(parse(v) for v in values))

    return parse_list


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
    e.add_argument("--methods", default="all", help="comma-separated methods, or all (default)")
    e.add_argument("--out", default="report", help="report folder (default: report/)")
    e.add_argument("--jobs", type=int, default=1, help="processes to use (default 1)")
    add_options(e, Options, ("landmarker",))  # the clones'; the scores' are always dlib's, so that both compare
    variants = "; every combination of --global-warps, --image-warps, --strengths and --retargets is a variant, scored beside the others"
    e.add_argument(
        "--global-warps",
        type=listed(GLOBAL_WARPS, "global warp"),
        default=GLOBAL_WARPS[:1],
        metavar="LIST",
        help=f"comma-separated global warps ({', '.join(GLOBAL_WARPS)}; default similarity){variants}",
    )
    e.add_argument(
        "--image-warps",
        type=listed(IMAGE_WARPS, "image warp"),
        default=IMAGE_WARPS[:1],
        metavar="LIST",
        help=f"comma-separated image warps ({', '.join(IMAGE_WARPS)}; default mesh)",
    )
    strength = value_type(Options, "strength")
    e.add_argument(
        "--strengths", type=listed(strength, "strength"), default=(1.0,), metavar="LIST", help="comma-separated strengths (default 1)"
    )
    e.add_argument(
        "--expression",
        type=lambda text: tuple(v.strip() for v in text.split(",")),
        default=(),
        metavar="LIST",
        help="also clone these built-in expressions (names, or .json files: tools/build_expressions.py) onto every person"
        " not made into them, scored beside the pairs' individual sources on the same targets; expressions of one name"
        " made without different people (--folds) score each person with the first made without them",
    )
    e.add_argument(
        "--retargets",
        type=lambda text: tuple(value == "on" for value in listed(("on", "off"), "retarget")(text)),
        default=(True,),
        metavar="LIST",
        help="on (default), off (the paper's global and local stages, --no-retarget), or on,off",
    )


def run(args: argparse.Namespace) -> None:
    from pathlib import Path

    from .. import data as samples
    from ..evaluation.expression import held_out
    from ..evaluation.expression import section as expression_section
    from ..evaluation.london import Dataset
    from ..evaluation.report import write_report
    from ..evaluation.runner import run as score
    from ..evaluation.runner import variants
    from ..expressions import load
    from ..io.progress import Bar
    from ..methods import METHODS, lookup

    with_methods = METHODS if args.methods == "all" else tuple(m.strip() for m in args.methods.split(","))
    try:
        methods = tuple(m.name for m in lookup(with_methods))
    except ExprCloneError as e:
        raise ExprCloneError("--methods", e.problem) from None
    data = Dataset.open(args.data or samples.london())
    pairs = data.pairs(args.pairs, args.seed)
    chosen = variants(args.global_warps, args.image_warps, args.strengths, args.retargets)
    bar = lambda total, what: Bar(sys.stderr, total, what)  # noqa: E731
    held = held_out([load(name) for name in args.expression], data) if args.expression else []
    landmarker = str(options_of(args, Options, ("landmarker",)).landmarker)
    rows, landmarks = score(data, pairs, methods, jobs=max(1, args.jobs), progress=bar, variants=chosen, landmarker=landmarker)
    sections: list[str] = []
    if held:
        jobs = max(1, args.jobs)
        found, sections = expression_section(Path(args.out), data, held, rows, landmarks, methods, chosen, jobs, bar, landmarker)
        rows += found
    command = "exprclone evaluate " + " ".join(sys.argv[2:]) if sys.argv[1:2] == ["evaluate"] else "exprclone evaluate"
    print(write_report(Path(args.out), data, rows, landmarks, methods, command, chosen, tuple(sections)))
    if sections:
        print(sections[2])
    print(f"report: {Path(args.out) / 'summary.md'}")
