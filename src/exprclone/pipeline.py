"""The E+MD pipeline (paper Fig. 5) and the other six methods of Fig. 11: the entry points.

Stages: landmarks -> shape stages (global warping GI, local warping LI, the elastic
model with lambda_k by the DB metric; :data:`exprclone.stages.SHAPE_STAGES`) ->
geometric warp FI -> details (ERI, MD model, mouth interior) -> F_IMG. :func:`clone`
and :func:`clone_methods` check the three photos, find their landmarks, and hand them
to a :class:`~exprclone.cloner.Cloner`, which prepares the two neutral faces and runs
the stages. What each method runs is read from its row of
:data:`exprclone.methods.TABLE`; how its stages run, from the
:class:`~exprclone.options.Options`: which global warp gives GI (the paper's, Seol and
Lewis's RBF transfer, or landmarks given by any other method, which the elastic model
refines as in the paper's Figs. 19-21), which image warp gives FI, how much of the
expression is transferred (:mod:`exprclone.transfer`), and whether the source's motion
is first made the target's (:mod:`exprclone.retarget`, not in the paper;
``retarget=False`` runs the paper's global and local stages).
"""

from __future__ import annotations

import dataclasses
import warnings
from typing import Any

import numpy as np

from . import role_check
from .checks import check_face, check_image, check_lambda, check_points, options_from
from .cloner import Cloner, CloneResult
from .eigenface import Eigenfaces
from .errors import ExprCloneWarning
from .landmarkers import DEFAULT, Landmarker, name_of, resolve
from .layout import DLIB68, Layout
from .methods import METHODS, lookup
from .options import Options
from .roles import ROLES

__all__ = ["CloneResult", "Cloner", "clone", "clone_methods"]


def clone(
    source_neutral: np.ndarray,
    source_expression: np.ndarray,
    target_neutral: np.ndarray,
    method: str = "e+md",
    lambda_k: float | str = "auto",
    landmarks: tuple[np.ndarray | None, np.ndarray | None, np.ndarray | None] | None = None,
    *,
    landmarker: str | Landmarker = DEFAULT,
    eigenfaces: Eigenfaces | None = None,
    layout: Layout = DLIB68,
    mouth: bool = True,
    options: Options | None = None,
    **keywords: Any,
) -> CloneResult:
    """Put the source's expression on the target's face.

    Parameters
    ----------
    source_neutral, source_expression, target_neutral : ndarray of shape (H, W, 3), uint8 RGB
        The three photos; they may differ in size.
    method : str
        One of :data:`METHODS`.
    lambda_k : float or "auto"
        Elasticity ratio ``k_A' / k_N`` (Eq. 6); "auto" picks it by the DB metric (Eq. 8).
    landmarks : tuple of three (N, 2) arrays or None, optional
        Known landmarks for each photo; None entries are detected.
    landmarker, eigenfaces, layout, mouth, options, **keywords
        See :func:`clone_methods`.

    Returns
    -------
    CloneResult
        The image at the target photo's size, and every intermediate stage.

    Raises
    ------
    ExprCloneError
        A bad input, its ``subject`` the photo's role (:data:`ROLES`), ``method``, ``lambda`` or the option's name;
        a photo with no face raises its subclass ``NoFaceError``.

    See Also
    --------
    clone_methods : several methods at once.
    Cloner : one pair of neutral faces prepared for many expressions.

    Examples
    --------
    >>> import exprclone
    >>> from exprclone import data
    >>> result = exprclone.clone(data.photo("126"), data.photo("126", "smile"), data.photo("003"), method="e+md")
    >>> result.image.shape, result.landmarks["final"].shape
    ((1350, 1350, 3), (68, 2))

    The options change how the stages run, given as keywords or as ``options=Options(...)`` (not both);
    bad input says which input is wrong:

    >>> exprclone.clone(data.photo("126"), data.photo("126", "smile"), data.photo("003"), strength=0.5).options.strength
    0.5
    >>> from exprclone.options import Options
    >>> exprclone.clone(data.photo("126"), data.photo("126", "smile"), data.photo("003"), options=Options(only=("mouth",))).options.only
    ('mouth',)
    >>> import numpy as np
    >>> exprclone.clone(data.photo("126"), data.photo("126", "smile"), np.full((400, 400, 3), 128, np.uint8))
    Traceback (most recent call last):
    ...
    exprclone.errors.NoFaceError: target_neutral: no face found (use a frontal photo, or give its landmarks)
    """
    results = clone_methods(
        source_neutral,
        source_expression,
        target_neutral,
        (method,),
        lambda_k,
        landmarks,
        landmarker=landmarker,
        eigenfaces=eigenfaces,
        layout=layout,
        mouth=mouth,
        options=options,
        **keywords,
    )
    return results[method]


def clone_methods(
    source_neutral: np.ndarray,
    source_expression: np.ndarray,
    target_neutral: np.ndarray,
    methods: tuple[str, ...] = METHODS,
    lambda_k: float | str = "auto",
    landmarks: tuple[np.ndarray | None, np.ndarray | None, np.ndarray | None] | None = None,
    *,
    landmarker: str | Landmarker = DEFAULT,
    eigenfaces: Eigenfaces | None = None,
    layout: Layout = DLIB68,
    mouth: bool = True,
    options: Options | None = None,
    **keywords: Any,
) -> dict[str, CloneResult]:
    """Several methods at once, sharing the stages they have in common (Fig. 5).

    Parameters
    ----------
    source_neutral, source_expression, target_neutral, lambda_k, landmarks
        As for :func:`clone`.
    methods : tuple of str
        Any of :data:`METHODS`.
    landmarker : str or Landmarker
        What places the landmarks of photos without given ones: a name of
        :data:`exprclone.landmarkers.LANDMARKERS` (``"dlib"``, the default, or ``"mesh"``),
        or any object with their methods (:class:`exprclone.landmarkers.Landmarker`).
    eigenfaces : Eigenfaces, optional
        Basis of the DB metric; the packaged one by default.
    layout : Layout
    mouth : bool
        Fill an opened mouth with the source's mouth interior (teeth) in the methods
        with ERI (:mod:`exprclone.mouth_fill`); False leaves the stretched lips.
    options : Options, optional
        How the clone is made beyond its method (:class:`~exprclone.options.Options`);
        the defaults if None.
    **keywords
        The same options as keywords, instead of ``options`` (``strength=0.5``):

        - ``global_warp``: ``"similarity"`` (the paper's GI, the default) or ``"rbf"``
          (Seol and Lewis's RBF transfer, the paper's Figs. 19-20);
        - ``global_landmarks``: ``(N, 2)`` landmarks of the target's expression made by
          any other method, taken as GI (the paper's Fig. 21);
        - ``image_warp``: ``"mesh"`` (piecewise-affine, the default) or ``"tps"``
          (thin-plate spline);
        - ``strength``: from 0 (the target as it is) to 2, 1 by default;
        - ``only``: region names (``"mouth"``, ``"eyes"``, ``"brows"``) whose motion
          alone is transferred, None (the default) for the whole face;
        - ``retarget``: True (the default) makes the source's motion the target's before
          the global and local stages (:mod:`exprclone.retarget`); False runs the paper's.

    Returns
    -------
    dict of str to CloneResult
        One result per method, in the order asked.

    Raises
    ------
    ExprCloneError
        As for :func:`clone`; an unknown method names ``method``.

    Examples
    --------
    >>> import exprclone
    >>> from exprclone import data
    >>> results = exprclone.clone_methods(data.photo("126"), data.photo("126", "smile"), data.photo("003"), ("global", "e+md"))
    >>> list(results), results["global"].lambda_k is None
    (['global', 'e+md'], True)
    """
    lookup(methods)
    check_lambda(lambda_k)
    asked = options_from(options, keywords)
    images = [check_image(im, role) for im, role in zip((source_neutral, source_expression, target_neutral), ROLES)]
    given = landmarks if landmarks is not None else (None, None, None)
    name, detector = name_of(landmarker), resolve(landmarker)
    s_neu, s_exp, t_neu = (
        detector.detect(im, role) if p is None else check_face(check_points(p, im.shape, layout.n_points, role), layout, role)
        for im, p, role in zip(images, given, ROLES)
    )
    cloner = Cloner(images[0], s_neu, images[2], t_neu, eigenfaces=eigenfaces, layout=layout, options=asked)
    neutral, expression = role_check.Photo.of(images[0], s_neu, layout), role_check.Photo.of(images[1], s_exp, layout)
    said = tuple(role_check.judge_roles(neutral, expression, layout))
    for message in said:
        warnings.warn(message, ExprCloneWarning, stacklevel=2)
    results = cloner.clone_methods(images[1], s_exp, methods, lambda_k, mouth=mouth, crop=expression.crop)
    placed = name if any(p is None for p in given) else None
    return {m: dataclasses.replace(r, landmarker=placed, warnings=said) for m, r in results.items()}
