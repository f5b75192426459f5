"""Blendshape scores: how much of each of 52 named expressions a face shows, by MediaPipe's Face Landmarker.

A judge of any expression, not only of smiles: ``mouthSmileLeft``, ``jawOpen``,
``browInnerUp``, ``eyeBlinkLeft``, ``mouthFrownLeft``, ``mouthPucker``, ... each scored from
0 to 1 (:data:`NAMES`, ARKit's names). Two models of Google's Face Landmarker task bundle ship
inside the package (``exprclone/landmarks/mediapipe_models``, Apache-2.0, see the NOTICE there)
and run on LiteRT, as the face mesh does (:mod:`exprclone.landmarks.facemesh`):

1. BlazeFace finds the face and the crop is made as for the face mesh (:class:`IrisMesh` is
   :class:`~exprclone.landmarks.facemesh.MeshDetector` with the bundle's landmarks model:
   a 256x256 crop, 478 points, the irises' ten last, refined once in the crop of its own
   points as the mesh is).
2. The blendshape model reads :data:`SUBSET`, 146 of the 478 points, in that order, as
   ``(x, y)`` in the photo's pixels: MediaPipe's ``FaceBlendshapesGraph`` takes these indices
   (``kLandmarksSubsetIdxs``) and scales its normalised landmarks by the image's width and
   height (``LandmarksToTensorCalculator``). The model normalises the points itself: moved or
   scaled alike in x and y they score the same, to float precision (tests/landmarks/test_blendshapes.py).
   On MediaPipe's own test case (``face_blendshapes_in_landmarks.prototxt``, an 820x1024
   image) it gives ``face_blendshapes_out.prototxt``'s 52 scores within 2e-6.

MediaPipe's still-image mode fits the mesh once in the detector's crop; here it is fitted
again in the crop of its own points (the package's mesh does so: it fits the London Set's
templates better). On the London photos the two differ by at most 0.16 in a score, most in
``browInnerUp``.

The scores are grouped by the face's region in :data:`REGIONS`, the one place that says
which names are the mouth's, the eyes' and the brows'; the gaze (``eyeLook*``) and
``_neutral`` belong to none, as where the eyes look is not an expression.

Limits: the scores come from the 2-D landmarks alone (the model never sees the pixels), so a
fold, a dimple or teeth that change no landmark change no score; a score is the model's, trained
on Google's data, not a measure of muscles.

References
----------
I. Grishchenko, A. Ablavatski, Y. Kartynnik, K. Raveendran, M. Grundmann, "Attention Mesh:
High-fidelity Face Mesh Prediction in Real-time", CVPR Workshops, 2020.
"""

from __future__ import annotations

import functools

import numpy as np

from .facemesh import MeshDetector, Model, Roi

#: the 52 scores, in the model's order (MediaPipe's ``kBlendshapeNames``).
NAMES = (
    *("_neutral", "browDownLeft", "browDownRight", "browInnerUp", "browOuterUpLeft", "browOuterUpRight"),
    *("cheekPuff", "cheekSquintLeft", "cheekSquintRight", "eyeBlinkLeft", "eyeBlinkRight"),
    *("eyeLookDownLeft", "eyeLookDownRight", "eyeLookInLeft", "eyeLookInRight", "eyeLookOutLeft", "eyeLookOutRight"),
    *("eyeLookUpLeft", "eyeLookUpRight", "eyeSquintLeft", "eyeSquintRight", "eyeWideLeft", "eyeWideRight"),
    *("jawForward", "jawLeft", "jawOpen", "jawRight", "mouthClose", "mouthDimpleLeft", "mouthDimpleRight"),
    *("mouthFrownLeft", "mouthFrownRight", "mouthFunnel", "mouthLeft", "mouthLowerDownLeft", "mouthLowerDownRight"),
    *("mouthPressLeft", "mouthPressRight", "mouthPucker", "mouthRight", "mouthRollLower", "mouthRollUpper"),
    *("mouthShrugLower", "mouthShrugUpper", "mouthSmileLeft", "mouthSmileRight", "mouthStretchLeft", "mouthStretchRight"),
    *("mouthUpperUpLeft", "mouthUpperUpRight", "noseSneerLeft", "noseSneerRight"),
)
#: the 146 of the 478 mesh points the blendshape model reads, in its order (MediaPipe's ``kLandmarksSubsetIdxs``).
SUBSET = (
    *(0, 1, 4, 5, 6, 7, 8, 10, 13, 14, 17, 21, 33, 37, 39, 40, 46, 52, 53, 54, 55, 58, 61, 63, 65, 66, 67, 70, 78, 80),
    *(81, 82, 84, 87, 88, 91, 93, 95, 103, 105, 107, 109, 127, 132, 133, 136, 144, 145, 146, 148, 149, 150, 152, 153),
    *(154, 155, 157, 158, 159, 160, 161, 162, 163, 168, 172, 173, 176, 178, 181, 185, 191, 195, 197, 234, 246, 249),
    *(251, 263, 267, 269, 270, 276, 282, 283, 284, 285, 288, 291, 293, 295, 296, 297, 300, 308, 310, 311, 312, 314),
    *(317, 318, 321, 323, 324, 332, 334, 336, 338, 356, 361, 362, 365, 373, 374, 375, 377, 378, 379, 380, 381, 382),
    *(384, 385, 386, 387, 388, 389, 390, 397, 398, 400, 402, 405, 409, 415, 454, 466, 468, 469, 470, 471, 472, 473),
    *(474, 475, 476, 477),
)
#: the scores of each region of the face: the jaw, lips, cheeks' puff and nose (the mouth's muscles), the lids and
#: the cheeks that narrow the eyes, the brows. Every name but the gaze's and ``_neutral`` is in one.
REGIONS = {
    "mouth": tuple(n for n in NAMES if n.startswith(("jaw", "mouth", "nose")) or n == "cheekPuff"),
    "eyes": tuple(n for n in NAMES if n.startswith(("eyeBlink", "eyeSquint", "eyeWide", "cheekSquint"))),
    "brows": tuple(n for n in NAMES if n.startswith("brow")),
}
#: the names of an expression: every region's.
EXPRESSION = tuple(n for names in REGIONS.values() for n in names)


class IrisMesh(MeshDetector):
    """The Face Landmarker's face mesh: 478 points (the 468 of :class:`MeshDetector`'s, then each iris's centre and
    four points on its rim), from a 256x256 crop; found and refined as :class:`MeshDetector` does."""

    name = "mesh with irises"
    mesh_model, mesh_size = "face_landmarks_detector.tflite", 256
    advice = "use a photo that shows the face whole"


class Blendshapes:
    """The 52 blendshape scores of a face (:data:`NAMES`); the models are loaded on first use.

    One object serves every thread, one at a time in each model (:class:`~exprclone.landmarks.facemesh.Model`);
    :func:`shared` gives the process's own.

    Examples
    --------
    >>> from exprclone import data
    >>> judge = Blendshapes()
    >>> neutral, smile = (judge.scores(data.photo("001", kind)) for kind in ("neutral", "smile"))
    >>> smiling = NAMES.index("mouthSmileLeft")
    >>> bool(smile[smiling] > neutral[smiling] + 0.3)
    True
    """

    def __init__(self) -> None:
        self.mesh = IrisMesh()
        self._model: Model | None = None

    def of_mesh(self, points: np.ndarray) -> np.ndarray:
        """The scores ``(52,)`` of the face whose 478 mesh points ``(478, 2)`` (photo pixels) are given, in :data:`NAMES`' order."""
        if self._model is None:
            self._model = Model("face_blendshapes.tflite")
        return self._model(np.asarray(points, np.float32)[list(SUBSET)])[0].astype(np.float64)

    def scores(self, image: np.ndarray, subject: str = "image") -> np.ndarray:
        """The scores ``(52,)`` of the largest face in ``image`` (uint8 RGB, ``(H, W, 3)``), in :data:`NAMES`' order.

        Raises
        ------
        NoFaceError
            No face is found; its subject is ``subject``.
        """
        return self.of_mesh(self.mesh.detect_mesh(image, subject))

    def scores_at(self, image: np.ndarray, points: np.ndarray, eyes: tuple[int, int]) -> np.ndarray:
        """The scores ``(52,)`` of the face whose landmarks ``points`` ``(N, 2)`` (any layout; ``eyes`` the places of its
        outer eye corners, the subject's right first) are known: the mesh is fitted in the crop they give, as it is
        refined in the crop of its own points (no face to find: about 15 ms a photo)."""
        roi = Roi.around(points, points[eyes[0]], points[eyes[1]])
        return self.of_mesh(self.mesh.refine(image, roi))


def named(scores: np.ndarray) -> dict[str, float]:
    """Scores ``(52,)`` by name.

    >>> named(np.arange(52.0))["jawOpen"]
    25.0
    """
    return dict(zip(NAMES, map(float, scores)))


def indices(names: tuple[str, ...]) -> list[int]:
    """Where each of ``names`` is among :data:`NAMES`.

    >>> indices(("_neutral", "jawOpen"))
    [0, 25]
    """
    return [NAMES.index(n) for n in names]


@functools.cache
def shared() -> Blendshapes:
    """The process's one :class:`Blendshapes` (its models loaded on its first photo)."""
    return Blendshapes()


def scores(image: np.ndarray, subject: str = "image") -> dict[str, float]:
    """The blendshape scores of the largest face in ``image`` (uint8 RGB) by name (:data:`NAMES`), by :func:`shared`'s
    judge; NoFaceError about ``subject`` if there is none."""
    return named(shared().scores(image, subject))
