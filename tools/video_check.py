"""Smoothing and mouth motion of `exprclone video` on every GRID clip.

    python tools/video_check.py [--data ../shared/data] [--portrait 003] [--size 256]

For each clip, drives the portrait with e+md twice (landmarks smoothed, as shipped, and
raw) and prints: the jitter of the output's mouth landmarks (the geometry each frame is
rendered with; :func:`exprclone.drive.tracking.jitter`, in eye distances) with and without
smoothing; the correlation over time of the mouth opening (:func:`exprclone.mouth.measure.opening`)
between the driver, from the detector run afresh on every frame, and the output; the
frames without a face; the lambda_k chosen for the video; the neutral frame.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from exprclone import drive
from exprclone.data import sets as datasets
from exprclone.drive import tracking
from exprclone.drive.framing import resize_portrait
from exprclone.io.images import load_image
from exprclone.io.video import probe, read_frames
from exprclone.landmarks.backends import default_detector
from exprclone.landmarks.layout import DLIB68
from exprclone.mouth import measure

MOUTH = DLIB68.mouth_outer + DLIB68.mouth_inner


def openings(points: np.ndarray) -> np.ndarray:
    return np.array([measure.opening(p, DLIB68) for p in points])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    datasets.add_argument(parser)
    parser.add_argument("--portrait", default="003")
    parser.add_argument("--size", type=int, default=256)
    parser.add_argument("--neutral-frame", default=None, help="a frame number, or closed (default: the first frame with a face)")
    args = parser.parse_args()
    data = Path(args.data)
    portrait = resize_portrait(load_image(data / "london/neutral_front" / f"{args.portrait}_03.jpg"), None, args.size)[0]
    detector = default_detector()
    print(
        "clip | jitter smoothed | jitter raw | ratio | opening correlation, driver vs output | frames without a face | lambda_k | neutral"
    )
    print("---|---|---|---|---|---|---|---")
    ratios, correlations = [], []
    for clip in sorted((data / "grid").glob("*.mpg")):
        raw = []
        for frame in read_frames(clip):
            boxes = detector.faces(frame)
            raw.append(detector.fit(frame, boxes[0]) if boxes else None)
        out = {}
        for smooth in (True, False):
            neutral = int(args.neutral_frame) if (args.neutral_frame or "").isdigit() else args.neutral_frame
            recording = drive.prepare(
                portrait, None, lambda clip=clip: read_frames(clip), float(probe(clip).fps), smooth=smooth, neutral_frame=neutral
            )
            out[smooth] = recording, np.array([f.result.landmarks["final"] for f in recording.frames(read_frames(clip))])
        seen = [i for i, p in enumerate(raw) if p is not None]
        driver_opening = openings(np.array([raw[i] for i in seen]))
        result_opening = openings(out[True][1][seen])
        smoothed, rough = tracking.jitter(out[True][1], MOUTH), tracking.jitter(out[False][1], MOUTH)
        ratios.append(smoothed / rough)
        correlations.append(np.corrcoef(driver_opening, result_opening)[0, 1])
        d = out[True][0]
        cells = [clip.stem, f"{smoothed:.4f}", f"{rough:.4f}", f"{ratios[-1]:.2f}", f"{correlations[-1]:.3f}"]
        print(" | ".join(cells + [str(d.track.missing), f"{d.driver.lambda_k:g}", str(d.neutral_index)]))
    print(f"\nmedian jitter ratio {np.median(ratios):.2f}; correlation median {np.median(correlations):.3f}, min {min(correlations):.3f}")


if __name__ == "__main__":
    main()
