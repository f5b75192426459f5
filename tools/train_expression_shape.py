"""Train the model of how a face's neutral shape smiles, shipped in src/exprclone/data/expression_shape.npz.

    python tools/train_expression_shape.py [--data ../shared/data]

Learnt from the 72 people of the Face Research Lab London Set (DeBruine and Jones 2017, CC BY 4.0): each person's
neutral photo and smile, their landmarks placed by dlib's 68-point model
(:class:`exprclone.geometry.expression_shape.ExpressionShape`). ``exprclone evaluate --held-out`` judges models learnt
the same way without the people cloned.
"""

import argparse
from pathlib import Path

from exprclone.data import sets as datasets
from exprclone.evaluation.london import Dataset
from exprclone.geometry.expression_shape import ExpressionShape
from exprclone.io.images import load_image
from exprclone.landmarks.backends import shared
from exprclone.landmarks.layout import DLIB68

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
datasets.add_argument(parser, "london", holds="the London Set")
parser.add_argument("-o", "--output", default=str(Path(__file__).parents[1] / "src/exprclone/data/expression_shape.npz"))
args = parser.parse_args()
data = Dataset.open(args.data)
detect = shared("dlib").detect
faces = [tuple(detect(load_image(p), p) for p in (data.path(i, False), data.path(i, True))) for i in data.ids]
ExpressionShape.learn(faces, DLIB68).save(args.output)
print(f"{args.output}: learnt from {len(faces)} people's neutral photos and smiles")
