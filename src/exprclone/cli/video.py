"""``exprclone video``: a portrait driven by a video of the source person (:mod:`exprclone.drive` over a file)."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Iterator
from typing import TYPE_CHECKING

from ..errors import naming
from ..io.progress import Bar
from ..options import Driving, Framing, Options, names
from ..roles import SOURCE_NEUTRAL, TARGET_NEUTRAL
from .inputs import add_options, options_of, with_eigenfaces

if TYPE_CHECKING:
    import numpy as np

    from ..drive import Recording
    from ..io.video import VideoInfo

#: the clone's options a video takes: all but given GI (one set of landmarks for every frame) and faces (a video drives
#: one portrait's face).
CLONE = tuple(n for n in names(Options) if n not in ("global_landmarks", "faces"))


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    v = sub.add_parser("video", help="drive a neutral portrait with a video of the source person")
    v.add_argument(TARGET_NEUTRAL, help="photo of the target person, neutral (the portrait)")
    v.add_argument("driving_video", help="video of the source person (any format FFmpeg reads)")
    v.add_argument("-o", "--output", required=True, help="output video (.mp4, .mov or .mkv)")
    neutral = v.add_mutually_exclusive_group()
    neutral.add_argument("--source-neutral", metavar="IMAGE", help="a neutral photo of the source person instead of a video frame")
    add_options(neutral, Driving, ("neutral_frame",))
    v.add_argument("--target-neutral-landmarks", metavar="FILE", help="landmarks of the portrait (.json or .tem) instead of detecting them")
    add_options(v, Driving, tuple(n for n in names(Driving) if n != "neutral_frame"))
    add_options(v, Framing)
    add_options(v, Options, CLONE)


def prepare(args: argparse.Namespace, inputs: list[str]) -> tuple[VideoInfo, Recording]:
    """The video's probe and the recording prepared from the command's arguments (:func:`exprclone.drive.prepare`)."""
    from .. import drive  # (numpy and the rest: loaded when the command runs, not for --help)
    from ..drive.framing import resize_portrait
    from ..io import video as video_io
    from ..io.images import check_output_path, load_image
    from ..io.landmarks import read_landmarks

    check_output_path(args.output, inputs, extensions=video_io.EXTENSIONS)
    options, driving, framing = options_of(args, Options, CLONE), options_of(args, Driving), options_of(args, Framing)
    target = load_image(args.target_neutral)
    points = None if args.target_neutral_landmarks is None else read_landmarks(args.target_neutral_landmarks, target.shape)
    target, points = resize_portrait(target, points, framing.size)
    source = None if args.source_neutral is None else (load_image(args.source_neutral), None)
    info = video_io.probe(args.driving_video)
    named = {TARGET_NEUTRAL: args.target_neutral, SOURCE_NEUTRAL: args.source_neutral or "", "driving_video": args.driving_video}
    with naming(named):
        recording = drive.prepare(
            target,
            points,
            lambda: video_io.read_frames(args.driving_video),
            float(info.fps),
            source_neutral=source,
            options=with_eigenfaces(args, options),
            driving=driving,
        )
    return info, recording


def run(args: argparse.Namespace) -> None:
    from ..drive.framing import side_by_side  # (numpy and the rest: loaded when the command runs, not for --help)
    from ..io import video as video_io

    inputs = [p for p in (args.target_neutral, args.driving_video, args.source_neutral) if p]
    info, recording = prepare(args, inputs)
    bar = Bar(sys.stderr, len(recording.points), "frames")
    beside = options_of(args, Framing).side_by_side

    def frames() -> Iterator[np.ndarray]:
        for done, f in enumerate(recording.frames(video_io.read_frames(args.driving_video)), 1):
            yield side_by_side(f.driving, f.image) if beside else f.image
            bar.update(done, f"{done / bar.elapsed:.1f} fps")

    written = video_io.write_video(args.output, frames(), info.fps, audio_from=args.driving_video, inputs=inputs)
    method = recording.driver.method.name
    print(f"{args.output}: {written} frames at {float(info.fps):g} fps, {method}{describe(args, recording, written / bar.elapsed)}")


def describe(args: argparse.Namespace, recording: Recording, rate: float) -> str:
    """The end of the last line: how lambda_k was chosen, the neutral face, the frames without a face, the speed."""
    import numpy as np  # (numpy and the rest: loaded when the command runs, not for --help)

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
