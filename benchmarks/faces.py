"""Group photos: which detector finds every face, and a clone of six faces against six single clones.

In one run, on group photos made of London Set people (``exprclone.evaluation.groups``, as
``tools/group_photo.py`` makes them: six people drawn with a fixed seed, faces 120 to 400
pixels wide, 3000x2000, heads turned in the photo's plane by 0 to 40 degrees):

* detectors: for each way of finding faces, how many of the photos' faces it finds (a box
  holding the person's nose tip), how many boxes it gives over nobody, and its median time
  a photo: the landmarkers' own detectors (dlib's HOG on a copy at most 512 pixels wide,
  BlazeFace on the whole photo at 128), dlib's HOG on the photo scaled so that a 100-pixel
  face fills its upsampled window (0.4), BlazeFace over tiles
  (``exprclone.landmarks.crowd.proposals``), and the two together
  (``exprclone.landmarks.crowd.find``: BlazeFace proposes, the HOG confirms); then each on
  the 72 London portraits (1350x1350: one face each).
* speed: the clone of every face of one photo (``exprclone.expressions.clone(photo,
  "smile")``: faces found, each cloned in its region, blended back) against its peer, the
  six single clones of the same faces: each region cut out and cloned on its own, its face
  detected there by the landmarker (as ``exprclone clone CROP --expression smile`` did before
  faces were looked for), the two run in turn (``--repeat`` of each, medians); the ratio is
  the target (at most 1.2). Also each peer clone with its landmarks given, and with today's
  search for every face of the crop, for what the search costs.

Run from the repository root::

    EXPRCLONE_DATA=../shared/data PYTHONPATH=src python benchmarks/faces.py [--photos 6] [--repeat 5]
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
from pathlib import Path

import cv2
import numpy as np

import exprclone.expressions
from exprclone.data import sets as datasets
from exprclone.evaluation.groups import make
from exprclone.evaluation.london import Dataset
from exprclone.io.images import load_image
from exprclone.landmarks import crowd
from exprclone.landmarks.backends import shared
from exprclone.landmarks.dlib import hog

WIDTHS = (120, 176, 232, 288, 344, 400)
SIZE = (3000, 2000)
TILTS = (0, 10, 20, 30, 40, 0)
#: the scale of the photo for dlib's HOG alone: a 100-pixel face fills its 80-pixel window upsampled twice.
HOG_SCALE = 0.4


def hog_alone(image: np.ndarray) -> list[tuple[float, float, float, float]]:
    small = cv2.resize(image, None, fx=HOG_SCALE, fy=HOG_SCALE, interpolation=cv2.INTER_AREA)
    return [(r.left() / HOG_SCALE, r.top() / HOG_SCALE, r.right() / HOG_SCALE, r.bottom() / HOG_SCALE) for r in hog(small, 1)]


def detectors() -> dict:
    mesh = shared("mesh")
    return {
        "dlib's own (HOG at 512 px)": shared("dlib").faces,
        "BlazeFace's own (whole photo at 128 px)": mesh.faces,
        f"dlib's HOG at {HOG_SCALE}, upsampled": hog_alone,
        "BlazeFace over tiles": lambda im: crowd.proposals(im, mesh),
        "BlazeFace over tiles, HOG confirms (crowd.find)": lambda im: crowd.find(im, mesh),
    }


def tally(boxes, people) -> tuple[int, int]:
    """Faces found (a box holding the nose tip) and boxes over nobody."""
    held = [[b[0] <= p.landmarks[30][0] <= b[2] and b[1] <= p.landmarks[30][1] <= b[3] for p in people] for b in boxes]
    return sum(any(column) for column in zip(*held)) if held else 0, sum(not any(row) for row in held)


def timed(fn, *args):
    start = time.perf_counter()
    out = fn(*args)
    return out, time.perf_counter() - start


def compare_detectors(london: Path, photos: int) -> None:
    data = Dataset.open(london)
    rng = np.random.default_rng(0)
    made = []
    for k in range(photos):
        people = [str(p) for p in rng.choice(data.ids, len(WIDTHS), replace=False)]
        tilt = TILTS[k % len(TILTS)]
        made.append(make(london, people, WIDTHS, SIZE, seed=k, tilts=[tilt if j % 2 else -tilt for j in range(len(WIDTHS))]))
    portraits = [load_image(data.path(p, False)) for p in data.ids]
    total = photos * len(WIDTHS)
    print(f"detectors on {photos} group photos ({total} faces, {WIDTHS[0]}-{WIDTHS[-1]} px, {SIZE[0]}x{SIZE[1]}, tilts up to")
    print(f"{max(TILTS)} degrees) and on {len(portraits)} London portraits (1350x1350, one face each); medians a photo")
    for name, find in detectors().items():
        find(portraits[0])  # loaded
        found = [timed(find, image) + (people,) for image, people in made]
        counts = np.array([tally(boxes, people) for boxes, _, people in found])
        single = [timed(find, image) for image in portraits]
        one = sum(len(boxes) == 1 for boxes, _ in single)
        print(
            f"  {name:<50} {counts[:, 0].sum():>3}/{total} found, {counts[:, 1].sum():>2} over nobody,"
            f" {1000 * statistics.median(t for _, t, _ in found):6.0f} ms;"
            f" portraits: {one}/{len(portraits)} with one face, {1000 * statistics.median(t for _, t in single):5.0f} ms"
        )


def compare_speed(london: Path, repeat: int) -> None:
    data = Dataset.open(london)
    people = [str(p) for p in np.random.default_rng(0).choice(data.ids, len(WIDTHS), replace=False)]
    image, _ = make(london, people, WIDTHS, SIZE, seed=0)
    found = exprclone.expressions.clone(image, "smile").face_results
    crops = [image[y0:y1, x0:x1].copy() for x0, y0, x1, y1 in (f.region for f in found)]
    given = [f.result.landmarks["target_neutral"] for f in found]
    dlib = shared("dlib")

    def group():
        exprclone.expressions.clone(image, "smile")

    def singles():
        for crop in crops:
            exprclone.expressions.clone(crop, "smile", target_landmarks=dlib.detect(crop))

    def singles_given():
        for crop, points in zip(crops, given):
            exprclone.expressions.clone(crop, "smile", target_landmarks=points)

    def singles_searched():
        for crop in crops:
            exprclone.expressions.clone(crop, "smile")

    runs = {"one photo, six faces": group, "six single clones": singles, "six, landmarks given": singles_given}
    runs["six, every face searched"] = singles_searched
    times: dict[str, list[float]] = {name: [] for name in runs}
    for fn in runs.values():
        fn()
    for _ in range(repeat):
        for name, fn in runs.items():
            times[name].append(timed(fn)[1])
    medians = {name: statistics.median(t) for name, t in times.items()}
    peer = medians["six single clones"]
    sizes = ", ".join(f"{c.shape[1]}x{c.shape[0]}" for c in crops)
    print(f"\nspeed: one {SIZE[0]}x{SIZE[1]} photo, six faces ({sizes} regions), e+md with the smile; median of {repeat}, in turn")
    for name, seconds in medians.items():
        print(f"  {name:<50} {1000 * seconds:7.0f} ms  ({seconds / peer:.2f}x the six single clones)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    datasets.add_argument(parser)
    parser.add_argument("--photos", type=int, default=6, help="group photos for the detectors (default: 6)")
    parser.add_argument("--repeat", type=int, default=5, help="runs of each clone (default: 5)")
    args = parser.parse_args()
    london = Path(args.data) / "london"
    print(f"exprclone group photos benchmark: {os.cpu_count()} cores\n")
    compare_detectors(london, args.photos)
    compare_speed(london, args.repeat)


if __name__ == "__main__":
    main()
