"""Derive the table that maps the FRL 189-point template onto dlib's 68-point layout.

For each of the 72 neutral photos of the Face Research Lab London Set (``neutral_front/NNN_03``)
dlib's 68 landmarks are detected and the manual 189-point WebMorph template is read.  For each
dlib index the candidates are the template points of the same facial feature and the convex
combinations of two neighbouring points on that feature's template contour (weight fitted by least
squares over all faces).  Error is the distance to dlib's point divided by the inter-pupil distance
(template points 0 and 1); a candidate is scored by its median error over the faces.  A single
template point is kept unless the best two-point combination lowers the median error by at least
``PAIR_GAIN``.  Points with the same precise anatomical definition in both layouts (eye and mouth
corners, subnasale, chin) are pinned to their template point instead of fitted (``ANCHORS``).

Prints, per dlib index, the chosen template point(s) with weights and the median / 90th-percentile
normalised error, the overall figures, and the table as Python source for
``src/exprclone/frl_template.py``.

Run from the repository root::

    PYTHONPATH=src python tools/derive_frl_map.py [--data DIR]

DIR defaults to $EXPRCLONE_DATA, else ``../shared/data`` beside the checkout.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from exprclone.data import sets as datasets
from exprclone.io.images import load_image
from exprclone.io.landmarks import read_tem
from exprclone.landmarks.dlib import Detector

PAIR_GAIN = 0.01  # minimum drop in median normalised error that justifies two points over one


def _chain(points: tuple[int, ...], closed: bool = False) -> list[tuple[int, int]]:
    """Neighbouring pairs along a template contour."""
    ends = points[1:] + points[:1] if closed else points[1:]
    return list(zip(points, ends))


# Template contours, in order along the curve (taken from the .tem line definitions).
JAW = (109, 185, 110, 186, 111, 125, 126, 127, 128, 129, 130, 131, 132, 133, 114, 188, 113, 187, 112)
BROW_RIGHT = (71, 72, 73, 74, 75, 76)  # upper edge, subject's right brow: outer end 71 .. inner end 76
BROW_LEFT = (77, 78, 79, 80, 81, 82)  # upper edge, subject's left brow: inner end 77 .. outer end 82
NOSE_BASE = (63, 64, 65, 179, 180, 55, 181, 182, 70, 69, 68)  # alar crease .. subnasale 55 .. alar crease
PHILTRUM_TOPS = (170, 172)  # tops of the philtral columns, on the nose base below dlib's 32 / 34
EYE_RIGHT = (18, 19, 20, 21, 22, 30, 29, 28)  # corners 18 (outer), 22 (inner); upper lid 19-21
EYE_LEFT = (23, 24, 25, 26, 27, 33, 32, 31)  # corners 23 (inner), 27 (outer); upper lid 24-26
LIPS_OUTER = (87, 88, 89, 90, 91, 92, 93, 108, 107, 106, 105, 104)  # mouth corners 87, 93
LIPS_INNER_UPPER = (87, 94, 95, 96, 97, 98, 93)
LIPS_INNER_LOWER = (93, 103, 102, 101, 100, 99)
# The template has no midline points on the nose bridge: its nose is drawn as two side contours,
# 50-54 and 56-60, so dlib's bridge and tip (27-30) are combinations of left/right partners.
NOSE_SIDE_PAIRS = [(50, 56), (51, 57), (52, 58), (53, 59), (54, 60)]


# Per feature: the dlib indices, the template points each may map to, and the template point
# pairs whose convex combinations it may map to.
FEATURES = (
    (range(0, 17), JAW, _chain(JAW)),
    (range(17, 22), BROW_RIGHT, _chain(BROW_RIGHT)),
    (range(22, 27), BROW_LEFT, _chain(BROW_LEFT)),
    (range(27, 31), (), NOSE_SIDE_PAIRS),
    (range(31, 36), NOSE_BASE + PHILTRUM_TOPS, _chain(NOSE_BASE)),
    (range(36, 42), EYE_RIGHT, _chain(EYE_RIGHT, closed=True)),
    (range(42, 48), EYE_LEFT, _chain(EYE_LEFT, closed=True)),
    (range(48, 60), LIPS_OUTER, _chain(LIPS_OUTER, closed=True)),
    (range(60, 65), LIPS_INNER_UPPER, _chain(LIPS_INNER_UPPER)),
    (range(65, 68), LIPS_INNER_LOWER, _chain(LIPS_INNER_LOWER)),
)

# dlib index -> template point with the same anatomical definition.
ANCHORS = {
    8: 129,  # chin (menton)
    33: 55,  # subnasale
    36: 18,  # right eye, outer corner
    39: 22,  # right eye, inner corner
    42: 23,  # left eye, inner corner
    45: 27,  # left eye, outer corner
    48: 87,  # right mouth corner
    54: 93,  # left mouth corner
}


def load_faces(data_dir: Path) -> tuple[np.ndarray, np.ndarray]:
    """dlib points (F, 68, 2) and template points (F, 189, 2) of every neutral photo."""
    detector = Detector()
    dlib_points, template_points = [], []
    for tem in sorted((data_dir / "london" / "neutral_front").glob("*_03.tem")):
        jpg = tem.with_suffix(".jpg")
        dlib_points.append(detector.detect(load_image(jpg), str(jpg)))
        template_points.append(read_tem(tem))
    return np.array(dlib_points), np.array(template_points)


def normalised_error(estimate: np.ndarray, target: np.ndarray, ipd: np.ndarray) -> np.ndarray:
    """Per-face distance between (F, 2) point sets divided by the inter-pupil distance (F,)."""
    return np.linalg.norm(estimate - target, axis=-1) / ipd


def fit_weight(p: np.ndarray, q: np.ndarray, target: np.ndarray, ipd: np.ndarray) -> float:
    """Least-squares w in [0, 1] so that w p + (1 - w) q approximates target (IPD-normalised)."""
    a = (p - q) / ipd[:, None]
    b = (target - q) / ipd[:, None]
    return float(np.clip(np.sum(a * b) / np.sum(a * a), 0.0, 1.0))


def apply(entry: tuple, tem_pts: np.ndarray) -> np.ndarray:
    """The (F, 2) points that a table entry gives for (F, 189, 2) templates."""
    return sum(w * tem_pts[:, j] for j, w in entry)


def choose(i: int, dlib_pts: np.ndarray, tem_pts: np.ndarray, ipd: np.ndarray) -> tuple:
    """The table entry for dlib index i: ((j, 1.0),) or ((j, w), (k, 1 - w))."""
    if i in ANCHORS:
        return ((ANCHORS[i], 1.0),)
    target = dlib_pts[:, i]

    def median_error(entry: tuple) -> float:
        return float(np.median(normalised_error(apply(entry, tem_pts), target, ipd)))

    singles, pairs = next((singles, pairs) for indices, singles, pairs in FEATURES if i in indices)
    best_single = min((((j, 1.0),) for j in singles), key=median_error, default=None)
    mixes = []
    for j, k in pairs:
        w = round(fit_weight(tem_pts[:, j], tem_pts[:, k], target, ipd), 2)
        mixes.append(((j, w), (k, round(1 - w, 2))))
    best_pair = min(mixes, key=median_error)
    if best_single is not None and median_error(best_single) <= median_error(best_pair) + PAIR_GAIN:
        return best_single
    return best_pair


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    datasets.add_argument(parser, holds="the folder holding london/")
    args = parser.parse_args()

    dlib_pts, tem_pts = load_faces(args.data)
    ipd = np.linalg.norm(tem_pts[:, 0] - tem_pts[:, 1], axis=1)
    print(f"# {len(ipd)} faces; inter-pupil distance {ipd.min():.0f}-{ipd.max():.0f} px")

    table = [choose(i, dlib_pts, tem_pts, ipd) for i in range(68)]
    errors = np.stack([normalised_error(apply(e, tem_pts), dlib_pts[:, i], ipd) for i, e in enumerate(table)], axis=1)
    print("# dlib  template (index, weight)              median    p90   (error / inter-pupil distance)")
    for i, entry in enumerate(table):
        text = " + ".join(f"{j}*{w:.2f}" for j, w in entry)
        flag = "  anchored" if i in ANCHORS else ""
        print(f"# {i:4d}  {text:36s} {np.median(errors[:, i]):7.3f} {np.percentile(errors[:, i], 90):7.3f}{flag}")
    for name, part in (("overall (all points)", errors), ("jaw 0-16", errors[:, :17]), ("inner face 17-67", errors[:, 17:])):
        print(f"# {name}, all faces: median {np.median(part):.3f}, p90 {np.percentile(part, 90):.3f}")
    per_face_mean = errors.mean(axis=1)
    print(
        f"# per-face mean error: median {np.median(per_face_mean):.3f}, p90 {np.percentile(per_face_mean, 90):.3f}, "
        f"max {per_face_mean.max():.3f}"
    )
    corners = np.linalg.norm(dlib_pts[:, 36] - dlib_pts[:, 45], axis=1)
    per_face_corner = (errors * ipd[:, None]).mean(axis=1) / corners
    print(
        f"# per-face mean error / outer eye-corner distance (dlib 36-45): median {np.median(per_face_corner):.3f}, "
        f"p90 {np.percentile(per_face_corner, 90):.3f}, max {per_face_corner.max():.3f}"
    )

    print("FRL189_TO_DLIB68 = (")
    for i, entry in enumerate(table):
        print(f"    {tuple((j, w) for j, w in entry)!r},  # {i}")
    print(")")


if __name__ == "__main__":
    main()
