"""``exprclone demo``: a clone, the built-in smile, the comparison sheet and a driven video, from the samples shipped in the package."""

from __future__ import annotations

import argparse
import json
import os
from typing import TYPE_CHECKING

from .. import data
from ..io.record import result_record
from ..roles import ROLES

if TYPE_CHECKING:
    import numpy as np

#: the demo video's portrait size (its longest side, pixels).
VIDEO_SIZE = 256


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    d = sub.add_parser("demo", help="clone, compare and drive a video on the sample photos shipped in the package")
    d.add_argument("-o", "--output", default="exprclone-demo", metavar="DIR", help="folder to write into (default: exprclone-demo)")


def run(args: argparse.Namespace) -> None:
    from ..io.images import atomic_write, save_image  # (numpy and the rest: loaded when the command runs, not for --help)
    from ..pipeline.clone import clone_methods

    os.makedirs(args.output, exist_ok=True)
    people = (data.SOURCE, "neutral"), (data.SOURCE, "smile"), (data.TARGET, "neutral")
    paths = {role: data.path(*person) for role, person in zip(ROLES, people)}
    sn, se, tn = (data.photo(*person) for person in people)
    results = clone_methods(sn, se, tn)
    written = {"clone.png": f"e+md, lambda_k={results['e+md'].lambda_k:g}: person {data.SOURCE}'s smile on person {data.TARGET}"}
    save_image(os.path.join(args.output, "clone.png"), results["e+md"].image)
    record = json.dumps(result_record(results["e+md"], {k: str(v) for k, v in paths.items()}), indent=1).encode()
    atomic_write(os.path.join(args.output, "clone.json"), lambda f: f.write(record))
    written["clone.json"] = "the landmarks of every stage, lambda_k and the DB curve"
    written["smile.png"] = built_in_smile(os.path.join(args.output, "smile.png"), tn)
    from ..evaluation.figures import sheet

    paper = clone_methods(sn, se, tn, retarget=False)
    save_image(os.path.join(args.output, "compare.jpg"), sheet(paper, (sn, se, tn), results))
    written["compare.jpg"] = (
        f"the seven methods of Fig. 11 by the paper's stages (lambda_k={paper['e+md'].lambda_k:g}), the difference images of"
        " Figs. 12-13, the DB curve and its terms, and the default's seven below"
    )
    written["video.mp4"] = drive_video(os.path.join(args.output, "video.mp4"), tn)
    for name, what in written.items():
        print(f"{os.path.join(args.output, name)}: {what}")
    print(f"samples: {data.folder()} (credits and licence: {data.folder() / 'CREDITS.md'})")


def built_in_smile(output: str, portrait: np.ndarray) -> str:
    """The built-in prototype smile on the portrait (:func:`exprclone.expressions.clone`), from that one photo; what was written."""
    from .. import data, expressions  # (numpy and the rest: loaded when the command runs, not for --help)
    from ..io.images import save_image

    result = expressions.clone(portrait, expressions.DEFAULT)
    save_image(output, result.image)
    lam = "" if result.lambda_k is None else f", lambda_k={result.lambda_k:g}"
    return f"e+md{lam}: the built-in expression {expressions.DEFAULT!r} on person {data.TARGET}, from that one photo"


def drive_video(output: str, portrait: np.ndarray) -> str:
    """The sample clip driving the portrait, side by side, with its sound; what was written."""
    from .. import data, drive  # (numpy and the rest: loaded when the command runs, not for --help)
    from ..drive.framing import resize_portrait, side_by_side
    from ..io import video as video_io

    clip = str(data.clip())
    portrait, _ = resize_portrait(portrait, None, VIDEO_SIZE)
    fps = video_io.probe(clip).fps
    recording = drive.prepare(portrait, None, lambda: video_io.read_frames(clip), float(fps), neutral_frame="closed")
    frames = (side_by_side(f.driving, f.image) for f in recording.frames(video_io.read_frames(clip)))
    count = video_io.write_video(output, frames, fps, audio_from=clip)
    return f"{count} frames of the sample GRID clip driving person {data.TARGET}, side by side, with the clip's sound"
