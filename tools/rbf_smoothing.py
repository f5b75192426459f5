"""How much the RBF correspondence between two neutral faces is smoothed (``exprclone.geometry.global_warp.RBF_SMOOTHING``).

    python tools/rbf_smoothing.py [--data ../shared/data] [--pairs 300] [--smoothing 1e-4 0.001 0.01 0.05 0.1 0.15 0.2 0.3 1 1000]

For random ordered pairs of the London Set's neutral faces (seed 2; landmarks detected),
and each smoothing: the range of the map's Jacobians at the landmarks (largest and
smallest singular value over every landmark of every pair: how much the RBF transfer
may stretch or squash a motion), and how well the map predicts a landmark left out of
the fit (mean error in the target's inter-ocular distances, on the first 60 pairs). A
very large smoothing is an affine map. The smoothing chosen is the least whose Jacobians
all stay within a factor of 2.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from scipy.interpolate import RBFInterpolator

from exprclone.data import sets as datasets
from exprclone.evaluation.london import Dataset
from exprclone.geometry import global_warp
from exprclone.io.images import load_image
from exprclone.landmarks import align, lips
from exprclone.landmarks.backends import default_detector
from exprclone.landmarks.layout import DLIB68


def normalised(points: np.ndarray) -> np.ndarray:
    return (points - points.mean(0)) / align.interocular(points, DLIB68)


def left_out_error(s: np.ndarray, t: np.ndarray, smoothing: float) -> np.ndarray:
    """For each landmark, the distance between the target's and the map's prediction from the other landmarks."""
    out = []
    for i in range(len(s)):
        keep = np.arange(len(s)) != i
        f = RBFInterpolator(s[keep], t[keep], kernel=global_warp.RBF_KERNEL, smoothing=smoothing)
        out.append(np.linalg.norm(f(s[i : i + 1])[0] - t[i]))
    return np.array(out)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    datasets.add_argument(parser)
    parser.add_argument("--pairs", type=int, default=300)
    parser.add_argument("--smoothing", type=float, nargs="+", default=[1e-4, 1e-3, 1e-2, 0.05, 0.1, 0.15, 0.2, 0.3, 1, 1000])
    args = parser.parse_args()
    data = Dataset.open(Path(args.data) / "london")
    faces = {i: lips.uncross(default_detector().detect(load_image(data.path(i, False))), DLIB68) for i in data.ids}
    rng = np.random.default_rng(2)
    pairs = [tuple(rng.choice(data.ids, 2, replace=False)) for _ in range(args.pairs)]
    for smoothing in args.smoothing:
        global_warp.RBF_SMOOTHING = smoothing
        values = np.concatenate([np.linalg.svd(global_warp.rbf_jacobians(faces[a], faces[b], DLIB68), compute_uv=False) for a, b in pairs])
        # in each face's own inter-ocular distances: the Jacobian of two faces of one shape is 1
        units = np.repeat([align.interocular(faces[b], DLIB68) / align.interocular(faces[a], DLIB68) for a, b in pairs], 68)
        values = values / units[:, None]
        error = np.concatenate([left_out_error(normalised(faces[a]), normalised(faces[b]), smoothing) for a, b in pairs[:60]])
        spread = f"singular values {values[:, 1].min():.2f} to {values[:, 0].max():.2f}"
        print(f"smoothing {smoothing:g}: {spread}; left-out landmark error {error.mean():.4f}")


if __name__ == "__main__":
    main()
