"""``exprclone compare``: every method of Fig. 11 on one triple of photos, as the sheet of Figs. 11-13."""

from __future__ import annotations

import argparse

from ..errors import naming
from .inputs import add_inputs, load_inputs


def add_parser(sub) -> None:
    c = sub.add_parser("compare", help="the paper's Figs. 11-13 and the DB curve as one sheet")
    add_inputs(c)
    c.add_argument("-o", "--output", required=True, help="output image (.png, .jpg, ...)")


def run(args: argparse.Namespace) -> None:
    from ..evaluation.figures import sheet
    from ..io.images import check_output_path, save_image
    from ..pipeline import clone_methods

    paths = [args.source_neutral, args.source_expression, args.target_neutral]
    check_output_path(args.output, paths)
    names, images, options = load_inputs(args)
    with naming(names):
        results = clone_methods(*images, **options)
    save_image(args.output, sheet(results, images[1]), inputs=paths)
    print(f"{args.output}: 7 methods, lambda_k={results['e+md'].lambda_k:g}")
