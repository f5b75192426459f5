"""Automatic landmarks: dlib's HOG face detector and 68-point shape predictor.

The paper placed its feature points by hand or with an AAM (Sec. II, Fig. 18); we use
dlib's ensemble-of-regression-trees predictor, whose model ships in the
``face-recognition-models`` package. That package is located, never imported: its
``__init__`` needs ``pkg_resources``, which current setuptools no longer has.
"""

from __future__ import annotations

import functools
import importlib.util
import os
import threading
from typing import Any

import cv2
import numpy as np

from ..errors import ExprCloneError, one_face

#: the HOG detector runs on a copy whose longest side is at most this many pixels.
DETECT_SIZE = 512


def model_path(name: str) -> str:
    """Path of a model file shipped in ``face-recognition-models``."""
    spec = importlib.util.find_spec("face_recognition_models")
    if spec is None or spec.origin is None:
        raise ExprCloneError("face-recognition-models", "not installed: pip install face-recognition-models")
    path = os.path.join(os.path.dirname(spec.origin), "models", name)
    if not os.path.isfile(path):
        raise ExprCloneError(path, "model file missing; reinstall face-recognition-models")
    return path


#: one thread at a time in dlib's HOG detector (:func:`hog`).
_HOG_TURN = threading.Lock()


@functools.cache
def _hog_detector() -> Any:
    import dlib  # heavy import, only when a face is really looked for

    return dlib.get_frontal_face_detector()


def hog(image: np.ndarray, upsample: int) -> Any:
    """dlib's HOG face detector (five upright and turned filters) run on ``image`` (uint8, contiguous), upsampled
    ``upsample`` times: its ``dlib.rectangles``.

    One detector serves the process (it takes 0.4 s to load), one thread at a time: the detector keeps the image
    pyramid it scans in itself, and dlib lets other threads run while it scans, so two threads detecting at once with
    one detector scan each other's pyramids (wrong boxes, or a corrupted heap: ``tests/landmarks/test_dlib.py``).
    """
    detector = _hog_detector()
    with _HOG_TURN:
        return detector(image, upsample)


class Detector:
    """Face detector plus 68-point shape predictor, loaded lazily on first use."""

    #: its name among :data:`exprclone.landmarks.backends.LANDMARKERS`.
    name = "dlib"

    def __init__(self) -> None:
        # dlib's module and shape predictor, loaded by _load (dlib has no type information)
        self._dlib: Any = None
        self._predictor: Any = None

    def _load(self) -> None:
        import dlib  # heavy import, only when landmarks are really detected

        self._dlib = dlib
        self._predictor = dlib.shape_predictor(model_path("shape_predictor_68_face_landmarks.dat"))

    def faces(self, image: np.ndarray) -> list[tuple[float, float, float, float]]:
        """Face boxes ``(left, top, right, bottom)`` in full-resolution pixels, largest first.

        Detection runs on a copy downscaled to :data:`DETECT_SIZE`; if it finds nothing
        it tries once more with dlib's 2x upsampling, for small faces.
        """
        scale = min(1.0, DETECT_SIZE / max(image.shape[:2]))
        # dlib reads the buffer as if contiguous: a strided view (a crop, a video frame with
        # padded rows) would be read as garbage, so it gets a contiguous copy
        small = cv2.resize(image, None, fx=scale, fy=scale, interpolation=cv2.INTER_AREA) if scale < 1 else np.ascontiguousarray(image)
        rects = hog(small, 0)
        if len(rects) == 0:
            rects = hog(small, 1)
        boxes = [(r.left() / scale, r.top() / scale, r.right() / scale, r.bottom() / scale) for r in rects]
        return sorted(boxes, key=lambda b: -(b[2] - b[0]) * (b[3] - b[1]))

    def fit(self, image: np.ndarray, box: tuple[float, float, float, float]) -> np.ndarray:
        """Fit the 68 landmarks at full resolution inside a face box; ``(68, 2)`` float64."""
        if self._predictor is None:
            self._load()
        rect = self._dlib.rectangle(*(int(round(v)) for v in box))
        shape = self._predictor(np.ascontiguousarray(image), rect)
        return np.array([(p.x, p.y) for p in shape.parts()], dtype=float)

    def detect(self, image: np.ndarray, subject: str = "image") -> np.ndarray:
        """Landmarks of the largest face in ``image`` (uint8 RGB, ``(H, W, 3)``).

        Parameters
        ----------
        image : ndarray of shape (H, W, 3), uint8
        subject : str
            What the image is, for messages (its role, such as ``target_neutral``).

        Returns
        -------
        ndarray of shape (68, 2)

        Raises
        ------
        NoFaceError
            No face is found.
        """
        boxes = self.faces(image)
        one_face(len(boxes), subject, "use a frontal photo, or give its landmarks")
        return self.fit(image, boxes[0])
