"""The landmarkers that place the 68 points, by name, each loaded once: dlib's (:mod:`exprclone.landmarks.dlib`) or
MediaPipe's face mesh (:mod:`exprclone.landmarks.facemesh`).

Both answer the same three calls (:class:`Landmarker`), so every stage takes either, or
any object that answers them. They are named on every surface (``--landmarker``, the
API's ``landmarker=``, the page's select, the live start message) and recorded with a
clone. The names are plain data, so the command line lists them without loading numpy;
:func:`shared` loads one on first use and keeps it for the process.

- ``dlib`` (the default): the HOG detector and the 68-point shape predictor of
  face-recognition-models, trained on iBUG 300-W, whose terms exclude commercial use.
- ``mesh``: BlazeFace and the 468-point face mesh, Apache-2.0, run by LiteRT; finds faces
  rotated in the plane; loads in milliseconds where dlib's model takes most of a second.

dlib stays the default because the mouth, what the method transfers most, is where the
mesh is weaker (``benchmarks/landmarkers.py`` and ``exprclone evaluate``, 100 London
pairs): the e+md clones of smiles that show teeth show them in 83% of pairs with the mesh
and 92% with dlib; the mesh keeps the inner lips of some closed smiles apart (above the
paste's opening threshold, calibrated on dlib's fits), and in the GRID clips' speech its
inner lips open half as far as dlib's (0.061 against 0.130 outer-eye distances,
95th-5th percentile). Over the whole face it is as close to the manual templates (0.031
against 0.029 on held-out people), and it is the landmarker free of the non-commercial
terms.

>>> LANDMARKERS, DEFAULT
(('dlib', 'mesh'), 'dlib')
>>> check_landmarker("dlib")
'dlib'
"""

from __future__ import annotations

import functools
from typing import TYPE_CHECKING, Protocol

from ..errors import ExprCloneError

if TYPE_CHECKING:
    import numpy as np

#: the landmarkers by name; the first is the default.
LANDMARKERS = ("dlib", "mesh")
DEFAULT = LANDMARKERS[0]


class Landmarker(Protocol):
    """What a landmarker answers (as :class:`exprclone.landmarks.dlib.Detector` and :class:`exprclone.landmarks.facemesh.MeshDetector`)."""

    name: str

    def _load(self) -> object:
        """Load the model now, not on the first detection (a server's worker does, at its start)."""

    def detect(self, image: np.ndarray, subject: str = "image") -> np.ndarray:
        """The ``(68, 2)`` landmarks of the largest face; NoFaceError naming ``subject`` if there is none."""

    def faces(self, image: np.ndarray) -> list[tuple[float, float, float, float]]:
        """Face boxes ``(left, top, right, bottom)``, largest first."""

    def fit(self, image: np.ndarray, box: tuple[float, float, float, float]) -> np.ndarray:
        """The ``(68, 2)`` landmarks of the face in ``box``."""


def check_landmarker(name: str, subject: str = "landmarker") -> str:
    """``name`` if it is one of :data:`LANDMARKERS`, else an ExprCloneError about ``subject``."""
    if name not in LANDMARKERS:
        raise ExprCloneError(subject, f"unknown landmarker {name!r}; choose one of: {', '.join(LANDMARKERS)}")
    return name


def for_thread(name: str) -> Landmarker:
    """A landmarker that one thread may use while others use theirs: the mesh's own (its models run one thread at a
    time, :class:`~exprclone.landmarks.facemesh.Model`, and load in milliseconds), dlib's the shared one (its model
    takes most of a second to load; its shape predictor keeps no state between calls, and its face detector runs one
    thread at a time, :func:`~exprclone.landmarks.dlib.hog`)."""
    if check_landmarker(name) == "mesh":
        from .facemesh import MeshDetector  # (each landmarker's runtime loaded when it is chosen)

        return MeshDetector()
    return shared(name)


def resolve(landmarker: str | Landmarker) -> Landmarker:
    """A landmarker given by name (:func:`shared`) or as itself."""
    if not isinstance(landmarker, str):
        return landmarker
    return shared(landmarker)


def name_of(landmarker: str | Landmarker) -> str:
    """What a clone's record calls its landmarker: its name (a landmarker's ``name`` attribute), else its class's."""
    if isinstance(landmarker, str):
        return check_landmarker(landmarker)
    return str(getattr(landmarker, "name", type(landmarker).__name__))


@functools.cache
def shared(name: str) -> Landmarker:
    """The process's one landmarker of that name (:data:`LANDMARKERS`), loaded lazily on its first detection."""
    if check_landmarker(name) == "mesh":
        from .facemesh import MeshDetector  # (each landmarker's runtime loaded when it is chosen)

        return MeshDetector()
    from .dlib import Detector  # (each landmarker's runtime loaded when it is chosen)

    return Detector()


def default_detector() -> Landmarker:
    """The default landmarker (:data:`DEFAULT`, dlib's), shared, for calls that pass none.

    Returns
    -------
    Landmarker
        Its ``detect(image, subject)`` gives the ``(68, 2)`` landmarks of the largest face,
        or raises :class:`~exprclone.errors.NoFaceError` about ``subject`` when there is none;
        its model is loaded on the first detection.

    See Also
    --------
    shared : a landmarker by name (``"dlib"`` or ``"mesh"``).

    Examples
    --------
    >>> from exprclone import data
    >>> detector = default_detector()
    >>> detector.name, detector.detect(data.photo("003")).shape
    ('dlib', (68, 2))
    """
    return shared(DEFAULT)
