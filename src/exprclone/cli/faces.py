"""``exprclone faces``: the faces of a photo, numbered in reading order with their boxes (what ``--faces`` chooses from),
and a preview with the numbers drawn on it."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from ..landmarks.backends import shared
from ..options import Options
from .inputs import add_options, options_of

if TYPE_CHECKING:
    import numpy as np

    from ..pipeline.group import Found

#: the preview's outline of a face that can be cloned, and of one that cannot (RGB).
COLOURS = ((40, 220, 90), (235, 60, 50))


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    f = sub.add_parser("faces", help="list the faces of a photo, numbered as --faces chooses them, and draw them")
    f.add_argument("photo", help="a photo (JPEG, PNG, ...)")
    f.add_argument("--preview", metavar="OUT.png", help="write the photo with each face outlined and numbered")
    add_options(f, Options, ("landmarker",))


def run(args: argparse.Namespace) -> None:
    from ..io.images import check_output_path, load_image, save_image  # (numpy and the rest: loaded when the command runs, not for --help)
    from ..pipeline import group

    options = options_of(args, Options, ("landmarker",))
    if args.preview:
        check_output_path(args.preview, [args.photo])
    image = load_image(args.photo)
    found = group.find(image, shared(str(options.landmarker)), args.photo, options.landmarks_layout)
    if args.preview:
        save_image(args.preview, preview(image, found), inputs=[args.photo])
    print(f"{args.photo}: {len(found)} face{'s' if len(found) > 1 else ''}")
    for face in found:
        left, top, right, bottom = (round(v) for v in face.box)
        said = f"  (left as it is: {face.problem})" if face.problem else ""
        print(f"{face.number:>3}  box {left},{top} to {right},{bottom}, {right - left} px across{said}")


def preview(image: np.ndarray, faces: tuple[Found, ...]) -> np.ndarray:
    """``image`` with each face's box outlined (:data:`COLOURS`: red for a face that cannot be cloned) and its number
    written above it; a new array."""
    import cv2  # (numpy and the rest: loaded when the command runs, not for --help)

    out = image.copy()
    thick = max(2, round(max(image.shape[:2]) / 600))
    for face in faces:
        left, top, right, bottom = (round(v) for v in face.box)
        colour = COLOURS[bool(face.problem)]
        cv2.rectangle(out, (left, top), (right, bottom), colour, thick, cv2.LINE_AA)
        scale = max(0.6, (right - left) / 120)
        (width, height), _ = cv2.getTextSize(str(face.number), cv2.FONT_HERSHEY_SIMPLEX, scale, thick)
        corner = (left, max(height + thick, top - thick * 2))
        cv2.rectangle(out, (corner[0], corner[1] - height - thick), (corner[0] + width + thick, corner[1] + thick), colour, -1)
        cv2.putText(out, str(face.number), corner, cv2.FONT_HERSHEY_SIMPLEX, scale, (255, 255, 255), thick, cv2.LINE_AA)
    return out
