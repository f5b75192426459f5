"""What a clone gives: :class:`CloneResult` (the image and every intermediate worth looking at) and, for a target
photo of several faces, a :class:`FaceResult` per face. Pure data, made by :mod:`exprclone.pipeline.render`."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..geometry import db_metric
from ..options import Options


@dataclass(frozen=True)
class CloneResult:
    """A cloned expression and every intermediate worth looking at.

    Attributes
    ----------
    image : ndarray of shape (H, W, 3), uint8
        The target person with the source's expression (the target photo's size).
    method : str
    landmarks : dict of str to ndarray of shape (N, 2)
        ``source_neutral``, ``source_expression``, ``target_neutral`` (the inputs),
        ``global`` (GI), ``local`` (LI), ``elastic`` (for the chosen lambda_k) and
        ``final`` (the geometry of the output, after fold-over relaxation).
    lambda_k : float or None
        The elasticity ratio used (None for methods without the elastic model).
    db_curve : metric.DBCurve or None
        DB value per candidate lambda_k, when lambda_k was chosen automatically.
    eri : ndarray of shape (H, W) or None
        The expression ratio image in the target's frame (1 where nothing changes).
    muscle_mask : ndarray of shape (H, W) or None
        The MD model's detail-importance mask M (e+md only).
    muscle_strengths : ndarray of shape (A,) or None
        ``h`` of each key muscle area (e+md only).
    mouth_mask : ndarray of shape (H, W) or None
        Weight of the source's mouth interior pasted into the opened mouth
        (:mod:`exprclone.mouth.paste`; methods with ERI), None when nothing was pasted.
    unfolded_points : int
        Control points moved to stop triangles folding over.
    options : Options
        How it was made: its options (:class:`~exprclone.options.Options`), ``method`` its own.
    landmarker : str or None
        Which landmarker placed the photos' landmarks (:data:`exprclone.landmarks.backends.LANDMARKERS`),
        None when all were given.
    warnings : tuple of str
        What looked wrong with the inputs (:func:`exprclone.pipeline.role_check.judge_roles`), also issued as ExprCloneWarnings.
    face_results : tuple of FaceResult
        For a target photo of several faces (:mod:`exprclone.pipeline.group`), each face found, in reading order: its
        own clone in its region, or why it was left as it is. ``image`` is then the whole photo; the fields of one
        clone (``landmarks``, ``lambda_k``, the masks...) are each face's, and empty or None here. Empty for a photo
        of one face.

    See Also
    --------
    exprclone.clone, exprclone.clone_methods : which make it.

    Examples
    --------
    >>> import exprclone
    >>> from exprclone import data
    >>> result = exprclone.clone(data.photo("126"), data.photo("126", "smile"), data.photo("003"))
    >>> result.method, result.image.shape, result.image.dtype.name
    ('e+md', (1350, 1350, 3), 'uint8')
    >>> sorted(result.landmarks)
    ['elastic', 'final', 'global', 'local', 'source_expression', 'source_neutral', 'target_neutral']
    >>> result.db_curve.best == result.lambda_k, result.eri.shape, result.muscle_strengths.shape
    (True, (1350, 1350), (12,))
    """

    image: np.ndarray
    method: str
    landmarks: dict[str, np.ndarray]
    lambda_k: float | None = None
    db_curve: db_metric.DBCurve | None = None
    eri: np.ndarray | None = None
    muscle_mask: np.ndarray | None = None
    muscle_strengths: np.ndarray | None = None
    mouth_mask: np.ndarray | None = None
    unfolded_points: int = 0
    options: Options = Options()
    landmarker: str | None = None
    warnings: tuple[str, ...] = ()
    face_results: tuple[FaceResult, ...] = ()


@dataclass(frozen=True)
class FaceResult:
    """One face of a target photo of several (:attr:`CloneResult.face_results`).

    Attributes
    ----------
    number : int
        Its number in reading order, from 1 (as ``exprclone faces`` lists them).
    box : tuple of float
        Its box ``(left, top, right, bottom)`` in the photo.
    region : tuple of int
        ``(x0, y0, x1, y1)``: the part of the photo its clone was made on, the target photo of ``result``.
    result : CloneResult or None
        Its clone, in its region's pixels (add ``(x0, y0)`` to its landmarks for the photo's); None when it was left as
        it is.
    problem : str
        Why it was left as it is (not chosen, too small...); empty when it was cloned.
    """

    number: int
    box: tuple[float, float, float, float]
    region: tuple[int, int, int, int]
    result: CloneResult | None
    problem: str = ""
