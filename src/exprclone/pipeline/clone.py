"""The E+MD pipeline (paper Fig. 5) and the other six methods of Fig. 11: the entry points.

Stages: landmarks -> shape stages (global warping GI, local warping LI, the elastic
model with lambda_k by the DB metric; :data:`exprclone.pipeline.stages.SHAPE_STAGES`) ->
geometric warp FI -> details (ERI, MD model, mouth interior) -> F_IMG. :func:`prepare`
checks the three photos, finds their landmarks, hands them to a
:class:`~exprclone.Cloner`, which prepares the two neutral faces, and prepares
the source expression on them; its :meth:`~exprclone.pipeline.cloner.Prepared.render` makes the
images, as often as asked. :func:`clone` and :func:`clone_methods` are the two in one call. What each method runs is read from its row of
:data:`exprclone.methods.TABLE`; how its stages run, from the
:class:`~exprclone.options.Options`: which global warp gives GI (the paper's, Seol and
Lewis's RBF transfer, or landmarks given by any other method, which the elastic model
refines as in the paper's Figs. 19-21), which image warp gives FI, how much of the
expression is transferred (:mod:`exprclone.geometry.weights`), and whether the source's motion
is first made the target's (:mod:`exprclone.geometry.retarget`, not in the paper;
``retarget=False`` runs the paper's global and local stages).
"""

from __future__ import annotations

import dataclasses
import warnings
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..errors import ExprCloneError, ExprCloneWarning
from ..landmarks.backends import name_of, resolve
from ..methods import METHODS, lookup
from ..options import Options
from ..roles import ROLES, TARGET_NEUTRAL
from . import group, role_check
from .checks import check_face, check_image, check_points
from .cloner import Cloner, CloneResult, FaceResult, Prepared

__all__ = ["CloneResult", "Cloner", "FaceResult", "Prepared", "clone", "clone_methods", "prepare"]

#: given landmarks for the three photos (None entries are detected).
Landmarks = tuple[np.ndarray | None, np.ndarray | None, np.ndarray | None]


def prepare(
    source_neutral: np.ndarray,
    source_expression: np.ndarray,
    target_neutral: np.ndarray,
    methods: tuple[str, ...] | None = None,
    *,
    landmarks: Landmarks | None = None,
    options: Options | None = None,
    target_faces: Sequence[group.Found] | None = None,
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
    asked = Options.of(options, keywords)
    if methods is not None:
        lookup(methods)
    images = [check_image(im, role) for im, role in zip((source_neutral, source_expression, target_neutral), ROLES)]
    given = landmarks if landmarks is not None else (None, None, None)
    layout, detector = asked.landmarks_layout, resolve(asked.landmarker)
    s_neu, s_exp = (
        detector.detect(im, role) if p is None else check_face(check_points(p, im.shape, layout.n_points, role), layout, role)
        for im, p, role in zip(images[:2], given[:2], ROLES[:2])
    )
    placed = name_of(asked.landmarker) if any(p is None for p in given) else None
    if given[2] is None:
        found = tuple(target_faces) if target_faces is not None else group.find(images[2], detector, TARGET_NEUTRAL, layout)
        chosen = group.choose(found, asked.faces)
        if len(found) > 1:
            return _prepare_group(images, (s_neu, s_exp), found, chosen, methods, asked, placed)
        t_neu = found[0].points
    else:
        t_neu = check_face(check_points(given[2], images[2].shape, layout.n_points, TARGET_NEUTRAL), layout, TARGET_NEUTRAL)
        group.check_count(asked.faces, 1)
    return _prepare_one((images[0], images[1], images[2]), (s_neu, s_exp, t_neu), methods, asked, placed)


def _prepare_one(
    images: tuple[np.ndarray, np.ndarray, np.ndarray],
    points: tuple[np.ndarray, np.ndarray, np.ndarray],
    methods: tuple[str, ...] | None,
    options: Options,
    placed: str | None,
    stacklevel: int = 4,
) -> Prepared:
    """One face's clone prepared (:func:`prepare`): the photos and their landmarks, checked; what looked wrong with the
    photos issued as warnings (``stacklevel`` as :func:`warnings.warn`'s, from here)."""
    layout = options.landmarks_layout
    cloner = Cloner(images[0], points[0], images[2], points[2], options)
    neutral, expression, target = (role_check.Photo.of(im, p, layout) for im, p in zip(images, points))
    said = tuple(role_check.judge_roles(neutral, expression, layout, target))
    for message in said:
        warnings.warn(message, ExprCloneWarning, stacklevel=stacklevel)
    prepared = cloner.prepare(images[1], points[1], methods, crop=expression.crop)
    return dataclasses.replace(prepared, landmarker=placed, warnings=said)


def _prepare_group(
    images: list[np.ndarray],
    sources: tuple[np.ndarray, np.ndarray],
    found: tuple[group.Found, ...],
    chosen: tuple[group.Found, ...],
    methods: tuple[str, ...] | None,
    options: Options,
    placed: str | None,
) -> group.Group:
    """Several faces' clones prepared (:func:`prepare`), each chosen face's on its region (:mod:`exprclone.pipeline.group`);
    a face that cannot be cloned left as it is, with a warning naming it."""
    if options.global_landmarks is not None:
        raise ExprCloneError("global_landmarks", f"one face's, and {TARGET_NEUTRAL} shows {len(found)}: give its landmarks too")
    target, layout = images[2], options.landmarks_layout
    said: list[str] = [f"{TARGET_NEUTRAL}: face {f.number}: {f.problem}; left as it is" for f in chosen if f.problem]
    taken = {f.number for f in chosen}
    left = {f.number: f.problem or "not chosen" for f in found if f.problem or f.number not in taken}
    cloned = []
    for face in (f for f in chosen if not f.problem):
        x0, y0, x1, y1 = box = group.region(face.points, target.shape)
        crop = np.ascontiguousarray(target[y0:y1, x0:x1])
        try:
            points = check_face(check_points(face.points - (x0, y0), crop.shape, layout.n_points, TARGET_NEUTRAL), layout, TARGET_NEUTRAL)
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                one = _prepare_one((images[0], images[1], crop), (*sources, points), methods, options, placed)
        except ExprCloneError as e:
            if e.subject != TARGET_NEUTRAL:  # an option's or a source photo's: every face's
                raise
            said.append(f"{TARGET_NEUTRAL}: face {face.number}: {e.problem}; left as it is")
            left[face.number] = e.problem
            continue
        said += [str(w.message) for w in caught if str(w.message) not in said]
        cloned.append((face, box, one))
    for message in said:
        warnings.warn(message, ExprCloneWarning, stacklevel=3)
    weights = group.weights(found, [f for f, _, _ in cloned], [r for _, r, _ in cloned], target.shape)
    chosen_methods = lookup(methods or (options.method,))
    return group.Group(target, found, chosen_methods, options, tuple(cloned), tuple(weights), left, placed, tuple(said))


def clone(
    source_neutral: np.ndarray,
    source_expression: np.ndarray,
    target_neutral: np.ndarray,
    *,
    landmarks: Landmarks | None = None,
    options: Options | None = None,
    target_faces: Sequence[group.Found] | None = None,
    **keywords: Any,
) -> CloneResult:
    """Put the source's expression on the target's face: :func:`prepare` and render, by the options' ``method``.

    Parameters
    ----------
    source_neutral, source_expression, target_neutral : ndarray of shape (H, W, 3), uint8 RGB
        The three photos; they may differ in size.
    landmarks, options, target_faces, **keywords
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
        source_neutral, source_expression, target_neutral, landmarks=landmarks, options=options, target_faces=target_faces, **keywords
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
    **keywords: Any,
) -> dict[str, CloneResult]:
    """Several methods at once, sharing the stages they have in common (Fig. 5): :func:`prepare` and render.

    Parameters
    ----------
    source_neutral, source_expression, target_neutral, landmarks, options, target_faces, **keywords
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
        **keywords,
    ).render()
