"""Changes between two photos that are no expression: a lock of hair, a light that moved (the ERI's and fidelity tests)."""

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


def lit_from_the_side(image: np.ndarray, landmarks: np.ndarray) -> np.ndarray:
    """``image`` 30% brighter from one ear (landmark 0) to the other (16), as if the light had moved."""
    x = np.arange(image.shape[1], dtype=np.float32)
    gain = 0.85 + 0.3 * np.clip((x - landmarks[0, 0]) / (landmarks[16, 0] - landmarks[0, 0]), 0, 1)
    return np.clip(image * gain[None, :, None] + 0.5, 0, 255).astype(np.uint8)
