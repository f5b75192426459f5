"""How a driven video is framed (:class:`exprclone.options.Framing`): the portrait at the output's size, and the driving
frame beside the result."""

from __future__ import annotations

import cv2
import numpy as np


def resize_portrait(image: np.ndarray, points: np.ndarray | None, size: int | None) -> tuple[np.ndarray, np.ndarray | None]:
    """The portrait (and its landmarks) scaled so that its longest side is ``size`` pixels."""
    if size is None or size == max(image.shape[:2]):
        return image, points
    scale = size / max(image.shape[:2])
    shape = (max(1, round(image.shape[1] * scale)), max(1, round(image.shape[0] * scale)))
    resized = cv2.resize(image, shape, interpolation=cv2.INTER_AREA if scale < 1 else cv2.INTER_CUBIC)
    return resized, None if points is None else points * (np.array(shape) / image.shape[1::-1])


def side_by_side(driving: np.ndarray, result: np.ndarray) -> np.ndarray:
    """``driving | result``, the driving frame scaled to the result's height."""
    height = result.shape[0]
    width = max(1, round(driving.shape[1] * height / driving.shape[0]))
    return np.hstack([cv2.resize(driving, (width, height), interpolation=cv2.INTER_LINEAR), result])
