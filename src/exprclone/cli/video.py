"""``exprclone video``: a portrait driven by a video of the source person (:mod:`exprclone.drive` over a file)."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Iterator
from typing import TYPE_CHECKING

from ..errors import ExprCloneError
from ..roles import SOURCE_NEUTRAL, TARGET_NEUTRAL
from .inputs import add_eigenfaces, add_lambda, add_landmarker, add_mouth, add_transfer, frame_arg, transfer_options

if TYPE_CHECKING:
    import numpy as np

    from ..drive import Recording
    from ..io.video import VideoInfo

#: the smallest ``--size``.
MIN_SIZE = 16


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    from ..methods import METHODS

    v = sub.add_parser("video", help="drive a neutral portrait with a video of the source person")
    v.add_argument(TARGET_NEUTRAL, help="photo of the target person, neutral (the portrait)")
    v.add_argument("driving_video", help="video of the source person (any format FFmpeg reads)")
    v.add_argument("-o", "--output", required=True, help="output video (.mp4, .mov or .mkv)")
    neutral = v.add_mutually_exclusive_group()
    neutral.add_argument("--source-neutral", metavar="IMAGE", help="a neutral photo of the source person (default: a video frame)")
    neutral.add_argument(
        "--neutral-frame",
        type=frame_arg,
        metavar="N|closed",
        help="the video frame (from 0) with the source's neutral face, or closed: the one whose mouth is most closed"
        " (default: the first frame with a face)",
    )
    v.add_argument("--method", choices=METHODS, default="e+md", help="method of the paper's Fig. 11 (default: e+md)")
    add_lambda(v, "elasticity ratio k_A'/k_N; auto: the DB metric's median choice on the 5 most expressive frames (default)")
    v.add_argument("--lambda-per-frame", action="store_true", help="choose lambda_k by the DB metric on every frame (slower)")
    v.add_argument("--side-by-side", action="store_true", help="write the driving video and the result side by side")
    v.add_argument("--head-motion", action="store_true", help="carry the source's head motion over (a similarity of the whole frame)")
    v.add_argument("--size", type=int, metavar="PIXELS", help="scale the portrait so its longest side has this many pixels")
    v.add_argument("--no-smooth", dest="smooth", action="store_false", help="use the raw per-frame landmarks, without temporal smoothing")
    v.add_argument("--target-neutral-landmarks", metavar="FILE", help="landmarks of the portrait (.json or .tem) instead of detecting them")
    add_landmarker(v, "places and tracks the landmarks")
    add_eigenfaces(v)
    add_mouth(v)
    add_transfer(v, given=False)


def prepare(args: argparse.Namespace, inputs: list[str]) -> tuple[VideoInfo, Recording]:
    """The video's probe and the recording prepared from the command's arguments (:func:`exprclone.drive.prepare`)."""
    from .. import drive
    from ..errors import naming
    from ..io import video as video_io
    from ..io.frames import resize_portrait
    from ..io.images import check_output_path, load_image
    from ..io.landmarks import read_landmarks
    from .inputs import load_eigenfaces

    check_output_path(args.output, inputs, extensions=video_io.EXTENSIONS)
    if args.size is not None and args.size < MIN_SIZE:
        raise ExprCloneError("--size", f"expected at least {MIN_SIZE} pixels, got {args.size}")
    target = load_image(args.target_neutral)
    points = None if args.target_neutral_landmarks is None else read_landmarks(args.target_neutral_landmarks, target.shape)
    target, points = resize_portrait(target, points, args.size)
    source = None if args.source_neutral is None else (load_image(args.source_neutral), None)
    info = video_io.probe(args.driving_video)
    names = {TARGET_NEUTRAL: args.target_neutral, SOURCE_NEUTRAL: args.source_neutral or "", "driving_video": args.driving_video}
    with naming(names):
        recording = drive.prepare(
            target,
            points,
            lambda: video_io.read_frames(args.driving_video),
            float(info.fps),
            source_neutral=source,
            neutral_frame=args.neutral_frame,
            method=args.method,
            lambda_k=args.lambda_k,
            lambda_per_frame=args.lambda_per_frame,
            smooth=args.smooth,
            landmarker=args.landmarker,
            eigenfaces=load_eigenfaces(args.eigenfaces, args.landmarker),
            head_motion=args.head_motion,
            mouth=args.mouth,
            options=transfer_options(args),
        )
    return info, recording


def run(args: argparse.Namespace) -> None:
    from ..io import video as video_io
    from ..io.frames import side_by_side
    from ..io.progress import Bar

    inputs = [p for p in (args.target_neutral, args.driving_video, args.source_neutral) if p]
    info, recording = prepare(args, inputs)
    bar = Bar(sys.stderr, len(recording.points), "frames")

    def frames() -> Iterator[np.ndarray]:
        for done, f in enumerate(recording.frames(video_io.read_frames(args.driving_video)), 1):
            yield side_by_side(f.driving, f.image) if args.side_by_side else f.image
            bar.update(done, f"{done / bar.elapsed:.1f} fps")

    written = video_io.write_video(args.output, frames(), info.fps, audio_from=args.driving_video, inputs=inputs)
    print(f"{args.output}: {written} frames at {float(info.fps):g} fps, {args.method}{describe(args, recording, written / bar.elapsed)}")


def describe(args: argparse.Namespace, recording: Recording, rate: float) -> str:
    """The end of the last line: how lambda_k was chosen, the neutral face, the frames without a face, the speed."""
    import numpy as np

    lam = recording.driver.lambda_k
    if lam is None:
        how = ""
    elif lam == "auto":
        how = ", lambda_k chosen per frame"
    else:
        frames = recording.lambda_frames
        how = f", lambda_k={lam:g}" + (f" (the DB metric's median on frames {', '.join(map(str, frames))})" if frames else "")
    neutral = args.source_neutral if recording.neutral_index is None else f"frame {recording.neutral_index}"
    missing = [int(i) for i in np.flatnonzero(~recording.track.found)]
    if missing:
        shown = ", ".join(map(str, missing[:10])) + (", ..." if len(missing) > 10 else "")
        faces = f"no face on {len(missing)} frame(s) ({shown}): they hold the last landmarks found"
    else:
        faces = "a face on every frame"
    return f"{how}; neutral: {neutral}; {faces}; rendered at {rate:.1f} fps"
