"""BlazeFace (MediaPipe's short-range face detector): its anchors and the decoding of its outputs.

The network (``landmarks/mediapipe_models/face_detection_short_range.tflite``, run by :mod:`exprclone.landmarks.facemesh`)
sees a 128x128 image and answers, for each of 896 SSD anchors, a score logit and 16
regressed numbers: the box's centre offset and size, and six keypoints (the subject's
right and left eye, nose tip, mouth centre, right and left ear tragion), all in input
pixels relative to the anchor's centre. The anchors are those of MediaPipe's
``SsdAnchorsCalculator`` for this model: one grid per stride (8 and 16), with 2 and 6
anchors of fixed unit size per cell (its four layers of strides 8, 16, 16, 16 fold into
two grids, as the calculator merges layers of one stride). Overlapping boxes are merged
by MediaPipe's weighted non-maximum suppression: each group of boxes overlapping the
best one is averaged, weighted by score.

Everything here is in the model's normalised input coordinates ([0, 1] across the
128-pixel input); :mod:`exprclone.landmarks.facemesh` maps them to the photo.

References
----------
V. Bazarevsky et al., "BlazeFace: Sub-millisecond Neural Face Detection on Mobile GPUs",
CVPR Workshops, 2019.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

#: the network's input side, in pixels.
INPUT_SIZE = 128
#: (stride, anchors per cell) of each anchor grid.
GRIDS = ((8, 2), (16, 6))
#: a box counts as a face from this score on (MediaPipe's ``min_score_thresh``).
MIN_SCORE = 0.5
#: logits are clipped to +-this before the sigmoid (MediaPipe's ``score_clipping_thresh``).
SCORE_CLIP = 100.0
#: boxes overlapping the best one by more than this intersection over union merge into it.
MIN_SUPPRESSION_IOU = 0.3
#: keypoint indices: the subject's right and left eye (the right eye is on the image's left).
RIGHT_EYE, LEFT_EYE = 0, 1
KEYPOINTS = 6


@dataclass(frozen=True)
class Detections:
    """Faces found, best first.

    Attributes
    ----------
    boxes : ndarray of shape (K, 4)
        ``(left, top, right, bottom)``.
    keypoints : ndarray of shape (K, 6, 2)
        The six keypoints (x, y) of each face (see the module's notes).
    scores : ndarray of shape (K,)
        Face probabilities.
    """

    boxes: np.ndarray
    keypoints: np.ndarray
    scores: np.ndarray

    def __len__(self) -> int:
        return len(self.scores)


@functools.cache
def anchors() -> np.ndarray:
    """The anchors' centres, ``(896, 2)`` in normalised input coordinates, in the network's output order.

    Examples
    --------
    >>> a = anchors()
    >>> a.shape, a[0].tolist(), a[-1].tolist()
    ((896, 2), [0.03125, 0.03125], [0.9375, 0.9375])
    """
    centres = []
    for stride, per_cell in GRIDS:
        cells = INPUT_SIZE // stride
        grid = (np.arange(cells) + 0.5) / cells
        y, x = np.meshgrid(grid, grid, indexing="ij")
        centres.append(np.repeat(np.stack([x.ravel(), y.ravel()], axis=1), per_cell, axis=0))
    return np.concatenate(centres)


def decode(regressors: np.ndarray, logits: np.ndarray, min_score: float = MIN_SCORE) -> Detections:
    """The boxes and keypoints scoring at least ``min_score``, before suppression, best first.

    Parameters
    ----------
    regressors : ndarray of shape (896, 16)
        Per anchor: box centre offset (x, y) and size (w, h), then six keypoint offsets
        (x, y), in input pixels.
    logits : ndarray of shape (896,)
        Per anchor: the face score's logit.
    min_score : float

    Returns
    -------
    Detections
        In normalised input coordinates.
    """
    scores = 1.0 / (1.0 + np.exp(-np.clip(logits.astype(float), -SCORE_CLIP, SCORE_CLIP)))
    keep = np.flatnonzero(scores >= min_score)
    keep = keep[np.argsort(-scores[keep], kind="stable")]
    centre = anchors()[keep]
    raw = regressors[keep] / INPUT_SIZE
    middle, half = centre + raw[:, :2], raw[:, 2:4] / 2
    keypoints = centre[:, None, :] + raw[:, 4 : 4 + 2 * KEYPOINTS].reshape(-1, KEYPOINTS, 2)
    return Detections(np.hstack([middle - half, middle + half]), keypoints, scores[keep])


def iou(box: np.ndarray, boxes: np.ndarray) -> np.ndarray:
    """Intersection over union of ``box`` ``(4,)`` with each of ``boxes`` ``(K, 4)``.

    Examples
    --------
    >>> iou(np.array([0, 0, 2, 2.0]), np.array([[1, 0, 3, 2.0], [5, 5, 6, 6]])).round(3).tolist()
    [0.333, 0.0]
    """
    low, high = np.maximum(box[:2], boxes[:, :2]), np.minimum(box[2:], boxes[:, 2:])
    inter = np.prod(np.clip(high - low, 0, None), axis=1)
    union = _area(box) + _area(boxes) - inter
    return np.where(union > 0, inter / np.where(union > 0, union, 1), 0.0)


def _area(boxes: np.ndarray) -> np.ndarray:
    """The area of each box ``(..., 4)``, 0 for an empty one."""
    return np.prod(np.clip(boxes[..., 2:] - boxes[..., :2], 0, None), axis=-1)


def weighted_nms(found: Detections, threshold: float = MIN_SUPPRESSION_IOU) -> Detections:
    """MediaPipe's weighted non-maximum suppression.

    The best remaining box and every remaining box overlapping it by more than
    ``threshold`` (:func:`iou`) form one face: its box and keypoints are their
    score-weighted mean, its score the best one's.

    Parameters
    ----------
    found : Detections
        Best first (as :func:`decode` gives them).
    threshold : float

    Returns
    -------
    Detections
    """
    boxes, keypoints, scores = [], [], []
    left = np.arange(len(found))
    while left.size:
        group = left[iou(found.boxes[left[0]], found.boxes[left]) > threshold]
        group = np.union1d(group, left[:1])
        weights = found.scores[group] / found.scores[group].sum()
        boxes.append(weights @ found.boxes[group])
        keypoints.append(np.tensordot(weights, found.keypoints[group], axes=1))
        scores.append(found.scores[left[0]])
        left = np.setdiff1d(left, group, assume_unique=True)
        left = left[np.argsort(-found.scores[left], kind="stable")]
    if not scores:
        return Detections(np.zeros((0, 4)), np.zeros((0, KEYPOINTS, 2)), np.zeros(0))
    return Detections(np.array(boxes), np.array(keypoints), np.array(scores))
