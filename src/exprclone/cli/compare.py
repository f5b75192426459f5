"""``exprclone compare``: every method of Fig. 11 on one triple of photos, by the paper's stages, as the sheet of Figs.
11-13 (with a row of this project's default unless ``--no-retarget``); or Figs. 16-17, or 19-21."""

from __future__ import annotations

import argparse

from ..methods import FIGURES
from ..options import Options, names
from .inputs import add_inputs, load_inputs, source_photos


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    c = sub.add_parser(
        "compare", help="the paper's Figs. 11-13 by its stages, the DB curve and the default's row, as one sheet; or Figs. 16-17 or 19-21"
    )
    add_inputs(c, tuple(n for n in names(Options) if n != "method"))  # every method is on the sheet
    c.add_argument("-o", "--output", required=True, help="output image (.png, .jpg, ...)")
    c.add_argument(
        "--figure",
        choices=FIGURES,
        default=FIGURES[0],
        help="11: the seven methods by the paper's stages, Figs. 12-13's differences, the DB curve and its terms, and"
        " a row of this project's default (retarget; --no-retarget leaves it out) (default); 16: E+MD beside Song et al.'s"
        " method; 17: the elastic model and E+MD on Song et al.'s global warp (vtc); 19: the elastic model on the"
        " RBF transfer's result (Figs. 19-20), or on --global-landmarks from another method (Fig. 21)",
    )


def run(args: argparse.Namespace) -> None:
    from ..evaluation.figures import (
        draw,
        figure_request,
        one_face,
        summary,
    )  # (numpy and the rest: loaded when the command runs, not for --help)
    from ..io.images import check_output_path, save_image

    paths = source_photos(args)
    check_output_path(args.output, paths)
    inputs = load_inputs(args)
    runs = [inputs.clone(run.methods, run.options) for run in figure_request(args.figure, inputs.options, args.global_warp is not None)]
    save_image(args.output, draw(args.figure, runs, inputs.images), inputs=paths)
    print(f"{args.output}: {summary(args.figure, [one_face(results, inputs.images)[0] for results in runs])}")
