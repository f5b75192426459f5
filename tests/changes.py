"""Changes between two photos that are no expression: a lock of hair (the ERI's and fidelity tests; a light that moved,
and the other changes of light, are :mod:`exprclone.testing.lighting`'s)."""

import cv2
import numpy as np


def lock_of_hair(image: np.ndarray, centre, radius: float, colour=(70, 50, 38)) -> np.ndarray:
    """``image`` with a disc of strands of ``colour`` (dark brown by default; a third darker and lighter, 2 pixels across)."""
    disc = np.zeros(image.shape[:2], np.float32)
    cv2.circle(disc, tuple(int(v) for v in centre), int(radius), 1.0, -1)
    disc = cv2.GaussianBlur(disc, (0, 0), 1)[..., None]
    strands = np.random.default_rng(0).uniform(-1, 1, (1, image.shape[1])).astype(np.float32)
    strands = cv2.GaussianBlur(strands, (0, 0), 1)[..., None] / 0.3  # about -1..1 across the strands
    hair = np.array(colour, np.float32) * (1 + np.clip(strands, -1, 1) / 3)
    return np.clip(image * (1 - disc) + hair * disc + 0.5, 0, 255).astype(np.uint8)
