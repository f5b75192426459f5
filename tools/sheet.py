"""A contact sheet: every method on a few cross-person pairs, beside the real smiles.

    python tools/sheet.py [--data ../shared/data] [--pairs 5] [--seed 0] [-o out/sheet.jpg]

Each row is one ordered pair (source A, target B): A neutral, A smiling, B neutral, the
seven methods of Fig. 11 applied to B, and B's real smile, all cropped to B's face.
"""

import argparse
from pathlib import Path

import numpy as np

from exprclone import METHODS, clone_methods
from exprclone.data import sets as datasets
from exprclone.evaluation.figures import face_box
from exprclone.evaluation.london import Dataset
from exprclone.evaluation.panels import panel
from exprclone.io.images import load_image, save_image
from exprclone.landmarks.backends import default_detector


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    datasets.add_argument(parser)
    parser.add_argument("--pairs", type=int, default=5)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("-o", "--output", default="out/sheet.jpg")
    args = parser.parse_args()
    data = Dataset.open(Path(args.data) / "london")
    rows = []
    for a, b in data.pairs(args.pairs, args.seed):
        sn, se, tn, ts = (load_image(data.path(p, smiling)) for p, smiling in ((a, False), (a, True), (b, False), (b, True)))
        results = clone_methods(sn, se, tn)
        lm = results["e+md"].landmarks
        lam = results["e+md"].lambda_k
        crop = lambda image, points: image[face_box(points, image.shape)]  # noqa: E731
        cells = [
            panel(crop(sn, lm["source_neutral"]), f"A={a} neutral"),
            panel(crop(se, lm["source_expression"]), f"A={a} smile"),
            panel(crop(tn, lm["target_neutral"]), f"B={b} neutral"),
        ]
        cells += [
            panel(crop(results[m].image, lm["target_neutral"]), m + (f" lambda={lam:g}" if m in ("elastic", "e+md") else ""))
            for m in METHODS
        ]
        cells.append(panel(crop(ts, default_detector().detect(ts)), f"B={b} real smile"))
        rows.append(np.hstack(cells))
        print(f"{a} -> {b}: lambda_k={lam:g}", flush=True)
    save_image(args.output, np.vstack(rows))
    print(f"{args.output}: {len(rows)} pairs")


if __name__ == "__main__":
    main()
