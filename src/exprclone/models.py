"""The models a clone needs, each loaded once, lazily, and shared by every call that passes none of its own."""

from __future__ import annotations

import functools

from .eigenface import Eigenfaces
from .landmarkers import DEFAULT, Landmarker, check_landmarker


@functools.cache
def landmarker(name: str) -> Landmarker:
    """The process's one landmarker of that name (:data:`exprclone.landmarkers.LANDMARKERS`), loaded lazily on its first detection."""
    if check_landmarker(name) == "mesh":
        from .facemesh import MeshDetector

        return MeshDetector()
    from .landmarks import Detector

    return Detector()


def default_detector() -> Landmarker:
    """The default landmarker (:data:`exprclone.landmarkers.DEFAULT`, dlib's), shared, for calls that pass none.

    Returns
    -------
    Landmarker
        Its ``detect(image, subject)`` gives the ``(68, 2)`` landmarks of the largest face,
        or raises :class:`~exprclone.errors.NoFaceError` about ``subject`` when there is none;
        its model is loaded on the first detection.

    See Also
    --------
    landmarker : a landmarker by name (``"dlib"`` or ``"mesh"``).

    Examples
    --------
    >>> from exprclone import data
    >>> detector = default_detector()
    >>> detector.name, detector.detect(data.photo("003")).shape
    ('dlib', (68, 2))
    """
    return landmarker(DEFAULT)


@functools.cache
def default_eigenfaces() -> Eigenfaces:
    """The eigenface basis shipped with the package, loaded once."""
    return Eigenfaces.default()
