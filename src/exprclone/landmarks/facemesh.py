"""Automatic landmarks under a permissive licence: MediaPipe's BlazeFace and face mesh, run by LiteRT.

A second landmarker beside dlib's (:mod:`exprclone.landmarks.dlib`), with the same interface
(:meth:`MeshDetector.detect`, :meth:`~MeshDetector.faces`, :meth:`~MeshDetector.fit`),
so that every stage takes either. Its two models ship inside the package
(``exprclone/landmarks/mediapipe_models``, Apache-2.0, see the NOTICE there) and run on Google's LiteRT
runtime (``ai-edge-litert``), never on MediaPipe itself:

1. BlazeFace finds faces on a 128x128 letterboxed copy of the photo (:mod:`exprclone.landmarks.blazeface`).
2. The face crop: the detector's box, grown by :data:`ROI_SCALE` into a square and
   rotated upright by the line through the two eye keypoints, is sampled at 192x192,
   the mesh model's input; the 468 mesh points it answers are mapped back to the photo.
3. Refinement: a second crop from the first mesh (its box in the upright frame of its
   own outer eye corners, grown by :data:`ROI_SCALE`), as MediaPipe tracks a face from
   frame to frame. It fits the mesh tighter on the London Set's 1350-pixel photos
   (``tools/derive_mesh_map.py``, each table refitted: held-out error 0.0317 outer-eye
   distances without it, 0.0307 with one pass, the jaw 0.0591 -> 0.0554; a second pass
   adds nothing, 0.0307), and turns an upright box given to :meth:`MeshDetector.fit`
   (the tracker's) with a tilted face.
4. The 468 points become the 68 of :data:`exprclone.landmarks.layout.DLIB68` by the fixed
   barycentric table :data:`exprclone.landmarks.mesh_layout.MESH_TO_68`.

BlazeFace is trained on faces rotated in the plane, so a tilted head is found, and the
crop turns it upright for the mesh model.

References
----------
Y. Kartynnik et al., "Real-time Facial Surface Geometry from Monocular Video on Mobile
GPUs", CVPR Workshops, 2019.
"""

from __future__ import annotations

import contextlib
import os
import threading
from collections.abc import Iterator
from dataclasses import dataclass
from importlib import resources

import cv2
import numpy as np

from ..errors import ExprCloneError, one_face
from . import blazeface
from .mesh_layout import MESH_EYE_CORNERS, to_68

#: the face crop's side, in detector box (or mesh box) sides.
ROI_SCALE = 1.5
#: the mesh model's input side, in pixels.
MESH_SIZE = 192
#: second crops made from the mesh before it is kept (refinement, in the module's notes).
REFINE_PASSES = 1
#: how to install the runtime, for the error that says it is missing.
INSTALL = "pip install ai-edge-litert"


@contextlib.contextmanager
def _quiet_stderr() -> Iterator[None]:
    """Swallow what native code writes to stderr meanwhile (LiteRT's "Created TensorFlow Lite XNNPACK delegate" line)."""
    read, write = os.pipe()
    saved = os.dup(2)
    os.dup2(write, 2)
    try:
        yield
    finally:
        os.dup2(saved, 2)
        for fd in (saved, write):
            os.close(fd)
        os.set_blocking(read, False)
        with contextlib.suppress(BlockingIOError):
            os.read(read, 1 << 16)
        os.close(read)


class Model:
    """One LiteRT model of ``exprclone/landmarks/mediapipe_models``: one float32 input in (an NHWC image, or points), its
    outputs out; run by one thread at a time (a LiteRT interpreter is not for two at once: another thread's call
    raised "There is at least 1 reference to internal data"), so that the process's shared landmarkers and judges
    (:func:`exprclone.landmarks.backends.shared`) serve every thread."""

    def __init__(self, name: str) -> None:
        try:
            from ai_edge_litert.interpreter import Interpreter  # (LiteRT: loaded with its model, when chosen)
        except ImportError:
            raise ExprCloneError("landmarker mesh", f"needs the LiteRT runtime: {INSTALL}") from None
        path = resources.files(__package__) / "mediapipe_models" / name
        if not path.is_file():
            raise ExprCloneError(str(path), "model file missing; reinstall exprclone")
        #: the file it was read from, inside the package.
        self.path = str(path)
        self._interpreter = Interpreter(model_path=self.path, num_threads=1)
        with _quiet_stderr():
            self._interpreter.allocate_tensors()
        self._input = self._interpreter.get_input_details()[0]["index"]
        self._outputs = [d["index"] for d in self._interpreter.get_output_details()]
        self._turn = threading.Lock()

    def __call__(self, x: np.ndarray) -> list[np.ndarray]:
        """The model's outputs for one float32 input (an ``(S, S, 3)`` image, ``(N, 2)`` points), the batch axis removed
        where an output has one (the blendshape model's scores have none)."""
        with self._turn:
            self._interpreter.set_tensor(self._input, x[None])
            self._interpreter.invoke()
            outputs = [self._interpreter.get_tensor(i) for i in self._outputs]  # (copies)
        return [t[0] if t.ndim > 1 else t for t in outputs]


@dataclass(frozen=True)
class Roi:
    """A square face crop: its centre ``(x, y)`` and side in photo pixels, and its rotation (radians, the crop's x axis in the photo)."""

    centre: np.ndarray
    side: float
    angle: float

    def matrix(self, size: int) -> np.ndarray:
        """The ``(2, 3)`` affine map from the ``size``-pixel crop's pixels to the photo's (pixel centres at whole numbers).

        The mesh model's points are read in the same terms: shifted by half a crop pixel
        either way, the 68 points fit the London Set's templates worse (0.0299 and 0.0303
        outer-eye distances on the training people, against 0.0291)."""
        c, s = np.cos(self.angle), np.sin(self.angle)
        scale = self.side / size
        axes = scale * np.array([[c, -s], [s, c]])
        return np.hstack([axes, (self.centre - axes @ np.full(2, size / 2))[:, None]])

    @classmethod
    def around(cls, points: np.ndarray, right: np.ndarray, left: np.ndarray) -> Roi:
        """The crop upright by the line from ``right`` to ``left`` (the subject's eyes) around ``points`` ``(N, 2)``:
        centred on their box in that upright frame, :data:`ROI_SCALE` times its longer side (MediaPipe's landmarks-to-ROI)."""
        angle = float(np.arctan2(*(left - right)[::-1]))
        rotation = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
        upright = points @ rotation  # each point in the rotated axes
        low, high = upright.min(0), upright.max(0)
        return cls(rotation @ ((low + high) / 2), float(ROI_SCALE * max(high - low)), angle)

    @classmethod
    def of_box(cls, box: np.ndarray, right: np.ndarray | None = None, left: np.ndarray | None = None) -> Roi:
        """The crop on a face box ``(left, top, right, bottom)``: its centre, :data:`ROI_SCALE` times its longer side,
        turned by the line between the eye keypoints if given (MediaPipe's detection-to-ROI), else upright."""
        corners = np.asarray(box, float).reshape(2, 2)
        angle = 0.0 if right is None else float(np.arctan2(*(left - right)[::-1]))
        return cls(corners.mean(0), float(ROI_SCALE * max(corners[1] - corners[0])), angle)


def letterbox(image: np.ndarray, size: int) -> tuple[np.ndarray, float, np.ndarray]:
    """The photo shrunk (or grown) to fit a ``size`` square, centred on a black one, as MediaPipe feeds BlazeFace.

    The photo is first shrunk by a whole factor with a box filter (OpenCV's fast
    INTER_AREA), then bilinearly to fit.

    Returns
    -------
    square : ndarray of shape (size, size, 3), uint8
    scale : float
    shift : ndarray of shape (2,)
        A photo point ``p`` (pixel centres at whole numbers) is at ``(p + 0.5) * scale + shift``
        in the square's continuous coordinates (its edges at 0 and ``size``).
    """
    h, w = image.shape[:2]
    k = max(1, max(h, w) // size)
    if k > 1:
        image = cv2.resize(image[: h - h % k, : w - w % k], None, fx=1 / k, fy=1 / k, interpolation=cv2.INTER_AREA)
    scale = size / (k * max(image.shape[:2]))
    # the shrunk copy fills the square's side (the rows and columns cut to make k divide it are not in it)
    fitted = (max(1, round(image.shape[1] * k * scale)), max(1, round(image.shape[0] * k * scale)))
    small = cv2.resize(image, fitted, interpolation=cv2.INTER_LINEAR)
    x0, y0 = (size - fitted[0]) // 2, (size - fitted[1]) // 2
    square = np.zeros((size, size, 3), np.uint8)
    square[y0 : y0 + fitted[1], x0 : x0 + fitted[0]] = small
    return square, scale, np.array([x0, y0], float)


def to_unit_range(crop: np.ndarray, low: float) -> np.ndarray:
    """A uint8 RGB crop as float32 in ``[low, 1]`` (BlazeFace takes [-1, 1], the mesh model [0, 1])."""
    return (crop.astype(np.float32) * ((1 - low) / 255) + low).astype(np.float32)


class MeshDetector:
    """BlazeFace plus the 468-point face mesh, given as dlib's 68 points; loaded lazily on first use.

    Examples
    --------
    >>> from exprclone import data
    >>> points = MeshDetector().detect(data.photo("003"), "003")
    >>> points.shape
    (68, 2)
    """

    #: its name among :data:`exprclone.landmarks.backends.LANDMARKERS`.
    name = "mesh"
    #: the mesh model's file in ``mediapipe_models`` and its input side, in pixels.
    mesh_model, mesh_size = "face_landmark.tflite", MESH_SIZE
    #: what the error of a photo without a face advises.
    advice = "use a photo that shows the face whole, or give its landmarks"

    def __init__(self) -> None:
        self._models: tuple[Model, Model] | None = None

    def _load(self) -> tuple[Model, Model]:
        """BlazeFace and the mesh model, loaded on the first call."""
        if self._models is None:
            self._models = (Model("face_detection_short_range.tflite"), Model(self.mesh_model))
        return self._models

    def detections(self, image: np.ndarray) -> blazeface.Detections:
        """BlazeFace's faces in ``image`` (uint8 RGB), in photo pixels, best first (:func:`blazeface.weighted_nms`)."""
        letterboxed, scale, shift = letterbox(image, blazeface.INPUT_SIZE)
        regressors, logits = self._load()[0](to_unit_range(letterboxed, -1.0))
        found = blazeface.weighted_nms(blazeface.decode(regressors, logits[:, 0]))

        def to_photo(q: np.ndarray) -> np.ndarray:
            return (q * blazeface.INPUT_SIZE - shift) / scale - 0.5

        boxes = to_photo(found.boxes.reshape(-1, 2, 2)).reshape(-1, 4)
        return blazeface.Detections(boxes, to_photo(found.keypoints), found.scores)

    def faces(self, image: np.ndarray) -> list[tuple[float, float, float, float]]:
        """Face boxes ``(left, top, right, bottom)`` in photo pixels, largest first (as :meth:`exprclone.landmarks.dlib.Detector.faces`)."""
        boxes = [(float(b[0]), float(b[1]), float(b[2]), float(b[3])) for b in self.detections(image).boxes]
        return sorted(boxes, key=lambda b: -(b[2] - b[0]) * (b[3] - b[1]))

    def mesh(self, image: np.ndarray, roi: Roi) -> tuple[np.ndarray, float]:
        """The mesh points ``(P, 2)`` in photo pixels fitted in one crop (468; 478 with the irises of
        :class:`exprclone.landmarks.blendshapes.IrisMesh`), and the model's face probability there."""
        to_photo = roi.matrix(self.mesh_size)
        flags = cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP
        crop = cv2.warpAffine(image, to_photo, (self.mesh_size, self.mesh_size), flags=flags, borderMode=cv2.BORDER_REPLICATE)
        points, presence = self._load()[1](to_unit_range(crop, 0.0))[:2]
        xy = points.reshape(-1, 3)[:, :2]
        probability = 1.0 / (1.0 + np.exp(-float(presence.ravel()[0])))
        return xy @ to_photo[:, :2].T + to_photo[:, 2], probability

    def refine(self, image: np.ndarray, roi: Roi) -> np.ndarray:
        """The mesh fitted in ``roi``, then again in the crop its own points give, :data:`REFINE_PASSES` times; ``(P, 2)``."""
        points, _ = self.mesh(image, roi)
        for _ in range(REFINE_PASSES):
            points, _ = self.mesh(image, Roi.around(points, *points[list(MESH_EYE_CORNERS)]))
        return points

    def fit_mesh(self, image: np.ndarray, box: tuple[float, float, float, float]) -> np.ndarray:
        """The mesh points of the face in ``box`` (upright: the refinement turns the crop with the face); ``(P, 2)``."""
        return self.refine(image, Roi.of_box(np.asarray(box, float)))

    def fit(self, image: np.ndarray, box: tuple[float, float, float, float]) -> np.ndarray:
        """The 68 landmarks (:data:`exprclone.landmarks.mesh_layout.MESH_TO_68`) of the face in ``box``; ``(68, 2)`` float64."""
        return to_68(self.fit_mesh(image, box))

    def detect_mesh(self, image: np.ndarray, subject: str = "image") -> np.ndarray:
        """The mesh points of the largest face in ``image``, ``(P, 2)``; as :meth:`detect`, whose errors and warnings it gives."""
        found = self.detections(image)
        one_face(len(found), subject, self.advice, stacklevel=3)
        largest = int(np.argmax(np.prod(found.boxes[:, 2:] - found.boxes[:, :2], axis=1)))
        eyes = found.keypoints[largest, [blazeface.RIGHT_EYE, blazeface.LEFT_EYE]]
        return self.refine(image, Roi.of_box(found.boxes[largest], *eyes))

    def detect(self, image: np.ndarray, subject: str = "image") -> np.ndarray:
        """Landmarks of the largest face in ``image`` (uint8 RGB, ``(H, W, 3)``), as :meth:`exprclone.landmarks.dlib.Detector.detect`.

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
        return to_68(self.detect_mesh(image, subject))
