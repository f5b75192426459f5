"""The E+MD pipeline (paper Fig. 5) and the other six methods of Fig. 11: the entry points of Python.

Stages: landmarks -> shape stages (global warping GI, local warping LI, the elastic
model with lambda_k by the DB metric; :data:`exprclone.pipeline.stages.SHAPE_STAGES`) ->
geometric warp FI -> details (ERI, MD model, mouth interior) -> F_IMG. :func:`prepare`
builds the :class:`~exprclone.pipeline.request.Request` of three arrays and hands it to the
door (:mod:`exprclone.pipeline.request`), which checks it, places the landmarks, checks the
photos' roles, prepares the two neutral faces and the source expression on them; the
prepared clone's :meth:`~exprclone.pipeline.cloner.Prepared.render` makes the images, as often
as asked. :func:`clone` and :func:`clone_methods` are the two in one call. What each method
runs is read from its row of :data:`exprclone.methods.TABLE`; how its stages run, from the
:class:`~exprclone.options.Options`: which global warp gives GI (the paper's, Seol and
Lewis's RBF transfer, or landmarks given by any other method, which the elastic model
refines as in the paper's Figs. 19-21), which image warp gives FI, how much of the
expression is transferred (:mod:`exprclone.geometry.weights`), and whether the source's motion
is first made the target's (:mod:`exprclone.geometry.retarget`, not in the paper;
``retarget=False`` runs the paper's global and local stages).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from ..methods import METHODS
from ..options import Options
from . import group
from . import request as door
from .cloner import Cloner, Prepared
from .request import Landmarks, Request
from .result import CloneResult, FaceResult

__all__ = ["CloneResult", "Cloner", "FaceResult", "Prepared", "clone", "clone_methods", "prepare"]


def prepare(
    source_neutral: np.ndarray,
    source_expression: np.ndarray,
    target_neutral: np.ndarray,
    methods: tuple[str, ...] | None = None,
    *,
    landmarks: Landmarks | None = None,
    options: Options | None = None,
    target_faces: Sequence[group.Found] | None = None,
    check_roles: bool | None = None,
    **keywords: Any,
) -> Prepared | group.Group:
    """The three photos checked, their landmarks found, and the source's expression prepared on the two neutral faces:
    everything a clone costs but its render, which is then as cheap as the options' :data:`~exprclone.options.RENDER`.

    A target photo of several faces is prepared face by face, each chosen face (the options' ``faces``) on its own
    region of the photo (:mod:`exprclone.pipeline.group`).

    Parameters
    ----------
    source_neutral, source_expression, target_neutral : ndarray of shape (H, W, 3), uint8 RGB
        The three photos; they may differ in size.
    methods : tuple of str, optional
        The methods to prepare (any of :data:`METHODS`, sharing the stages they have in common); the options' ``method``
        alone by default.
    landmarks : tuple of three (N, 2) arrays or None, optional
        Known landmarks for each photo; None entries are placed by the options' ``landmarker``. Given target
        landmarks are one face's: the photo is cloned whole, for that face.
    options : Options, optional
        How the clone is made (:class:`~exprclone.options.Options`); the defaults if None.
    target_faces : sequence of Found, optional
        The faces of the target photo when they have been found (:func:`exprclone.pipeline.group.find`), instead of
        finding them again; not with given target landmarks.
    check_roles : bool, optional
        Whether the photos' roles are checked (:mod:`exprclone.pipeline.role_check`: the source's two photos one
        person's, its neutral one the less expressive), a warning saying what looks wrong; by default they are, unless
        every photo's landmarks are given (the caller vouches for them).
    **keywords
        Options as keywords (``strength=0.5``), changing ``options``.

    Returns
    -------
    Prepared or Group
        Its ``render`` gives one :class:`CloneResult` per method, with the options or other values of their cheap part
        (the strengths, ``only``, ``mouth``); a :class:`~exprclone.pipeline.group.Group` for a target photo of several
        faces.

    Raises
    ------
    ExprCloneError
        A bad input, its ``subject`` the photo's role (:data:`ROLES`) or the option's name; a photo with no face
        raises its subclass ``NoFaceError``.

    Examples
    --------
    >>> import exprclone
    >>> from exprclone import data
    >>> prepared = exprclone.prepare(data.photo("126"), data.photo("126", "smile"), data.photo("003"))
    >>> half, whole = prepared.render(strength=0.5)["e+md"], prepared.render()["e+md"]
    >>> half.options.strength, whole.lambda_k == half.lambda_k
    (0.5, True)
    """
    request = Request.of(
        source_neutral,
        source_expression,
        target_neutral,
        landmarks=landmarks,
        options=options,
        target_faces=target_faces,
        check_roles=check_roles,
        **keywords,
    )
    return door.prepare(request, methods)


def clone(
    source_neutral: np.ndarray,
    source_expression: np.ndarray,
    target_neutral: np.ndarray,
    *,
    landmarks: Landmarks | None = None,
    options: Options | None = None,
    target_faces: Sequence[group.Found] | None = None,
    check_roles: bool | None = None,
    **keywords: Any,
) -> CloneResult:
    """Put the source's expression on the target's face: :func:`prepare` and render, by the options' ``method``.

    Parameters
    ----------
    source_neutral, source_expression, target_neutral : ndarray of shape (H, W, 3), uint8 RGB
        The three photos; they may differ in size.
    landmarks, options, target_faces, check_roles, **keywords
        As for :func:`prepare`: ``method="e+md"``, ``lambda_k="auto"`` (the elasticity ratio ``k_A' / k_N`` of
        Eq. 6; "auto" picks it by the DB metric, Eq. 8), ``strength=0.5``, ... (:class:`~exprclone.options.Options`).

    Returns
    -------
    CloneResult
        The image at the target photo's size, and every intermediate stage; for a target photo of several faces, the
        whole photo with every chosen face cloned, and each face's own clone in its ``face_results``.

    Raises
    ------
    ExprCloneError
        As for :func:`prepare`.

    See Also
    --------
    clone_methods : several methods at once.
    prepare : a clone to render again with other strengths.

    Examples
    --------
    >>> import exprclone
    >>> from exprclone import data
    >>> result = exprclone.clone(data.photo("126"), data.photo("126", "smile"), data.photo("003"), method="e+md")
    >>> result.image.shape, result.landmarks["final"].shape
    ((1350, 1350, 3), (68, 2))

    The options change how the stages run, given as keywords or as ``options=Options(...)``;
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
    prepared = prepare(
        source_neutral,
        source_expression,
        target_neutral,
        landmarks=landmarks,
        options=options,
        target_faces=target_faces,
        check_roles=check_roles,
        **keywords,
    )
    return prepared.render()[prepared.methods[0].name]


def clone_methods(
    source_neutral: np.ndarray,
    source_expression: np.ndarray,
    target_neutral: np.ndarray,
    methods: tuple[str, ...] = METHODS,
    *,
    landmarks: Landmarks | None = None,
    options: Options | None = None,
    target_faces: Sequence[group.Found] | None = None,
    check_roles: bool | None = None,
    **keywords: Any,
) -> dict[str, CloneResult]:
    """Several methods at once, sharing the stages they have in common (Fig. 5): :func:`prepare` and render.

    Parameters
    ----------
    source_neutral, source_expression, target_neutral, landmarks, options, target_faces, check_roles, **keywords
        As for :func:`prepare` (the options' ``method`` is not used).
    methods : tuple of str
        Any of :data:`METHODS`.

    Returns
    -------
    dict of str to CloneResult
        One result per method, in the order asked.

    Examples
    --------
    >>> import exprclone
    >>> from exprclone import data
    >>> results = exprclone.clone_methods(data.photo("126"), data.photo("126", "smile"), data.photo("003"), ("global", "e+md"))
    >>> list(results), results["global"].lambda_k is None
    (['global', 'e+md'], True)
    """
    return prepare(
        source_neutral,
        source_expression,
        target_neutral,
        methods,
        landmarks=landmarks,
        options=options,
        target_faces=target_faces,
        check_roles=check_roles,
        **keywords,
    ).render()
