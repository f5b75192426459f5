"""Derive the table of src/exprclone/frl_template.py: FRL 189-point template -> dlib's 68.

    python tools/derive_frl_map.py [--data ../shared/data]

For each dlib index, the template point, or the convex combination of a template point
and one of its six nearest neighbours (weights 0.1..0.9), whose position has the smallest
median distance to dlib's detection over the London Set's neutral photos, in inter-pupil
distances (a pair must beat the best single point by 0.003). Prints the table as Python
source and the median and 90th-percentile errors.
"""

import argparse
import os
from pathlib import Path

import numpy as np

from exprclone.images import load_image
from exprclone.landmark_files import read_tem
from exprclone.landmarks import Detector

WEIGHTS = np.linspace(0.1, 0.9, 17)


def fit(detected: np.ndarray, templates: np.ndarray) -> tuple[list, np.ndarray]:
    """``detected`` (F, 68, 2), ``templates`` (F, 189, 2) -> table rows, errors (F, 68)."""
    ipd = np.linalg.norm(templates[:, 0] - templates[:, 1], axis=1)[:, None]
    mean_template = templates.mean(0)
    table, errors = [], []
    for i in range(detected.shape[1]):
        single = np.linalg.norm(templates - detected[:, i : i + 1], axis=2) / ipd
        median = np.median(single, axis=0)
        j = int(median.argmin())
        best = (median[j], ((j, 1.0),), single[:, j])
        for j in np.argsort(median)[:8]:
            for k in np.argsort(np.linalg.norm(mean_template - mean_template[j], axis=1))[1:7]:
                mix = templates[:, j, None] * WEIGHTS[None, :, None] + templates[:, k, None] * (1 - WEIGHTS[None, :, None])
                err = np.linalg.norm(mix - detected[:, i, None], axis=2) / ipd
                m = np.median(err, axis=0)
                w = int(m.argmin())
                if m[w] < best[0] - 0.003:
                    best = (m[w], ((int(j), round(float(WEIGHTS[w]), 3)), (int(k), round(float(1 - WEIGHTS[w]), 3))), err[:, w])
        table.append(best[1])
        errors.append(best[2])
    return table, np.array(errors).T


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", default=os.environ.get("EXPRCLONE_DATA", "../shared/data"))
    args = parser.parse_args()
    detector = Detector()
    detected, templates = [], []
    for tem in sorted((Path(args.data) / "london" / "neutral_front").glob("*_03.tem")):
        detected.append(detector.detect(load_image(tem.with_suffix(".jpg")), str(tem)))
        templates.append(read_tem(tem))
    table, errors = fit(np.array(detected), np.array(templates))
    print("FRL189_TO_DLIB68 = (")
    for i, row in enumerate(table):
        print(f"    {row!r},  # {i}")
    print(")")
    for name, part in (("jaw 0-16", errors[:, :17]), ("inner face 17-67", errors[:, 17:]), ("all", errors)):
        print(f"{name}: median {np.median(part):.3f}, 90th percentile {np.percentile(part, 90):.3f} inter-pupil distances")


if __name__ == "__main__":
    main()
