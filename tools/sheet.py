"""A contact sheet: every method on a few cross-person pairs, beside the real smiles.

    python tools/sheet.py [--data ../shared/data] [--pairs 5] [--seed 0] [-o out/sheet.jpg]

Each row is one ordered pair (source A, target B): A neutral, A smiling, B neutral, the
seven methods of Fig. 11 applied to B, and B's real smile, all cropped to B's face.
"""

import argparse
import os
from pathlib import Path

import cv2
import numpy as np

from exprclone import METHODS, clone_methods
from exprclone.clone import default_detector
from exprclone.images import load_image, save_image

CELL = 300  # pixels per cell side


def face_crop(image: np.ndarray, landmarks: np.ndarray) -> np.ndarray:
    """A square crop around the face, scaled to CELL."""
    centre = (landmarks.min(0) + landmarks.max(0)) / 2
    half = 0.75 * (landmarks.max(0) - landmarks.min(0)).max()
    x0, y0 = np.maximum(0, (centre - half).astype(int))
    x1, y1 = (centre + half).astype(int)
    return cv2.resize(image[y0:y1, x0:x1], (CELL, CELL), interpolation=cv2.INTER_AREA)


def label(cell: np.ndarray, text: str) -> np.ndarray:
    out = cell.copy()
    cv2.rectangle(out, (0, 0), (CELL, 26), (255, 255, 255), -1)
    cv2.putText(out, text, (6, 19), cv2.FONT_HERSHEY_SIMPLEX, 0.6, (0, 0, 0), 1, cv2.LINE_AA)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", default=os.environ.get("EXPRCLONE_DATA", "../shared/data"))
    parser.add_argument("--pairs", type=int, default=5)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("-o", "--output", default="out/sheet.jpg")
    args = parser.parse_args()
    london = Path(args.data) / "london"
    ids = sorted(p.name[:3] for p in (london / "neutral_front").glob("*.jpg"))
    rng = np.random.default_rng(args.seed)
    rows = []
    for _ in range(args.pairs):
        a, b = rng.choice(ids, 2, replace=False)
        sn, se = load_image(london / "neutral_front" / f"{a}_03.jpg"), load_image(london / "smiling_front" / f"{a}_08.jpg")
        tn, ts = load_image(london / "neutral_front" / f"{b}_03.jpg"), load_image(london / "smiling_front" / f"{b}_08.jpg")
        results = clone_methods(sn, se, tn)
        lm = results["e+md"].landmarks
        lam = results["e+md"].lambda_k
        cells = [
            label(face_crop(sn, lm["source_neutral"]), f"A={a} neutral"),
            label(face_crop(se, lm["source_expression"]), f"A={a} smile"),
            label(face_crop(tn, lm["target_neutral"]), f"B={b} neutral"),
        ]
        cells += [label(face_crop(results[m].image, lm["target_neutral"]), m + (f" l={lam:g}" if m in ("elastic", "e+md") else "")) for m in METHODS]
        cells.append(label(face_crop(ts, default_detector().detect(ts)), f"B={b} real smile"))
        rows.append(np.hstack(cells))
        print(f"{a} -> {b}: lambda_k={lam:g}", flush=True)
    save_image(args.output, np.vstack(rows))
    print(f"{args.output}: {len(rows)} pairs")


if __name__ == "__main__":
    main()
