"""``exprclone edit``: one photo's expression edited by named controls (:mod:`exprclone.expressions.editor`), or the
controls listed."""

from __future__ import annotations

import argparse

from ..errors import ExprCloneError, naming
from ..options import EDIT, Options
from ..roles import TARGET_NEUTRAL
from .inputs import add_options, options_of


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    e = sub.add_parser("edit", help="edit one photo's expression by named controls (exprclone edit --list names them)")
    e.add_argument("photo", nargs="?", help="a photo of a face (its largest face is edited)")
    e.add_argument("-o", "--output", help="the edited image (.png, .jpg, ...)")
    e.add_argument(
        "--set",
        dest="values",
        action="append",
        metavar="NAME=VALUE[,NAME=VALUE...]",
        help="the controls' values, each from 0 (the face as it is) to 1, e.g. --set smile=0.5,brows_up=1 (may be given"
        " again; the controls not set stay at 0)",
    )
    e.add_argument("--list", action="store_true", help="list the controls: each one's name, what it does and how it was made")
    e.add_argument("--landmarks", metavar="FILE", help="the photo's landmarks (.json, or a WebMorph .tem) instead of detecting them")
    add_options(e, Options, EDIT)


def listing() -> str:
    """The controls, one a line: the name, what it does, and whether it was learnt (from what) or built."""
    from ..expressions.controls import CONTROLS

    width = max(len(c.name) for c in CONTROLS)
    return "\n".join(f"{c.name:<{width}}  {c.sentence} ({c.made}: {c.source})" for c in CONTROLS)


def run(args: argparse.Namespace) -> None:
    if args.list:
        print(listing())
        return
    from ..expressions import editor  # (numpy and the rest: loaded when the command runs, not for --help)
    from ..expressions.controls import parse_values
    from ..io.images import check_output_path, save_image
    from ..io.inputs import Source, gather

    if args.photo is None or args.output is None:
        raise ExprCloneError("edit", "give a photo and -o OUT (or --list to see the controls)")
    values = {name: value for text in args.values or () for name, value in parse_values(text).items()}
    check_output_path(args.output, [args.photo])
    marks = None if args.landmarks is None else Source(args.landmarks)
    with naming({TARGET_NEUTRAL: args.photo}):
        request = gather([None, None, Source(args.photo)], [None, None, marks], options_of(args, Options, EDIT), expression=editor.SHADING)
        result = editor.Editor.of(request).render(values)
    save_image(args.output, result.image, inputs=[args.photo])
    print(f"{args.output}: {editor.describe(values)}")
