"""The two landmarkers side by side: accuracy against the London Set's manual templates, tilted faces, speed.

In one run, on the 72 neutral photos of the London Set (1350x1350):

* accuracy: each landmarker's 68 points against the manual template mapped to 68
  (``exprclone.io.frl_template``), the mean distance over the template's outer-eye-corner
  distance, per region (``exprclone.evaluation.accuracy.REGIONS``), on all 72 people and on
  the 24 held out of the mesh table's fit (``accuracy.split``). The template's mapping to 68
  was itself fitted to dlib's points (``tools/derive_frl_map.py``): the figures lean dlib's way.
* tilted faces: every photo rotated by 15, 30 and 45 degrees about its centre (the corners
  filled by replicating the edge); a face counts as found if the landmarker answers and its
  points are within 0.1 outer-eye distances of the rotated template on average.
* speed: the median time of one photo's landmarks (the model already loaded), and the median
  wall time of the one-shot command ``exprclone clone`` on three sample photos with each
  landmarker (``--runs`` of each, interleaved), which includes loading the landmarker.
* inner lips: on the smiling photos whose mesh shows an open mouth, how much of the mesh's
  20-point inner-lip contour the 8 inner-lip points of the 68 cover (intersection over union
  of the two polygons), which bounds what the dense lips could add to the mouth's paste.
* video: each landmarker's tracker (``exprclone.drive.tracking.track``) through the 11 GRID clips
  (360x288, 75 frames): milliseconds a frame, frames without a face, the jitter of the
  raw fits (the mean size of each point's second difference from frame to frame, over the
  outer-eye distance: speech moves the mouth smoothly, a fitter's noise does not), and how
  far the inner lips open in speech (the gap between points 62 and 66 over the outer-eye
  distance, its 95th minus 5th percentile in each clip, the median over the clips).

Run from the repository root::

    EXPRCLONE_DATA=../shared/data PYTHONPATH=src python benchmarks/landmarkers.py [--runs 5]
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import cv2
import numpy as np

from exprclone import data as samples
from exprclone.data import sets as datasets
from exprclone.drive import tracking
from exprclone.errors import ExprCloneError
from exprclone.evaluation.accuracy import point_errors, region_errors, split, templates
from exprclone.io.images import load_image
from exprclone.io.video import read_frames
from exprclone.landmarks.backends import LANDMARKERS, shared
from exprclone.landmarks.facemesh import MeshDetector
from exprclone.landmarks.layout import DLIB68
from exprclone.landmarks.mesh_layout import INNER_LIPS, to_68

ANGLES = (15, 30, 45)
#: a mouth counts as open when its dense inner-lip polygon covers this many squared mouth widths.
OPEN_AREA = 0.02
#: a tilted face counts as found when its points are this close to the template on average (outer-eye distances).
FOUND = 0.1


def rotated(image: np.ndarray, points: np.ndarray, degrees: float) -> tuple[np.ndarray, np.ndarray]:
    """The photo turned by ``degrees`` (counter-clockwise as seen) about its centre, and the points with it."""
    h, w = image.shape[:2]
    matrix = cv2.getRotationMatrix2D(((w - 1) / 2, (h - 1) / 2), degrees, 1.0)
    turned = cv2.warpAffine(image, matrix, (w, h), flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
    return turned, points @ matrix[:, :2].T + matrix[:, 2]


def accuracy(people: dict, name: str) -> tuple[dict, list[float]]:
    """Each person's 68 points by landmarker ``name``, and the seconds each took."""
    landmarker, found, seconds = shared(name), {}, []
    landmarker.detect(samples.photo(samples.TARGET))  # loaded before the clock starts
    for face_id, (path, _) in people.items():
        image = load_image(path)
        start = time.perf_counter()
        found[face_id] = landmarker.detect(image, str(path))
        seconds.append(time.perf_counter() - start)
    return found, seconds


def tilted(people: dict, name: str, degrees: float) -> tuple[int, float]:
    """How many tilted photos the landmarker finds (:data:`FOUND`), and its mean error on those it answers."""
    landmarker, found, errors = shared(name), 0, []
    for path, truth in people.values():
        image, turned_truth = rotated(load_image(path), truth, degrees)
        try:
            error = float(point_errors(landmarker.detect(image, str(path)), turned_truth).mean())
        except ExprCloneError:
            continue
        errors.append(error)
        found += error < FOUND
    return found, float(np.mean(errors)) if errors else float("nan")


def inner_lips(london: Path) -> list[float]:
    """Intersection over union of the 68-point inner-lip polygon and the mesh's dense one, on each open smile."""
    mesh, overlaps = MeshDetector(), []
    for path in sorted((london / "smiling_front").glob("*_08.jpg")):
        image = load_image(path)
        points = mesh.detect_mesh(image, str(path))
        dense = np.vstack([points[list(INNER_LIPS[0])], points[list(INNER_LIPS[1][-2:0:-1])]])
        masks = [np.zeros(image.shape[:2], np.uint8) for _ in range(2)]
        for mask, polygon in zip(masks, (dense, to_68(points)[list(DLIB68.mouth_inner)])):
            cv2.fillPoly(mask, [np.round(polygon * 4).astype(np.int32)], 1, shift=2)
        if masks[0].sum() > OPEN_AREA * np.linalg.norm(points[61] - points[291]) ** 2:
            overlaps.append((masks[0] & masks[1]).sum() / (masks[0] | masks[1]).sum())
    return overlaps


def video(clips: list[Path], name: str) -> tuple[float, int, float, float]:
    """Milliseconds a frame of tracking, frames without a face, the jitter and the lips' range, over ``clips``, by ``name``."""
    seconds, frames, missing, jitter, lips = 0.0, 0, 0, [], []
    for clip in clips:
        decoded = list(read_frames(clip))
        start = time.perf_counter()
        track = tracking.track(decoded, shared(name), str(clip))
        seconds, frames, missing = seconds + time.perf_counter() - start, frames + len(decoded), missing + track.missing
        corners = np.linalg.norm(track.points[:, 36] - track.points[:, 45], axis=1)
        second = np.linalg.norm(np.diff(track.points, n=2, axis=0), axis=2) / corners[1:-1, None]
        jitter.append(second[track.found[2:] & track.found[1:-1] & track.found[:-2]].mean())
        gap = np.linalg.norm(track.points[:, 66] - track.points[:, 62], axis=1) / corners
        lips.append(np.percentile(gap, 95) - np.percentile(gap, 5))
    return 1000 * seconds / frames, missing, float(np.mean(jitter)), float(np.median(lips))


def one_shot(runs: int) -> dict[str, list[float]]:
    """Wall seconds of ``exprclone clone`` on the samples with each landmarker, ``runs`` times, interleaved."""
    photos = [str(samples.path(samples.SOURCE)), str(samples.path(samples.SOURCE, "smile")), str(samples.path(samples.TARGET))]
    times: dict[str, list[float]] = {name: [] for name in LANDMARKERS}
    with tempfile.TemporaryDirectory() as folder:
        for _ in range(runs):
            for name in LANDMARKERS:
                command = [
                    sys.executable,
                    "-m",
                    "exprclone",
                    "clone",
                    *photos,
                    "-o",
                    str(Path(folder) / f"{name}.png"),
                    "--landmarker",
                    name,
                ]
                start = time.perf_counter()
                subprocess.run(command, check=True, capture_output=True)
                times[name].append(time.perf_counter() - start)
    return times


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    datasets.add_argument(parser, holds="the folder holding london/")
    parser.add_argument("--runs", type=int, default=5, help="runs of the one-shot command with each landmarker")
    args = parser.parse_args()
    people = templates(Path(args.data) / "london")
    _, held = split(list(people))
    print(f"# {len(people)} London people, {len(held)} held out of the mesh table's fit; machine shared with other work")
    for name in LANDMARKERS:
        found, seconds = accuracy(people, name)
        for part, ids in (("all", list(people)), ("held-out", held)):
            errors = region_errors(point_errors(np.array([found[i] for i in ids]), np.array([people[i][1] for i in ids])))
            print(f"{name:5s} error, {part:8s}: " + ", ".join(f"{k} {v:.4f}" for k, v in errors.items()))
        print(f"{name:5s} one photo's landmarks: median {1000 * np.median(seconds):.1f} ms")
    for degrees in ANGLES:
        for name in LANDMARKERS:
            count, error = tilted(people, name, degrees)
            print(f"{name:5s} tilted {degrees:2d} degrees: found {count}/{len(people)}, mean error where answered {error:.4f}")
    overlaps = inner_lips(Path(args.data) / "london")
    print(f"inner lips, {len(overlaps)} open smiles: the 8 points' polygon over the mesh's 20, IoU median {np.median(overlaps):.3f}")
    clips = sorted((Path(args.data) / "grid").glob("*.mpg"))
    for name in LANDMARKERS:
        ms, missing, jitter, lips = video(clips, name)
        print(
            f"{name:5s} tracking {len(clips)} GRID clips: {ms:.1f} ms a frame, {missing} frames without a face, jitter {jitter:.4f},"
            f" inner lips' range {lips:.3f}"
        )
    times = one_shot(args.runs)
    medians = {name: float(np.median(t)) for name, t in times.items()}
    for name, t in times.items():
        print(f"{name:5s} exprclone clone (one shot): median {medians[name]:.2f} s of {len(t)} ({', '.join(f'{s:.2f}' for s in t)})")
    print(f"mesh / dlib one-shot time: {medians['mesh'] / medians['dlib']:.2f}")


if __name__ == "__main__":
    main()
