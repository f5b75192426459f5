"""Train the eigenface basis shipped in src/exprclone/data/eigenfaces.npz.

    python tools/train_eigenfaces.py [--data ../shared/data]

Uses the 144 photos (72 neutral, 72 smiling) of the Face Research Lab London Set
(DeBruine and Jones 2017, CC BY 4.0): the organs' patches of each photo's features' crop
(:mod:`exprclone.geometry.eigenface`), each person's mean removed before the PCA, so the
basis spans expression (here: smiling) rather than identity, as the paper's basis of one
person's expressions does. Prints the basis's unit: the root-mean-square distance between
a person's two photos.
"""

import argparse
from pathlib import Path

from exprclone.data import sets as datasets
from exprclone.geometry.eigenface import train
from exprclone.io.images import load_image
from exprclone.landmarks.dlib import Detector
from exprclone.landmarks.layout import DLIB68

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
datasets.add_argument(parser)
parser.add_argument("-o", "--output", default=str(Path(__file__).parents[1] / "src/exprclone/data/eigenfaces.npz"))
args = parser.parse_args()
london = Path(args.data) / "london"
paths = sorted(london.glob("neutral_front/*.jpg")) + sorted(london.glob("smiling_front/*.jpg"))
detector = Detector()
faces = ((image, detector.detect(image, str(p))) for p, image in ((p, load_image(p)) for p in paths))
basis = train(faces, DLIB68, people=[p.name[:3] for p in paths])
basis.save(args.output)
size = Path(args.output).stat().st_size
print(f"{args.output}: {basis.components.shape[0]} components of {basis.components.shape[1]} pixels from {len(paths)} photos,")
print(f"unit {basis.unit:.4f} (a person's two photos apart, root-mean-square), {size / 1e6:.1f} MB")
