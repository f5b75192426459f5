"""What a change of light in the source's photos alone does to a clone (issue 57): made grey, relit by +-15% from one
ear to the other, or given another white balance (:mod:`exprclone.testing.lighting`).

    PYTHONPATH=src python tools/relight.py [--data ../shared/data/london] [--pairs 12] [--method e+md]

For each of ``--pairs`` London pairs (each person in turn the source, the next person the target), the clone of the
source's real photos is made, then again with the source's expression photo changed (``relit+``, ``relit-``, ``warm``,
``cool``, and ``noise``: Gaussian noise of one grey level, no change of light, the reference) or both source photos made
grey (``grey``), each twice:

- ``found``: the changed photo's landmarks found afresh, as a user's clone finds them;
- ``kept``: the landmarks of the unchanged photo: what the change does through the details (the ERI, its tint, the MD
  model's weighting, the mouth's paste) alone, the geometry the same.

It prints, for each change, the change of the clone inside the face (the hull of the final landmarks: grey levels,
each pixel's averaged over R, G and B, :func:`exprclone.testing.lighting.change`, so that a colour carried counts; the
mean over the pairs of each pair's mean, and of its 95th percentile), and how far the landmarks found on the
changed photo moved (pixels, mean over the points; and in eye distances). Where ``found`` is near ``noise``'s, a change
reaches the clone through where the landmarker places the points, as any change the eye cannot see does, not through
the light: ``kept`` is the light's share.
"""

from __future__ import annotations

import argparse

import numpy as np

from exprclone import clone
from exprclone.data import sets as datasets
from exprclone.io.images import load_image
from exprclone.landmarks import align
from exprclone.landmarks.backends import default_detector
from exprclone.landmarks.layout import DLIB68
from exprclone.testing.lighting import change, changes, face, noisy

#: the changes measured: those of the expression photo alone, and the grey source (both photos).
EXPRESSION_ONLY = ("relit+", "relit-", "warm", "cool", "noise")


def measure(photos: tuple[np.ndarray, np.ndarray, np.ndarray], method: str) -> dict[str, tuple[float, ...]]:
    """One pair's rows: for each change, the clone's change with the landmarks found and kept (mean, 95th percentile of
    each), and the found landmarks' motion (pixels, eye distances)."""
    detect = default_detector().detect
    points = tuple(detect(p) for p in photos)
    base = clone(*photos, landmarks=points, method=method)
    mask = face(photos[2].shape, base.landmarks["final"])
    iod = align.interocular(points[1], DLIB68)
    rows = {}
    for name, image in {**changes(photos[1], points[1]), "noise": noisy(photos[1])}.items():
        if name == "grey":
            source = (image, changes(photos[0], points[0])["grey"])
        elif name in EXPRESSION_ONLY:
            source = (image, photos[0])
        else:
            continue
        found = (detect(source[1]), detect(source[0]), points[2])
        moved = float(np.linalg.norm(found[1] - points[1], axis=1).mean())
        by_found = change(base.image, clone(source[1], source[0], photos[2], landmarks=found, method=method).image, mask)
        by_kept = change(base.image, clone(source[1], source[0], photos[2], landmarks=points, method=method).image, mask)
        rows[name] = (*by_found, *by_kept, moved, moved / iod)
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    datasets.add_argument(parser, "london", holds="the London Set folder")
    parser.add_argument("--pairs", type=int, default=12, help="pairs measured (default: 12)")
    parser.add_argument("--method", default="e+md", help="the method (default: e+md)")
    args = parser.parse_args()
    people = sorted(p.stem[:3] for p in (args.data / "neutral_front").glob("*_03.jpg"))
    if not people:
        raise SystemExit(f"no London Set photos in {args.data}/neutral_front (give --data)")
    step = max(1, len(people) // args.pairs)
    table: dict[str, list[tuple[float, ...]]] = {}
    for k in range(0, step * args.pairs, step):
        source, target = people[k % len(people)], people[(k + 1) % len(people)]
        photos = (
            load_image(args.data / "neutral_front" / f"{source}_03.jpg"),
            load_image(args.data / "smiling_front" / f"{source}_08.jpg"),
            load_image(args.data / "neutral_front" / f"{target}_03.jpg"),
        )
        for name, row in measure(photos, args.method).items():
            table.setdefault(name, []).append(row)
            found, kept = f"{row[0]:5.2f} (p95 {row[1]:5.2f})", f"{row[2]:5.2f} (p95 {row[3]:5.2f})"
            print(f"{source} onto {target} {name:7s} found {found}  kept {kept}  landmarks moved {row[4]:4.2f} px", flush=True)
    print(f"\n{args.method}, {args.pairs} London pairs: the clone's change inside the face (grey levels, R, G and B)")
    print("(the mean over the pairs of each pair's mean and of its 95th percentile)")
    print("change   landmarks found (mean, p95)   landmarks kept (mean, p95)   landmarks moved (px, eye distances)")
    for name, rows in table.items():
        m = np.mean(rows, axis=0)
        print(f"{name:7s}  {m[0]:6.2f} {m[1]:6.2f}                 {m[2]:6.2f} {m[3]:6.2f}                {m[4]:5.2f} {m[5]:.4f}")


if __name__ == "__main__":
    main()
