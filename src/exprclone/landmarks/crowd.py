"""Every face of a group photo, small or large: BlazeFace over tiles proposes them, dlib's HOG detector confirms each.

A landmarker's own detector looks for one face on a small copy of the photo: dlib's on a
copy at most 512 pixels wide, BlazeFace on a 128-pixel one. In a group photo 3000 pixels
wide a face 120 pixels across is then 20 or 5 pixels, below what either finds (dlib's HOG
window is 80 pixels, 40 upsampled; BlazeFace finds faces from about 16 of its 128 pixels):
only the largest faces are found. Ways to find the others, measured on
made group photos (:mod:`exprclone.evaluation.groups`: six London people at face widths from
120 to 400 pixels in 3000x2000, heads upright or turned up to 40 degrees in the photo's
plane, six photos) and on the 72 London portraits (``benchmarks/faces.py``):

- the landmarkers' own detectors: 15 (dlib's) and 13 (BlazeFace's) of the 36 faces;
- dlib's HOG on the photo scaled so that a 100-pixel face fills its upsampled window (0.4):
  all 36 and nothing else, in 0.30 s a photo (0.09 s a 1350-pixel portrait);
- BlazeFace over tiles (:func:`tiles`, :data:`TILES`): all 36 and nothing else on these
  photos, in 0.13 s (0.03 s a portrait), and heads turned by 60 degrees, which the HOG
  misses, too; but with smaller tiles (512 pixels) it called background and half faces
  faces, and its boxes are not dlib's (whose shape predictor fits from the HOG's boxes).

So BlazeFace proposes, over tiles of :data:`TILES` pixels overlapping by half and over the
whole photo, and the HOG confirms each proposal on a small crop scaled to its face
(:func:`confirm`), giving dlib's box: a proposal the HOG does not confirm is no face (nor is a
head turned further than the HOG sees, about 45 degrees in the photo's plane). All
36 faces, nothing else, in 0.15 s a photo (0.04 s a portrait: what looking for every face adds
to a clone of a portrait, whose one face is then placed as before). Both
detectors are free of the non-commercial terms of dlib's 68-point model (the HOG
detector ships in dlib's code, BlazeFace under Apache-2.0), so the mesh landmarker
(``--landmarker mesh``) fits its points in the same boxes.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import cv2
import numpy as np

from .dlib import hog

if TYPE_CHECKING:
    from .facemesh import MeshDetector

#: a face box ``(left, top, right, bottom)`` in photo pixels.
Box = tuple[float, float, float, float]

#: the tiles' sides, pixels: a tile finds faces from an eighth of its side (16 of BlazeFace's 128 pixels: it finds the
#: London faces from 14) to a half (a larger face is whole in a larger tile): 640 finds 80 to 320 pixels, 2560 to 1280,
#: the whole photo the larger.
TILES = (640, 2560)
#: two proposals overlapping by more than this share of the smaller's area are one face.
SAME_FACE = 0.4
#: a proposal is confirmed on a crop of this many of its box's sides, around its centre...
CONFIRM_CROP = 1.6
#: ...scaled so that its box is this many pixels wide (the HOG's window is 80; a proposal's box may be a third too large).
CONFIRM_SIDE = 120
#: dlib's HOG at most this far from the proposal's centre, in the proposal's box sides, is the face proposed.
CONFIRM_REACH = 0.35
#: faces whose centres lie within this share of their mean height of each other's are in one row (reading order).
ROW = 0.5


def tiles(shape: tuple[int, ...], side: int) -> list[tuple[int, int, int, int]]:
    """Square tiles ``(x0, y0, x1, y1)`` of ``side`` pixels over a photo of ``shape``, each overlapping the next by half
    (the last of a row or column flush with the photo's edge); the whole photo when it is no larger.

    >>> tiles((600, 1000), 512)
    [(0, 0, 512, 512), (256, 0, 768, 512), (488, 0, 1000, 512), (0, 88, 512, 600), (256, 88, 768, 600), (488, 88, 1000, 600)]
    """
    h, w = shape[:2]
    if side >= max(h, w):
        return [(0, 0, w, h)]

    def starts(length: int) -> list[int]:
        if length <= side:
            return [0]
        found = list(range(0, length - side + 1, side // 2))
        return found if found[-1] == length - side else [*found, length - side]

    return [(x, y, min(w, x + side), min(h, y + side)) for y in starts(h) for x in starts(w)]


def proposals(image: np.ndarray, mesh: MeshDetector) -> list[Box]:
    """BlazeFace's faces over :func:`tiles` of every side in :data:`TILES` smaller than the photo, and over the whole
    photo: best first, one box a face (:data:`SAME_FACE`). A face cut by a tile's inner edge, or larger than half a
    tile, is left to another tile."""
    h, w = image.shape[:2]
    boxes, scores = [], []
    for side in [s for s in TILES if s < max(h, w)] + [max(h, w)]:
        for x0, y0, x1, y1 in tiles(image.shape, side):
            found = mesh.detections(np.ascontiguousarray(image[y0:y1, x0:x1]))
            for box, score in zip(found.boxes + [x0, y0, x0, y0], found.scores):
                inside = (box[0] >= x0 or x0 == 0) and (box[1] >= y0 or y0 == 0) and (box[2] < x1 or x1 == w) and (box[3] < y1 or y1 == h)
                if inside and (side == max(h, w) or box[2] - box[0] <= side / 2):
                    boxes.append(box)
                    scores.append(score)
    kept: list[np.ndarray] = []
    for k in np.argsort(-np.array(scores), kind="stable"):
        if all(_overlap(boxes[k], other) <= SAME_FACE for other in kept):
            kept.append(boxes[k])
    return [_box(b) for b in kept]


def _overlap(a: np.ndarray | Sequence[float], b: np.ndarray | Sequence[float]) -> float:
    """The area two boxes share, as a share of the smaller's."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    inter = float(np.prod(np.clip(np.minimum(a[2:], b[2:]) - np.maximum(a[:2], b[:2]), 0, None)))
    return inter / max(min(float(np.prod(a[2:] - a[:2])), float(np.prod(b[2:] - b[:2]))), 1e-9)


def _box(values: np.ndarray | Sequence[float]) -> Box:
    return (float(values[0]), float(values[1]), float(values[2]), float(values[3]))


def confirm(image: np.ndarray, proposal: Box) -> Box | None:
    """dlib's HOG box of the face ``proposal`` outlines (see the module's notes), or None where the HOG finds none.

    The HOG runs on a crop :data:`CONFIRM_CROP` times the proposal's side around its centre,
    scaled so that the proposal is :data:`CONFIRM_SIDE` pixels wide; the box it finds nearest the
    centre, within :data:`CONFIRM_REACH` sides, is mapped back to the photo.
    """
    h, w = image.shape[:2]
    centre = np.array([proposal[0] + proposal[2], proposal[1] + proposal[3]]) / 2
    side = max(proposal[2] - proposal[0], proposal[3] - proposal[1])
    x0, y0 = (max(0, int(c - CONFIRM_CROP * side / 2)) for c in centre)
    x1, y1 = min(w, int(centre[0] + CONFIRM_CROP * side / 2) + 1), min(h, int(centre[1] + CONFIRM_CROP * side / 2) + 1)
    scale = CONFIRM_SIDE / side
    crop = cv2.resize(image[y0:y1, x0:x1], None, fx=scale, fy=scale, interpolation=cv2.INTER_AREA if scale < 1 else cv2.INTER_LINEAR)
    found = [np.array([r.left(), r.top(), r.right(), r.bottom()]) / scale + [x0, y0, x0, y0] for r in hog(crop, 0)]
    reach = [float(np.linalg.norm((b[:2] + b[2:]) / 2 - centre)) for b in found]
    if not found or min(reach) > CONFIRM_REACH * side:
        return None
    return _box(found[int(np.argmin(reach))])


def reading_order(boxes: Sequence[Box]) -> list[int]:
    """The boxes' indices in reading order: rows from the top (a face joins the row whose first face's centre is within
    :data:`ROW` of their mean height of its own), each row from the left.

    >>> reading_order([(300, 10, 400, 110), (0, 40, 100, 140), (150, 300, 250, 400)])
    [1, 0, 2]
    """
    centres = [((b[0] + b[2]) / 2, (b[1] + b[3]) / 2, b[3] - b[1]) for b in boxes]
    rows: list[list[int]] = []
    for k in sorted(range(len(boxes)), key=lambda k: centres[k][1]):
        first = centres[rows[-1][0]] if rows else None
        if first is not None and abs(centres[k][1] - first[1]) <= ROW * (first[2] + centres[k][2]) / 2:
            rows[-1].append(k)
        else:
            rows.append([k])
    return [k for row in rows for k in sorted(row, key=lambda k: centres[k][0])]


def find(image: np.ndarray, mesh: MeshDetector) -> list[Box]:
    """Every face of ``image`` (uint8 RGB): dlib's box of each, in reading order (:func:`reading_order`).

    Parameters
    ----------
    image : ndarray of shape (H, W, 3), uint8
    mesh : MeshDetector
        Whose BlazeFace proposes (from any thread: its model takes one at a time,
        :class:`~exprclone.landmarks.facemesh.Model`).

    Returns
    -------
    list of tuple
        ``(left, top, right, bottom)`` in photo pixels; none where no face is found.
    """
    confirmed: list[Box] = []
    for proposal in proposals(image, mesh):
        box = confirm(image, proposal)
        if box is not None and all(_overlap(box, other) <= SAME_FACE for other in confirmed):
            confirmed.append(box)
    return [confirmed[k] for k in reading_order(confirmed)]
